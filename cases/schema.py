"""Typed, frozen case records loaded from ``cases/<name>.toml``.

A case names its geometry, material, loading, discretisation, solver method, which analytic
predictions apply and the tolerances it must meet. Units: mm, N, MPa; loads are per unit thickness
(N/mm); angles are in radians.

Validation is strict: an unknown key, a wrong type, a missing required field or an out-of-range value
raises :class:`CaseError` whose message is ONE line naming the file, the field and the allowed range.
The command-line layer turns it into exit code 2 before anything is written.

A case may carry ``[[variant]]`` tables. Each variant overrides fields of the base case (same section
layout, e.g. ``[variant.solver] kinematics = "convective"``) and is run as its own FEM run; the case's
``metrics.json`` holds one entry per variant.
"""

from __future__ import annotations

import copy
import math
import tomllib
from dataclasses import MISSING, dataclass, field, fields, replace
from pathlib import Path
from typing import Any

__all__ = [
    "CASE_DIR",
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
    "load_case",
]

CASE_DIR = Path(__file__).resolve().parent

class CaseError(ValueError):
    """A case file is malformed or holds an out-of-range value (one-line message)."""


# --- records -----------------------------------------------------------------------------------


@dataclass(frozen=True)
class Material:
    """Linear elastic material of the deformable body (the indenter is rigid).

    Attributes:
        E: Young's modulus in MPa, E > 0.
        nu: Poisson's ratio, -1 < nu < 0.5. The FEM bulk model is plane strain.
    """

    E: float
    nu: float


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
    """

    degree: int = 2
    h_contact: float = 0.05
    growth: float = 1.3
    levels: tuple[float, ...] = ()
    ci_level: float | None = None


@dataclass(frozen=True)
class Solver:
    """Contact formulation and kinematics.

    Attributes:
        method: ``"nitsche"``, ``"penalty"`` or ``"augmented_lagrangian"`` (Uzawa updates of a nodal
            multiplier around the penalty Newton: the constraint holds exactly for any kappa0,
            :mod:`fem.methods.augmented_lagrangian`).
        kinematics: ``"small"`` (gap at the undeformed position, the Hertz hypothesis) or
            ``"convective"`` (obstacle evaluated at the current position X + u).
        traction: ``"halfplane"`` (vertical gap and traction, as half-plane theory assumes) or
            ``"obstacle"`` (gap and traction along the rigid curve's normal).
        kappa0: Dimensionless penalty factor, kappa = kappa0 E / h, > 0 (the augmentation stiffness of the
            augmented Lagrangian).
        gamma0: Dimensionless Nitsche factor, gamma = gamma0 E / h, > 0.
        theta: Nitsche variant: 1 (symmetric), 0 (skew-less), -1 (skew-symmetric).
    """

    method: str = "nitsche"
    kinematics: str = "small"
    traction: str = "halfplane"
    kappa0: float = 1.0e3
    gamma0: float = 10.0
    theta: int = 1


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
    ("loading", "control"): ("force", "displacement"),
    ("discretisation", "degree"): (1, 2),
    ("solver", "method"): ("nitsche", "penalty", "augmented_lagrangian"),
    ("solver", "kinematics"): ("small", "convective"),
    ("solver", "traction"): ("halfplane", "obstacle"),
    ("solver", "theta"): (1, 0, -1),
}
# (low, high, low_inclusive, high_inclusive, text)
_RANGES = {
    ("material", "E"): (0.0, math.inf, False, False, "E > 0 (MPa)"),
    ("material", "nu"): (-1.0, 0.5, False, False, "-1 < nu < 0.5"),
    ("geometry", "radius"): (0.0, math.inf, False, False, "radius > 0 (mm)"),
    ("geometry", "wedge_angle"): (0.0, math.pi / 2, False, False, "0 < wedge_angle < pi/2 (rad)"),
    ("geometry", "width_factor"): (10.0, math.inf, True, False, "width_factor >= 10"),
    ("geometry", "height_factor"): (10.0, math.inf, True, False, "height_factor >= 10"),
    ("loading", "P"): (0.0, math.inf, False, False, "P > 0 (N/mm)"),
    ("loading", "half_width"): (0.0, math.inf, False, False, "half_width > 0 (mm)"),
    ("loading", "steps"): (1, 1000, True, True, "1 <= steps <= 1000"),
    ("discretisation", "h_contact"): (0.0, 1.0, False, True, "0 < h_contact <= 1 (fraction of half-width)"),
    ("discretisation", "ci_level"): (0.0, 1.0, False, True, "0 < ci_level <= 1"),
    ("discretisation", "growth"): (1.05, 2.0, True, True, "1.05 <= growth <= 2"),
    ("solver", "kappa0"): (0.0, math.inf, False, False, "kappa0 > 0"),
    ("solver", "gamma0"): (0.0, math.inf, False, False, "gamma0 > 0"),
}
_SEQ_RANGES = {
    ("loading", "d"): (0.0, math.inf, False, False, "every d > 0 (mm)"),
    ("discretisation", "levels"): (0.0, 1.0, False, True, "every level in (0, 1]"),
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
            raise CaseError(f"{where} = {value!r} has the wrong type; expected a number")
        if not math.isfinite(value):
            raise CaseError(f"{where} = {value!r} must be a finite number")
        return float(value)
    if base == "int":
        if isinstance(value, bool) or not isinstance(value, int):
            raise CaseError(f"{where} = {value!r} has the wrong type; expected an integer")
        return value
    if base == "bool":
        if not isinstance(value, bool):
            raise CaseError(f"{where} = {value!r} has the wrong type; expected true or false")
        return value
    if base == "str":
        if not isinstance(value, str):
            raise CaseError(f"{where} = {value!r} has the wrong type; expected a string")
        return value
    if base == "tuple[float,...]":
        if not isinstance(value, list | tuple) or any(
            isinstance(v, bool) or not isinstance(v, int | float) for v in value
        ):
            raise CaseError(f"{where} = {value!r} has the wrong type; expected a list of numbers")
        return tuple(float(v) for v in value)
    if base == "tuple[str,...]":
        if not isinstance(value, list | tuple) or any(not isinstance(v, str) for v in value):
            raise CaseError(f"{where} = {value!r} has the wrong type; expected a list of strings")
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
            raise CaseError(f"{where}.{key} is an unknown key; allowed keys: {', '.join(known)}")
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
                raise CaseError(f"{where}.{name} = {value!r} is not allowed; allowed values: {allowed}")
            spec = _RANGES.get((section, name))
            if spec is not None and not _in_range(value, spec):
                raise CaseError(f"{where}.{name} = {value!r} is out of range; allowed: {spec[4]}")
            spec = _SEQ_RANGES.get((section, name))
            if spec is not None and not all(_in_range(v, spec) for v in value):
                raise CaseError(f"{where}.{name} = {list(value)!r} is out of range; allowed: {spec[4]}")
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
            raise CaseError(f"{where}: loading.d = {list(ld.d)!r} must be increasing")
        if ld.P is not None or ld.half_width is not None:
            raise CaseError(f"{where}: loading.P/half_width are only allowed with control = 'force'")


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
        raise CaseError(f"{where}: {field_} = {value!r} cannot be reached by a circle of radius {g.radius} mm "
                        f"(Hertz half-width {a:.4g} mm); allowed: half-width < radius/2 = {limit:.4g} mm")


def load_case(path: str | Path) -> Case:
    """Load and validate a case file.

    Args:
        path: A path to a TOML file, or a case name resolved as ``cases/<name>.toml``.

    Returns:
        The frozen :class:`Case` record.

    Raises:
        CaseError: One line naming the file, the field and the allowed range.
    """
    p = Path(path)
    if p.suffix != ".toml":
        p = CASE_DIR / f"{path}.toml"
    if not p.is_file():
        known = ", ".join(case_names()) or "none"
        raise CaseError(f"{path}: no such case file; known cases: {known}")
    try:
        raw = tomllib.loads(p.read_text())
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise CaseError(f"{p.name}: malformed TOML: {str(exc).splitlines()[0]}") from None
    where = p.name
    allowed_top = {"case", *_SECTIONS, "tolerances", "variant"}
    for key in raw:
        if key not in allowed_top:
            raise CaseError(f"{where}: {key} is an unknown key; allowed keys: {', '.join(sorted(allowed_top))}")
    head = raw.get("case", {})
    if not isinstance(head, dict):
        raise CaseError(f"{where}: case must be a table")
    for key in head:
        if key not in ("name", "description"):
            raise CaseError(f"{where}: case.{key} is an unknown key; allowed keys: name, description")
    name = head.get("name", p.stem)
    if not isinstance(name, str) or not name:
        raise CaseError(f"{where}: case.name must be a non-empty string")
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
            raise CaseError(f"{where}: tolerances.{key} is an unknown key; allowed keys: {', '.join(_TOLERANCE_KEYS)}")
        if isinstance(value, bool) or not isinstance(value, int | float) or not value > 0:
            raise CaseError(f"{where}: tolerances.{key} = {value!r} is out of range; allowed: a number > 0")
        tol[key] = float(value)
    variants = raw.get("variant", [])
    if not isinstance(variants, list) or any(not isinstance(v, dict) for v in variants):
        raise CaseError(f"{where}: variant must be an array of tables ([[variant]])")
    for i, var in enumerate(variants):
        for key, value in var.items():
            if key == "label":
                if not isinstance(value, str):
                    raise CaseError(f"{where}: variant[{i}].label must be a string")
            elif key not in _SECTIONS or key == "analytic":
                raise CaseError(
                    f"{where}: variant[{i}].{key} is an unknown key; allowed keys: label, "
                    + ", ".join(s for s in _SECTIONS if s != "analytic")
                )
            elif not isinstance(value, dict):
                raise CaseError(f"{where}: variant[{i}].{key} must be a table")
    case = Case(
        name=name,
        path=p,
        description=str(head.get("description", "")),
        tolerances=tol,
        variants=tuple(copy.deepcopy(variants)),
        **records,
    )
    case.runs()  # validate every variant now, so no run starts on a bad file
    return case


def case_names() -> list[str]:
    """Names of the case files in ``cases/``."""
    return sorted(p.stem for p in CASE_DIR.glob("*.toml"))
