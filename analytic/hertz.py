"""Hertz line contact (2D, plane strain): two parallel cylinders, or a cylinder on a half-plane.

2D formulas ONLY (never the sphere ones). Units: mm, N, MPa; P is a load per unit thickness (N/mm).
Pressure is positive in compression.

Equations (Johnson, Contact Mechanics, sec. 4.2; eqs. (3)-(7) of the close-to-conformal paper):
    relative radius      1/R = 1/R1 + 1/R2            (a concave radius is negative)
    half-width           a = sqrt(4 P R / (pi E*))     (paper eq. 5)
    peak pressure        p0 = 2 P / (pi a) = E* a / (2 R)   (paper eq. 4)
    pressure             p(x) = p0 sqrt(1 - (x - c)^2 / a^2) for |x - c| < a, 0 outside (paper eq. 3)

The paper quotes *full* patch widths 2a ("contact patch size"); the functions here name half and full
widths explicitly (``half_width`` = a, ``full_width`` = 2a).
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from analytic.materials import validate_positive as _positive

__all__ = [
    "HertzContact",
    "hertz",
    "hertz_half_width",
    "hertz_load_from_half_width",
    "hertz_peak_pressure",
    "hertz_pressure",
    "load_from_half_width",
    "patch_width_eq4",
    "patch_width_eq5",
    "relative_radius",
    "PaperRadii",
    "Table1Row",
    "PAPER_E_STAR",
    "PAPER_RADII",
    "TABLE1",
    "Eq5Width",
    "Table1Patch",
    "table1_patch_sizes",
]


class HertzContact(NamedTuple):
    """Hertz line-contact solution (mm, N/mm, MPa).

    Attributes:
        P: Load per unit thickness (N/mm).
        R: Relative radius of curvature (mm).
        E_star: Composite plane-strain modulus (MPa).
        half_width: a (mm).
        full_width: 2a (mm), the paper's "contact patch size".
        p0: Peak pressure (MPa).
    """

    P: float
    R: float
    E_star: float
    half_width: float
    full_width: float
    p0: float


def relative_radius(R1: float, R2: float = math.inf) -> float:
    """Relative radius R from 1/R = 1/R1 + 1/R2 (mm); a concave radius is negative, inf = flat.

    Raises:
        ValueError: if 1/R1 + 1/R2 <= 0 (no convex contact: flat-on-flat, or the concave surface is
            more curved than the convex one).
    """
    R1, R2 = float(R1), float(R2)
    if R1 == 0.0 or R2 == 0.0 or math.isnan(R1) or math.isnan(R2):
        raise ValueError(f"R1, R2 = {R1!r}, {R2!r} out of range: need nonzero radii (mm)")
    curvature = 1.0 / R1 + 1.0 / R2
    if not curvature > 0.0:
        raise ValueError(
            f"R1, R2 = {R1!r}, {R2!r} out of range: need 1/R1 + 1/R2 > 0 (a convex contact; concave radius < 0)"
        )
    return 1.0 / curvature


def hertz_half_width(P: float, R: float, E_star: float) -> float:
    """Half-width a = sqrt(4 P R / (pi E*)) in mm (paper eq. 5)."""
    P = _positive(P, "P", "N/mm")
    R = _positive(R, "R", "mm")
    E_star = _positive(E_star, "E_star", "MPa")
    return math.sqrt(4.0 * P * R / (math.pi * E_star))


def hertz_load_from_half_width(a: float, R: float, E_star: float) -> float:
    """Load per unit thickness P = pi E* a^2 / (4 R) (N/mm) that gives half-width a (inverse of eq. 5)."""
    a = _positive(a, "a", "mm")
    R = _positive(R, "R", "mm")
    E_star = _positive(E_star, "E_star", "MPa")
    return math.pi * E_star * a * a / (4.0 * R)


load_from_half_width = hertz_load_from_half_width


def hertz_peak_pressure(P: float, a: float) -> float:
    """Peak pressure p0 = 2 P / (pi a) in MPa (paper eq. 4)."""
    return 2.0 * _positive(P, "P", "N/mm") / (math.pi * _positive(a, "a", "mm"))


def hertz(P: float, R: float, E_star: float) -> HertzContact:
    """Hertz line contact for load P (N/mm), relative radius R (mm) and composite modulus E* (MPa)."""
    a = hertz_half_width(P, R, E_star)
    return HertzContact(
        P=float(P),
        R=float(R),
        E_star=float(E_star),
        half_width=a,
        full_width=2.0 * a,
        p0=hertz_peak_pressure(P, a),
    )


def hertz_pressure(x: Any, *, a: float, p0: float, center: float = 0.0, xp: Any = np) -> Any:
    """Hertz pressure p(x) = p0 sqrt(max(1 - (x - c)^2/a^2, 0)) (MPa, compression positive).

    Written once for numpy and UFL: ``xp`` is the math module (``numpy`` default, or ``ufl``). The clip
    to zero outside the patch is conditional-free: ``xp.maximum`` for numpy, ``ufl.max_value`` for UFL,
    so the FEM error integral and the report use this same line.

    Args:
        x: Coordinate(s) in mm (array, scalar, or UFL expression).
        a: Half-width (mm).
        p0: Peak pressure (MPa).
        center: Patch centre c (mm).
        xp: Math module providing ``sqrt`` and ``maximum`` (numpy) or ``max_value`` (ufl).
    """
    xi = (x - center) / a
    arg = 1.0 - xi * xi
    clip = getattr(xp, "max_value", None) or xp.maximum
    return p0 * xp.sqrt(clip(arg, 0.0))


def patch_width_eq4(P: float, p0: float) -> float:
    """Full patch width 2a = 4 P / (pi p0) (mm) of the ellipse with load P (N/mm) and peak p0 (MPa), eq. (4)."""
    return 4.0 * _positive(P, "P", "N/mm") / (math.pi * _positive(p0, "p0", "MPa"))


def patch_width_eq5(P: float, R: float, E_star: float) -> float:
    """Full patch width 2a = 2 sqrt(4 P R / (pi E*)) (mm) from load, relative radius and E*, eq. (5)."""
    return 2.0 * hertz_half_width(P, R, E_star)


# --- data of the close-to-conformal paper -------------------------------------------------------------


class Table1Row(NamedTuple):
    """One row of Table 1 of the close-to-conformal paper (mm, N/mm, MPa).

    Attributes:
        config: ``"symmetrical"`` or ``"close_to_conformal"``.
        d: Prescribed displacement of the convex particle (mm).
        delta: Indentation, the distance between the points of the plausible LCP solution (mm).
        P: Load per unit thickness (N/mm), the integral of the FEA pressure.
        p0: Maximum FEA pressure (MPa).
    """

    config: str
    d: float
    delta: float
    P: float
    p0: float


TABLE1: tuple[Table1Row, ...] = (
    Table1Row("symmetrical", 0.60, 0.086, 5106.0, 8361.0),
    Table1Row("symmetrical", 0.80, 0.27, 17693.0, 15444.0),
    Table1Row("symmetrical", 1.00, 0.46, 31393.0, 20620.0),
    Table1Row("close_to_conformal", 0.46, 0.00043, 208.0, 578.0),
    Table1Row("close_to_conformal", 0.47, 0.010, 979.0, 1143.0),
    Table1Row("close_to_conformal", 0.48, 0.020, 1862.0, 1518.0),
    Table1Row("close_to_conformal", 0.50, 0.040, 3688.0, 2179.0),
    Table1Row("close_to_conformal", 0.70, 0.24, 23560.0, 7569.0),
    Table1Row("close_to_conformal", 1.00, 0.54, 55625.0, 13879.0),
)
"""Table 1 of the close-to-conformal paper, verbatim."""

PAPER_E_STAR = 235000.0
"""E* the paper quotes (MPa): E = 214 GPa, nu = 0.3, rigid particle -> 214000/(1 - 0.09) = 235165 MPa."""


class PaperRadii(NamedTuple):
    """Radii quoted in the close-to-conformal paper for one contact pair (mm).

    Attributes:
        config: Table-1 configuration the pair belongs to.
        d: Displacement of the Table-1 row the radii were quoted for (mm).
        pair: ``"primary"`` (LCP solution) or ``"intersection"`` (leftmost curve intersection).
        R_convex: Convex (particle) radius, > 0.
        R_concave: Concave radius magnitude as printed (enters 1/R with a minus sign).
        R_printed: Relative radius the paper prints.
        width_printed: Full patch width 2a from eq. (5) the paper prints (mm).
    """

    config: str
    d: float
    pair: str
    R_convex: float
    R_concave: float
    R_printed: float
    width_printed: float

    @property
    def R_computed(self) -> float:
        """1/R = 1/R_convex - 1/R_concave (the concave radius is negative in eq. 7)."""
        return relative_radius(self.R_convex, -self.R_concave)


PAPER_RADII: tuple[PaperRadii, ...] = (
    PaperRadii("symmetrical", 0.60, "primary", 2.96, 6.81, 5.23, 0.76),
    PaperRadii("close_to_conformal", 0.46, "primary", 41.0, 50.0, 233.0, 1.02),
    PaperRadii("close_to_conformal", 0.46, "intersection", 23.0, 44.0, 50.0, 0.47),
)
"""Radii the paper quotes. 1/(1/2.96 - 1/6.81) = 5.236 (printed 5.23, agrees); 1/(1/41 - 1/50) = 227.8
(printed 233: does NOT follow); 1/(1/23 - 1/44) = 48.19 (printed 50: does NOT follow, a rounding at best)."""


class Eq5Width(NamedTuple):
    """Eq. (5) full patch width for one published radius pair of a Table-1 row (mm)."""

    pair: str
    R_printed: float
    R_computed: float
    width_eq5_R_printed: float
    width_eq5_R_computed: float
    width_printed: float


class Table1Patch(NamedTuple):
    """Patch sizes of one Table-1 row: eq. (4) from (P, p0); eq. (5) from (P, R, E*) where R is published.

    Attributes:
        row: The Table-1 row.
        width_eq4: Full width 2a = 4 P / (pi p0) (mm).
        eq5: One entry per published radius pair; empty tuple = "R not published".
    """

    row: Table1Row
    width_eq4: float
    eq5: tuple[Eq5Width, ...]


def table1_patch_sizes(*, E_star: float = PAPER_E_STAR) -> tuple[Table1Patch, ...]:
    """Eq. (4) and eq. (5) full patch widths 2a for every Table-1 row (eq. 5 only where R is published)."""
    out = []
    for row in TABLE1:
        eq5 = tuple(
            Eq5Width(
                pair=r.pair,
                R_printed=r.R_printed,
                R_computed=r.R_computed,
                width_eq5_R_printed=patch_width_eq5(row.P, r.R_printed, E_star),
                width_eq5_R_computed=patch_width_eq5(row.P, r.R_computed, E_star),
                width_printed=r.width_printed,
            )
            for r in PAPER_RADII
            if r.config == row.config and r.d == row.d
        )
        out.append(Table1Patch(row=row, width_eq4=patch_width_eq4(row.P, row.p0), eq5=eq5))
    return tuple(out)
