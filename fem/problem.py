"""The contact problem of one solve: spaces, supports, forms, load measures and the dolfinx NonlinearProblem.

Plane strain, units mm, N, MPa; loads P per unit thickness (N/mm). Gap g > 0 open; pressure p >= 0
compressive. The weak forms are documented in :mod:`fem.contact_forms` and the method modules
(:mod:`fem.methods`); the load stepping that drives this object is :class:`fem.stepping.LoadStepper`.

Solution: semismooth Newton (PETSc SNES ``newtonls`` with ``basic`` full steps; the linear solver of
:mod:`fem.linear_solver`, default LU/MUMPS), options with a
unique prefix; the Jacobian is the exact Gateaux derivative of the residual.

Bulk: the material model's stress (:mod:`fem.hyperelastic`): small-strain sigma(u), or for finite kinematics the
first Piola-Kirchhoff P(u) in a total Lagrangian form (then ``a(u, w) = int P(u) : Grad w dX``).

Measured load ``P`` (virtual work): ``P = -F(u; w)``, the whole residual ``F = a + F_c`` (bulk and contact
terms) tested with ``w``, equal to the loading direction at every Dirichlet-constrained component dof and 0
elsewhere (and the mixed pressure test q = 0): the support reaction along the direction. With ``e`` the rigid
translation along the direction, ``e - w`` is an admissible test field, so at a converged state
``P = -F(u; e) + F(u; e - w) = -F_c(u; e) + (residual)`` and ``a(u, e) = 0``: P equals the discrete contact
force. ``P_pressure = int p (n_o . direction) ds`` is the resultant of the contact pressure along the direction
(with the method's contact quadrature; finite kinematics: the current pressure times the surface Jacobian
ds/dS, :mod:`fem.contact_forms`); ``-F_c(u; e)`` is exactly that for penalty, Nitsche and the augmented
Lagrangian, because the Nitsche stress terms vanish for a rigid test field, so ``P = P_pressure`` up to the
residual (round-off): a consistency check of the assembly and of the solve. The bulk part ``-a(u, w)`` alone
is not the reaction where the contact boundary reaches a support: there ``F_c(u; w)`` (the symmetric Nitsche
term ``-theta/gamma int sigma_n(u) sigma_n(w) ds`` on the facets of the corner cells) is the part of the
reaction carried by the contact terms. For ``symmetric_half=True`` both are doubled (full-body values).
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

import itertools
from collections.abc import Sequence
from contextlib import contextmanager

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import ufl
from mpi4py import MPI
from petsc4py import PETSc

from fem.coefficients import lame_constants
from fem.compiled_forms import compile_forms
from fem.contact_forms import ContactForms, build_contact_forms
from fem.elasticity import lame, mixed_constraint, plane_strain_modulus, sigma_mixed
from fem.far_field import HalfPlaneFarField
from fem.hyperelastic import bulk_law
from fem.linear_solver import configure as configure_linear_solver
from fem.linear_solver import snes_options
from fem.newton_controls import NewtonControls
from fem.options import ContactOptions
from fem.postprocess import (
    LOCKING_NU,
    SurfaceSampler,
    SurfaceSamples,
    contact_edges,
    oscillation_warnings,
    penetration_warning,
    resolution_warnings,
)
from fem.predictor import HertzPredictor
from fem.split_jacobian import SplitJacobian
from fem.supports import COMPONENTS, group_facets, resolve_supports
from vocabulary import FINITE

__all__ = ["ContactProblem", "MAX_ZONES", "resolve_supports"]

# Contact runs the prescribed-active-set predictor iteration can hold (intervals of X1; more: no predictor).
MAX_ZONES = 4

_counter = itertools.count()


def _ghost_forward(vec) -> None:
    """Copy owned values of a (non-nested) PETSc vector to its ghosts."""
    vec.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)


class ContactProblem(NewtonControls):
    """One frictionless contact problem (the body meshed in ``mesh_data``, a rigid ``obstacle``): a
    :class:`fem.partner_problem.PartnerProblem`.

    Attributes (main ones):
        u: displacement Function (mm); ph: the mixed formulation's pressure Function (MPa) or None.
        d: dolfinx Constant, rigid displacement of the obstacle along its direction (mm).
        lame: the Lame parameters as dolfinx Constants (MPa); every number of the forms is a Constant
            (:mod:`fem.coefficients`), so a form compiles once whatever E, nu, the obstacle or kappa0 are.
        mask: Constants ``(on, lo_0, hi_0, ..., lo_3, hi_3)`` of the prescribed-active-set predictor law.
        forms: :class:`fem.contact_forms.ContactForms`; method: its contact method instance.
        bcs: Dirichlet supports; ds_c: the Gauss contact measure (``quadrature_degree``).
        problem: the dolfinx NonlinearProblem; snes: its SNES; prefix: its PETSc options prefix.
        far_field: :class:`fem.far_field.HalfPlaneFarField`, the values of ``halfplane`` supports (load level).
        qdeg, sdeg: contact quadrature and sample degrees; mult: 2 for a half model, else 1.
    """

    def __init__(self, mesh_data, obstacle, options: ContactOptions):
        self.options = opts = options
        self.mesh_data, self.obstacle = mesh_data, obstacle
        self.mesh = mesh_data.mesh
        self.lame = lame_constants(self.mesh, lame(E=opts.E, nu=opts.nu))  # Constants: no recompile per E, nu
        self.E_star = plane_strain_modulus(E=opts.E, nu=opts.nu)
        self.comm = self.mesh.comm
        self.supports = resolve_supports(mesh_data, opts.supports, opts.symmetric_half)
        self.qdeg = opts.contact_quadrature_degree
        self.sdeg = self.qdeg if opts.sample_degree is None else int(opts.sample_degree)
        self.mult = 2.0 if opts.symmetric_half else 1.0
        self._build_spaces()
        self.forms: ContactForms = self._build_forms()
        self.method = self.forms.method
        self._samplers: dict = {}
        self.method_rule = self.method.sample_rule(degree=opts.degree)  # None: Gauss points of the contact rule
        self.sample_rule = self.method_rule if opts.sample_degree is None else None
        self._build_supports()
        self._build_solver()
        self.extras = ([] if self.ph is None else [self.ph]) + list(self.method.state_functions())
        self.n_u = self.u.x.array.size

    # -- construction ---------------------------------------------------------------------------------------
    def _build_spaces(self) -> None:
        opts, mesh = self.options, self.mesh
        self.V = dolfinx.fem.functionspace(mesh, ("Lagrange", opts.degree, (2,)))
        self.u = dolfinx.fem.Function(self.V, name="displacement")
        self.d = dolfinx.fem.Constant(mesh, 0.0)
        self.mask = tuple(dolfinx.fem.Constant(mesh, 0.0) for _ in range(1 + 2 * MAX_ZONES))  # (on, lo_k, hi_k)
        self.contact_facets = group_facets(self.mesh_data, opts.contact_group)
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=self.mesh_data.facet_tags,
                         metadata={"quadrature_degree": self.qdeg})
        self.ds_c = ds(self.mesh_data.physical_groups[opts.contact_group].tag)
        self.ph = None
        if opts.mixed:
            Q = dolfinx.fem.functionspace(mesh, ("Lagrange", opts.degree - 1))
            self.ph = dolfinx.fem.Function(Q, name="pressure")

    def _build_forms(self) -> ContactForms:
        """Bulk (displacement or Taylor-Hood u-p) plus the method's contact terms."""
        opts, u, lm = self.options, self.u, self.lame
        if self.ph is not None:
            W = ufl.MixedFunctionSpace(self.V, self.ph.function_space)
            v_t, q_t = ufl.TestFunctions(W)
            self._test_to_support = {v_t: None, q_t: dolfinx.fem.Constant(self.mesh, 0.0)}  # None: w, below
            self._trials = ufl.TrialFunctions(W)
            self.stress = sigma_mixed(u, self.ph, lm)
            bulk = (ufl.inner(self.stress, ufl.grad(v_t)) + mixed_constraint(u, self.ph, q_t, lm)) * ufl.dx
            mixed_kw = dict(v=v_t, stress_u=self.stress, stress_v=sigma_mixed(v_t, q_t, lm), bulk=bulk)
        else:  # the bulk law of the material model: sigma(u) (linear) or the first Piola-Kirchhoff P(u)
            v_t = ufl.TestFunction(self.V)
            law = bulk_law(u, v_t, opts.material_model, lm)
            self.stress = law.stress
            mixed_kw = dict(v=v_t, stress_u=law.stress, stress_v=law.stress_v)
            self._test_to_support = {v_t: None}
        obstacle = self.obstacle.with_constants(self.mesh) if self.obstacle.analytic else self.obstacle
        return build_contact_forms(u=u, obstacle=obstacle, d=self.d, lame=lm, method=opts.method,
                                   kinematics=opts.kinematics, traction=opts.traction, ds_c=self.ds_c,
                                   contact_facets=self.contact_facets, mask=self.mask, **opts.method_params(),
                                   **mixed_kw)

    def _build_supports(self) -> None:
        """Dirichlet supports and the virtual-work field w (direction at constrained component dofs)."""
        V, fdim = self.V, self.mesh.topology.dim - 1
        self.bcs = []
        self.far_field = HalfPlaneFarField(mesh=self.mesh, E=self.options.E, nu=self.options.nu)
        w = dolfinx.fem.Function(V)
        direction = self.obstacle.direction
        for name, kind in self.supports.items():
            facets = group_facets(self.mesh_data, name)
            for c in COMPONENTS[kind]:
                Vc, _ = V.sub(c).collapse()
                dofs = dolfinx.fem.locate_dofs_topological((V.sub(c), Vc), fdim, facets)
                # halfplane: Flamant's field scaled by the load level (fem/far_field.py); else 0
                value = self.far_field.value_function(Vc, c) if kind == "halfplane" else dolfinx.fem.Function(Vc)
                self.bcs.append(dolfinx.fem.dirichletbc(value, dofs, V.sub(c)))
                w.x.array[dofs[0]] = direction[c]
        self.far_field.set_load(self.options.target)  # the stepper sets each force level's own
        # the whole residual, contact terms included: where Gamma_c reaches a support (concave body: the spline
        # ends at the clamped corners) the symmetric Nitsche term -theta/gamma sigma_n(u) sigma_n(w) works on the
        # support dofs too (-a(u, w) alone missed 1.5e-3 of P in concave_symmetric)
        tests = {k: (w if v is None else v) for k, v in self._test_to_support.items()}
        forms = self.forms
        self._ufl_measures = {  # compiled with the solver's forms (_build_solver)
            "reaction": -ufl.replace(forms.F, tests),
            "pressure": forms.on_surface(-forms.pressure * ufl.dot(forms.n_c, ufl.as_vector(direction))) * forms.ds_c}

    def _build_solver(self) -> None:
        """NonlinearProblem with SNES newtonls/basic, LU (MUMPS); atol scaled by E and the body size L."""
        opts, forms, comm = self.options, self.forms, self.comm
        self.prefix = opts.petsc_prefix or f"fem_contact_{next(_counter)}_"
        x_all = self.mesh.geometry.x
        L = comm.allreduce(float(np.max(np.ptp(x_all[:, :2], axis=0))) if x_all.size else 0.0, op=MPI.MAX)
        # linear_solver="auto" decides by these
        solver_kw = dict(ndofs=self.ndofs, saddle=self.ph is not None, linear_bulk=self.linear_bulk)
        petsc = {"snes_type": "newtonls", "snes_linesearch_type": "basic", **snes_options(opts.linear_solver,
                                                                                          **solver_kw),
                 "snes_rtol": opts.snes_rtol, "snes_atol": 1e-13 * opts.E * L, "snes_stol": 0.0,
                 "snes_max_it": opts.max_it}
        petsc.update(opts.petsc_options or {})
        # every form of the problem in one FFCx module (fem/compiled_forms.py): F and J, the load measures, the
        # split Jacobian's K and J_c, the method's own (e.g. the augmented Lagrangian's nodal averages)
        ufl_forms = dict(self._ufl_measures)
        if self.ph is not None:
            du_t, dp_t = self._trials
            J_full = ufl.derivative(forms.F, self.u, du_t) + ufl.derivative(forms.F, self.ph, dp_t)
            ufl_forms |= {"F": ufl.extract_blocks(forms.F), "J": ufl.extract_blocks(J_full)}
        else:
            ufl_forms |= {"F": forms.F, "J": forms.J}
        # J = K (assembled once) + contact terms per iteration; not for a hyperelastic bulk (K depends on u)
        split = self.ph is None and opts.split_jacobian and opts.material_model == "linear"
        if split:
            ufl_forms |= SplitJacobian.ufl_forms(u=self.u, contact_residual=forms.F_c)
        if self.ph is None:  # dP/du as a vector: the force-controlled Newton's load row (fem.force_newton)
            ufl_forms["load_gradient"] = ufl.derivative(self._ufl_measures["reaction"], self.u,
                                                        ufl.TestFunction(self.V))
        method_forms = self.method.extra_forms()
        key, sampling = self._sampling()  # the default surface sampler's expressions join the module too
        sampler_expressions = SurfaceSampler.expressions(u=self.u, forms=forms, **sampling)
        compiled, expressions = compile_forms(ufl_forms | method_forms, comm=comm, expressions=sampler_expressions)
        self._samplers[key] = SurfaceSampler(u=self.u, forms=forms, facets=self.contact_facets, compiled=expressions,
                                             **sampling)
        self.method.bind_forms({name: compiled[name] for name in method_forms})
        self.reaction_form, self.pressure_form = compiled["reaction"], compiled["pressure"]
        self.load_gradient_form = compiled.get("load_gradient")
        if self.ph is not None:
            self.problem = dolfinx.fem.petsc.NonlinearProblem(
                compiled["F"], [self.u, self.ph], bcs=self.bcs, J=compiled["J"], kind="mpi",
                petsc_options_prefix=self.prefix, petsc_options=petsc)
        else:
            self.problem = dolfinx.fem.petsc.NonlinearProblem(compiled["F"], self.u, bcs=self.bcs, J=compiled["J"],
                                                              petsc_options_prefix=self.prefix,
                                                              petsc_options=petsc)
        self.snes = self.problem.solver
        configure_linear_solver(self.snes, self.problem.A, self.V, opts.linear_solver, **solver_kw)
        if split:
            self.split_jacobian = SplitJacobian(u=self.u, Jc_form=compiled["Jc"],
                                                J_form=self.problem.J, bcs=self.bcs)
            self.snes.setJacobian(self.split_jacobian, self.problem.A, self.problem.P_mat)
        if forms.update is not None:
            self.snes.setFunction(self._residual_with_update, self.problem.b)

    def _residual_with_update(self, snes, x, b) -> None:
        """SNES residual that refreshes the nodal gap data (Curve obstacles) at the iterate first."""
        _ghost_forward(x)
        dolfinx.fem.petsc.assign(x, self.u)
        self.forms.update(self.u)
        dolfinx.fem.petsc.assemble_residual(snes, x, b, u=self.u, residual=self.problem.F,
                                            jacobian=self.problem.J, bcs=self.bcs)

    # -- the partner protocol (fem.partner_problem.PartnerProblem) ----------------------------------------------
    @property
    def tangent_applies(self) -> bool:
        """The force control's tangent correction applies: the displacement formulation, no gap data to refresh
        (curve obstacles), a method without an outer loop, small or convective kinematics (P linear in u)."""
        opts = self.options
        return (not opts.mixed and self.forms.update is None and self.method.supports_tangent
                and opts.kinematics != FINITE)

    @property
    def linear_bulk(self) -> bool:
        """The bulk is linear in u: small or convective kinematics with the linear material (what
        ``linear_solver="auto"`` and :meth:`nested_guess` decide by)."""
        return self.options.material_model == "linear" and self.options.kinematics != FINITE

    @property
    def pressure_field(self):
        """The mixed formulation's P1 pressure ``p = -lambda div u`` (MPa), or None."""
        return self.ph

    def set_load_level(self, P: float) -> None:
        """Force control: ``halfplane`` supports carry Flamant's field of the load level P (N/mm)."""
        self.far_field.set_load(P)

    @property
    def hertz_applicable(self) -> bool:
        """The obstacle has Hertz data (circle, parabola) and moves along (0, -1): the Hertz predictor applies."""
        ob = self.obstacle
        return hasattr(ob, "hertz_contact") and abs(ob.direction[0]) < 1e-14 and ob.direction[1] < 0

    def hertz_predictor(self) -> HertzPredictor:
        """The Hertz predictor of this problem (:mod:`fem.predictor`; needs :attr:`hertz_applicable`)."""
        return HertzPredictor(u=self.u, obstacle=self.obstacle, lame=self.lame, E_star=self.E_star, bcs=self.bcs,
                              ds_c=self.ds_c, facets=self.contact_facets, prefix=self.prefix + "hertz_",
                              linear_solver=self.options.linear_solver)

    def law_samples(self) -> SurfaceSamples:
        """Samples where the discrete law holds: the method's points (e.g. the augmented Lagrangian's nodes), else
        the contact quadrature."""
        return self.sample(rule=self.method_rule) if self.method_rule is not None else self.sample(self.qdeg)

    # -- state ----------------------------------------------------------------------------------------------
    @property
    def ndofs(self) -> int:
        """Global number of unknowns: displacement dofs (plus the mixed pressure dofs)."""
        n = self.V.dofmap.index_map.size_global * 2
        return n + (self.ph.function_space.dofmap.index_map.size_global if self.ph is not None else 0)

    def measure(self) -> tuple[float, float]:
        """(P, P_pressure) in N/mm, full body (module docstring)."""
        P = self.mult * self.comm.allreduce(dolfinx.fem.assemble_scalar(self.reaction_form), op=MPI.SUM)
        Pp = self.mult * self.comm.allreduce(dolfinx.fem.assemble_scalar(self.pressure_form), op=MPI.SUM)
        return P, Pp

    def load_gradient(self, out) -> None:
        """``dP/du`` at the current state into the PETSc vector ``out`` (the displacement layout; N/mm per mm):
        ``P(u + du) = P(u) + out . du`` while no contact point changes state (the load :meth:`measure` gives is
        linear in u there). Displacement formulation only."""
        with out.localForm() as loc:
            loc.set(0.0)
        dolfinx.fem.petsc.assemble_vector(out, self.load_gradient_form)
        out.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        out.scale(self.mult)

    def get_state(self) -> np.ndarray:
        """Local array of the unknowns: u, then the mixed pressure and the method's own unknowns (if any)."""
        if not self.extras:
            return self.u.x.array.copy()
        return np.concatenate([self.u.x.array] + [f.x.array for f in self.extras])

    def unloaded_guess(self, d_value: float, unloaded: np.ndarray) -> np.ndarray:
        """The start of the first solve at d_value from the unloaded state: the unloaded state itself (the rigid
        obstacle carries d; a deformable partner moves its driven body instead)."""
        return unloaded

    def set_state(self, arr: np.ndarray, rest: np.ndarray | None = None) -> None:
        """Set u (and the extra unknowns); a displacement-only ``arr`` takes them from the full state ``rest``."""
        n_u = self.n_u
        self.u.x.array[:] = arr[:n_u]
        self.u.x.scatter_forward()
        src, k = (arr if arr.size > n_u else rest), n_u
        for f in self.extras:
            m = f.x.array.size
            f.x.array[:] = src[k:k + m]
            f.x.scatter_forward()
            k += m

    def force_newton(self, *, P_goal: float, d0: float, x0: np.ndarray, zone: tuple | None, max_it: int):
        """Newton iterations for (u, d) at the load P_goal (:class:`fem.force_newton.ForceNewton`: d is an unknown of
        every iteration; the first on the prescribed active set ``zone``): its
        :class:`fem.force_newton.ForceNewtonResult`. Needs :attr:`tangent_applies`."""
        from fem.force_newton import ForceNewton
        from fem.linear_solver import GAMG_MAX_KRYLOV, REUSE_MAX_KRYLOV, resolve

        kind = resolve(self.options.linear_solver, ndofs=self.ndofs, saddle=self.ph is not None,
                       linear_bulk=self.linear_bulk)
        # built per call, not kept: a ForceNewton holding this problem would make a reference cycle, and the PETSc
        # objects of a finished problem (its factor or multigrid) would wait for the garbage collector
        newton = ForceNewton(self, reuse=kind != "lu", bordered=kind == "gamg",
                             max_krylov=GAMG_MAX_KRYLOV if kind == "gamg" else REUSE_MAX_KRYLOV)
        return newton.solve(P_goal=P_goal, d0=d0, x0=x0, zone=zone, max_it=max_it)

    # -- nested iteration (fem.nested_start) ----------------------------------------------------------------
    def nested_source(self, *, d: float, P: float, zones: tuple | None = None):
        """The converged state as the start of a finer mesh's solve (:class:`fem.nested_start.NestedStart`): its
        d, P and contact runs (``zones``: the stepper's of that state; None: sampled here). ``u`` is this
        problem's displacement Function (the result's), kept for the record: :meth:`nested_guess` does not
        interpolate it."""
        from fem.nested_start import NestedStart

        cells = np.arange(self.mesh.topology.index_map(self.mesh.topology.dim).size_local, dtype=np.int32)
        return NestedStart(d=d, P=P, u=self.u, body_cells=(cells,), X1=np.zeros(0), surface=np.zeros(0),
                           zones=self.contact_zones() if zones is None else zones)

    def nested_guess(self, start) -> np.ndarray:
        """The start of a solve from a coarser mesh's converged state (:mod:`fem.nested_start`): the unloaded
        displacement. What the coarse state gives is its active set and d (the stepper prescribes the one and
        solves at the other). The bulk is linear here (small or convective kinematics, linear material), so the
        prescribed-set Newton iteration lands on that set's solution from any start, up to the contact law's own
        curvature on the surface: an interpolated coarse displacement saves no iteration (measured on the bench's
        graded 88k-dof mesh from its 23k-dof coarse mesh: the same Newton iterations, [1, 1, 1]) and costs a point
        search (0.43-0.82 s there, more than the fine solve's factorisation). ValueError at finite strain or with
        a hyperelastic material: from the unloaded state at the full d a large-strain solve needs its load path."""
        opts = self.options
        if not self.linear_bulk:
            raise ValueError("nested_start: the rigid obstacle's problem starts a nested solve from the unloaded "
                             "state, which needs a linear bulk; allowed: kinematics small or convective with "
                             f"material_model linear (got kinematics {opts.kinematics!r}, material_model "
                             f"{opts.material_model!r})")
        return np.zeros(self.n_u)

    # -- surface --------------------------------------------------------------------------------------------
    def sample(self, degree: int | None = None, rule=None) -> SurfaceSamples:
        """Surface samples of the current state.

        Default: at the result's sample points (``sample_degree``, else the method's own points, e.g. the nodal
        points of the augmented Lagrangian, else the contact quadrature). ``degree``: the Gauss points of that
        degree; ``rule``: a :class:`fem.methods.base.SampleRule`.
        """
        key, sampling = self._sampling(degree, rule)
        if key not in self._samplers:
            self._samplers[key] = SurfaceSampler(u=self.u, forms=self.forms, facets=self.contact_facets, **sampling)
        return self._samplers[key]()

    def _sampling(self, degree: int | None = None, rule=None) -> tuple:
        """The samplers' key and keywords of :meth:`sample`'s arguments (none: the default sample points)."""
        if degree is None and rule is None:
            rule = self.sample_rule
            degree = self.sdeg
        key = ("rule", id(rule)) if rule is not None else degree
        return key, {"quadrature_degree": degree, "rule": rule}

    def contact_zones(self) -> tuple[tuple[float, float], ...]:
        """The contact runs (lo, hi) in X1 of the current state where the discrete law holds (the contact
        quadrature or the method's points), in order of X1; lo = -inf for a run that starts at the first sample.
        Empty: no contact. With u = 0 these are the runs of the rigid overlap (the gap of the undeformed state)."""
        smp = self.law_samples()
        return tuple(((-np.inf if i == 0 else left), right) for left, right, i, _ in contact_edges(smp.s, smp.q))

    def contact_zone(self) -> tuple[float, float] | None:
        """The single contact run (lo, hi) of :meth:`contact_zones`; None: no contact or several patches."""
        runs = self.contact_zones()
        return runs[0] if len(runs) == 1 else None

    def quality_warnings(self, smp: SurfaceSamples, d_now: float) -> list[str]:
        """Named warnings of a converged state: resolution, penetration, oscillation, locking risk."""
        opts = self.options
        per_facet = self.sample_rule.points_per_facet if self.sample_rule is not None else None
        out = resolution_warnings(smp, quadrature_degree=self.sdeg, half=opts.symmetric_half,
                                  min_facets_across=opts.min_facets_across, points_per_facet=per_facet)
        pen = penetration_warning(smp, d=d_now)
        out += ([pen] if pen else []) + oscillation_warnings(smp)
        if not opts.mixed and opts.nu >= LOCKING_NU:
            out.append(f"near-incompressible: nu = {opts.nu:g} >= {LOCKING_NU} with the displacement formulation "
                       "(volumetric locking); use formulation='mixed'")
        return out

    # -- solves ---------------------------------------------------------------------------------------------
    def newton(self, *, force_iteration: bool = False) -> tuple[int, int]:
        """One SNES solve from the current state: (converged reason, iterations).

        ``force_iteration``: at least one Newton iteration even when the initial residual already meets
        ``snes_atol`` (a method that changed a coefficient of F, e.g. a multiplier, by a small amount).
        """
        if not force_iteration:
            self.problem.solve()
            return self.snes.getConvergedReason(), self.snes.getIterationNumber()
        self.snes.setForceIteration(True)
        try:
            self.problem.solve()
        finally:
            self.snes.setForceIteration(False)
        return self.snes.getConvergedReason(), self.snes.getIterationNumber()

    @contextmanager
    def prescribed_active_set(self, zones: Sequence[tuple[float, float]]):
        """While inside: the contact law holds on the prescribed active set ``lo_k < X1 < hi_k`` (at most
        :data:`MAX_ZONES` runs) instead of the sign of the Nitsche/penalty argument; off afterwards."""
        mask = self.mask
        if len(zones) > MAX_ZONES:
            raise ValueError(f"at most {MAX_ZONES} predicted contact runs, got {len(zones)}")
        mask[0].value = 1.0
        for k in range(MAX_ZONES):
            lo, hi = zones[k] if k < len(zones) else (1e300, 1e300)
            mask[1 + 2 * k].value, mask[2 + 2 * k].value = max(lo, -1e300), min(hi, 1e300)
        try:
            yield
        finally:
            mask[0].value = 0.0

    def refresh(self) -> None:
        """Before a solve: the nodal gap data of a curve obstacle at the current state (others: nothing)."""
        if self.forms.update is not None:
            self.forms.update(self.u)

    def load_solver_state(self, arr: np.ndarray) -> None:
        """u (:meth:`set_state`) and the solver's vector ``problem.x`` (ghosts included) from the state ``arr``:
        where the SNES callbacks (:meth:`residual_into`) read the state."""
        x = self.problem.x
        self.set_state(arr)
        dolfinx.fem.petsc.assign(self.u, x)
        _ghost_forward(x)

    def displacement_of(self, vec) -> np.ndarray:
        """The owned + ghost displacement array (the layout of ``u``) of the PETSc vector ``vec`` in the solver's
        layout; ``u`` holds it afterwards."""
        _ghost_forward(vec)
        dolfinx.fem.petsc.assign(vec, self.u)
        return self.u.x.array.copy()

    def residual_into(self, out) -> None:
        """The SNES residual ``F`` at the solver's vector ``problem.x`` (and the current d, mask) into ``out``; a
        Ctrl-C raised in the Python residual comes back as KeyboardInterrupt, not as a PETSc error."""
        try:
            self.snes.computeFunction(self.problem.x, out)
        except PETSc.Error as exc:
            if isinstance(exc.__cause__, KeyboardInterrupt):
                raise exc.__cause__ from None
            raise

    def load_derivative_into(self, out, *, d: float, F=None, fixed_set: bool = False) -> None:
        """``-dF/dd`` (N/mm per mm) at the solver's vector ``problem.x`` into ``out``: a forward difference of the
        residual in d, exact up to round-off because F is affine in d on a fixed active set (d restored). ``F``: the
        residual at d if the caller holds it (else assembled here). The step is ``|d|`` where the active set is
        prescribed (``fixed_set``: inside :meth:`prescribed_active_set`) and ``1e-6 |d|`` under the true law, whose
        set must not change within the step. Its round-off is about ``eps ||F|| / step`` (N/mm): with ``1e-6 |d|``
        from the unloaded state (``||F||`` 1.9e5 N, d 0.065 mm: the Hertz zone of the bench's 161k-dof mesh) that is
        6e-4 N/mm, and the force-controlled Newton's first step (dd = -0.016 mm) was left at a residual of 9e-6 N
        (Newton tolerance 1.9e-5 N, snes_atol 2.1e-7 N) where the step ``|d|`` leaves 9.5e-10 N."""
        delta = (1.0 if fixed_set else 1e-6) * max(abs(d), 1e-300)
        base = None
        try:
            if F is None:
                base = out.duplicate()
                self.d.value = d
                self.residual_into(base)
            self.d.value = d + delta
            self.residual_into(out)
            out.axpy(-1.0, F if F is not None else base)
            out.scale(-1.0 / delta)
        finally:
            self.d.value = d
            if base is not None:
                base.destroy()

    def tangent(self, state: np.ndarray, d0: float, *, fixed_set: bool = False) -> tuple[np.ndarray, float] | None:
        """Tangent ``t = du/dd`` of the converged ``state`` at ``d0`` for its active set, and ``dP/dd`` (N/mm/mm).

        ``J t = -dF/dd`` (:meth:`load_derivative_into`; ``fixed_set``: the set is prescribed) with the LU factors
        the last Newton solve left in the KSP (no new factorisation); ``dP/dd = P(t)`` because P is linear in u.
        Returns None when t is not finite or ``dP/dd <= 0``. The state is restored.
        """
        x = self.problem.x
        self.load_solver_state(state)
        g, t = x.duplicate(), x.duplicate()
        try:
            self.load_derivative_into(g, d=d0, fixed_set=fixed_set)
            self.snes.getKSP().solve(g, t)  # the Jacobian already factored: no new LU
            t_arr = self.displacement_of(t)
        finally:
            for vec in (g, t):
                vec.destroy()
        dP = self.measure()[0]  # P is linear in u: the load of the tangent field t
        self.set_state(state)
        finite = self.comm.allreduce(bool(np.all(np.isfinite(t_arr))), op=MPI.LAND)  # same decision on all ranks
        if not (finite and np.isfinite(dP) and dP > 0):
            return None
        return t_arr, dP
