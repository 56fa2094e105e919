"""Frictionless contact of a plane-strain elastic body against a rigid analytic obstacle (dolfinx 0.11).

Units: mm, N, MPa; loads P per unit thickness (N/mm). Gap g > 0 open; pressure p >= 0 compressive. The weak
forms (penalty, Nitsche) are documented in :mod:`fem.contact_forms`.

Solution: semismooth Newton (PETSc SNES ``newtonls`` with ``basic`` full steps, LU/MUMPS) per load step.
Because small-strain frictionless contact is path independent, the cost is all in the active set. Measured on
the Hertz scene, semismooth Newton started from a predicted u whose active set is decided by the sign of its
tiny gaps releases about one quadrature point per iteration (10-25 iterations per step). So every solve
starts with ONE Newton iteration on a prescribed active set ``lo < X1 < hi`` (the Hertz zone of the load
level, or the contact edges of the last two states extrapolated linearly in d), then the true law:

* predictor ``hertz`` (force control, circle/parabola, direction (0, -1); :mod:`fem.predictor`): u from a
  linear solve with the Hertz pressure as a Neumann load, d from its displacement at the first-contact point;
* predictor ``extrapolate``: u linear in d from the last two converged states; without history a short first
  step at ``first_step_fraction`` of the first level.

Reported ``iterations`` count that predictor iteration too (1 = the prescribed active set was already right).

* ``control="displacement"``: the obstacle moves by ``d_k = target k / n_steps`` along its direction.
* ``control="force"``: load levels ``P_k = target k / n_steps``; d from the Hertz predictor or the secant
  through the last two (d, P) states (the first from a stiffness guess 0.3 E'); the last level is corrected on
  d until ``|P - target| <= force_rtol target`` (each a separate record, kind ``force-correction``). For a
  fixed active set the small-strain equations are linear in (u, d), so a correction first tries the tangent
  of the last converged state with the LU factors the Newton solve already holds: ``J t = -dF/dd`` (dF/dd by
  a central difference in d of the residual), ``dP/dd = P(t)``, ``Delta d = (target - P) / (dP/dd)``,
  ``u + Delta d t``; that state then goes through the same SNES solve (true law, same tolerances and
  converged-reason checks), which accepts it without iterating (0 iterations recorded) when the active set
  did not change, and may take one Newton iteration otherwise. When the tangent does not apply (mixed
  formulation, curve obstacles, a miss above 1 % of the target), its solve needs more than one iteration
  (discarded), or it needed one or cut the force miss less than tenfold (an active-set change between the
  factored J and the converged state), the remaining corrections are secant steps through the last two
  (d, P) states. ``iterations`` 0: the tangent state was accepted as it was.

Divergence (SNES converged reason <= 0) restores the last converged state and halves the increment, up to
``max_cutbacks`` times per step, then raises :class:`ContactSolveError` naming the reason (e.g. ``-5
(DIVERGED_MAX_IT)``). A converged result carries named ``warnings`` instead of silently wrong numbers:
"contact unresolved" (< ``min_facets_across`` facets across a patch), "contact truncated", "no contact",
"penetration", "pressure oscillation" (:mod:`fem.postprocess`) and "near-incompressible" (displacement
formulation at nu >= 0.45; ``formulation="mixed"`` is the locking-free Taylor-Hood u-p option).

Measured load ``P`` (virtual work): ``P = -a(u, w)`` with ``w`` equal to the loading direction at every
Dirichlet-constrained component dof and 0 elsewhere, i.e. the support reaction along the direction; it
equals the discrete contact force. ``P_pressure = int p (n_o . direction) ds`` is the resultant of the
contact pressure along the direction (for both methods it equals P up to round-off, because the Nitsche
stress terms vanish for a rigid test field; it is a consistency check of the assembly). For
``symmetric_half=True`` both are doubled (full-body values) and patches are mirrored.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

import itertools
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import dolfinx
import dolfinx.fem.petsc
import dolfinx.la.petsc
import numpy as np
import ufl
from mpi4py import MPI

from fem.contact_forms import build_contact_forms
from fem.elasticity import lame, mixed_constraint, plane_strain_modulus, sigma, sigma_mixed
from fem.postprocess import (
    LOCKING_NU,
    Patch,
    SurfaceSampler,
    SurfaceSamples,
    contact_edges,
    find_patches,
    oscillation_warnings,
    penetration_warning,
    resolution_warnings,
)
from fem.predictor import HertzPredictor as _HertzPredictor

__all__ = ["ContactSolveError", "ContactResult", "Snapshot", "solve_contact", "snes_reason_name", "SUPPORT_KINDS",
           "FORMULATIONS", "MIN_FACETS_ACROSS"]

SUPPORT_KINDS = ("clamped", "roller_x", "roller_y", "free")
FORMULATIONS = ("displacement", "mixed")
# A patch spanning fewer contact facets than this is reported "contact unresolved" (ContactResult.warnings):
# with P2 and 2 Gauss points per facet the edge-location error is about one Gauss spacing, so < 8 facets
# across the patch means a half-width error above ~ 1/16 and a peak that depends on where the nodes fall.
MIN_FACETS_ACROSS = 8
_counter = itertools.count()


class ContactSolveError(RuntimeError):
    """A nonlinear contact solve failed (after cut-backs); the message names case, step and SNES reason."""


@dataclass(frozen=True)
class ContactResult:
    """Result of :func:`solve_contact` (full-body values for a half model).

    Attributes:
        ndofs: global number of displacement dofs.
        wall_time_s: wall time of the load stepping (s); the forms are compiled before the clock starts.
        newton_iterations: Newton iterations per converged solve (load steps and force corrections), the
            prescribed-active-set predictor iteration included.
        load_steps: one dict per converged solve: d (mm), P (N/mm), iterations, time (s), kind.
        d: final rigid displacement (mm).
        P: final load by virtual work / support reaction (N/mm).
        P_pressure: final resultant of the contact pressure along the loading direction (N/mm).
        samples: surface samples (half-model samples are NOT mirrored; s = X1).
        patches: contact patches (full body).
        u: displacement Function.
        options: the solver options used.
        half: True for a half model.
        forms: the ContactForms (UFL pieces) for output.
        lame: Lame parameters.
        snapshots: one :class:`Snapshot` per ``record_at`` displacement (displacement control).
        warnings: named warnings about the result's trustworthiness, e.g. ``"contact unresolved: ..."`` when a
            patch spans fewer than ``min_facets_across`` contact facets (see
            :func:`fem.postprocess.resolution_warnings`); empty when none.
        pressure_field: the P1 pressure ``p = -lambda div u`` (MPa) of the mixed formulation, else None.
    """

    ndofs: int
    wall_time_s: float
    newton_iterations: list
    load_steps: list
    d: float
    P: float
    P_pressure: float
    samples: SurfaceSamples
    patches: list[Patch]
    u: Any
    options: dict
    half: bool
    forms: Any = field(repr=False)
    lame: Any = field(repr=False)
    snapshots: list = field(default_factory=list)
    warnings: list = field(default_factory=list)
    pressure_field: Any = field(default=None, repr=False)


class Snapshot(NamedTuple):
    """Surface state at one recorded displacement (``record_at``): d (mm), P and P_pressure (N/mm, full
    body), surface samples, patches, the Newton iterations of the solve that reached it, and the named
    warnings of that state (as :attr:`ContactResult.warnings`)."""

    d: float
    P: float
    P_pressure: float
    samples: SurfaceSamples
    patches: list[Patch]
    iterations: int
    warnings: tuple = ()


def snes_reason_name(reason: int) -> str:
    """PETSc's name of a SNES converged reason (e.g. -5 -> ``DIVERGED_MAX_IT``)."""
    from petsc4py import PETSc

    names = {v: k for k, v in vars(PETSc.SNES.ConvergedReason).items() if k.isupper() and isinstance(v, int)}
    return names.get(int(reason), f"UNKNOWN_{int(reason)}")


def _supports(mesh_data, supports, symmetric_half):
    groups = mesh_data.physical_groups
    if supports is None:
        supports = {"clamped": "clamped"}
        if symmetric_half:
            supports["symmetry"] = "roller_x"
    for name, kind in supports.items():
        if kind not in SUPPORT_KINDS:
            raise ValueError(f"supports[{name!r}] must be one of {SUPPORT_KINDS}, got {kind!r}")
        if name not in groups:
            raise ValueError(f"supports names unknown physical group {name!r}; known: {sorted(groups)}")
    return supports


def _group_facets(mesh_data, name):
    tag = mesh_data.physical_groups[name].tag
    return mesh_data.facet_tags.find(tag)


def solve_contact(mesh_data, obstacle, *, E: float, nu: float, degree: int = 2, method: str = "nitsche",
                  kinematics: str = "small", traction: str = "obstacle", kappa0: float = 1e3,
                  gamma0: float = 10.0, theta: float = 1.0, control: str = "displacement",
                  target: float, n_steps: int = 4, symmetric_half: bool = False,
                  on_step: Callable | None = None, petsc_prefix: str | None = None, max_cutbacks: int = 5,
                  supports: dict | None = None, contact_group: str = "contact",
                  quadrature_degree: int | None = None, force_rtol: float = 1e-10, snes_rtol: float = 1e-10,
                  max_it: int = 40, case: str = "contact", petsc_options: dict | None = None,
                  predictor: str = "auto", sample_degree: int | None = None,
                  active_set_predictor: bool = True, first_step_fraction: float = 0.1,
                  record_at: Sequence[float] | None = None, formulation: str = "displacement",
                  min_facets_across: int = MIN_FACETS_ACROSS) -> ContactResult:
    """Solve frictionless contact of the meshed body against a rigid obstacle.

    Args:
        mesh_data: dolfinx ``MeshData`` (mesh, facet_tags, physical_groups) of the elastic body.
        obstacle: rigid obstacle from :mod:`fem.obstacles`.
        E: Young's modulus (MPa) > 0.  nu: Poisson's ratio in [0, 0.5).
        degree: Lagrange degree (1 or 2).
        method: ``"nitsche"`` or ``"penalty"``.  kinematics: ``"small"`` or ``"convective"``.
        traction: ``"obstacle"`` or ``"halfplane"``.  kappa0, gamma0, theta: method parameters.
        control: ``"displacement"`` (target = d, mm) or ``"force"`` (target = P, N/mm; full body).
        n_steps: number of load steps >= 1.
        symmetric_half: the mesh is the half x >= 0 with a ``symmetry`` edge (default support roller_x).
        on_step: callable(dict) called after every converged solve with the load-step record.
        petsc_prefix: unique PETSc options prefix (default: generated).
        max_cutbacks: step halvings allowed per load step.
        supports: physical group name -> one of SUPPORT_KINDS (default clamped bottom ``clamped``, and
            ``symmetry``: roller_x for a half model).
        contact_group: name of the candidate contact boundary.
        quadrature_degree: Gauss degree of the contact integral (default 2 degree - 1: 2 points per P2 facet,
            1 per P1 facet; more points than trace dofs over-constrain the penalty and make p oscillate).
        sample_degree: Gauss degree of the post-processing sample points (default: the contact quadrature, where
            the discrete law holds; between those points the law of a penalty/Nitsche solution oscillates).
        predictor: ``"extrapolate"`` (u linear in d from the last two states), ``"hertz"`` (force control,
            circle/parabola, direction (0, -1): linear solve with the Hertz pressure of the load level as a
            Neumann load; d from the displacement at the first-contact point) or ``"auto"`` (hertz when
            applicable).
        active_set_predictor: before each Newton solve do one iteration with a prescribed active set (the
            Hertz zone, or contact edges extrapolated linearly in d from the last two states; single-patch
            scenes with the surface coordinate X1). Without it the sign of the tiny gaps of the predicted u
            decides the first active set and semismooth Newton then releases about one quadrature point
            per iteration.
        first_step_fraction: without the Hertz predictor, an extra first step at this fraction of the first
            load level (few quadrature points are in the initial overlap, so the unpredicted first solve is
            short); 1 disables it.
        record_at: displacement control only: increasing displacements (mm) ending at ``target``; the solver
            steps through them (``n_steps`` sub-steps to the first) and keeps a :class:`Snapshot` at each.
        force_rtol: relative tolerance of the final load in force control.
        snes_rtol: SNES relative residual tolerance.  max_it: SNES max iterations.
        case: name used in error messages.
        petsc_options: extra SNES options overriding the defaults (e.g. ``{"snes_linesearch_type": "l2"}``).
        formulation: ``"displacement"`` (default) or ``"mixed"``: Taylor-Hood u-p plane strain (P``degree`` u,
            P``degree-1`` p = -lambda div u, :mod:`fem.elasticity`), locking-free as nu -> 1/2; the contact
            terms are unchanged (Nitsche uses the mixed stress ``2 mu eps - p I``). Needs degree >= 2 and an
            analytic obstacle.
        min_facets_across: a patch spanning fewer contact facets adds a "contact unresolved" warning.

    Raises:
        ValueError: bad option.  ContactSolveError: SNES failure after the allowed cut-backs.
    """
    if degree not in (1, 2, 3):
        raise ValueError(f"degree must be 1, 2 or 3, got {degree}")
    if control not in ("displacement", "force"):
        raise ValueError(f"control must be 'displacement' or 'force', got {control!r}")
    if not (target > 0 and np.isfinite(target)):
        raise ValueError(f"target must be > 0 (mm or N/mm), got {target}")
    if int(n_steps) < 1:
        raise ValueError(f"n_steps must be >= 1, got {n_steps}")
    if contact_group not in mesh_data.physical_groups:
        raise ValueError(f"contact_group {contact_group!r} not in mesh physical groups")
    if formulation not in FORMULATIONS:
        raise ValueError(f"formulation must be one of {FORMULATIONS}, got {formulation!r}")
    mixed = formulation == "mixed"
    if mixed and degree < 2:
        raise ValueError(f"degree must be >= 2 for formulation='mixed' (Taylor-Hood), got {degree}")
    if mixed and not getattr(obstacle, "analytic", False):
        raise ValueError("formulation='mixed' needs an analytic obstacle (not a CurveObstacle)")
    lm = lame(E=E, nu=nu)
    mesh = mesh_data.mesh
    comm = mesh.comm
    fdim = mesh.topology.dim - 1
    supports = _supports(mesh_data, supports, symmetric_half)
    qdeg = 2 * degree - 1 if quadrature_degree is None else int(quadrature_degree)
    sdeg = qdeg if sample_degree is None else int(sample_degree)
    mult = 2.0 if symmetric_half else 1.0

    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (2,)))
    u = dolfinx.fem.Function(V, name="displacement")
    d = dolfinx.fem.Constant(mesh, 0.0)
    mask = tuple(dolfinx.fem.Constant(mesh, 0.0) for _ in range(3))  # (on, lo, hi) active-set predictor
    contact_facets = _group_facets(mesh_data, contact_group)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=mesh_data.facet_tags,
                     metadata={"quadrature_degree": qdeg})
    ds_c = ds(mesh_data.physical_groups[contact_group].tag)
    ph = None
    if mixed:
        Q = dolfinx.fem.functionspace(mesh, ("Lagrange", degree - 1))
        ph = dolfinx.fem.Function(Q, name="pressure")
        W = ufl.MixedFunctionSpace(V, Q)
        v_t, q_t = ufl.TestFunctions(W)
        du_t, dp_t = ufl.TrialFunctions(W)
        stress = sigma_mixed(u, ph, lm)
        bulk = (ufl.inner(stress, ufl.grad(v_t)) + mixed_constraint(u, ph, q_t, lm)) * ufl.dx
        mixed_kw = dict(v=v_t, stress_u=stress, stress_v=sigma_mixed(v_t, q_t, lm), bulk=bulk)
    else:
        stress = sigma(u, lm)
        mixed_kw = {}
    forms = build_contact_forms(u=u, obstacle=obstacle, d=d, lame=lm, E=E, method=method, kinematics=kinematics,
                                traction=traction, kappa0=kappa0, gamma0=gamma0, theta=theta, ds_c=ds_c,
                                contact_facets=contact_facets, mask=mask, **mixed_kw)

    # Dirichlet supports and the virtual-work field w (direction at constrained component dofs).
    bcs = []
    w = dolfinx.fem.Function(V)
    direction = obstacle.direction
    for name, kind in supports.items():
        comps = {"clamped": (0, 1), "roller_x": (0,), "roller_y": (1,), "free": ()}[kind]
        facets = _group_facets(mesh_data, name)
        for c in comps:
            Vc, _ = V.sub(c).collapse()
            dofs = dolfinx.fem.locate_dofs_topological((V.sub(c), Vc), fdim, facets)
            bcs.append(dolfinx.fem.dirichletbc(dolfinx.fem.Function(Vc), dofs, V.sub(c)))
            w.x.array[dofs[0]] = direction[c]
    reaction_form = dolfinx.fem.form(-ufl.inner(stress, ufl.grad(w)) * ufl.dx)
    pressure_form = dolfinx.fem.form(-forms.pressure * ufl.dot(forms.n_c, ufl.as_vector(direction)) * ds_c)

    prefix = petsc_prefix or f"fem_contact_{next(_counter)}_"
    x_all = mesh.geometry.x
    L = comm.allreduce(float(np.max(np.ptp(x_all[:, :2], axis=0))) if x_all.size else 0.0, op=MPI.MAX)
    opts = {"snes_type": "newtonls", "snes_linesearch_type": "basic", "ksp_type": "preonly", "pc_type": "lu",
            "pc_factor_mat_solver_type": "mumps", "snes_rtol": snes_rtol, "snes_atol": 1e-13 * E * L,
            "snes_stol": 0.0, "snes_max_it": max_it}
    opts.update(petsc_options or {})
    if mixed:
        J_full = ufl.derivative(forms.F, u, du_t) + ufl.derivative(forms.F, ph, dp_t)
        problem = dolfinx.fem.petsc.NonlinearProblem(ufl.extract_blocks(forms.F), [u, ph], bcs=bcs,
                                                     J=ufl.extract_blocks(J_full), kind="mpi",
                                                     petsc_options_prefix=prefix, petsc_options=opts)
    else:
        problem = dolfinx.fem.petsc.NonlinearProblem(forms.F, u, bcs=bcs, J=forms.J, petsc_options_prefix=prefix,
                                                     petsc_options=opts)
    snes = problem.solver
    if forms.update is not None:
        ctx = {"u": u, "residual": problem.F, "jacobian": problem.J, "bcs": bcs}

        def residual(snes_, x, b):
            dolfinx.la.petsc._ghost_update(x, dolfinx.fem.petsc.PETSc.InsertMode.INSERT,
                                           dolfinx.fem.petsc.PETSc.ScatterMode.FORWARD)
            dolfinx.fem.petsc.assign(x, u)
            forms.update(u)
            dolfinx.fem.petsc.assemble_residual(snes_, x, b, **ctx)

        snes.setFunction(residual, problem.b)

    def measure():
        P = mult * comm.allreduce(dolfinx.fem.assemble_scalar(reaction_form), op=MPI.SUM)
        Pp = mult * comm.allreduce(dolfinx.fem.assemble_scalar(pressure_form), op=MPI.SUM)
        return P, Pp

    n_u = u.x.array.size

    def get_state():
        return u.x.array.copy() if ph is None else np.concatenate([u.x.array, ph.x.array])

    def set_state(arr):
        """Set u (and the mixed pressure); a displacement-only array keeps the last converged pressure."""
        u.x.array[:] = arr[:n_u]
        u.x.scatter_forward()
        if ph is not None:
            ph.x.array[:] = arr[n_u:] if arr.size > n_u else states[-1][2][n_u:]
            ph.x.scatter_forward()

    states = [(0.0, 0.0, get_state() * 0.0)]  # converged (d, P, state = u or [u, p]) history
    records: list[dict] = []
    edges: list = [None]  # contact zone (lo, hi) of each state (None: unknown or not a single patch)
    t_start = time.perf_counter()
    E_star = plane_strain_modulus(E=E, nu=nu)
    if predictor not in ("auto", "hertz", "extrapolate"):
        raise ValueError(f"predictor must be 'auto', 'hertz' or 'extrapolate', got {predictor!r}")
    hertz_ok = (control == "force" and hasattr(obstacle, "hertz_contact")
                and abs(obstacle.direction[0]) < 1e-14 and obstacle.direction[1] < 0)
    if predictor == "hertz" and not hertz_ok:
        raise ValueError("predictor='hertz' needs control='force', a circle/parabola obstacle and direction (0, -1)")
    hertz_pred = (_HertzPredictor(u=u, obstacle=obstacle, lame=lm, E_star=E_star, bcs=bcs, ds_c=ds_c,
                                  facets=contact_facets, prefix=prefix + "hertz_")
                  if (predictor == "hertz" or (predictor == "auto" and hertz_ok)) else None)

    def extrapolate(d_new):
        if len(states) == 1:
            return states[-1][2]
        (d1, _, u1), (d2, _, u2) = states[-2], states[-1]
        if d2 == d1:
            return u2
        return u2 + (d_new - d2) / (d2 - d1) * (u2 - u1)

    samplers: dict[int, SurfaceSampler] = {}  # Gauss degree -> sampler (one Expression per solve and degree)

    def sample(degree):
        if degree not in samplers:
            samplers[degree] = SurfaceSampler(u=u, forms=forms, facets=contact_facets, quadrature_degree=degree)
        return samplers[degree]()

    def edges_now():
        if not active_set_predictor:
            return None
        smp = sample(qdeg)
        runs = contact_edges(smp.s, smp.q)
        if len(runs) != 1:
            return None
        left, right, i, _ = runs[0]
        return (-np.inf if i == 0 else left), right

    def predicted_edges(d_new):
        if len(edges) < 2 or edges[-1] is None:
            return None
        (d1, e1), (d2, e2) = (states[-2][0], edges[-2]), (states[-1][0], edges[-1])
        if e1 is None and len(states) == 2:  # from the unloaded state: a zone shrunk to the first-contact point
            c = 0.0 if np.isinf(e2[0]) else 0.5 * (e2[0] + e2[1])
            e1 = (e2[0] if np.isinf(e2[0]) else c, c)
        if e1 is None:
            return None
        if d2 == d1:
            return e2
        f = (d_new - d2) / (d2 - d1)
        lo = -np.inf if np.isinf(e2[0]) else e2[0] + f * (e2[0] - e1[0])
        return lo, e2[1] + f * (e2[1] - e1[1])

    def attempt(d_new, u_pred, kind, zone=None, predict_active_set=True):
        t0 = time.perf_counter()
        d.value = d_new
        set_state(u_pred)
        if forms.update is not None:
            forms.update(u)
        pre = 0
        if zone is None and predict_active_set:
            zone = predicted_edges(d_new)
        if zone is not None and active_set_predictor and predict_active_set:
            # One Newton iteration with the predicted active set lo < X1 < hi, then the true law.
            mask[0].value, mask[1].value, mask[2].value = 1.0, max(zone[0], -1e300), zone[1]
            snes.setTolerances(max_it=1)
            problem.solve()
            snes.setTolerances(max_it=max_it)
            mask[0].value = 0.0
            pre = 1
        problem.solve()
        reason, its = snes.getConvergedReason(), snes.getIterationNumber() + pre
        factored[0] = factored[0] or its > 0
        if reason <= 0:
            return reason, its
        P, Pp = measure()
        states.append((d_new, P, get_state()))
        edges.append(edges_now())
        rec = {"d": d_new, "P": P, "P_pressure": Pp, "iterations": its, "time": time.perf_counter() - t0,
               "kind": kind, "reason": reason}
        records.append(rec)
        if on_step is not None:
            on_step(rec)
        return reason, its

    factored = [False]  # the SNES's KSP holds LU factors of a Jacobian of this problem
    tangent_ok = not mixed and forms.update is None

    def tangent_correction(P_goal) -> bool:
        """One force correction along the tangent of the last converged state (module docstring).

        Returns True when it produced a converged state; False (state restored) when the tangent does not
        apply or its SNES solve did not converge within one iteration, so the caller falls back to the secant.
        """
        if not (tangent_ok and factored[0]):
            return False
        d0, P0, u0 = states[-1]
        x = problem.x
        set_state(u0)
        dolfinx.fem.petsc.assign(u, x)
        dolfinx.la.petsc._ghost_update(x, dolfinx.fem.petsc.PETSc.InsertMode.INSERT,
                                       dolfinx.fem.petsc.PETSc.ScatterMode.FORWARD)
        f_plus, f_minus, t = x.duplicate(), x.duplicate(), x.duplicate()
        try:
            delta = 1e-6 * max(abs(d0), 1e-300)
            for dv, f in ((d0 + delta, f_plus), (d0 - delta, f_minus)):
                d.value = dv
                try:
                    snes.computeFunction(x, f)
                except dolfinx.fem.petsc.PETSc.Error as exc:  # Ctrl-C in the Python residual: re-raise it as such
                    if isinstance(exc.__cause__, KeyboardInterrupt):
                        raise exc.__cause__ from None
                    raise
            d.value = d0
            f_plus.axpy(-1.0, f_minus)
            f_plus.scale(-1.0 / (2.0 * delta))  # -dF/dd
            snes.getKSP().solve(f_plus, t)  # the Jacobian already factored: no new LU
            dolfinx.la.petsc._ghost_update(t, dolfinx.fem.petsc.PETSc.InsertMode.INSERT,
                                           dolfinx.fem.petsc.PETSc.ScatterMode.FORWARD)
            dolfinx.fem.petsc.assign(t, u)
            t_arr = u.x.array.copy()
        finally:
            for vec in (f_plus, f_minus, t):
                vec.destroy()
        dP = measure()[0]  # P is linear in u: the load of the tangent field t
        set_state(u0)
        finite = comm.allreduce(bool(np.all(np.isfinite(t_arr))), op=MPI.LAND)  # the same decision on every rank
        if not (finite and np.isfinite(dP) and dP > 0):
            return False
        dd = (P_goal - P0) / dP
        if not abs(dd) <= 0.5 * abs(d0):
            return False
        # At most one Newton iteration from the tangent state: more means the active set moved, which the
        # secant step with its active-set predictor handles in fewer iterations than semismooth Newton does.
        snes.setTolerances(max_it=1)
        try:
            reason, _ = attempt(d0 + dd, u0 + dd * t_arr, "force-correction", predict_active_set=False)
        finally:
            snes.setTolerances(max_it=max_it)
        if reason > 0:
            return True
        d.value = d0
        set_state(u0)
        return False

    def reach(d_target, step, kind, u_pred=None, zone=None):
        """Reach d_target from the last converged state, halving the increment on divergence."""
        cut = 0
        while True:
            d_prev = states[-1][0]
            d_try = d_target if cut == 0 else d_prev + (d_target - d_prev) / 2.0**cut
            guess = u_pred if (cut == 0 and u_pred is not None) else extrapolate(d_try)
            reason, its = attempt(d_try, guess, kind if cut == 0 else "cutback", zone if cut == 0 else None)
            if reason > 0:
                if d_try == d_target:
                    return
                cut = 0
                u_pred = zone = None
                continue
            cut += 1
            if cut > max_cutbacks:
                raise ContactSolveError(f"{case}: load step {step} (d = {d_try:.6g} mm) diverged: SNES reason "
                                        f"{reason} ({snes_reason_name(reason)}) after {its} iterations and "
                                        f"{max_cutbacks} cut-backs")

    def quality_warnings(smp, d_now):
        """Named warnings of a converged state: resolution, penetration, oscillation, locking risk."""
        out = resolution_warnings(smp, quadrature_degree=sdeg, half=symmetric_half,
                                  min_facets_across=min_facets_across)
        pen = penetration_warning(smp, d=d_now)
        out += ([pen] if pen else []) + oscillation_warnings(smp)
        if not mixed and nu >= LOCKING_NU:
            out.append(f"near-incompressible: nu = {nu:g} >= {LOCKING_NU} with the displacement formulation "
                       "(volumetric locking); use formulation='mixed'")
        return out

    if not 0.0 < first_step_fraction <= 1.0:
        raise ValueError(f"first_step_fraction must be in (0, 1], got {first_step_fraction}")
    snapshots: list[Snapshot] = []
    if control == "displacement" and record_at:
        # Step through the recorded displacements in turn (n_steps sub-steps to the first one, one step between
        # the others, cut back as needed) and keep a snapshot of the surface at each.
        levels = [float(v) for v in record_at]
        if any(v <= 0 for v in levels) or levels != sorted(levels) or levels[-1] != float(target):
            raise ValueError("record_at must be increasing values > 0 (mm) ending at target")
        for k in range(1, n_steps + 1):
            reach(levels[0] * k / n_steps, k, "step")
        for k, level in enumerate(levels):
            if k > 0:
                reach(level, n_steps + k, "step")
            smp = sample(sdeg)
            P_k, Pp_k = measure()
            snapshots.append(Snapshot(d=level, P=float(P_k), P_pressure=float(Pp_k), samples=smp,
                                      patches=find_patches(smp, half=symmetric_half),
                                      iterations=int(records[-1]["iterations"]) if records else 0,
                                      warnings=tuple(quality_warnings(smp, level))))
    elif control == "displacement":
        if first_step_fraction < 1.0:
            reach(first_step_fraction * target / n_steps, 0, "first")
        for k in range(1, n_steps + 1):
            reach(target * k / n_steps, k, "step")
    else:
        def secant(P_goal):
            (d1, P1, _), (d2, P2, _) = states[-2], states[-1]
            if P2 == P1:
                return d2 * P_goal / P2 if P2 > 0 else P_goal / (0.3 * E_star)
            return d2 + (P_goal - P2) * (d2 - d1) / (P2 - P1)

        for k in range(1, n_steps + 1):
            P_goal = target * k / n_steps
            zone = None
            if hertz_pred is not None:
                d_next, u_next, zone = hertz_pred(P_goal, half=symmetric_half)
            else:
                if len(states) == 1 and first_step_fraction < 1.0:
                    reach(first_step_fraction * P_goal / (0.3 * E_star), 0, "first")
                d_next = P_goal / (0.3 * E_star) if len(states) == 1 else secant(P_goal)
                u_next = None
            reach(d_next, k, "step", u_next, zone)
        use_tangent = True
        for _ in range(30):
            miss = abs(states[-1][1] - target)
            if miss <= force_rtol * target:
                break
            # The tangent is tried for a small miss only (<= 1 %: the step came from the Hertz predictor or a
            # secant); a large one moves the active set by many points and needs the active-set predictor.
            if use_tangent and miss <= 1e-2 * target and tangent_correction(target):
                # A tangent state that needed a Newton iteration sits across an active-set change (the factored
                # J is not the one of the converged state), and so will the next one: the secant takes over.
                use_tangent = records[-1]["iterations"] == 0 and abs(states[-1][1] - target) <= 0.1 * miss
            else:
                use_tangent = False
                reach(secant(target), n_steps, "force-correction")
        else:
            raise ContactSolveError(f"{case}: force control did not reach P = {target} N/mm (last P = "
                                    f"{states[-1][1]:.10g}) in 30 secant corrections")
    wall = time.perf_counter() - t_start

    samples = sample(sdeg)
    patches = find_patches(samples, half=symmetric_half)
    warns = quality_warnings(samples, states[-1][0])
    P, Pp = measure()
    options = dict(E=E, nu=nu, degree=degree, method=method, kinematics=kinematics, traction=traction,
                   kappa0=kappa0, gamma0=gamma0, theta=theta, control=control, target=target, n_steps=n_steps,
                   symmetric_half=symmetric_half, supports=supports, quadrature_degree=qdeg, sample_degree=sdeg,
                   prefix=prefix, predictor="hertz" if hertz_pred is not None else "extrapolate",
                   formulation=formulation)
    ndofs = V.dofmap.index_map.size_global * 2 + (ph.function_space.dofmap.index_map.size_global if mixed else 0)
    return ContactResult(ndofs=ndofs, wall_time_s=wall,
                         newton_iterations=[r["iterations"] for r in records], load_steps=records,
                         d=float(states[-1][0]), P=float(P), P_pressure=float(Pp), samples=samples,
                         patches=patches, u=u, options=options, half=symmetric_half, forms=forms, lame=lm,
                         snapshots=snapshots, warnings=warns, pressure_field=ph)
