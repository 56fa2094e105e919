"""Frictionless contact of a symmetric profile on an elastic half-plane, any smooth profile, at a given load.

Two materials: the indenter (body 1, carries the profile, rigid or elastic) on the flat block (body 2) enter only
through the composite modulus E* and Dundurs' beta (:func:`analytic.materials.bimaterial`, which states the sign
convention); beta of either sign, -1/2 <= beta <= 1/2. The classical (beta = 0) half-width depends on E* alone.

Classical (beta = 0) and convective (Ciavarella-Hills, beta != 0) theory for the profiles ``circle`` (the exact
gap h = R - sqrt(R^2 - x^2), not Hertz's parabola), ``parabola`` (h = x^2/(2R): Hertz) and ``wedge`` (h = m|x|).
Conventions as in :mod:`analytic.convective`: pressure p >= 0 compressive, load P = int p > 0 (N/mm), plane-strain
modulus E* (MPa), composite compliance A = 2/E*, half-width b (mm) in material coordinates of the flat body, the
load FIXED.

Equations (bounded at both ends of |x| < b):
    (1/A) H'(x) = (1/pi) PV int_{-b}^{b} p(xi) / (x - xi) dxi,
    H'(X) = h'(X - g(X)) (1 + beta A p(X)),   g(X) = -beta A int_0^X p      (H = h for beta = 0).
Method 1 (:func:`solve_halfplane`, spectral): with X = b s, s = cos(theta), the Chebyshev coefficients a_k of
H'(b s) (DCT-II at N Gauss-Chebyshev nodes) give A p(b cos theta) = sum_k a_k sin(k theta) exactly term by term
and the load P = (pi/2) b a_1 / A; b is the root of that load equation (brentq). For beta != 0 the pressure's
shape (A p and its integral as functions of s) is iterated to a fixed point, b re-found at each iteration; for
the wedge and the power profiles this is :func:`analytic.convective.solve`'s self-similar iteration.
Moments: int x^2 p / int p = (b^2/4) (1 + a_3/a_1), so the moment half-width 2 sqrt(M2/M0) = b sqrt(1 + a_3/a_1)
(= b for Hertz, 2b/sqrt(6) for the wedge).
Method 2 (:func:`classical_by_quadrature`, beta = 0 only, independent of method 1): adaptive Gauss-Kronrod
(scipy quad) of the Shtaerman load P = (2b/A) int_0^{pi/2} h'(b sin u) sin u du and of the bounded inversion with
the Cauchy singularity subtracted (PV int_{-b}^{b} dt / (sqrt(b^2 - t^2)(t - x)) = 0 for |x| < b):
    p(x) = sqrt(b^2 - x^2) / (pi A) int_{-pi/2}^{pi/2} [h'(b sin u) - h'(x)] / (b sin u - x) du.
Closed forms it reduces to: parabola -> Hertz (b = sqrt(4PR/(pi E*)), p0 = 2P/(pi b)); wedge -> b = P/(E* m);
circle -> P = E* R [K(b/R) - E(b/R)] (:mod:`analytic.circle`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy import optimize

from analytic.convective import _check_beta, _coeffs, _cumulative, _nodes, _sine_series
from analytic.materials import validate_positive as _positive

__all__ = ["HalfPlaneContact", "Profile", "PROFILES", "N_NODES", "classical_by_quadrature", "profile",
           "solve_halfplane", "spectral_load"]

PROFILES = ("circle", "parabola", "wedge")
# Gauss-Chebyshev nodes: the circle's and parabola's series converge geometrically (round-off by N = 256 for
# b/R <= 0.9); the wedge's sign(x) slope converges like N^-2 in b (analytic.convective.self_convergence).
N_NODES = 4096


class Profile(NamedTuple):
    """A rigid symmetric indenter profile: ``kind`` in :data:`PROFILES`, radius R (mm) or face slope m."""

    kind: str
    R: float | None = None
    m: float | None = None

    def slope(self, x: np.ndarray) -> np.ndarray:
        """Gap slope h'(x) (dimensionless) at x (mm); the circle needs |x| < R."""
        x = np.asarray(x, dtype=float)
        if self.kind == "circle":
            return x / np.sqrt(self.R * self.R - x * x)
        if self.kind == "parabola":
            return x / self.R
        return self.m * np.sign(x)

    @property
    def label(self) -> str:
        return f"wedge m={self.m:.6g}" if self.kind == "wedge" else f"{self.kind} R={self.R:.6g}"


def profile(kind: str, *, R: float | None = None, m: float | None = None) -> Profile:
    """A checked :class:`Profile` (ValueError, one line naming the field and its range)."""
    if kind not in PROFILES:
        raise ValueError(f"profile = {kind!r} out of range: need one of {PROFILES}")
    if kind == "wedge":
        if m is None:
            raise ValueError("m = None out of range: the wedge needs a face slope 0 < m")
        return Profile(kind, m=_positive(m, "m", "-"))
    if R is None:
        raise ValueError(f"R = None out of range: the {kind} needs a radius R > 0 (mm)")
    return Profile(kind, R=_positive(R, "R", "mm"))


class HalfPlaneContact(NamedTuple):
    """The half-plane solution at load P (mm, MPa, N/mm).

    Attributes:
        profile, P, E_star, beta: The problem.
        half_width: b (mm, material coordinates).
        p_max: Peak pressure (MPa); ``inf`` for the wedge (log-singular apex).
        moment_half_width: 2 sqrt(M2/M0) of the pressure (mm).
        b_classical: The beta = 0 half-width at the same load (mm), so b/b0 = half_width / b_classical.
        n_nodes, iterations: Gauss-Chebyshev nodes; fixed-point iterations (0 for beta = 0).
        coefficients: a_k of A p(b cos theta) = sum a_k sin(k theta) (k = 0 .. N-1).
    """

    profile: Profile
    P: float
    E_star: float
    beta: float
    half_width: float
    p_max: float
    moment_half_width: float
    b_classical: float
    n_nodes: int
    iterations: int
    coefficients: np.ndarray

    def pressure(self, x) -> np.ndarray:
        """p(x) (MPa) at material abscissa x (mm); 0 outside |x| < b."""
        x = np.asarray(x, dtype=float)
        b = self.half_width
        theta = np.arccos(np.clip(x / b, -1.0, 1.0))
        k = np.arange(self.coefficients.size)
        w = np.sin(np.multiply.outer(theta, k)) @ self.coefficients
        return np.where(np.abs(x) < b, np.maximum(w, 0.0) * 0.5 * self.E_star, 0.0)


def _limit(prof: Profile) -> float:
    """Largest admissible half-width (mm): b < R for the circle, unbounded otherwise."""
    return prof.R * (1.0 - 1e-12) if prof.kind == "circle" else math.inf


def spectral_load(prof: Profile, b: float, *, E_star: float, n_nodes: int = N_NODES) -> float:
    """Classical load (N/mm) that opens the half-width b, by the Chebyshev a_1 of h'(b s): P = (pi/2) b a_1 / A."""
    _, s = _nodes(int(n_nodes))
    return 0.25 * math.pi * b * E_star * float(_coeffs(prof.slope(b * s))[1])


def _root_b(load, P: float, guess: float, upper: float) -> float:
    """The half-width b with load(b) = P (load increasing in b), bracketed geometrically around ``guess``."""
    lo = hi = min(guess, upper)
    while load(lo) > P:
        lo *= 0.5
    while load(hi) < P:
        if hi >= upper:
            raise ValueError(f"P = {P!r} out of range: the profile cannot carry it on a half-plane "
                             f"(the half-width reaches its limit {upper:.6g} mm)")
        hi = min(2.0 * hi, upper)
    if lo == hi:
        return hi
    return optimize.brentq(lambda b: load(b) - P, lo, hi, xtol=1e-300, rtol=4 * np.finfo(float).eps, maxiter=500)


def _guess(prof: Profile, P: float, E_star: float) -> float:
    if prof.kind == "wedge":
        return P / (E_star * prof.m)
    return min(math.sqrt(4.0 * P * prof.R / (math.pi * E_star)), 0.5 * prof.R)


def solve_halfplane(prof: Profile, *, P: float, E_star: float, beta: float = 0.0, n_nodes: int = N_NODES,
                    tol: float = 1e-14, max_iter: int = 200) -> HalfPlaneContact:
    """Half-width, peak pressure and pressure series at the load P (spectral method 1, see the module).

    Args:
        prof: From :func:`profile`.
        P: Load per unit thickness (N/mm), > 0.
        E_star: Composite plane-strain modulus (MPa), 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 (rigid indenter:
            E2/(1 - nu2^2)); :func:`analytic.materials.bimaterial` gives it with beta.
        beta: Dundurs beta, -0.5 <= beta <= 0.5, either sign (rigid indenter: -(1 - 2 nu)/(2 (1 - nu)) <= 0);
            0: classical.
        n_nodes: Gauss-Chebyshev nodes (even, >= 64).
        tol, max_iter: Fixed-point stop (relative change of b) and cap (RuntimeError beyond).

    Raises:
        ValueError: a bad value (one line), or a load the exact circle cannot carry (b -> R).
    """
    _positive(P, "P", "N/mm")
    _positive(E_star, "E_star", "MPa")
    beta = _check_beta(beta)
    N = int(n_nodes)
    if N < 64 or N % 2:
        raise ValueError(f"n_nodes = {n_nodes!r} out of range: need an even integer >= 64")
    theta, s = _nodes(N)
    A = 2.0 / E_star
    upper = _limit(prof)

    def classical_load(b: float) -> float:
        return 0.5 * math.pi * b * float(_coeffs(prof.slope(b * s))[1]) / A

    b0 = _root_b(classical_load, P, _guess(prof, P, E_star), upper)
    if beta != 0.0 and prof.kind == "parabola" and not b0 < prof.R:  # as convective.parabola_profile: 0 < b0/R < 1
        raise ValueError(f"P = {P!r} out of range: the convective parabola needs a classical half-width b0 < R "
                         f"(b0/R = {b0 / prof.R:.6g} at this P, E* = {E_star:.6g} MPa, R = {prof.R:.6g} mm)")
    a = _coeffs(prof.slope(b0 * s))
    b, its = b0, 0
    if beta != 0.0:
        change = math.inf
        for its in range(1, max_iter + 1):  # noqa: B007  (its is reported)
            w, W = _sine_series(a), _cumulative(a, theta)
            shift, factor = s + beta * W, 1.0 + beta * w

            def load(bb: float, shift=shift, factor=factor) -> float:
                return 0.5 * math.pi * bb * float(_coeffs(prof.slope(bb * shift) * factor)[1]) / A

            b_new = _root_b(load, P, b, upper)
            a = _coeffs(prof.slope(b_new * shift) * factor)
            change, b = abs(b_new - b) / b, b_new
            if change < tol:
                break
        else:
            raise RuntimeError(f"convective iteration did not converge in {max_iter} iterations "
                               f"(last relative change {change:.3g})")
    a = a.copy()
    a[0] = 0.0
    if prof.kind == "wedge":
        p_max = math.inf
    else:
        p_max = 0.5 * E_star * _series_max(a, theta)
    moment = b * math.sqrt(1.0 + a[3] / a[1])
    if prof.kind == "wedge":  # self-similar: rescale so that b0 is the closed form P/(E* m), b/b0 unchanged
        scale = P / (E_star * prof.m) / b0
        b, b0, moment = b * scale, b0 * scale, moment * scale
    return HalfPlaneContact(prof, float(P), float(E_star), beta, float(b), float(p_max), float(moment), float(b0),
                            N, its, a)


def _series_max(a: np.ndarray, theta: np.ndarray) -> float:
    """max over theta of sum_k a_k sin(k theta): the centre (theta = pi/2), or the largest node refined by a bounded
    scalar search between its neighbours (a wide circle peaks off the centre, towards its edges)."""
    k = np.arange(a.size)

    def w(t: float) -> float:
        return float(np.sum(a * np.sin(k * t)))

    j = int(np.argmax(_sine_series(a)))
    lo, hi = theta[max(j - 1, 0)], theta[min(j + 1, theta.size - 1)]
    best = optimize.minimize_scalar(lambda t: -w(t), bounds=(lo, hi), method="bounded",
                                    options={"xatol": 1e-14}).fun
    return max(w(0.5 * math.pi), -float(best))


class QuadratureSolution(NamedTuple):
    """Classical solution by method 2 (adaptive quadrature): half-width b (mm), p(0) (MPa), the pressure at x."""

    half_width: float
    p_centre: float
    x: np.ndarray
    p: np.ndarray


def _quad(f, lo: float, hi: float) -> float:
    from scipy import integrate  # imported here: a run that never integrates skips its ~20 ms import

    return integrate.quad(f, lo, hi, epsabs=0.0, epsrel=1e-12, limit=400)[0]


def classical_by_quadrature(prof: Profile, *, P: float, E_star: float, x=()) -> QuadratureSolution:
    """Method 2 (beta = 0): b from the Shtaerman load integral and p(x) from the singularity-subtracted inversion,
    both by adaptive Gauss-Kronrod quadrature (no Chebyshev series, no elliptic integrals)."""
    _positive(P, "P", "N/mm")
    _positive(E_star, "E_star", "MPa")
    A = 2.0 / E_star

    def load(b: float) -> float:
        return 2.0 * b / A * _quad(lambda u: float(prof.slope(b * math.sin(u))) * math.sin(u), 0.0, 0.5 * math.pi)

    b = _root_b(load, P, _guess(prof, P, E_star), _limit(prof))

    def p_at(xv: float) -> float:
        if abs(xv) >= b:
            return 0.0
        hx = float(prof.slope(xv))

        def f(u: float) -> float:
            t = b * math.sin(u)
            return 0.0 if t == xv else (float(prof.slope(t)) - hx) / (t - xv)

        u0 = math.asin(xv / b)
        val = _quad(f, -0.5 * math.pi, u0) + _quad(f, u0, 0.5 * math.pi)
        return math.sqrt(b * b - xv * xv) / (math.pi * A) * val

    xs = np.asarray(x, dtype=float).reshape(-1)
    centre = math.inf if prof.kind == "wedge" else p_at(0.0)
    return QuadratureSolution(float(b), centre, xs, np.array([p_at(v) for v in xs]))
