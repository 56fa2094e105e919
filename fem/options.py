"""Options of a contact solve: ONE frozen record, :class:`ContactOptions`, passed whole to the solver, made of
records by concern (issue 37):

* :class:`ContactLaw`: the method, the kinematics and the method's factors (kappa0 with one meaning on both
  partners: ``kappa = kappa0 E* / h``);
* :class:`LoadControl`: the load path (control, target, steps, recorded displacements, predictors, cut-backs);
* :class:`NewtonSolve`: the SNES tolerances, the linear solver and a prefixed PETSc options dict;
* :class:`RigidBody`: against a rigid obstacle only, the body's material (E, nu, model, formulation) and how it
  meets the obstacle (traction, contact group, quadrature); two meshed bodies carry theirs in
  :class:`fem.two_body.problem.MeshedPartner` and the options have no body (``body = None``);
* shared: the element degree, the half model, the supports, the resolution warning, the case name.

Units: mm, N, MPa; loads P per unit thickness (N/mm, full body). Every field is named, typed, defaulted and
documented once, on its record; :func:`fem.solver.solve_contact` takes the options (its keyword convenience sorts
flat keywords into the records, :meth:`ContactOptions.from_fields`), the case layer
(:func:`workbench.scenes.wiring.solver_options`) and the studies derive their options from it
(:meth:`ContactOptions.replace`); every field reads flat too (``options.kappa0``). The vocabularies are
:mod:`vocabulary`'s; this module holds the checks that need no mesh.

Adding an option: one field (with its documentation) on the record of its concern, its check in
:func:`check_options` if it has a vocabulary or range, and its use in :mod:`fem.problem` / :mod:`fem.stepping`;
a case-file field of the same name in :class:`cases.schema.Solver` is then passed through by the wiring without a
further line (``tests/test_options_record.py`` checks the two defaults agree or are listed as intentional
differences in :data:`cases.schema.CASE_LEVEL_DEFAULTS`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import MISSING, dataclass, fields
from typing import Any

import numpy as np

from analytic.materials import plane_strain_modulus
from vocabulary import (
    ACTIVE_SET_UPDATES,
    ACTIVE_SETS,
    CONTROLS,
    FINITE,
    FINITE_METHODS,
    FORMULATIONS,
    HYPERELASTIC_MODELS,
    LINEAR_SOLVERS,
    MATERIAL_MODELS,
    PREDICTORS,
    SUPPORT_KINDS,
    model_conflict,
)

__all__ = [
    "ContactOptions", "ContactLaw", "LoadControl", "NewtonSolve", "RigidBody", "SUPPORT_KINDS", "FORMULATIONS",
    "CONTROLS", "PREDICTORS", "ACTIVE_SETS", "ACTIVE_SET_UPDATES", "MIN_FACETS_ACROSS", "LINEAR_SOLVERS",
    "MATERIAL_MODELS", "HYPERELASTIC_MODELS", "FINITE_METHODS", "NU_DISPLACEMENT_MAX", "check_options"
]

# The vocabularies (the allowed words of every choice) are the bottom layer's, written once (vocabulary).
# A patch spanning fewer contact facets than this is reported "contact unresolved" (ContactResult.warnings):
# with P2 and 2 Gauss points per facet the edge-location error is about one Gauss spacing, so < 8 facets
# across the patch means a half-width error above ~ 1/16 and a peak that depends on where the nodes fall.
MIN_FACETS_ACROSS = 8
# nu -> 1/2: the displacement formulation locks. Measured (stability study, Hertz scene, P2 h = a/10): at nu =
# 0.499 it converges with RMS/p0 8 % and named warnings, at 0.4999 it diverges (DIVERGED_MAX_IT). Above this
# value it is refused with the advice to use formulation='mixed' (the case schema's "auto" switches itself).
NU_DISPLACEMENT_MAX = 0.499


@dataclass(frozen=True, kw_only=True)
class ContactLaw:
    """The contact law, the same on both partners: the method (:mod:`fem.methods`, one registry for the rigid
    obstacle and two meshed bodies), the kinematics and the method's parameters.

    Attributes:
        method: a registered contact method (:mod:`fem.methods`): ``"nitsche"``, ``"penalty"`` or
            ``"augmented_lagrangian"``.
        kinematics: ``"small"``, ``"convective"`` or ``"finite"`` (finite-strain hyperelasticity, total
            Lagrangian, contact at the deformed position; :mod:`fem.hyperelastic`).
        kappa0: penalty stiffness factor, dimensionless: ``kappa = kappa0 E* / h`` (MPa/mm) with E* the plane-strain
            modulus of the contact pair (``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2``; against a rigid obstacle
            ``E* = E/(1 - nu^2)``; :func:`fem.methods.base.penalty_stiffness`, the same on both partners), also
            the augmentation stiffness of the augmented Lagrangian.
        gamma0: Nitsche factor (gamma = gamma0 E / h).
        theta: Nitsche variant: 1 (symmetric), 0 (skew-less), -1 (skew-symmetric).
        uzawa_rtol: augmented Lagrangian only: the Uzawa loop of a load level stops when the nodal gaps satisfy
            the contact conditions to uzawa_rtol times the largest displacement (mm/mm;
            :mod:`fem.methods.augmented_lagrangian`).
        uzawa_max_it: augmented Lagrangian only: Uzawa updates allowed per load level (then ContactSolveError).
    """

    method: str = "nitsche"
    kinematics: str = "small"
    kappa0: float = 1e3
    gamma0: float = 10.0
    theta: float = 1.0
    uzawa_rtol: float = 1e-10
    uzawa_max_it: int = 100


@dataclass(frozen=True, kw_only=True)
class LoadControl:
    """The load path (:class:`fem.stepping.LoadStepper`): what is driven to which target, in how many steps, and
    the predictors and active-set updates that start each solve.

    Attributes:
        target: the load target: d (mm) in displacement control, P (N/mm, full body) in force control.
        control: ``"displacement"`` (target = d, mm) or ``"force"`` (target = P, N/mm; full body).
        n_steps: number of load steps >= 1.
        record_at: displacement control only: increasing displacements (mm) ending at ``target``; the solver
            steps through them (``n_steps`` sub-steps to the first) and keeps a :class:`fem.stepping.Snapshot`
            at each.
        first_step_fraction: without the Hertz predictor, an extra first step at this fraction of the first
            load level (few quadrature points are in the initial overlap, so the unpredicted first solve is
            short); 1 disables it.
        max_cutbacks: step halvings allowed per load step.
        force_rtol: relative tolerance of the final load in force control.
        predictor: ``"extrapolate"`` (u linear in d from the last two states), ``"hertz"`` (force control,
            circle/parabola, direction (0, -1): linear solve with the Hertz pressure of the load level as a
            Neumann load; d from the displacement at the first-contact point), ``"hertz_zone"`` (the same
            applicability; the first load level from the unloaded state with the Hertz zone as the prescribed
            active set and d from that set's tangent, no stiffness solve:
            :meth:`fem.stepping.LoadStepper.hertz_zone_start`, or with d solved in the Newton iterations,
            :mod:`fem.force_newton`; later levels as ``"hertz"``) or ``"auto"`` (hertz_zone where the
            force-controlled Newton applies: a rigid obstacle, the displacement formulation, a method without an
            outer loop, small or convective kinematics, ``active_set_update="newton"``; else hertz when applicable).
        active_set_predictor: before each Newton solve do one iteration with a prescribed active set (the
            Hertz zone, or contact edges extrapolated linearly in d from the last two states; single-patch
            scenes with the surface coordinate X1). Without it the sign of the tiny gaps of the predicted u
            decides the first active set and semismooth Newton then releases about one quadrature point
            per iteration.
        active_set: where the prescribed active set comes from. ``"extrapolate"`` (default): single-patch
            states only, as above. ``"geometry"``: also several patches (each run's edges extrapolated; up to
            :data:`fem.problem.MAX_ZONES` runs) and the first contact of a step from an open state: the runs of
            the rigid overlap at the new d, shrunk about their centres (:data:`fem.stepping.GEOMETRIC_SHRINK`).
            It needs no analytic predictor; the converged answer is the same, the Newton path differs.
        active_set_update: after the prescribed active set, ``"newton"`` (default): one iteration on it, then
            semismooth Newton; ``"edge_fit"``: iterations on prescribed sets whose edges are extrapolated from
            the pressure of the last iterate (``q |q|`` linear near the edge, :mod:`fem.active_set_update`) until
            the set of contact points repeats (at most :data:`fem.stepping.EDGE_FIT_MAX`), then semismooth
            Newton, which decides the answer.
        on_step: callable(dict) called after every converged solve with the load-step record.
        warm_start: a :class:`fem.warm_start.WarmStart` (converged states of the same problem, e.g.
            :attr:`fem.solver.ContactResult.warm_start`): each level solved once from its state, no load path
            (the error budget's tightened re-solve); None (default): the load path from the unloaded state.
        nested_start: a :class:`fem.nested_start.NestedStart` (the converged state of a coarser mesh of the same
            problem, :attr:`fem.solver.ContactResult.nested_start`): the target solved once from its
            interpolation, with its active set and d, then force control's correction; no load path (nested
            iteration, the error budget's grid hierarchy). Not with ``warm_start`` or ``record_at``.
    """

    target: float
    control: str = "displacement"
    n_steps: int = 4
    record_at: Sequence[float] | None = None
    first_step_fraction: float = 0.1
    max_cutbacks: int = 5
    force_rtol: float = 1e-10
    predictor: str = "auto"
    active_set_predictor: bool = True
    active_set: str = "extrapolate"
    active_set_update: str = "newton"
    on_step: Callable | None = None
    warm_start: Any = None
    nested_start: Any = None


@dataclass(frozen=True, kw_only=True)
class NewtonSolve:
    """The Newton iterations (PETSc SNES) and their linear solve. ``petsc_options`` are passed under the prefix
    ``petsc_prefix`` (the dolfinx demos' ``petsc_options_prefix`` / ``petsc_options``) and override the defaults.

    Attributes:
        snes_rtol: SNES relative residual tolerance.
        max_it: SNES max iterations.
        linear_solver: the linear solver of the Newton iterations and the Hertz predictor
            (:mod:`fem.linear_solver`): ``"lu"`` (MUMPS LU of every Jacobian), ``"lu_reuse"`` (GMRES
            preconditioned by the MUMPS LU of an earlier Jacobian, refactored when the Krylov solve slows down)
            or ``"gamg"`` (GMRES + algebraic multigrid with the rigid-body near-nullspace; displacement
            formulation), or ``"auto"`` (by the number of unknowns: ``"lu_reuse"`` with MUMPS's AMF
            ordering up to ``fem.linear_solver.AUTO_GAMG_NDOFS``, ``"gamg"`` above; ``"lu"`` for a hyperelastic or
            finite-strain bulk). The converged answer is the same.
        split_jacobian: assemble the elastic stiffness once and only the contact terms per Newton iteration
            (displacement formulation, linear material; :mod:`fem.split_jacobian`); the same Jacobian to
            round-off. Not used for a hyperelastic material (its stiffness depends on u).
        petsc_prefix: unique PETSc options prefix (default: generated).
        petsc_options: extra SNES options overriding the defaults (e.g. ``{"snes_linesearch_type": "l2"}``).
    """

    snes_rtol: float = 1e-10
    max_it: int = 40
    linear_solver: str = "lu"
    split_jacobian: bool = True
    petsc_prefix: str | None = None
    petsc_options: dict | None = None


@dataclass(frozen=True, kw_only=True)
class RigidBody:
    """The one elastic body pressed by a rigid obstacle, with its material and how it meets the obstacle: what the
    rigid partner needs beyond the shared options (two meshed bodies carry their materials in
    :attr:`fem.two_body.problem.MeshedPartner.bodies` and take none of these).

    Attributes:
        E: Young's modulus (MPa) > 0.
        nu: Poisson's ratio in (-1, 0.5).
        material_model: ``"linear"`` (small-strain Hooke; kinematics small/convective) or a hyperelastic model
            ``"saint_venant_kirchhoff"`` / ``"neo_hookean"`` (kinematics="finite" only; both with the
            small-strain E and nu, :mod:`fem.hyperelastic`).
        formulation: ``"displacement"`` (default) or ``"mixed"``: Taylor-Hood u-p plane strain (P``degree`` u,
            P``degree-1`` p = -lambda div u, :mod:`fem.elasticity`), locking-free as nu -> 1/2; the contact
            terms are unchanged (Nitsche uses the mixed stress ``2 mu eps - p I``). Needs degree >= 2 and an
            analytic obstacle.
        traction: ``"obstacle"`` (gap and traction along the rigid curve's normal; the default of a bare solve,
            right for any geometry and the only one finite kinematics supports) or ``"halfplane"`` (vertical gap
            and traction, as half-plane theory assumes; the case files' default, :mod:`cases.schema`).
        contact_group: name of the candidate contact boundary.
        quadrature_degree: Gauss degree of the contact integral (default 2 degree - 1: 2 points per P2 facet,
            1 per P1 facet; more points than trace dofs over-constrain the penalty and make p oscillate).
        sample_degree: Gauss degree of the post-processing sample points (default: the contact quadrature, where
            the discrete law holds; between those points the law of a penalty/Nitsche solution oscillates; the
            augmented Lagrangian's default samples are its contact nodes).
    """

    E: float
    nu: float
    material_model: str = "linear"
    formulation: str = "displacement"
    traction: str = "obstacle"
    contact_group: str = "contact"
    quadrature_degree: int | None = None
    sample_degree: int | None = None


_SECTIONS = {"law": ContactLaw, "load": LoadControl, "newton": NewtonSolve, "body": RigidBody}
_SHARED = ('degree', 'symmetric_half', 'supports', 'min_facets_across', 'case',)
# the flat keyword order of solve_contact (and of the error lines that list them)
_FLAT_ORDER = (
    'E', 'nu', 'target', 'degree', 'method', 'kinematics', 'traction', 'kappa0', 'gamma0', 'theta', 'control',
    'n_steps', 'symmetric_half', 'on_step', 'petsc_prefix', 'max_cutbacks', 'supports', 'contact_group',
    'quadrature_degree', 'force_rtol', 'snes_rtol', 'max_it', 'case', 'petsc_options', 'predictor',
    'sample_degree', 'active_set_predictor', 'active_set', 'active_set_update', 'first_step_fraction',
    'record_at', 'formulation', 'min_facets_across', 'uzawa_rtol', 'uzawa_max_it', 'linear_solver',
    'split_jacobian', 'material_model', 'warm_start', 'nested_start'
)


@dataclass(frozen=True, kw_only=True)
class ContactOptions:
    """The options of one contact solve (:func:`fem.solver.solve_contact`), by concern: the contact law
    (:class:`ContactLaw`), the load path (:class:`LoadControl`), the Newton and linear solve (:class:`NewtonSolve`)
    and, against a rigid obstacle only, the body (:class:`RigidBody`: E, nu, material model, formulation); two
    meshed bodies carry their materials in the partner (``body = None``). No field is one the solve ignores.

    ``ContactOptions.of(E=..., nu=..., target=..., method=...)`` sorts the flat keywords into the records (the
    keyword form of ``solve_contact``); every field of a record is also read flat (``options.kappa0`` is
    ``options.law.kappa0``); ``options.replace(n_steps=8)`` varies one of them.

    Attributes:
        law: the contact law.  load: the load path.  newton: the Newton and linear solve.
        body: the rigid obstacle's body, or None (a meshed partner).
        degree: Lagrange degree (1, 2 or 3).
        symmetric_half: the mesh is the half x >= 0 with a ``symmetry`` edge (default support roller_x).
        supports: physical group name -> one of SUPPORT_KINDS (default clamped bottom ``clamped``, and
            ``symmetry``: roller_x for a half model).
        min_facets_across: a patch spanning fewer contact facets adds a "contact unresolved" warning.
        case: name used in error messages.
    """

    load: LoadControl
    law: ContactLaw = ContactLaw()
    newton: NewtonSolve = NewtonSolve()
    body: RigidBody | None = None
    degree: int = 2
    symmetric_half: bool = False
    supports: dict | None = None
    min_facets_across: int = MIN_FACETS_ACROSS
    case: str = "contact"

    @property
    def mixed(self) -> bool:
        """True for the Taylor-Hood u-p formulation (a rigid obstacle's body only)."""
        return self.body is not None and self.body.formulation == "mixed"

    @property
    def contact_quadrature_degree(self) -> int:
        """Gauss degree of the contact integral (default ``2 degree - 1``)."""
        return 2 * self.degree - 1 if self.quadrature_degree is None else int(self.quadrature_degree)

    def method_params(self) -> dict:
        """The keywords a rigid obstacle's contact method receives (:func:`fem.methods.create`)."""
        return dict(E=self.E, E_star=plane_strain_modulus(self.E, self.nu), kappa0=self.kappa0, gamma0=self.gamma0,
                    theta=self.theta, uzawa_rtol=self.uzawa_rtol, uzawa_max_it=self.uzawa_max_it)

    # -- the flat keyword form ---------------------------------------------------------------------------------
    @classmethod
    def field_names(cls) -> tuple[str, ...]:
        """Every flat keyword (the fields of the records and the shared ones; what :func:`fem.solver.solve_contact`
        accepts)."""
        return _FLAT_ORDER

    @classmethod
    def section_of(cls, name: str) -> str:
        """The record a flat keyword belongs to (``"law"``, ``"load"``, ``"newton"``, ``"body"``, or ``""``)."""
        return next((k for k, rec in _SECTIONS.items() if name in {f.name for f in fields(rec)}), "")

    @classmethod
    def required_names(cls) -> tuple[str, ...]:
        """The flat keywords without a default (E and nu for a rigid obstacle's body, target)."""
        return tuple(f.name for rec in (RigidBody, LoadControl) for f in fields(rec)
                     if f.default is MISSING and f.default_factory is MISSING)

    @classmethod
    def defaults(cls) -> dict:
        """Flat keyword -> default of every one that has one."""
        out = {}
        for rec in (*_SECTIONS.values(), cls):
            out |= {f.name: f.default for f in fields(rec) if f.default is not MISSING and f.name not in _SECTIONS}
        return {k: out[k] for k in _FLAT_ORDER if k in out}

    @classmethod
    def from_fields(cls, fields_: dict, *, caller: str = "ContactOptions") -> ContactOptions:
        """The options of flat keywords ``fields_``, sorted into the records; a TypeError naming an unknown keyword
        or a missing required one. The body record is made when any of its keywords is given (then E and nu are
        required), else ``body`` is None (a meshed partner's bodies carry their materials)."""
        unknown = sorted(k for k in fields_ if k not in _FLAT_ORDER)
        if unknown:
            raise TypeError(f"{caller}() got an unexpected keyword argument {unknown[0]!r}; allowed: the fields "
                            f"of ContactOptions ({', '.join(_FLAT_ORDER)})")
        parts: dict = {k: {} for k in _SECTIONS}
        top = {}
        for k, v in fields_.items():
            sec = cls.section_of(k)
            (parts[sec] if sec else top)[k] = v
        need = ["target"] + (["E", "nu"] if parts["body"] else [])
        missing = [k for k in sorted(need, key=_FLAT_ORDER.index) if fields_.get(k) is None]
        if missing:
            raise TypeError(f"{caller}() missing required keyword-only argument(s): {missing}")
        body = RigidBody(**parts["body"]) if parts["body"] else None
        return cls(law=ContactLaw(**parts["law"]), load=LoadControl(**parts["load"]),
                   newton=NewtonSolve(**parts["newton"]), body=body, **top)

    @classmethod
    def of(cls, **fields_) -> ContactOptions:
        """:meth:`from_fields` of keywords: ``ContactOptions.of(E=210000.0, nu=0.3, target=0.01)``."""
        return cls.from_fields(fields_, caller="ContactOptions.of")

    def flat(self) -> dict:
        """Flat keyword -> value of every field these options hold (no body keywords when ``body`` is None)."""
        out = {}
        for sec in _SECTIONS:
            rec = getattr(self, sec)
            if rec is not None:
                out |= {f.name: getattr(rec, f.name) for f in fields(rec)}
        out |= {n: getattr(self, n) for n in _SHARED}
        return {k: out[k] for k in _FLAT_ORDER if k in out}

    def replace(self, **changes) -> ContactOptions:
        """These options with the flat keywords ``changes`` replaced (``options.replace(n_steps=8)``)."""
        return self.from_fields(self.flat() | changes, caller="ContactOptions.replace")


def _flat_reader(section: str, name: str) -> property:
    def read(self):
        rec = getattr(self, section)
        if rec is None:
            raise AttributeError(f"ContactOptions.{name} belongs to the rigid obstacle's body, and these options "
                                 "have none (a meshed partner's bodies carry their materials)")
        return getattr(rec, name)

    return property(read, doc=f"``{section}.{name}`` (:class:`{_SECTIONS[section].__name__}`).")


for _section, _rec in _SECTIONS.items():
    for _f in fields(_rec):
        setattr(ContactOptions, _f.name, _flat_reader(_section, _f.name))


def check_options(opts: ContactOptions, *, mesh_data, obstacle) -> None:
    """The checks that need no function space (ValueError naming the option)."""
    if opts.degree not in (1, 2, 3):
        raise ValueError(f"degree must be 1, 2 or 3, got {opts.degree}")
    if opts.control not in CONTROLS:
        raise ValueError(f"control must be 'displacement' or 'force', got {opts.control!r}")
    if not (opts.target > 0 and np.isfinite(opts.target)):
        raise ValueError(f"target must be > 0 (mm or N/mm), got {opts.target}")
    if int(opts.n_steps) < 1:
        raise ValueError(f"n_steps must be >= 1, got {opts.n_steps}")
    from fem.far_field import check_far_field

    check_far_field(supports=opts.supports, control=opts.control, obstacle=obstacle)
    if opts.contact_group not in mesh_data.physical_groups:
        raise ValueError(f"contact_group {opts.contact_group!r} not in mesh physical groups")
    if opts.formulation not in FORMULATIONS:
        raise ValueError(f"formulation must be one of {FORMULATIONS}, got {opts.formulation!r}")
    if not opts.mixed and opts.nu > NU_DISPLACEMENT_MAX:
        raise ValueError(f"nu = {opts.nu:g} > {NU_DISPLACEMENT_MAX} with formulation='displacement': volumetric "
                         "locking (it diverged at nu = 0.4999); use formulation='mixed' (Taylor-Hood, degree >= 2)")
    if opts.mixed and opts.degree < 2:
        raise ValueError(f"degree must be >= 2 for formulation='mixed' (Taylor-Hood), got {opts.degree}")
    if opts.mixed and not getattr(obstacle, "analytic", False):
        raise ValueError("formulation='mixed' needs an analytic obstacle (not a CurveObstacle)")
    check_model(opts, obstacle=obstacle)
    if opts.predictor not in PREDICTORS:
        raise ValueError(f"predictor must be one of {PREDICTORS}, got {opts.predictor!r}")
    if opts.active_set not in ACTIVE_SETS:
        raise ValueError(f"active_set must be 'extrapolate' or 'geometry', got {opts.active_set!r}")
    if opts.active_set_update not in ACTIVE_SET_UPDATES:
        raise ValueError(f"active_set_update must be one of {ACTIVE_SET_UPDATES}, got {opts.active_set_update!r}")
    if not 0.0 < opts.first_step_fraction <= 1.0:
        raise ValueError(f"first_step_fraction must be in (0, 1], got {opts.first_step_fraction}")
    if opts.linear_solver not in LINEAR_SOLVERS:
        raise ValueError(f"linear_solver must be one of {LINEAR_SOLVERS}, got {opts.linear_solver!r}")
    if opts.linear_solver == "gamg" and opts.mixed:
        raise ValueError("linear_solver='gamg' needs formulation='displacement' (the mixed u-p system is a saddle "
                         "point); use 'lu' or 'lu_reuse'")
    if opts.control == "displacement" and opts.record_at:
        levels = [float(v) for v in opts.record_at]
        if any(v <= 0 for v in levels) or levels != sorted(levels) or levels[-1] != float(opts.target):
            raise ValueError("record_at must be increasing values > 0 (mm) ending at target")


def check_model(opts: ContactOptions, *, obstacle=None) -> None:
    """The model combination (ValueError naming the option): the material model against the kinematics, and
    what finite strain supports (traction='obstacle', the displacement formulation, :data:`FINITE_METHODS`); the
    rule is :func:`vocabulary.model_conflict`, the same the case files are checked with."""
    if opts.material_model not in MATERIAL_MODELS:
        raise ValueError(f"material_model must be one of {MATERIAL_MODELS}, got {opts.material_model!r}")
    bad = model_conflict(kinematics=opts.kinematics, material_model=opts.material_model, traction=opts.traction,
                         formulation=opts.formulation, method=opts.method)
    if bad is None:
        return
    if bad.name == "material_model" and opts.kinematics == FINITE:
        raise ValueError(f"kinematics='finite' needs a hyperelastic material_model {HYPERELASTIC_MODELS}, got "
                         f"{opts.material_model!r}")
    if bad.name == "material_model":
        raise ValueError(f"material_model={opts.material_model!r} needs kinematics='finite' (got "
                         f"{opts.kinematics!r}); small and convective kinematics use material_model='linear'")
    if bad.name == "traction":
        raise ValueError(f"kinematics='finite' needs traction='obstacle' (the traction along the obstacle's normal "
                         f"in the current configuration), got traction={opts.traction!r}")
    if bad.name == "formulation":
        raise ValueError("kinematics='finite' supports formulation='displacement' only, got formulation='mixed'")
    raise ValueError(f"kinematics='finite' supports method in {FINITE_METHODS}, got {opts.method!r}")
