"""Frictionless rigid wedge pressed into an elastic half-plane (2D, plane strain).

Classical solution (Johnson, Contact Mechanics, sec. 5.3; Ciavarella & Hills sec. 3 with beta = 0).
Units: mm, N, MPa; P per unit thickness (N/mm); pressure positive in compression.

Profile (initial gap) h(x) = m |x| with slope m > 0. For a wedge whose faces make the angle theta with
the flat surface (C&H's "external angle"), the true geometry has m = tan(theta); Ciavarella & Hills use
the small-angle slope m = theta. :func:`wedge_slope` converts, and every other function takes m.

Equations (bounded at both ends, b = contact half-width):
    p(x) = (E* m / pi) arccosh(b / |x|) = (E* m / pi) ln[(b + sqrt(b^2 - x^2)) / |x|],  |x| < b
    P    = integral of p = E* m b      (so b = P / (E* m))
The pressure has a logarithmic singularity at the apex x = 0.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from analytic.materials import validate_positive as _positive

__all__ = [
    "WedgeContact",
    "wedge",
    "wedge_half_width",
    "wedge_load_from_half_width",
    "wedge_moment_half_width",
    "wedge_pressure",
    "wedge_slope",
]

_CONVENTIONS = ("paper", "exact")


class WedgeContact(NamedTuple):
    """Classical wedge solution (mm, N/mm, MPa).

    Attributes:
        P: Load per unit thickness (N/mm).
        m: Face slope (dimensionless).
        E_star: Composite plane-strain modulus (MPa).
        half_width: b = P / (E* m) (mm).
        full_width: 2b (mm).
    """

    P: float
    m: float
    E_star: float
    half_width: float
    full_width: float


def wedge_slope(theta: float, *, convention: str) -> float:
    """Face slope m of a wedge with external angle theta (rad), 0 < theta < pi/2.

    Args:
        theta: Angle between a wedge face and the undeformed flat surface (rad).
        convention: ``"paper"``: m = theta (the small-angle slope of Ciavarella & Hills);
            ``"exact"``: m = tan(theta) (the true straight-faced wedge an FEM mesh sees).
    """
    theta = float(theta)
    if not (0.0 < theta < 0.5 * math.pi):
        raise ValueError(f"theta = {theta!r} out of range: need 0 < theta < pi/2 (rad)")
    if convention == "paper":
        return theta
    if convention == "exact":
        return math.tan(theta)
    raise ValueError(f"convention = {convention!r} out of range: need one of {_CONVENTIONS}")


def wedge_half_width(P: float, m: float, E_star: float) -> float:
    """Half-width b = P / (E* m) in mm."""
    return _positive(P, "P", "N/mm") / (_positive(E_star, "E_star", "MPa") * _positive(m, "m", "-"))


def wedge_load_from_half_width(b: float, m: float, E_star: float) -> float:
    """Load P = E* m b (N/mm) that gives half-width b (mm)."""
    return _positive(E_star, "E_star", "MPa") * _positive(m, "m", "-") * _positive(b, "b", "mm")


def wedge_moment_half_width(b: float) -> float:
    """sqrt(M2/M0) of the classical wedge pressure of half-width b (mm): b / sqrt(6).

    M0 = int p dx = pi b (E* m / pi) and M2 = int p x^2 dx = (pi b^3 / 6) (E* m / pi)
    (int_0^1 s^k arccosh(1/s) ds = pi/2, pi/12 for k = 0, 2), so M2/M0 = b^2 / 6; Hertz's is a^2 / 4.
    """
    return _positive(b, "b", "mm") / math.sqrt(6.0)


def wedge(P: float, m: float, E_star: float) -> WedgeContact:
    """Classical wedge contact for load P (N/mm), face slope m and composite modulus E* (MPa)."""
    b = wedge_half_width(P, m, E_star)
    return WedgeContact(P=float(P), m=float(m), E_star=float(E_star), half_width=b, full_width=2.0 * b)


def wedge_pressure(x: Any, *, b: float, m: float, E_star: float, xp: Any = np) -> Any:
    """Classical wedge pressure p(x) = (E* m/pi) ln[(b + sqrt(b^2 - x^2))/|x|] (MPa), 0 for |x| >= b.

    Written once for numpy and UFL (``xp=ufl``); the clips are conditional-free
    (``xp.maximum`` / ``ufl.max_value``). At the apex x = 0 the value is +inf (log singularity): numpy
    callers get ``inf``; UFL callers must integrate with a quadrature that has no point at x = 0.
    """
    clip = getattr(xp, "max_value", None) or xp.maximum
    ax = abs(x)
    root = xp.sqrt(clip(b * b - x * x, 0.0))
    with np.errstate(divide="ignore"):
        return (E_star * m / math.pi) * clip(xp.log((b + root) / ax), 0.0)
