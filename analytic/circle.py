"""Frictionless contact of a rigid EXACT circle on an elastic half-plane (no parabolic approximation).

Hertz replaces the cylinder's gap ``h(x) = R - sqrt(R^2 - x^2)`` by the parabola ``x^2 / (2R)``. Half-plane
theory (Muskhelishvili; Johnson, Contact Mechanics, ch. 5) solves the exact profile just as well. Conventions as
in :mod:`analytic.convective` (beta = 0): pressure p >= 0 compressive, load P = int p > 0 (N/mm), plane strain
modulus E* (MPa), composite compliance A = 2/E*, half-width b (mm), lengths in mm.

Equations (the classical problem, bounded at both ends of the contact |x| < b):
    h'(x) = (1/pi) PV int_{-b}^{b} A p(xi) / (x - xi) dxi,      h'(x) = x / sqrt(R^2 - x^2).
Load (Shtaerman):  P = (1/A) int_{-b}^{b} t h'(t) / sqrt(b^2 - t^2) dt = E* R [K(k) - E(k)],  k = b/R,
with K, E the complete elliptic integrals of modulus k (scipy's parameter m = k^2). For k -> 0,
K - E = (pi/4) k^2 (1 + 3 k^2 / 8 + ...), which gives Hertz, P = pi E* b^2 / (4 R), and the first correction:
at a given load the exact circle's half-width is SMALLER than Hertz's, by about 3 k^2 / 16 relative.
Pressure: with x = b cos(theta) and h'(b cos theta) = sum_k a_k T_k (Chebyshev series, DCT at Gauss-Chebyshev
nodes), the bounded inversion is exact term by term, A p(b cos theta) = sum_k a_k sin(k theta), and
P = (pi/2) b a_1 / A. h' is analytic on [-b, b] for b < R, so the series converges geometrically.
Dissimilar materials enter through E* alone here (beta = 0); the exact circle at any Dundurs beta (convective)
is :func:`analytic.halfplane.solve_halfplane` with ``profile("circle", R=R)``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy import fft, optimize, special

from analytic.materials import validate_positive as _positive

__all__ = ["CircleContact", "circle_load", "circle_half_width", "circle_contact", "circle_pressure", "N_CHEBYSHEV"]

# Chebyshev terms of h'(b s): the series of x / sqrt(R^2 - x^2) on |x| <= b decays like (k / (1 + sqrt(1 - k^2)))^n;
# 256 terms reach round-off for b/R <= 0.9 (measured: p0 changes < 1e-14 from 256 to 4096 terms at b/R = 0.17).
N_CHEBYSHEV = 256


class CircleContact(NamedTuple):
    """Exact-circle half-plane contact (mm, MPa, N/mm): load, half-width b, peak pressure p0 at x = 0, radius."""

    P: float
    half_width: float
    p0: float
    R: float


def circle_load(b: float, R: float, E_star: float) -> float:
    """Load per unit thickness (N/mm) that opens the half-width b < R: ``P = E* R [K(b/R) - E(b/R)]``."""
    _positive(b, "b", "mm")
    _positive(R, "R", "mm")
    _positive(E_star, "E_star", "MPa")
    if not b < R:
        raise ValueError(f"b = {b!r} out of range: the exact circle needs 0 < b < R = {R} (mm)")
    m = (b / R) ** 2
    return float(E_star * R * (special.ellipk(m) - special.ellipe(m)))


def _coefficients(b: float, R: float, n: int) -> np.ndarray:
    """Chebyshev coefficients a_k of h'(b s) = b s / sqrt(R^2 - b^2 s^2) (DCT-II at Gauss-Chebyshev nodes)."""
    s = np.cos((np.arange(n) + 0.5) * np.pi / n)
    a = fft.dct(b * s / np.sqrt(R * R - (b * s) ** 2), type=2) / n
    a[0] *= 0.5
    return a


def circle_pressure(x, *, b: float, R: float, E_star: float, n: int = N_CHEBYSHEV) -> np.ndarray:
    """Contact pressure p(x) (MPa) of the exact circle with half-width b (mm); 0 outside |x| < b."""
    x = np.asarray(x, dtype=float)
    a = _coefficients(b, R, n)
    u = np.clip(x / b, -1.0, 1.0)
    theta = np.arccos(u)
    k = np.arange(n)
    p = (np.sin(np.multiply.outer(theta, k)) @ a) * (0.5 * E_star)  # A p = sum a_k sin(k theta), A = 2/E*
    return np.where(np.abs(x) < b, np.maximum(p, 0.0), 0.0)


def circle_half_width(P: float, R: float, E_star: float) -> float:
    """Half-width b (mm) of the exact circle under the load P (N/mm): the root of ``circle_load(b) = P``."""
    _positive(P, "P", "N/mm")
    _positive(R, "R", "mm")
    _positive(E_star, "E_star", "MPa")
    P_max = circle_load(R * (1.0 - 1e-12), R, E_star)
    if not P < P_max:
        raise ValueError(f"P = {P!r} out of range: the exact circle on a half-plane carries P < {P_max:.6g} N/mm "
                         f"(b -> R) for R = {R} mm, E* = {E_star} MPa")
    b_hertz = math.sqrt(4.0 * P * R / (math.pi * E_star))
    hi = min(R * (1.0 - 1e-12), 1.5 * b_hertz)
    return float(optimize.brentq(lambda t: circle_load(t, R, E_star) - P, 1e-9 * b_hertz, hi, xtol=1e-15 * R,
                                 rtol=1e-15))


def circle_contact(P: float, R: float, E_star: float) -> CircleContact:
    """Half-width and peak pressure of the exact circle under the load P (N/mm)."""
    b = circle_half_width(P, R, E_star)
    p0 = float(circle_pressure(np.array([0.0]), b=b, R=R, E_star=E_star)[0])
    return CircleContact(float(P), b, p0, float(R))
