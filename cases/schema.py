"""Typed, frozen case records loaded from ``cases/<name>.toml``.

A case names its geometry, material, loading, discretisation, solver method, which analytic
predictions apply and the tolerances it must meet. Units: mm, N, MPa; loads are per unit thickness
(N/mm); angles are in radians.

Validation is strict: an unknown key, a wrong type, a missing required field or an out-of-range value
raises :class:`CaseError` whose message is ONE line naming the file, the field and the allowed range.
The command-line layer turns it into exit code 2 before anything is written. Values and keys are cut to
``MAX_ECHO`` characters in messages, so a huge value is never echoed back whole.

Every accepted field is used, or refused here: ``[case] name`` is a slug (it names the output folder);
``[analytic] predictions`` must be ones the scene and indenter compute; a geometry field the scene ignores
(``radius`` of a wedge, ``design`` of a block, ...) is refused when given; the block scene is force-
controlled and the concave scene displacement-controlled; ``[solver] formulation`` switches itself to the
mixed one from ``nu >= NU_MIXED`` (``"auto"``), and an explicit ``"displacement"`` beyond ``NU_DISPLACEMENT_MAX``
is refused with that advice. The model hierarchy (``docs/models.md``): ``[material] model`` (linear or a
hyperelastic model) goes with ``[solver] kinematics`` (small/convective or finite), and finite kinematics
needs ``traction = "obstacle"``, the displacement formulation and the block scene; other combinations are
refused. Magnitudes the solver cannot represent are refused with their cause (E beyond ``E_MAX``; a block
contact smaller than ``MIN_A_OVER_R`` of the radius or outside ``HALF_WIDTH_RANGE``).

A case may carry ``[[variant]]`` tables. Each variant overrides fields of the base case (same section
layout, e.g. ``[variant.solver] kinematics = "convective"``) and is run as its own FEM run; the case's
``metrics.json`` holds one entry per variant.
"""

from __future__ import annotations

import copy
import math
import re
import tomllib
from dataclasses import MISSING, dataclass, field, fields, replace
from pathlib import Path
from typing import Any

__all__ = [
    "CASE_DIR",
    "CASE_LEVEL_DEFAULTS",
    "Analytic",
    "Case",
    "CaseError",
    "Discretisation",
    "Geometry",
    "Loading",
    "Material",
    "Run",
    "Solver",
    "case_names",
    "effective_formulation",
    "load_case",
    "CASE_NAME_RE",
    "MAX_ECHO",
    "RESERVED_NAMES",
    "label_folder",
]

CASE_DIR = Path(__file__).resolve().parent

# A case name names its output folder and its mesh-cache files: a slug, nothing path-like.
CASE_NAME_RE = re.compile(r"[A-Za-z0-9_-]{1,64}")
# Names the workbench gives its own folders and files under the output folder (``workbench.paths``): no case may
# take one (its results folder would replace them). Compared case-insensitively.
RESERVED_NAMES = ("mesh_cache", "analytic", "logs", "ci", "ci_report", "convergence", "stability", "bench",
                  "validity", "report", "results", "faults", "vtk")
MAX_LABEL = 64  # characters of a [[variant]] label (it names files: cut in file names, refused beyond)
MAX_ECHO = 60  # characters of a value or key echoed in an error message
# Near-incompressibility (fem.postprocess.LOCKING_NU: the solver's 'near-incompressible' warning starts there).
# formulation = "auto" uses the Taylor-Hood mixed formulation from NU_MIXED on; an explicit "displacement"
# is refused above NU_DISPLACEMENT_MAX (the stability study: P2 displacement at nu = 0.4999 diverged, at 0.499
# it converged with RMS/p0 8 % and named warnings).
NU_MIXED = 0.45
NU_DISPLACEMENT_MAX = 0.499
# Extreme magnitudes. E: kappa = kappa0 E / h and the SNES tolerance 1e-13 E L must stay finite (E = 1e300
# gave inf/NaN residuals); the stability study's scale sweep covers 1e-3 ... 1e6 MPa.
E_MAX = 1e12
# A block contact: the approach d ~ a^2 / R must stay far above the round-off of the coordinates (~1e-16 R).
# Measured on hertz_cylinder (P2, h = a/20): a/R = 1e-5 within the case tolerances (p_max 0.05 %), 1e-6
# p_max 1 % with an oscillating pressure, 1e-7 round-off noise (13 patches, p_max 87 % off).
MIN_A_OVER_R = 1e-5
# The classical half-width (mm) the mesh is sized from: measured sound from 5e-8 mm (R = 1e-6 mm) upwards.
HALF_WIDTH_RANGE = (1e-8, 1e8)
# Block size over the half-width. W = 1e6 a (H = 40 a) gave a 1.9 % load-balance error with no warning;
# W = H = 1e5 a measured 7.5e-13. Width and height beyond 1e4 a are refused, and W/H is kept within 1e3.
MAX_SIZE_FACTOR = 1e4
BUDGET_SPAN = 8.0  # error budget: largest over smallest level (the grading is refined with h_c)
# [bands]: checks whose tolerance is the error budget's band (make run only). A listed quantity selects every
# budget row of that quantity (block: one per run; concave: one per step and patch); "name[k]" selects the
# rows of patch k only.
BAND_KINDS = {
    "contain_theory": "the band (GCI + truncation) of the quantity contains its theory",
    "exclude_alt": "the band of the quantity excludes its alternative theory (e.g. first order, Hertz)",
    "exclude_theory": "the band of the quantity excludes its theory (a theory the scene shows to fail)",
}
BAND_QUANTITIES = {
    "block": ("p_max", "half_width", "half_width_moment", "b_over_b0", "b_over_b0_moment"),
    "concave": ("load_symmetry", "first_contact_width", "width_moment", "width_fem"),
}
MAX_ASPECT = 1e3
# Penalty / Nitsche factors: the contact terms add kappa0 (gamma0) times the bulk stiffness entries of the contact
# rows (kappa = kappa0 E / h integrated over an edge of length h ~ kappa0 E). LU resolves the bulk part of those
# rows to about eps * kappa0 relative (eps = 2.2e-16): at the upper bound 1e12 that is 2e-4, beyond it the bulk is
# lost in round-off (1e303 even overflows to inf in the compiled form). The stability study sweeps 1e0 ... 1e10.
# Below 1e-6 the contact term is a millionth of the bulk stiffness: penetrations of 1e6 times the elastic approach,
# no contact to speak of. Between 1e-6 and ~1 a Nitsche factor may lose coercivity and the solve diverges: a named
# solver failure (exit 1, logs/<case>.log; tests/test_stability_faults.py provokes it with gamma0 = 1e-6).
FACTOR_RANGE = (1e-6, 1e12)
# Limits no real case reaches (the largest case file is 3 kB): refused in one line, so a huge file is never copied.
MAX_FILE_BYTES = 1_000_000
MAX_DESCRIPTION = 2000  # characters
MAX_LIST = 100  # entries of levels, d, budget lists
MAX_VARIANTS = 100
MAX_TOLERANCE = 10.0  # a relative error of 1000 %: anything above checks nothing
E_MIN = 1e-6  # MPa: the stability study's scale sweep starts at 1e-3
# The finite-strain material models (material.model; "linear" is the small-strain one), docs/models.md.
HYPERELASTIC_MODELS = ("saint_venant_kirchhoff", "neo_hookean")


def _r(value: Any) -> str:
    """``repr(value)`` cut to MAX_ECHO characters (a 200 kB string is never echoed back whole)."""
    text = repr(value)
    return text if len(text) <= MAX_ECHO else text[:MAX_ECHO - 3] + "..."

class CaseError(ValueError):
    """A case file is malformed or holds an out-of-range value (one-line message)."""


# --- records -----------------------------------------------------------------------------------


@dataclass(frozen=True)
class Material:
    """Elastic material of the deformable body (the indenter is rigid), plane strain.

    Attributes:
        E: Young's modulus in MPa, E > 0 (the small-strain modulus of every model).
        nu: Poisson's ratio, -1 < nu < 0.5 (the small-strain ratio of every model).
        model: ``"linear"`` (small-strain Hooke, with solver.kinematics "small" or "convective"),
            ``"saint_venant_kirchhoff"`` or ``"neo_hookean"`` (hyperelastic, with solver.kinematics = "finite"
            only; :mod:`fem.hyperelastic`, ``docs/models.md``).
    """

    E: float
    nu: float
    model: str = "linear"


@dataclass(frozen=True)
class Geometry:
    """Scene geometry.

    Attributes:
        scene: ``"block"`` (elastic block under a rigid indenter) or ``"concave"`` (concave elastic body
            under the rigid convex particle of the close-to-conformal paper).
        indenter: ``"circle"``, ``"parabola"`` or ``"wedge"`` for the block scene; ``"particle"`` for
            the concave scene.
        radius: Indenter radius R in mm (circle, parabola).
        wedge_angle: External wedge angle theta in rad, 0 < theta < pi/2.
        wedge_slope: ``"exact"`` (face slope tan(theta), the true geometry) or ``"paper"`` (slope
            theta, the small-angle profile of Ciavarella & Hills).
        design: Concave configuration, ``"symmetric"`` or ``"close_to_conformal"``.
        width_factor: Block width W over the classical contact half-width (>= 10).
        height_factor: Block height H over the classical contact half-width (>= 10).
        half_model: Mesh half the block with a symmetry edge (symmetric block scenes only).
        far_field: Outer boundary of the block: ``"clamped"`` (bottom clamped, sides free) or ``"halfplane"``
            (bottom and sides moved as the half-plane under the line load P, Flamant's field:
            :mod:`fem.far_field`; block scenes only, force control). The error budget always uses
            ``"halfplane"``.
    """

    scene: str
    indenter: str
    radius: float | None = None
    wedge_angle: float | None = None
    wedge_slope: str = "exact"
    design: str | None = None
    width_factor: float = 40.0
    height_factor: float = 40.0
    half_model: bool = True
    far_field: str = "clamped"


@dataclass(frozen=True)
class Loading:
    """Loading of the rigid body.

    Exactly one of ``P`` (target load per unit thickness, N/mm) and ``half_width`` (target classical
    contact half-width b0 in mm, from which P follows by the analytic theory) sets a force-controlled
    load; ``d`` (list of rigid-body displacements in mm, recorded in order) sets displacement control.

    Attributes:
        control: ``"force"`` or ``"displacement"``.
        P: Target load per unit thickness in N/mm, > 0.
        half_width: Target classical half-width b0 in mm, > 0.
        d: Displacements of the rigid body in mm (increasing, > 0), displacement control only.
        steps: Number of load steps to the target (force control), >= 1.
    """

    control: str
    P: float | None = None
    half_width: float | None = None
    d: tuple[float, ...] = ()
    steps: int = 4


@dataclass(frozen=True)
class Discretisation:
    """Mesh and element choice.

    Attributes:
        degree: Lagrange degree of the displacement, 1 or 2.
        h_contact: Element size in the contact zone as a fraction of the contact half-width, in (0, 1].
        levels: Refinement levels for studies, as h_contact fractions, coarse to fine.
        ci_level: Fraction used by ``make ci`` (the coarsest that still meets the tolerances).
        growth: Element-to-element size ratio of the mesh grading away from the contact, in [1.05, 2].
        budget_levels: Three h_contact fractions of the error budget (``make run`` solves each run on all
            three, block scenes on the largest budget block), or empty for no budget.
        budget_widths: Three block sizes W/a (width = height, in [10, MAX_SIZE_FACTOR]) of the budget's
            truncation study (at the finest budget level); required with ``budget_levels`` in block scenes,
            refused in concave scenes (their body is the real geometry).
    """

    degree: int = 2
    h_contact: float = 0.05
    growth: float = 1.3
    levels: tuple[float, ...] = ()
    ci_level: float | None = None
    budget_levels: tuple[float, ...] = ()
    budget_widths: tuple[float, ...] = ()


@dataclass(frozen=True)
class Solver:
    """Contact formulation and kinematics.

    Attributes:
        method: ``"nitsche"``, ``"penalty"`` or ``"augmented_lagrangian"`` (Uzawa updates of a nodal
            multiplier around the penalty Newton: the constraint holds exactly for any kappa0,
            :mod:`fem.methods.augmented_lagrangian`).
        kinematics: ``"small"`` (gap at the undeformed position, the Hertz hypothesis),
            ``"convective"`` (obstacle evaluated at the current position X + u) or ``"finite"`` (finite-strain
            hyperelasticity, total Lagrangian; contact at X + u with the traction along the obstacle's current
            normal; needs a hyperelastic material.model, traction = "obstacle", the displacement formulation and
            the block scene; ``docs/models.md``).
        traction: ``"halfplane"`` (vertical gap and traction, as half-plane theory assumes) or
            ``"obstacle"`` (gap and traction along the rigid curve's normal).
        kappa0: Dimensionless penalty factor, kappa = kappa0 E / h, > 0 (the augmentation stiffness of the
            augmented Lagrangian).
        gamma0: Dimensionless Nitsche factor, gamma = gamma0 E / h, > 0.
        theta: Nitsche variant: 1 (symmetric), 0 (skew-less), -1 (skew-symmetric).
        formulation: ``"auto"`` (displacement below nu = NU_MIXED, Taylor-Hood mixed from there on),
            ``"displacement"`` (refused above nu = NU_DISPLACEMENT_MAX) or ``"mixed"`` (degree 2, block scenes).
        linear_solver: The linear solver of the Newton iterations (:mod:`fem.linear_solver`): ``"lu"`` (MUMPS LU
            of every Jacobian), ``"lu_reuse"`` (GMRES preconditioned by the LU of an earlier Jacobian) or
            ``"gamg"`` (GMRES + algebraic multigrid with the rigid-body near-nullspace; not with the mixed
            formulation). The converged answer is the same.
    """

    method: str = "nitsche"
    kinematics: str = "small"
    traction: str = "halfplane"
    kappa0: float = 1.0e3
    gamma0: float = 10.0
    theta: int = 1
    formulation: str = "auto"
    linear_solver: str = "lu"


# Every [solver] field is the solver option (fem.options.ContactOptions) of the same name, with the same default,
# except these: case-level choices, each with its reason (tests/test_options_record.py checks the rest agree).
CASE_LEVEL_DEFAULTS = {
    "traction": "the case files compare with half-plane theory, which assumes a vertical gap and traction "
                "('halfplane'); a bare solve defaults to the obstacle's normal ('obstacle'), right for any geometry "
                "and the only traction finite kinematics supports",
    "formulation": "'auto' is a case-level choice resolved by nu (effective_formulation: the mixed formulation "
                   "from NU_MIXED on); the solver takes the resolved 'displacement' or 'mixed'",
}


@dataclass(frozen=True)
class Analytic:
    """Analytic predictions compared with the FEM (names of analytic/ predictions).

    Attributes:
        predictions: e.g. ``("hertz",)``, ``("wedge",)``, ``("convective",)``,
            ``("hertz_superposition", "elliptical_fit")``.
    """

    predictions: tuple[str, ...] = ()


@dataclass(frozen=True)
class Run:
    """One FEM run of a case: the base case with one variant's overrides applied."""

    label: str
    material: Material
    geometry: Geometry
    loading: Loading
    discretisation: Discretisation
    solver: Solver


@dataclass(frozen=True)
class Case:
    """A verification scene as loaded from ``cases/<name>.toml``."""

    name: str
    path: Path
    description: str
    material: Material
    geometry: Geometry
    loading: Loading
    discretisation: Discretisation
    solver: Solver
    analytic: Analytic
    tolerances: dict[str, float] = field(default_factory=dict)
    bands: dict[str, tuple[str, ...]] = field(default_factory=dict)
    variants: tuple[dict[str, Any], ...] = ()

    def runs(self, *, h_contact: float | None = None) -> tuple[Run, ...]:
        """The runs of this case: one per variant (or the base case alone), optionally at another h_c."""
        out = []
        raw_variants = self.variants or ({"label": "base"},)
        for i, var in enumerate(raw_variants):
            where = f"{self.path.name}: variant[{i}]"
            sections = {}
            for name, cls in _SECTIONS.items():
                if name == "analytic":
                    continue
                base = getattr(self, name)
                over = var.get(name, {})
                merged = {f.name: getattr(base, f.name) for f in fields(cls)} | over
                sections[name] = _build(cls, merged, f"{where}: {name}", partial_ok=False)
            if h_contact is not None:
                d = sections["discretisation"]
                sections["discretisation"] = replace(d, h_contact=h_contact)
            run = Run(label=str(var.get("label", f"variant{i}")), **sections)
            _check_run(run, where)
            out.append(run)
        return tuple(out)


_SECTIONS = {
    "material": Material,
    "geometry": Geometry,
    "loading": Loading,
    "discretisation": Discretisation,
    "solver": Solver,
    "analytic": Analytic,
}
_REQUIRED_SECTIONS = ("material", "geometry", "loading")

# allowed values and ranges, checked per field
_CHOICES = {
    ("geometry", "scene"): ("block", "concave"),
    ("geometry", "indenter"): ("circle", "parabola", "wedge", "particle"),
    ("geometry", "wedge_slope"): ("exact", "paper"),
    ("geometry", "design"): ("symmetric", "close_to_conformal"),
    ("geometry", "far_field"): ("clamped", "halfplane"),
    ("loading", "control"): ("force", "displacement"),
    ("discretisation", "degree"): (1, 2),
    ("solver", "method"): ("nitsche", "penalty", "augmented_lagrangian"),
    ("material", "model"): ("linear", "saint_venant_kirchhoff", "neo_hookean"),
    ("solver", "kinematics"): ("small", "convective", "finite"),
    ("solver", "traction"): ("halfplane", "obstacle"),
    ("solver", "theta"): (1, 0, -1),
    ("solver", "formulation"): ("auto", "displacement", "mixed"),
    ("solver", "linear_solver"): ("lu", "lu_reuse", "gamg"),
}
# (low, high, low_inclusive, high_inclusive, text)
_RANGES = {
    ("material", "E"): (E_MIN, E_MAX, True, True, f"E > 0, {E_MIN:g} <= E <= {E_MAX:g} (MPa)"),
    ("material", "nu"): (-1.0, 0.5, False, False, "-1 < nu < 0.5"),
    ("geometry", "radius"): (0.0, math.inf, False, False, "radius > 0 (mm)"),
    ("geometry", "wedge_angle"): (0.0, math.pi / 2, False, False, "0 < wedge_angle < pi/2 (rad)"),
    ("geometry", "width_factor"): (10.0, MAX_SIZE_FACTOR, True, True, f"10 <= width_factor <= {MAX_SIZE_FACTOR:g}"),
    ("geometry", "height_factor"): (10.0, MAX_SIZE_FACTOR, True, True,
                                    f"10 <= height_factor <= {MAX_SIZE_FACTOR:g}"),
    ("loading", "P"): (0.0, math.inf, False, False, "P > 0 (N/mm)"),
    ("loading", "half_width"): (0.0, math.inf, False, False, "half_width > 0 (mm)"),
    ("loading", "steps"): (1, 1000, True, True, "1 <= steps <= 1000"),
    ("discretisation", "h_contact"): (0.0, 1.0, False, True, "0 < h_contact <= 1 (fraction of half-width)"),
    ("discretisation", "ci_level"): (0.0, 1.0, False, True, "0 < ci_level <= 1"),
    ("discretisation", "growth"): (1.05, 2.0, True, True, "1.05 <= growth <= 2"),
    ("solver", "kappa0"): (*FACTOR_RANGE, True, True, f"kappa0 > 0, {FACTOR_RANGE[0]:g} <= kappa0 <= "
                           f"{FACTOR_RANGE[1]:g} (the LU solve resolves the bulk up to eps x kappa0)"),
    ("solver", "gamma0"): (*FACTOR_RANGE, True, True, f"gamma0 > 0, {FACTOR_RANGE[0]:g} <= gamma0 <= "
                           f"{FACTOR_RANGE[1]:g} (the LU solve resolves the bulk up to eps x gamma0)"),
}
_SEQ_RANGES = {
    ("loading", "d"): (0.0, math.inf, False, False, "every d > 0 (mm)"),
    ("discretisation", "levels"): (0.0, 1.0, False, True, "every level in (0, 1]"),
    ("discretisation", "budget_levels"): (0.0, 1.0, False, True, "every budget level in (0, 1]"),
    ("discretisation", "budget_widths"): (10.0, MAX_SIZE_FACTOR, True, True,
                                          f"every budget width in [10, {MAX_SIZE_FACTOR:g}] (W/a)"),
}
_TOLERANCE_KEYS = {
    "p_max": "relative error of the peak pressure",
    "half_width": "relative error of the contact half-width",
    "rms": "RMS(p_fem - p_theory) / p0",
    "load_balance": "|P - P_pressure| / P",
    "b_over_b0": "relative error of the FEM convective ratio b/b0 against the converged theory",
    "rms_convective": "RMS(p_fem - p_convective)/p_ref of the convective run against the converged theory",
    "fit_rms": "elliptical-fit RMS / p0 (upper bound)",
    "patch_size": "relative mismatch of eq. (4) and eq. (5) patch sizes",
}


def _coerce(value: Any, annotation: str, where: str) -> Any:
    """Check ``value`` against a field annotation string (postponed annotations) and coerce it."""
    ann = annotation.replace(" ", "")
    optional = ann.endswith("|None")
    base = ann.removesuffix("|None")
    if value is None:
        if optional:
            return None
        raise CaseError(f"{where} must not be empty")
    if base == "float":
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise CaseError(f"{where} = {_r(value)} has the wrong type; expected a number")
        if not math.isfinite(value):
            raise CaseError(f"{where} = {_r(value)} must be a finite number")
        return float(value)
    if base == "int":
        if isinstance(value, bool) or not isinstance(value, int):
            raise CaseError(f"{where} = {_r(value)} has the wrong type; expected an integer")
        return value
    if base == "bool":
        if not isinstance(value, bool):
            raise CaseError(f"{where} = {_r(value)} has the wrong type; expected true or false")
        return value
    if base == "str":
        if not isinstance(value, str):
            raise CaseError(f"{where} = {_r(value)} has the wrong type; expected a string")
        return value
    if base == "tuple[float,...]":
        if not isinstance(value, list | tuple) or any(
            isinstance(v, bool) or not isinstance(v, int | float) for v in value
        ):
            raise CaseError(f"{where} = {_r(value)} has the wrong type; expected a list of numbers")
        if len(value) > MAX_LIST:
            raise CaseError(f"{where} has {len(value)} entries; allowed: at most {MAX_LIST}")
        if not all(math.isfinite(v) for v in value):
            raise CaseError(f"{where} = {_r(value)} must hold finite numbers")
        return tuple(float(v) for v in value)
    if base == "tuple[str,...]":
        if not isinstance(value, list | tuple) or any(not isinstance(v, str) for v in value):
            raise CaseError(f"{where} = {_r(value)} has the wrong type; expected a list of strings")
        if len(value) > MAX_LIST:
            raise CaseError(f"{where} has {len(value)} entries; allowed: at most {MAX_LIST}")
        return tuple(value)
    raise AssertionError(f"unhandled annotation {annotation}")  # pragma: no cover


def _in_range(value: float, spec: tuple) -> bool:
    lo, hi, lo_inc, hi_inc, _ = spec
    ok_lo = value >= lo if lo_inc else value > lo
    ok_hi = value <= hi if hi_inc else value < hi
    return ok_lo and ok_hi


def _build(cls: type, table: Any, where: str, *, partial_ok: bool = False) -> Any:
    """Build a section record from a TOML table, validating keys, types and ranges."""
    if not isinstance(table, dict):
        raise CaseError(f"{where} must be a table")
    section = where.rsplit(": ", 1)[-1]
    known = {f.name: f for f in fields(cls)}
    for key in table:
        if key not in known:
            raise CaseError(f"{where}.{_r(key)[1:-1]} is an unknown key; allowed keys: {', '.join(known)}")
    values = {}
    for name, f in known.items():
        if name in table:
            raw = table[name]
        elif f.default is not MISSING or f.default_factory is not MISSING:
            continue
        else:
            raise CaseError(f"{where}.{name} is a required field and is missing")
        value = _coerce(raw, f.type, f"{where}.{name}")
        if value is not None:
            choices = _CHOICES.get((section, name))
            if choices is not None and value not in choices:
                allowed = ", ".join(repr(c) for c in choices)
                raise CaseError(f"{where}.{name} = {_r(value)} is not allowed; allowed values: {allowed}")
            spec = _RANGES.get((section, name))
            if spec is not None and not _in_range(value, spec):
                raise CaseError(f"{where}.{name} = {_r(value)} is out of range; allowed: {spec[4]}")
            spec = _SEQ_RANGES.get((section, name))
            if spec is not None and not all(_in_range(v, spec) for v in value):
                raise CaseError(f"{where}.{name} = {_r(list(value))} is out of range; allowed: {spec[4]}")
        values[name] = value
    return cls(**values)


def _check_run(run: Run, where: str) -> None:
    """Cross-field checks of one run (after variant overrides)."""
    g, ld = run.geometry, run.loading
    if g.scene == "block":
        if g.indenter == "particle":
            raise CaseError(f"{where}: geometry.indenter = 'particle' needs geometry.scene = 'concave'")
        if g.indenter in ("circle", "parabola") and g.radius is None:
            raise CaseError(f"{where}: geometry.radius is required for a {g.indenter}; allowed: radius > 0 (mm)")
        if g.indenter == "wedge" and g.wedge_angle is None:
            raise CaseError(
                f"{where}: geometry.wedge_angle is required for a wedge; allowed: 0 < wedge_angle < pi/2 (rad)"
            )
    else:
        if g.indenter != "particle":
            raise CaseError(f"{where}: geometry.indenter must be 'particle' for geometry.scene = 'concave'")
        if g.design is None:
            raise CaseError(
                f"{where}: geometry.design is required for a concave scene; "
                "allowed values: 'symmetric', 'close_to_conformal'"
            )
    if g.indenter == "circle" and ld.control == "force" and (ld.P is None) != (ld.half_width is None):
        _check_circle_reachable(run, where)
    if ld.control == "force":
        if (ld.P is None) == (ld.half_width is None):
            raise CaseError(f"{where}: loading needs exactly one of P (N/mm) or half_width (mm) for force control")
        if ld.d:
            raise CaseError(f"{where}: loading.d is only allowed with control = 'displacement'")
    else:
        if not ld.d:
            raise CaseError(f"{where}: loading.d (list of displacements in mm) is required for displacement control")
        if list(ld.d) != sorted(ld.d):
            raise CaseError(f"{where}: loading.d = {_r(list(ld.d))} must be increasing")
        if ld.P is not None or ld.half_width is not None:
            raise CaseError(f"{where}: loading.P/half_width are only allowed with control = 'force'")
    if g.scene == "block" and ld.control != "force":
        raise CaseError(f"{where}: loading.control = {_r(ld.control)} is not supported by the block scene; "
                        "allowed: 'force' (with P or half_width)")
    if g.scene == "concave" and ld.control != "displacement":
        raise CaseError(f"{where}: loading.control = {_r(ld.control)} is not supported by the concave scene; "
                        "allowed: 'displacement' (with d)")
    if g.scene == "block" and ld.control == "force" and (ld.P is None) != (ld.half_width is None):
        _check_block_scale(run, where)
    _check_formulation(run, where)
    _check_model(run, where)
    _check_budget(run, where)


def _check_model(run: Run, where: str) -> None:
    """The model hierarchy's combinations (``docs/models.md``): a hyperelastic material goes with finite
    kinematics and finite kinematics with a hyperelastic material, the obstacle traction, the displacement
    formulation and the block scene (the options :func:`fem.options.check_model` checks again)."""
    model, sol = run.material.model, run.solver
    if sol.kinematics == "finite":
        if model not in HYPERELASTIC_MODELS:
            raise CaseError(f"{where}: solver.kinematics = 'finite' needs a hyperelastic material.model (got "
                            f"{_r(model)}); allowed: 'saint_venant_kirchhoff', 'neo_hookean'")
        if sol.traction != "obstacle":
            raise CaseError(f"{where}: solver.kinematics = 'finite' needs solver.traction = 'obstacle' (got "
                            f"{_r(sol.traction)}); allowed: 'obstacle' (traction along the obstacle's current normal)")
        if effective_formulation(run) != "displacement":
            raise CaseError(f"{where}: solver.kinematics = 'finite' supports the displacement formulation only (got "
                            f"{_r(effective_formulation(run))}); allowed: formulation = 'displacement' or 'auto' with "
                            f"nu < {NU_MIXED}")
        if run.geometry.scene != "block":
            raise CaseError(f"{where}: solver.kinematics = 'finite' is not supported by the {_r(run.geometry.scene)} "
                            "scene; allowed: scene = 'block'")
    elif model != "linear":
        raise CaseError(f"{where}: material.model = {_r(model)} needs solver.kinematics = 'finite' (got "
                        f"{_r(sol.kinematics)}); allowed with small or convective kinematics: model = 'linear'")


def _check_budget(run: Run, where: str) -> None:
    """The error budget needs three distinct levels and three distinct block sizes, block scenes only."""
    d = run.discretisation
    if not d.budget_levels and not d.budget_widths:
        return
    block = run.geometry.scene == "block"
    if not block and d.budget_widths:
        raise CaseError(f"{where}: discretisation.budget_widths = {_r(list(d.budget_widths))} is not supported by "
                        f"the {_r(run.geometry.scene)} scene (its body is the real geometry); allowed: scene = 'block'")
    for name, seq in (("budget_levels", d.budget_levels), ("budget_widths", d.budget_widths))[:2 if block else 1]:
        if len(seq) != 3 or len(set(seq)) != 3:
            raise CaseError(f"{where}: discretisation.{name} = {_r(list(seq))} is not allowed; allowed: exactly "
                            "three distinct values (block scenes: with both budget_levels and budget_widths)")
    if max(d.budget_levels) > BUDGET_SPAN * min(d.budget_levels):
        raise CaseError(f"{where}: discretisation.budget_levels = {_r(list(d.budget_levels))} spans more than a "
                        f"factor {BUDGET_SPAN:g}; allowed: max <= {BUDGET_SPAN:g} min (the grading is refined with "
                        "h_c, so a wider span meshes the finest level far too densely)")


def effective_formulation(run: Run) -> str:
    """The bulk formulation a run is solved with: ``solver.formulation``, ``"auto"`` resolved by nu
    (``"mixed"`` from NU_MIXED on, else ``"displacement"``)."""
    f = run.solver.formulation
    if f == "auto":
        return "mixed" if run.material.nu >= NU_MIXED else "displacement"
    return f


def _check_formulation(run: Run, where: str) -> None:
    """nu -> 1/2: the displacement formulation locks; the mixed one needs degree 2 and an analytic obstacle."""
    nu, sol = run.material.nu, run.solver
    form = effective_formulation(run)
    if form == "displacement" and nu > NU_DISPLACEMENT_MAX:
        raise CaseError(f"{where}: solver.formulation = 'displacement' at material.nu = {nu!r} locks (volumetric "
                        f"locking; it diverged at nu = 0.4999); allowed: nu <= {NU_DISPLACEMENT_MAX}, or "
                        "formulation = 'mixed' or 'auto' (Taylor-Hood, degree = 2)")
    if form == "mixed":
        why = (f"material.nu = {nu!r} >= {NU_MIXED} needs the mixed formulation (formulation = 'auto')"
               if sol.formulation == "auto" else "solver.formulation = 'mixed'")
        if run.discretisation.degree < 2:
            raise CaseError(f"{where}: {why}, which needs discretisation.degree = 2 (Taylor-Hood P2/P1); "
                            "allowed: degree = 2")
        if run.geometry.scene != "block":
            raise CaseError(f"{where}: {why}, which needs an analytic obstacle (block scenes); allowed on the "
                            f"concave scene: nu < {NU_MIXED}")
        if sol.linear_solver == "gamg":
            raise CaseError(f"{where}: solver.linear_solver = 'gamg' with the mixed formulation ({why}): a saddle "
                            "point; allowed: linear_solver = 'lu' or 'lu_reuse'")


def _classical_half_width(run: Run) -> float:
    """The classical half-width (mm) of a force-controlled block run (Hertz or wedge)."""
    from analytic import hertz, materials, wedge

    g, ld = run.geometry, run.loading
    if ld.half_width is not None:
        return ld.half_width
    E_star = materials.plane_strain_modulus(run.material.E, run.material.nu)
    if g.indenter == "wedge":
        return wedge.wedge(ld.P, wedge.wedge_slope(g.wedge_angle, convention=g.wedge_slope), E_star).half_width
    return hertz.hertz_half_width(ld.P, g.radius, E_star)


def _check_block_scale(run: Run, where: str) -> None:
    """Magnitudes a double-precision solve resolves: the contact against the radius and in absolute size."""
    g, ld = run.geometry, run.loading
    field_ = "loading.half_width" if ld.half_width is not None else "loading.P"
    value = ld.half_width if ld.half_width is not None else ld.P
    try:
        a = _classical_half_width(run)
    except (ValueError, ArithmeticError):
        a = math.nan
    if g.indenter == "parabola" and a >= 0.5 * g.radius:
        raise CaseError(f"{where}: {field_} = {_r(value)} gives a contact half-width a = {a:.4g} mm against "
                        f"radius {g.radius:g} mm: strains of order a/R, beyond the small-strain model; allowed: "
                        f"half-width < radius/2 = {0.5 * g.radius:.4g} mm")
    if g.indenter in ("circle", "parabola") and math.isfinite(a) and a < MIN_A_OVER_R * g.radius:
        raise CaseError(f"{where}: {field_} = {_r(value)} gives a contact half-width a = {a:.3g} mm, a/R = "
                        f"{a / g.radius:.2g}: the approach a^2/R is at the round-off of the coordinates (the "
                        f"pressure would be noise, not a mesh-resolution problem); allowed: a/R >= {MIN_A_OVER_R:g} "
                        "(raise the load)")
    lo, hi = HALF_WIDTH_RANGE
    if not (math.isfinite(a) and lo <= a <= hi):
        raise CaseError(f"{where}: {field_} = {_r(value)} with material.E = {run.material.E!r} gives a contact "
                        f"half-width of {a:.3g} mm; allowed: {lo:g} <= half-width <= {hi:g} mm (change the load or "
                        "E, or the units)")
    if max(g.width_factor / g.height_factor, g.height_factor / g.width_factor) > MAX_ASPECT:
        raise CaseError(f"{where}: geometry.width_factor / height_factor = {g.width_factor:g} / {g.height_factor:g} "
                        f"makes far-field elements too stretched for load balance; allowed: a ratio within "
                        f"1/{MAX_ASPECT:g} ... {MAX_ASPECT:g}")


def _check_circle_reachable(run: Run, where: str) -> None:
    """A rigid circle cannot make a contact wider than itself: the Hertz half-width must stay below R/2
    (the half-plane theory and the case's comparison mean nothing beyond that)."""
    from analytic import hertz, materials

    g, ld = run.geometry, run.loading
    limit = 0.5 * g.radius
    if ld.half_width is not None:
        a = ld.half_width
    else:
        a = hertz.hertz_half_width(ld.P, g.radius, materials.plane_strain_modulus(run.material.E, run.material.nu))
    if a >= limit:
        field_ = "loading.half_width" if ld.half_width is not None else "loading.P"
        value = ld.half_width if ld.half_width is not None else ld.P
        raise CaseError(f"{where}: {field_} = {_r(value)} cannot be reached by a circle of radius {g.radius} mm "
                        f"(Hertz half-width {a:.4g} mm); allowed: half-width < radius/2 = {limit:.4g} mm")


def label_folder(label: str) -> str:
    """The folder (and file-name part) of a run label: ``vtk/<folder>/``, ``render_<folder>.png``.

    ASCII letters, digits, ``-``, ``_`` and ``.`` are kept, every other character becomes ``_``, and a leading
    ``.`` becomes ``_`` (never ``.``, ``..`` or a hidden name). Two labels of one case that map to the same
    folder are refused by :func:`load_case`.
    """
    text = "".join(c if (c.isascii() and c.isalnum()) or c in "-_." else "_" for c in str(label))
    return "_" + text[1:] if text.startswith(".") else text


def load_case(path: str | Path) -> Case:
    """Load and validate a case file.

    Args:
        path: A path to a TOML file, or a case name resolved as ``cases/<name>.toml``.

    Returns:
        The frozen :class:`Case` record.

    Raises:
        CaseError: One line naming the file, the field and the allowed range.
    """
    known = ", ".join(case_names()) or "none"
    p = Path(path)
    if p.suffix != ".toml":
        if not CASE_NAME_RE.fullmatch(str(path)):
            raise CaseError(f"{_r(str(path))}: no such case file; known cases: {known} (or a path to a .toml file)")
        p = CASE_DIR / f"{path}.toml"
    where = _r(p.name)[1:-1]
    raw = _read_toml(p, str(path), known)
    allowed_top = {"case", *_SECTIONS, "tolerances", "bands", "variant"}
    for key in raw:
        if key not in allowed_top:
            raise CaseError(f"{where}: {_r(key)[1:-1]} is an unknown key; "
                            f"allowed keys: {', '.join(sorted(allowed_top))}")
    head = raw.get("case", {})
    if not isinstance(head, dict):
        raise CaseError(f"{where}: case must be a table")
    for key in head:
        if key not in ("name", "description"):
            raise CaseError(f"{where}: case.{_r(key)[1:-1]} is an unknown key; allowed keys: name, description")
    name = head.get("name", p.stem)
    if not isinstance(name, str) or not CASE_NAME_RE.fullmatch(name):
        field_ = "case.name" if "name" in head else "case.name (the file name)"
        raise CaseError(f"{where}: {field_} = {_r(name)} is not allowed; allowed: 1 to 64 letters, digits, '_' "
                        "or '-' (it names the output folder)")
    if name.lower() in RESERVED_NAMES:
        field_ = "[case] name" if "name" in head else "[case] name (the file name)"
        raise CaseError(f"{where}: {field_} = {_r(name)} is reserved (the workbench's own folders and files under "
                        f"--out: {', '.join(RESERVED_NAMES)}); allowed: any other name")
    for sec in _REQUIRED_SECTIONS:
        if sec not in raw:
            raise CaseError(f"{where}: [{sec}] is a required section and is missing")
    records = {
        sec: _build(cls, raw.get(sec, {}), f"{where}: {sec}") for sec, cls in _SECTIONS.items()
    }
    tolerances = raw.get("tolerances", {})
    if not isinstance(tolerances, dict):
        raise CaseError(f"{where}: tolerances must be a table")
    tol = {}
    for key, value in tolerances.items():
        if key not in _TOLERANCE_KEYS:
            raise CaseError(f"{where}: tolerances.{_r(key)[1:-1]} is an unknown key; "
                           f"allowed keys: {', '.join(_TOLERANCE_KEYS)}")
        if (isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value)
                or not 0 < value <= MAX_TOLERANCE):
            raise CaseError(f"{where}: tolerances.{key} = {_r(value)} is out of range; allowed: a finite number "
                            f"with 0 < {key} <= {MAX_TOLERANCE:g}")
        tol[key] = float(value)
    variants = raw.get("variant", [])
    if not isinstance(variants, list) or any(not isinstance(v, dict) for v in variants):
        raise CaseError(f"{where}: variant must be an array of tables ([[variant]])")
    if len(variants) > MAX_VARIANTS:
        raise CaseError(f"{where}: {len(variants)} [[variant]] tables; allowed: at most {MAX_VARIANTS}")
    description = head.get("description", "")
    if not isinstance(description, str) or len(description) > MAX_DESCRIPTION:
        raise CaseError(f"{where}: case.description is not allowed ({type(description).__name__} of "
                        f"{len(description) if isinstance(description, str) else '?'} characters); allowed: a string "
                        f"of at most {MAX_DESCRIPTION} characters")
    for i, var in enumerate(variants):
        for key, value in var.items():
            if key == "label":
                if not isinstance(value, str) or not 0 < len(value) <= MAX_LABEL or not value.isprintable():
                    raise CaseError(f"{where}: variant[{i}].label = {_r(value)} is not allowed; allowed: a string of "
                                    f"1 to {MAX_LABEL} printable characters")
            elif key not in _SECTIONS or key == "analytic":
                raise CaseError(
                    f"{where}: variant[{i}].{_r(key)[1:-1]} is an unknown key; allowed keys: label, "
                    + ", ".join(s for s in _SECTIONS if s != "analytic")
                )
            elif not isinstance(value, dict):
                raise CaseError(f"{where}: variant[{i}].{key} must be a table")
    case = Case(
        name=name,
        path=p,
        description=description,
        tolerances=tol,
        bands=_parse_bands(raw.get("bands", {}), where),
        variants=tuple(copy.deepcopy(variants)),
        **records,
    )
    runs = case.runs()  # validate every variant now, so no run starts on a bad file
    labels = [r.label for r in runs]
    if len(set(labels)) != len(labels):
        raise CaseError(f"{where}: variant labels must be unique; got {_r(labels)}")
    folders: dict[str, int] = {}
    for i, label in enumerate(labels):  # each run writes vtk/<folder>/: two labels must not share one
        j = folders.setdefault(label_folder(label), i)
        if j != i:
            raise CaseError(f"{where}: variant[{i}].label = {_r(label)} and variant[{j}].label = {_r(labels[j])} "
                            f"both name the run folder {_r(label_folder(label))}; allowed: labels that differ in "
                            "their ASCII letters, digits, '-', '_' or '.' (other characters become '_')")
    for i, run in enumerate(runs):
        given = set(raw.get("geometry", {})) | set((variants[i] if variants else {}).get("geometry", {}))
        _check_used_geometry(run, given, f"{where}: variant[{i}]" if variants else where)
    _check_predictions(case, runs, where)
    _check_bands(case, runs, where)
    return case


def _read_toml(p: Path, given: str, known: str) -> dict:
    """Read and parse a case file: one line for a folder, a missing file, a file too large, bytes that are not
    UTF-8 (with the byte offset) or TOML nested too deeply. A UTF-8 byte-order mark is accepted."""
    where = _r(p.name)[1:-1]
    if p.is_dir():
        raise CaseError(f"{_r(given)}: is a folder, not a case file; allowed: a .toml file or a case name ({known})")
    try:
        found = p.is_file()
        size = p.stat().st_size if found else 0
        if size > MAX_FILE_BYTES:
            raise CaseError(f"{where}: the case file has {size} bytes; allowed: at most {MAX_FILE_BYTES} bytes")
        data = p.read_bytes() if found else b""
    except OSError as exc:
        raise CaseError(f"{_r(given)}: cannot read the case file: {_r(exc.strerror or str(exc))[1:-1]}") from None
    if not found:
        raise CaseError(f"{_r(given)}: no such case file; known cases: {known}")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise CaseError(f"{where}: the case file is not UTF-8 text: byte 0x{data[exc.start]:02x} at byte offset "
                        f"{exc.start}; allowed: a UTF-8 text file") from None
    text = text.removeprefix("\ufeff")  # a byte-order mark (some editors write one): accepted
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise CaseError(f"{where}: malformed TOML: {_r(str(exc).splitlines()[0])[1:-1]}") from None
    except RecursionError:
        raise CaseError(f"{where}: malformed TOML: arrays or tables nested too deeply; allowed: a case file "
                        "(its deepest nesting is 3)") from None
    return raw


def _parse_bands(raw: Any, where: str) -> dict[str, tuple[str, ...]]:
    """``[bands]``: ``contain_theory`` / ``exclude_alt`` = lists of budget quantities (see BAND_KINDS)."""
    if not isinstance(raw, dict):
        raise CaseError(f"{where}: bands must be a table; allowed keys: {', '.join(BAND_KINDS)}")
    out = {}
    for key, value in raw.items():
        if key not in BAND_KINDS:
            raise CaseError(f"{where}: bands.{_r(key)[1:-1]} is an unknown key; allowed keys: {', '.join(BAND_KINDS)}")
        if (not isinstance(value, list) or not value or any(not isinstance(v, str) for v in value)
                or len(set(value)) != len(value)):
            raise CaseError(f"{where}: bands.{key} = {_r(value)} is not allowed; allowed: a non-empty list of "
                            "distinct budget quantity names")
        out[key] = tuple(value)
    return out


def _check_bands(case: Case, runs: tuple[Run, ...], where: str) -> None:
    """Band checks need the error budget (budget_levels) and name quantities the scene's budget has."""
    if not case.bands:
        return
    if not case.discretisation.budget_levels:
        raise CaseError(f"{where}: bands need the error budget; allowed: [bands] together with "
                        "discretisation.budget_levels (three levels)")
    for run in runs:
        allowed = BAND_QUANTITIES.get(run.geometry.scene, ())
        for key, names in case.bands.items():
            for name in names:
                if re.sub(r"\[\d+\]$", "", name) not in allowed:
                    raise CaseError(f"{where}: bands.{key} = {_r(list(names))}: {_r(name)} is not a budget quantity "
                                    f"of the {run.geometry.scene} scene; allowed values: "
                                    f"{', '.join(repr(a) for a in allowed)} (concave: optionally name[k], patch k)")


# geometry fields each scene / indenter reads (a field given but not read is refused)
_GEOMETRY_USED = {
    ("block", "circle"): {"radius", "width_factor", "height_factor", "half_model", "far_field"},
    ("block", "parabola"): {"radius", "width_factor", "height_factor", "half_model", "far_field"},
    ("block", "wedge"): {"wedge_angle", "wedge_slope", "width_factor", "height_factor", "half_model",
                         "far_field"},
    ("concave", "particle"): {"design"},
}
# predictions each scene / indenter computes; "convective" also needs a small and a convective run
_PREDICTIONS = {
    ("block", "circle"): ("hertz", "convective"),
    ("block", "parabola"): ("hertz", "convective"),
    ("block", "wedge"): ("wedge", "convective"),
    ("concave", "particle"): ("hertz_superposition", "elliptical_fit"),
}


def _check_used_geometry(run: Run, given: set, where: str) -> None:
    g = run.geometry
    used = _GEOMETRY_USED.get((g.scene, g.indenter), set())
    for key in sorted(given - used - {"scene", "indenter"}):
        raise CaseError(f"{where}: geometry.{key} is not used by a {g.scene} scene with a {g.indenter} indenter; "
                        f"allowed keys: scene, indenter, {', '.join(sorted(used))}")


def _check_predictions(case: Case, runs: tuple[Run, ...], where: str) -> None:
    """Every listed prediction is one the scene computes for the indenter (an empty list: the scene's own)."""
    for run in runs:
        g = run.geometry
        allowed = _PREDICTIONS.get((g.scene, g.indenter), ())
        for name in case.analytic.predictions:
            if name not in allowed:
                raise CaseError(f"{where}: analytic.predictions = {_r(list(case.analytic.predictions))}: "
                                f"{_r(name)} is not computed for a {g.scene} scene with a {g.indenter} indenter; "
                                f"allowed values: {', '.join(repr(a) for a in allowed)}")
    if "convective" in case.analytic.predictions:
        kinematics = {r.solver.kinematics for r in runs}
        if not {"small", "convective"} <= kinematics:
            raise CaseError(f"{where}: analytic.predictions lists 'convective', which compares a small and a "
                            f"convective run; got kinematics {sorted(kinematics)}; allowed: [[variant]] runs with "
                            "solver.kinematics = 'small' and 'convective' (finite runs may be added)")


def case_names() -> list[str]:
    """Names of the case files in ``cases/``."""
    return sorted(p.stem for p in CASE_DIR.glob("*.toml"))
