"""Frictionless contact of a plane-strain elastic body against a rigid analytic obstacle (dolfinx 0.11).

Units: mm, N, MPa; loads P per unit thickness (N/mm). Gap g > 0 open; pressure p >= 0 compressive. The weak
forms are documented in :mod:`fem.contact_forms` and in the method modules (:mod:`fem.methods`: penalty,
Nitsche, augmented Lagrangian).

:func:`solve_contact` is the whole solve in three objects:

* :class:`fem.problem.ContactProblem`: spaces, supports, forms, the load measures (P by virtual work,
  P_pressure) and the dolfinx NonlinearProblem (SNES ``newtonls``/``basic``, LU/MUMPS);
* :class:`fem.stepping.LoadStepper`: load steps, cut-backs, force control (secant and tangent corrections),
  the Hertz / extrapolation / active-set predictors and the converged states;
* :class:`ContactResult`: what the caller gets back.

Reported ``iterations`` count the predictor iteration too (1 = the prescribed active set was already right;
0 = a tangent force-correction state accepted as it was).

Divergence (SNES converged reason <= 0) restores the last converged state and halves the increment, up to
``max_cutbacks`` times per step, then raises :class:`ContactSolveError` naming the reason (e.g. ``-5
(DIVERGED_MAX_IT)``). A converged result carries named ``warnings`` instead of silently wrong numbers:
"contact unresolved" (< ``min_facets_across`` facets across a patch), "contact truncated", "no contact",
"penetration", "pressure oscillation" (:mod:`fem.postprocess`) and "near-incompressible" (displacement
formulation at nu >= 0.45; ``formulation="mixed"`` is the locking-free Taylor-Hood u-p option).

Measured load ``P`` (virtual work): ``P = -a(u, w)`` with ``w`` equal to the loading direction at every
Dirichlet-constrained component dof and 0 elsewhere, i.e. the support reaction along the direction; it
equals the discrete contact force. ``P_pressure = int p (n_o . direction) ds`` is the resultant of the
contact pressure along the direction (it equals P up to round-off, because the Nitsche stress terms vanish for
a rigid test field; it is a consistency check of the assembly). For ``symmetric_half=True`` both are doubled
(full-body values) and patches are mirrored.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

import inspect
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, fields
from typing import Any

from fem.errors import ContactSolveError, snes_reason_name
from fem.options import FORMULATIONS, MIN_FACETS_ACROSS, SUPPORT_KINDS, ContactOptions, check_options
from fem.postprocess import Patch, SurfaceSamples, find_patches
from fem.problem import ContactProblem
from fem.stepping import LoadStepper, Snapshot

__all__ = ["ContactSolveError", "ContactResult", "ContactOptions", "Snapshot", "solve_contact", "solve_problem",
           "snes_reason_name",
           "SUPPORT_KINDS", "FORMULATIONS", "MIN_FACETS_ACROSS"]

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


def solve_contact(mesh_data, obstacle, *, E: float | None = None, nu: float | None = None, degree: int = 2,
                  method: str = "nitsche", kinematics: str = "small", traction: str = "obstacle",
                  kappa0: float = 1e3, gamma0: float = 10.0, theta: float = 1.0, control: str = "displacement",
                  target: float | None = None, n_steps: int = 4, symmetric_half: bool = False,
                  on_step: Callable | None = None, petsc_prefix: str | None = None, max_cutbacks: int = 5,
                  supports: dict | None = None, contact_group: str = "contact",
                  quadrature_degree: int | None = None, force_rtol: float = 1e-10, snes_rtol: float = 1e-10,
                  max_it: int = 40, case: str = "contact", petsc_options: dict | None = None,
                  predictor: str = "auto", sample_degree: int | None = None,
                  active_set_predictor: bool = True, active_set: str = "extrapolate",
                  active_set_update: str = "newton", first_step_fraction: float = 0.1,
                  record_at: Sequence[float] | None = None, formulation: str = "displacement",
                  min_facets_across: int = MIN_FACETS_ACROSS, uzawa_rtol: float = 1e-10, uzawa_max_it: int = 100,
                  linear_solver: str = "lu", split_jacobian: bool = True, material_model: str = "linear",
                  options: ContactOptions | None = None) -> ContactResult:
    """Solve frictionless contact of the meshed body against a rigid obstacle.

    Args:
        mesh_data: dolfinx ``MeshData`` (mesh, facet_tags, physical_groups) of the elastic body.
        obstacle: rigid obstacle from :mod:`fem.obstacles`.
        E: Young's modulus (MPa) > 0.  nu: Poisson's ratio in (-1, 0.5).
        degree: Lagrange degree (1 or 2).
        method: a registered contact method (:mod:`fem.methods`): ``"nitsche"``, ``"penalty"`` or
            ``"augmented_lagrangian"``.  kinematics: ``"small"``, ``"convective"`` or ``"finite"`` (finite-strain
            hyperelasticity, total Lagrangian, contact at the deformed position; :mod:`fem.hyperelastic`).
        traction: ``"obstacle"`` or ``"halfplane"``.  kappa0, gamma0, theta: method parameters (kappa0: penalty
            stiffness, and the augmentation stiffness of the augmented Lagrangian; gamma0, theta: Nitsche).
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
            the discrete law holds; between those points the law of a penalty/Nitsche solution oscillates; the
            augmented Lagrangian's default samples are its contact nodes).
        predictor: ``"extrapolate"`` (u linear in d from the last two states), ``"hertz"`` (force control,
            circle/parabola, direction (0, -1): linear solve with the Hertz pressure of the load level as a
            Neumann load; d from the displacement at the first-contact point), ``"hertz_zone"`` (the same
            applicability; the first load level from the unloaded state with the Hertz zone as the prescribed active
            set and d from that set's tangent, no stiffness solve: :meth:`fem.stepping.LoadStepper.hertz_zone_start`;
            later levels as ``"hertz"``) or ``"auto"`` (hertz when applicable).
        active_set_predictor: before each Newton solve do one iteration with a prescribed active set (the
            Hertz zone, or contact edges extrapolated linearly in d from the last two states; single-patch
            scenes with the surface coordinate X1). Without it the sign of the tiny gaps of the predicted u
            decides the first active set and semismooth Newton then releases about one quadrature point
            per iteration.
        active_set: where the prescribed active set comes from. ``"extrapolate"`` (default): single-patch
            states only, as above. ``"geometry"``: also several patches (each run's edges extrapolated; up to
            :data:`fem.problem.MAX_ZONES` runs) and the first contact of a step from an open state: the runs of the
            rigid overlap at the new d, shrunk about their centres (:data:`fem.stepping.GEOMETRIC_SHRINK`). It
            needs no analytic predictor; the converged answer is the same, the Newton path differs.
        active_set_update: after the prescribed active set, ``"newton"`` (default): one iteration on it, then
            semismooth Newton; ``"edge_fit"``: iterations on prescribed sets whose edges are extrapolated from the
            pressure of the last iterate (``q |q|`` linear near the edge, :mod:`fem.active_set_update`) until the
            set of contact points repeats (at most :data:`fem.stepping.EDGE_FIT_MAX`), then semismooth Newton,
            which decides the answer.
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
        uzawa_rtol: augmented Lagrangian only: the Uzawa loop of a load level stops when the nodal gaps satisfy
            the contact conditions to uzawa_rtol times the largest displacement (mm/mm;
            :mod:`fem.methods.augmented_lagrangian`).
        uzawa_max_it: augmented Lagrangian only: Uzawa updates allowed per load level (then ContactSolveError).
        linear_solver: the linear solver of the Newton iterations and the Hertz predictor (:mod:`fem.linear_solver`):
            ``"lu"`` (MUMPS LU of every Jacobian), ``"lu_reuse"`` (GMRES preconditioned by the MUMPS LU of an earlier
            Jacobian, refactored when the Krylov solve slows down) or ``"gamg"`` (GMRES + algebraic multigrid
            with the rigid-body near-nullspace; displacement formulation). The converged answer is the same.
        split_jacobian: assemble the elastic stiffness once and only the contact terms per Newton iteration
            (displacement formulation, linear material; :mod:`fem.split_jacobian`); the same Jacobian to
            round-off. Not used for a hyperelastic material (its stiffness depends on u).
        material_model: ``"linear"`` (small-strain Hooke; kinematics small/convective) or a hyperelastic model
            ``"saint_venant_kirchhoff"`` / ``"neo_hookean"`` (kinematics="finite" only; both with the small-strain
            E and nu, :mod:`fem.hyperelastic`).
        options: a :class:`ContactOptions` instead of the keywords above (then pass none of them).

    Raises:
        ValueError: bad option.  ContactSolveError: SNES failure after the allowed cut-backs.
    """
    given = {k: v for k, v in locals().items() if k not in ("mesh_data", "obstacle", "options")}
    opts = _options(given, options)
    check_options(opts, mesh_data=mesh_data, obstacle=obstacle)
    return solve_problem(ContactProblem(mesh_data, obstacle, opts))


def solve_problem(problem: ContactProblem, *, step_callbacks: Sequence[Callable[[dict], None]] = ()) -> ContactResult:
    """Drive a built :class:`ContactProblem` through its load path (:class:`LoadStepper`) and collect the result.

    ``step_callbacks`` are called after every converged solve with its record, after ``options.on_step``, while
    the problem holds that state (e.g. :class:`fem.output.FrameRecorder` copies it for a VTK time series);
    they must only read the state.
    """
    stepper = LoadStepper(problem, on_step=problem.options.on_step)
    for fn in step_callbacks:
        stepper.add_step_callback(fn)
    stepper.run()
    return _result(problem, stepper)


def _options(given: dict, options: ContactOptions | None) -> ContactOptions:
    """The ContactOptions of a call: ``options``, or the keywords (E, nu and target required)."""
    if options is not None:
        defaults = {k: p.default for k, p in inspect.signature(solve_contact).parameters.items() if k in given}
        extra = sorted(k for k, v in given.items() if not _is_default(v, defaults[k]))
        if extra:
            raise TypeError(f"solve_contact() takes options= or keywords, not both (got {extra})")
        return options
    missing = [k for k in ("E", "nu", "target") if given[k] is None]
    if missing:
        raise TypeError(f"solve_contact() missing required keyword-only argument(s): {missing}")
    return ContactOptions(**{f.name: given[f.name] for f in fields(ContactOptions)})


def _is_default(value, default) -> bool:
    return value is default or (isinstance(value, (bool, int, float, str)) and value == default)


def _result(problem: ContactProblem, stepper: LoadStepper) -> ContactResult:
    """The ContactResult of the final converged state."""
    opts = problem.options
    samples = problem.sample()
    patches = find_patches(samples, half=opts.symmetric_half)
    warns = problem.quality_warnings(samples, stepper.states[-1].d)
    P, Pp = problem.measure()
    options = dict(E=opts.E, nu=opts.nu, degree=opts.degree, method=opts.method, kinematics=opts.kinematics,
                   traction=opts.traction, kappa0=opts.kappa0, gamma0=opts.gamma0, theta=opts.theta,
                   control=opts.control, target=opts.target, n_steps=opts.n_steps, symmetric_half=opts.symmetric_half,
                   supports=problem.supports, quadrature_degree=problem.qdeg, sample_degree=problem.sdeg,
                   prefix=problem.prefix, predictor="hertz" if stepper.hertz is not None else "extrapolate",
                   formulation=opts.formulation, material_model=opts.material_model, **problem.method.options())
    records = stepper.records
    return ContactResult(ndofs=problem.ndofs, wall_time_s=stepper.wall_time_s,
                         newton_iterations=[r["iterations"] for r in records], load_steps=records,
                         d=float(stepper.states[-1].d), P=float(P), P_pressure=float(Pp), samples=samples,
                         patches=patches, u=problem.u, options=options, half=opts.symmetric_half,
                         forms=problem.forms, lame=problem.lame, snapshots=stepper.snapshots, warnings=warns,
                         pressure_field=problem.ph)
