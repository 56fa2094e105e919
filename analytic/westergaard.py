"""Westergaard's periodic wavy contact: the exact multi-patch reference of the interacting-patch model.

A rigid surface with the gap g(x) = g0 (1 - cos(2 pi x / L)) (g0: the cosine amplitude, half the peak-to-peak
height, mm; L the wavelength, mm) is pressed on an elastic half-plane (composite plane-strain modulus E*, MPa)
with the mean pressure p_mean (MPa); one contact patch |x| < a per period, the patches interacting through the
half-plane. Conventions of :mod:`analytic.interacting_patches` (p >= 0 compressive, v into the half-plane).

Exact solution (Westergaard 1939; Johnson, Contact Mechanics, sec. 13.2):
    p(x) = 2 p_mean cos(pi x / L) sqrt(sin^2(pi a / L) - sin^2(pi x / L)) / sin^2(pi a / L)    (|x| < a)
    p_mean = p* sin^2(pi a / L),   p* = pi E* g0 / L   (full contact at p_mean = p*).
p* follows from full contact: v = const + g0 cos(2 pi x/L) needs the pressure p_mean + p1 cos(2 pi x/L), and a
half-plane answers p1 cos(k x) with the displacement (2 p1 / (E* k)) cos(k x), so p1 = E* k g0 / 2 = p*; the
exact p at a = L/2 is p_mean (1 + cos(2 pi x/L)), i.e. p1 = p_mean = p*.

Numerical solution (:func:`solve_wavy`, independent of the closed form). The periodic kernel: the images
sum_n 1/(x - s - n L) = (pi/L) cot(pi (x - s)/L), so the contact slope equation over one period is
    (2 / (pi E*)) (pi / L) PV int_{-a}^{a} p(s) cot(pi (x - s) / L) ds = g'(x)        (|x| < a).
With X = tan(pi x/L), S = tan(pi s/L): cot(alpha - beta) ds = (L/pi) [1/(X - S) + S/(1 + S^2)] dS, and the
second term integrates to zero for a symmetric p, so with Q(S) = p(s(S)) on |S| < A = tan(pi a/L):
    (2 / (pi E*)) PV int_{-A}^{A} Q(S) / (X - S) dS = g'(x(X)),     P_period = (L/pi) int Q(S) / (1 + S^2) dS,
the half-plane equation in S, solved by the bounded Gauss-Chebyshev series of :mod:`analytic.chebyshev_kernels`
(Q = sqrt(1 - t^2) sum alpha_n U_n(t), S = A t, alpha_n = (E*/2) G_{n+1}, G_m the Chebyshev coefficients of
g'(x(A t))), the load by Gauss-Chebyshev quadrature of the second kind, and a by brentq on the mean pressure.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy import optimize

from analytic.chebyshev_kernels import chebyshev_coefficients, gauss_chebyshev_nodes, series_pressure
from analytic.materials import validate_positive as _positive

__all__ = ["WavySolution", "exact_half_width", "exact_pressure", "full_contact_pressure", "solve_wavy"]


def full_contact_pressure(*, g0: float, L: float, E_star: float) -> float:
    """p* = pi E* g0 / L (MPa): the mean pressure that closes the gap completely."""
    return math.pi * E_star * g0 / L


def exact_half_width(*, p_mean: float, g0: float, L: float, E_star: float) -> float:
    """a = (L/pi) arcsin(sqrt(p_mean / p*)) (mm), 0 < p_mean < p*."""
    ratio = p_mean / full_contact_pressure(g0=g0, L=L, E_star=E_star)
    if not 0.0 < ratio < 1.0:
        raise ValueError(f"p_mean = {p_mean!r} out of range: need 0 < p_mean < p* = pi E* g0 / L (partial contact)")
    return L / math.pi * math.asin(math.sqrt(ratio))


def exact_pressure(x, *, a: float, p_mean: float, L: float) -> np.ndarray:
    """Westergaard's p(x) (MPa) in the period |x| <= L/2 (module docstring), 0 outside the patch."""
    x = np.asarray(x, dtype=float)
    sa2 = math.sin(math.pi * a / L) ** 2
    arg = np.maximum(sa2 - np.sin(np.pi * x / L) ** 2, 0.0)
    return np.where(np.abs(x) < a, 2.0 * p_mean * np.cos(np.pi * x / L) * np.sqrt(arg) / sa2, 0.0)


class WavySolution(NamedTuple):
    """Periodic-kernel solution: half-width a (mm), mean pressure (MPa), the series alpha in S = A t."""

    a: float
    p_mean: float
    L: float
    alpha: np.ndarray

    def pressure(self, x) -> np.ndarray:
        """p(x) (MPa) for |x| <= L/2."""
        x = np.asarray(x, dtype=float)
        A = math.tan(math.pi * self.a / self.L)
        t = np.tan(np.pi * x / self.L) / A
        return np.where(np.abs(x) < self.a, series_pressure(t, self.alpha), 0.0)


def _series(a: float, *, g0: float, L: float, E_star: float, n: int) -> tuple[np.ndarray, float]:
    """alpha and the mean pressure for the half-width a (the periodic slope equation, module docstring)."""
    A = math.tan(math.pi * a / L)
    _, t = gauss_chebyshev_nodes(n)
    x = L / math.pi * np.arctan(A * t)
    G = chebyshev_coefficients(n) @ (g0 * 2.0 * math.pi / L * np.sin(2.0 * math.pi * x / L))
    alpha = 0.5 * E_star * G[1:]
    m = 4 * n  # Gauss-Chebyshev (second kind) for int sqrt(1 - t^2) f(t) dt; f = sum alpha U / (1 + A^2 t^2)
    th = np.arange(1, m + 1) * math.pi / (m + 1)
    tq = np.cos(th)
    q = series_pressure(tq, alpha)  # = sqrt(1 - t^2) sum alpha U_n(t)
    load = L / math.pi * A * float(np.sum(math.pi / (m + 1) * np.sin(th) * q / (1.0 + (A * tq) ** 2)))
    return alpha, load / L


def solve_wavy(*, g0: float, L: float, E_star: float, p_mean: float, n_terms: int = 256) -> WavySolution:
    """Half-width and pressure of the wavy contact at the mean pressure p_mean, 0 < p_mean < p* (periodic kernel)."""
    g0 = _positive(g0, "g0", "mm")
    L = _positive(L, "L", "mm")
    E_star = _positive(E_star, "E_star", "MPa")
    p_mean = _positive(p_mean, "p_mean", "MPa")
    if not p_mean < full_contact_pressure(g0=g0, L=L, E_star=E_star):
        raise ValueError(f"p_mean = {p_mean!r} out of range: need p_mean < p* = pi E* g0 / L (partial contact)")
    n = int(n_terms)

    def excess(a: float) -> float:
        return _series(a, g0=g0, L=L, E_star=E_star, n=n)[1] - p_mean

    hi = 0.45 * L
    while excess(hi) < 0.0 and hi < 0.499 * L:
        hi = 0.5 * (hi + 0.5 * L)
    a = optimize.brentq(excess, 1e-6 * L, hi, xtol=1e-15 * L, rtol=4 * np.finfo(float).eps,
                        maxiter=500)
    alpha, pm = _series(a, g0=g0, L=L, E_star=E_star, n=n)
    return WavySolution(float(a), float(pm), L, alpha)
