"""Options of a contact solve: one frozen record with the keywords (and defaults) of :func:`fem.solver.solve_contact`.

Units: mm, N, MPa; loads P per unit thickness (N/mm, full body). The meaning of every field is documented once,
in :func:`fem.solver.solve_contact`; this module holds the record, the option vocabularies and the checks that
need no mesh.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, fields

import numpy as np

from fem.linear_solver import LINEAR_SOLVERS

__all__ = ["ContactOptions", "SUPPORT_KINDS", "FORMULATIONS", "CONTROLS", "PREDICTORS", "ACTIVE_SETS",
           "ACTIVE_SET_UPDATES", "MIN_FACETS_ACROSS", "LINEAR_SOLVERS", "MATERIAL_MODELS", "HYPERELASTIC_MODELS",
           "FINITE_METHODS", "NU_DISPLACEMENT_MAX", "check_options"]

SUPPORT_KINDS = ("clamped", "roller_x", "roller_y", "free", "halfplane")  # halfplane: fem/far_field.py
FORMULATIONS = ("displacement", "mixed")
CONTROLS = ("displacement", "force")
PREDICTORS = ("auto", "hertz", "extrapolate", "hertz_zone")
ACTIVE_SETS = ("extrapolate", "geometry")
# How the prescribed active set of a solve is updated before the true law (fem/stepping.py, fem/active_set_update.py):
# "newton": one prescribed iteration, then semismooth Newton; "edge_fit": prescribed iterations with the edges
# extrapolated from the pressure until the set repeats, then semismooth Newton.
ACTIVE_SET_UPDATES = ("newton", "edge_fit")
# Bulk material models (:mod:`fem.hyperelastic`): "linear" is small-strain Hooke (kinematics small or convective);
# the hyperelastic ones are the finite-strain models and go with kinematics="finite" only (and it needs one).
MATERIAL_MODELS = ("linear", "saint_venant_kirchhoff", "neo_hookean")
HYPERELASTIC_MODELS = ("saint_venant_kirchhoff", "neo_hookean")
# Contact methods with a finite-strain form (current-configuration pressure, surface Jacobian ds/dS; the
# Nitsche terms use the current normal traction n_c . P N / (ds/dS), :mod:`fem.contact_forms`).
FINITE_METHODS = ("penalty", "nitsche", "augmented_lagrangian")
# A patch spanning fewer contact facets than this is reported "contact unresolved" (ContactResult.warnings):
# with P2 and 2 Gauss points per facet the edge-location error is about one Gauss spacing, so < 8 facets
# across the patch means a half-width error above ~ 1/16 and a peak that depends on where the nodes fall.
MIN_FACETS_ACROSS = 8
# nu -> 1/2: the displacement formulation locks. Measured (stability study, Hertz scene, P2 h = a/10): at nu =
# 0.499 it converges with RMS/p0 8 % and named warnings, at 0.4999 it diverges (DIVERGED_MAX_IT). Above this
# value it is refused with the advice to use formulation='mixed' (the case schema's "auto" switches itself).
NU_DISPLACEMENT_MAX = 0.499


@dataclass(frozen=True, kw_only=True)
class ContactOptions:
    """The keyword options of :func:`fem.solver.solve_contact` (same names, same defaults; see its docstring).

    ``solve_contact(mesh_data, obstacle, options=ContactOptions(E=..., nu=..., target=...))`` is the same
    solve as passing the fields as keywords; ``dataclasses.replace(options, n_steps=8)`` varies one of them.
    """

    E: float
    nu: float
    target: float
    degree: int = 2
    method: str = "nitsche"
    kinematics: str = "small"
    traction: str = "obstacle"
    kappa0: float = 1e3
    gamma0: float = 10.0
    theta: float = 1.0
    control: str = "displacement"
    n_steps: int = 4
    symmetric_half: bool = False
    on_step: Callable | None = None
    petsc_prefix: str | None = None
    max_cutbacks: int = 5
    supports: dict | None = None
    contact_group: str = "contact"
    quadrature_degree: int | None = None
    force_rtol: float = 1e-10
    snes_rtol: float = 1e-10
    max_it: int = 40
    case: str = "contact"
    petsc_options: dict | None = None
    predictor: str = "auto"
    sample_degree: int | None = None
    active_set_predictor: bool = True
    active_set: str = "extrapolate"
    active_set_update: str = "newton"
    first_step_fraction: float = 0.1
    record_at: Sequence[float] | None = None
    formulation: str = "displacement"
    min_facets_across: int = MIN_FACETS_ACROSS
    uzawa_rtol: float = 1e-10
    uzawa_max_it: int = 100
    linear_solver: str = "lu"
    split_jacobian: bool = True
    material_model: str = "linear"

    @property
    def mixed(self) -> bool:
        """True for the Taylor-Hood u-p formulation."""
        return self.formulation == "mixed"

    @property
    def contact_quadrature_degree(self) -> int:
        """Gauss degree of the contact integral (default ``2 degree - 1``)."""
        return 2 * self.degree - 1 if self.quadrature_degree is None else int(self.quadrature_degree)

    def method_params(self) -> dict:
        """The keywords a contact method's constructor receives (:func:`fem.methods.create`)."""
        return dict(E=self.E, kappa0=self.kappa0, gamma0=self.gamma0, theta=self.theta,
                    uzawa_rtol=self.uzawa_rtol, uzawa_max_it=self.uzawa_max_it)

    @classmethod
    def field_names(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls))


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
    what finite strain supports (traction='obstacle', the displacement formulation, :data:`FINITE_METHODS`)."""
    if opts.material_model not in MATERIAL_MODELS:
        raise ValueError(f"material_model must be one of {MATERIAL_MODELS}, got {opts.material_model!r}")
    finite = opts.kinematics == "finite"
    if finite and opts.material_model not in HYPERELASTIC_MODELS:
        raise ValueError(f"kinematics='finite' needs a hyperelastic material_model {HYPERELASTIC_MODELS}, got "
                         f"{opts.material_model!r}")
    if not finite and opts.material_model != "linear":
        raise ValueError(f"material_model={opts.material_model!r} needs kinematics='finite' (got "
                         f"{opts.kinematics!r}); small and convective kinematics use material_model='linear'")
    if finite and opts.traction != "obstacle":
        raise ValueError(f"kinematics='finite' needs traction='obstacle' (the traction along the obstacle's normal "
                         f"in the current configuration), got traction={opts.traction!r}")
    if finite and opts.mixed:
        raise ValueError("kinematics='finite' supports formulation='displacement' only, got formulation='mixed'")
    if finite and opts.method not in FINITE_METHODS:
        raise ValueError(f"kinematics='finite' supports method in {FINITE_METHODS}, got {opts.method!r}")
