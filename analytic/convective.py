"""Convective effect in frictionless plane contact of dissimilar materials (Ciavarella & Hills 1999).

Re-derived here; the PDF's equations are garbled. Conventions (different from the paper's signs):

* pressure p >= 0 in compression; load P = integral of p > 0 (the paper writes P = -int p, p <= 0);
* h(x) >= 0 is the initial gap of a symmetric convex indenter profile (the paper's h is minus this);
* A = 2/E* is the composite compliance (C&H eq. 2), beta the Dundurs constant (C&H eq. 6), both of ANY two
  materials (:func:`analytic.materials.bimaterial`: body 1 the indenter, body 2 the flat block, Gam = mu2/mu1);
  for a rigid indenter on a body with Poisson ratio nu2, beta = -(1 - 2 nu2)/(2 (1 - nu2)) (plane strain).
  beta takes either sign, -1/2 <= beta <= 1/2: beta < 0 (indenter the stiffer) widens the contact, b > b0;
  beta > 0 (block the stiffer) narrows it, b < b0; beta = 0 is the classical problem (e.g. identical materials);
* the load P is FIXED; b0 is the classical (beta = 0) half-width at that load; b is the half-width in
  material (undeformed) coordinates X of the flat elastic body.

Classical problem (C&H eq. 1), bounded at both ends:
    (1/A) h'(x) = (1/pi) PV int_{-b}^{b} p(xi) / (x - xi) dxi,   |x| < b.
Its bounded inversion and the load condition (Shtaerman) are
    p(x) = (1/(pi A)) sqrt(b^2 - x^2) PV int_{-b}^{b} h'(t) / (sqrt(b^2 - t^2) (t - x)) dt,
    P    = (1/A) int_{-b}^{b} t h'(t) / sqrt(b^2 - t^2) dt.

Convective problem. A surface particle of the elastic body at X moves tangentially by the relative
displacement g(X) (C&H eq. 9, 5):  g(X) = -beta A int_0^X p,  so g' = -beta A p, g odd, and for beta < 0
(rigid indenter on a compliant body) particles move towards the centre. The particle at X therefore meets
the indenter where the gap is h(X - g(X)), and the displacement condition v(X) = delta - h(X - g(X)),
differentiated in X, replaces h'(X) in the classical equation by the derivative of the *effective profile*
    H(X) = h(X - g(X)),   H'(X) = h'(X - g(X)) (1 + beta A p(X)).
(C&H eq. 8 prints h'(x - sign(x) g(x)) with g measured as a magnitude; the chain-rule factor 1 + beta A p
is what their eqs. (22) and (32) actually use, and it is the only first-order term for the wedge, whose
h' is constant.) The convective problem is the classical problem for the profile H, with H depending on p:
solved by iteration p0 -> g -> p1 -> ... with b re-found from the load condition at each step.

First-order closed forms (beta^2 dropped in H', classical pressure taken at the current half-width b):
    wedge    h = m |x|:          b/b0 = 1 / (1 + (2/pi) m beta ln 2)
    parabola h = x^2/(2R):      (b/b0)^2 = 1 / (1 + 4 beta b / (pi R))
(the wedge integral is int_0^1 s arccosh(1/s) / sqrt(1 - s^2) ds = ln 2; the parabola one is
int_{-1}^{1} s [G(s) + s sqrt(1 - s^2)] / sqrt(1 - s^2) ds = 2 with G = (s sqrt(1-s^2) + arcsin s)/2.)

Numerical method. Lengths in units of b, x = b s, s = cos(theta). Writing A h'-type slopes as Chebyshev
series F(s) = sum a_k T_k(s), the bounded inversion is exact term by term:
    A p(b s) = sum_k a_k sin(k theta)          (because (1/pi) PV int T_k / (sqrt(1-t^2)(t - s)) = U_{k-1}(s)),
    P        = (pi/2) b a_1 / A,
and int_0^s A p ds is again a closed sine/cosine series. The coefficients come from a DCT-II at the
Gauss-Chebyshev nodes theta_j = (j + 1/2) pi / N; sine series are summed by a DST-III: O(N log N) per
iteration (Gauss-Chebyshev collocation of the Cauchy singular equation, evaluated by FFT). The wedge's
log singularity at the apex needs no special treatment for b/b0: the error is O(N^-2) (measured by
:func:`self_convergence`).

Dimensionless profiles (b0 = 1, A = 1):
    wedge     h'(x) = m sign(x)                         lam = m
    parabola  h'(x) = x / R                             lam = b0/R
    power     h(x) = |x|^n / (n R^(n-1)), h'(x) = sign(x) |x/R|^(n-1),   lam = (b0/R)^(n-1)
so the wedge result depends on (m beta) only and the parabola on (b0/R, beta).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Sequence
from typing import NamedTuple

import numpy as np
from scipy import fft, optimize

__all__ = [
    "ConvectiveSolution",
    "converged_b_over_b0",
    "Profile",
    "SelfConvergenceRow",
    "parabola_first_order",
    "parabola_first_order_from_b0",
    "parabola_profile",
    "power_profile",
    "profile_from_args",
    "self_convergence",
    "solve",
    "wedge_first_order",
    "wedge_profile",
]

LN2 = math.log(2.0)


# --- profiles -----------------------------------------------------------------------------------


class Profile(NamedTuple):
    """Dimensionless symmetric convex profile h'(x) = lam sign(x) |x|^(n-1) (lengths in units of b0).

    Attributes:
        kind: ``"wedge"``, ``"parabola"`` or ``"power"``.
        n: Profile exponent (1 wedge, 2 parabola).
        lam: Slope scale: m (wedge), b0/R (parabola), (b0/R)^(n-1) (power).
        label: Human-readable parameters.
    """

    kind: str
    n: float
    lam: float
    label: str


def _check_pos(value: float, name: str, upper: float = math.inf, unit: str = "-") -> float:
    value = float(value)
    if not (0.0 < value < upper):
        raise ValueError(f"{name} = {value!r} out of range: need 0 < {name} < {upper} ({unit})")
    return value


def wedge_profile(m: float) -> Profile:
    """Wedge h = m |x| with face slope m > 0 (see :func:`analytic.wedge.wedge_slope`)."""
    m = _check_pos(m, "m")
    return Profile("wedge", 1.0, m, f"wedge m={m:.6g}")


def parabola_profile(b0_over_R: float) -> Profile:
    """Parabola h = x^2 / (2R) with classical half-width ratio b0/R in (0, 1)."""
    r = _check_pos(b0_over_R, "b0_over_R", 1.0)
    return Profile("parabola", 2.0, r, f"parabola b0/R={r:.6g}")


def power_profile(n: float, b0_over_R: float) -> Profile:
    """Power profile h = |x|^n / (n R^(n-1)), n >= 1, with b0/R in (0, 1)."""
    n = float(n)
    if not (1.0 <= n <= 8.0):
        raise ValueError(f"n = {n!r} out of range: need 1 <= n <= 8")
    r = _check_pos(b0_over_R, "b0_over_R", 1.0)
    return Profile("power", n, r ** (n - 1.0), f"power n={n:.6g} b0/R={r:.6g}")


def profile_from_args(
    kind: str, *, m: float | None = None, b0_over_R: float | None = None, n: float | None = None
) -> Profile:
    """Build a :class:`Profile` from a kind name and its parameter(s) (CLI helper)."""
    if kind == "wedge":
        if m is None:
            raise ValueError("m = None out of range: the wedge needs a slope 0 < m < inf")
        return wedge_profile(m)
    if kind == "parabola":
        if b0_over_R is None:
            raise ValueError("b0_over_R = None out of range: the parabola needs 0 < b0_over_R < 1")
        return parabola_profile(b0_over_R)
    if kind == "power":
        if n is None or b0_over_R is None:
            raise ValueError(
                "n, b0_over_R = None out of range: the power profile needs 1 <= n <= 8, 0 < b0/R < 1"
            )
        return power_profile(n, b0_over_R)
    raise ValueError(f"profile = {kind!r} out of range: need one of ('wedge', 'parabola', 'power')")


def _check_beta(beta: float) -> float:
    beta = float(beta)
    if not (-0.5 <= beta <= 0.5):
        raise ValueError(f"beta = {beta!r} out of range: need -0.5 <= beta <= 0.5")
    return beta


# --- first-order closed forms ---------------------------------------------------------------------


def wedge_first_order(m: float, beta: float) -> float:
    """First-order b/b0 for the wedge at fixed load: 1 / (1 + (2/pi) m beta ln 2).

    Derivation: H' = m sign(x) (1 + beta A p0) to first order, with p0 = (2m/(pi A)) arccosh(b/|x|);
    the load condition P = (1/A) int t H'(t)/sqrt(b^2 - t^2) dt = (2 m b/A) [1 + (2/pi) m beta ln 2].
    For m = pi/5, beta = -1/2: 1/(1 - 0.2 ln 2) = 1.16096 (C&H print 1.097, which is
    1/(1 - (4/pi^2) theta |beta| ln 2): an extra factor 2/pi).
    """
    m = _check_pos(m, "m")
    beta = _check_beta(beta)
    return 1.0 / (1.0 + (2.0 / math.pi) * m * beta * LN2)


def parabola_first_order(b_over_R: float, beta: float) -> float:
    """First-order b/b0 for the parabola in terms of the CORRECTED b/R (C&H's form): (1 + 4 beta b/(pi R))^-1/2.

    For b/R = 1/4, beta = -1/2: (1 - 1/(2 pi))^-1/2 = 1.0904 (C&H: 1.09); for b/R = 0.4: 1.1583 (C&H:
    "about 16 %").
    """
    r = _check_pos(b_over_R, "b_over_R", 1.0)
    beta = _check_beta(beta)
    return 1.0 / math.sqrt(1.0 + 4.0 * beta * r / math.pi)


def parabola_first_order_from_b0(b0_over_R: float, beta: float) -> float:
    """First-order b/b0 for the parabola given the CLASSICAL b0/R: the root q of q^2 (1 + 4 beta (b0/R) q / pi) = 1."""
    r0 = _check_pos(b0_over_R, "b0_over_R", 1.0)
    beta = _check_beta(beta)
    c = 4.0 * beta * r0 / math.pi
    return _root_near_one(lambda q: q * q * (1.0 + c * q) - 1.0)


def _root_near_one(f: Callable[[float], float]) -> float:
    """Root of f closest to 1 (the physical branch of b/b0), bracketed by stepping away from 1."""
    f1 = f(1.0)
    if f1 == 0.0:
        return 1.0
    lo = hi = 1.0
    for _ in range(200):
        lo, hi = lo / 1.02, hi * 1.02
        if f(hi) * f1 < 0.0:
            return optimize.brentq(f, hi / 1.02, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps)
        if f(lo) * f1 < 0.0:
            return optimize.brentq(f, lo, lo * 1.02, xtol=1e-15, rtol=4 * np.finfo(float).eps)
    raise RuntimeError("no root of the load condition within a factor 50 of b0")


# --- spectral machinery ---------------------------------------------------------------------------


def _nodes(N: int) -> tuple[np.ndarray, np.ndarray]:
    theta = (np.arange(N) + 0.5) * np.pi / N
    return theta, np.cos(theta)


def _coeffs(F: np.ndarray) -> np.ndarray:
    """Chebyshev coefficients a_k (k >= 1) of F sampled at the first-kind nodes (DCT-II)."""
    return fft.dct(F, type=2) / F.size


def _sine_series(a: np.ndarray) -> np.ndarray:
    """sum_{k=1}^{N-1} a_k sin(k theta_j) at the nodes (DST-III)."""
    x = np.zeros(a.size)
    x[:-1] = 0.5 * a[1:]
    return fft.dst(x, type=3)


def _cumulative(a: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """W(s) = int_0^s sum_k a_k sin(k theta(s')) ds' at the nodes, in closed form term by term."""
    N = a.size
    ap = np.zeros(N + 2)
    ap[:N] = a
    k = np.arange(1, N + 1)
    e = 0.5 * (ap[k + 1] - np.where(k >= 2, ap[k - 1], 0.0))
    c = e / k
    x = np.empty(N)
    x[:-1] = 0.5 * c[:-1]
    x[-1] = c[-1]
    const = float(np.sum(c * np.sin(0.5 * np.pi * k)))
    return 0.5 * a[1] * (0.5 * np.pi - theta) + const - fft.dst(x, type=3)


def _slope(y: np.ndarray, n: float) -> np.ndarray:
    """sign(y) |y|^(n-1)."""
    return np.sign(y) if n == 1.0 else np.sign(y) * np.abs(y) ** (n - 1.0)


def _a1_classical(profile: Profile) -> float:
    """Exact a_1 of lam sign(s)|s|^(n-1): (2/pi) lam int_0^pi |cos t|^n dt."""
    n = profile.n
    return (
        (2.0 / math.pi)
        * profile.lam
        * math.sqrt(math.pi)
        * math.gamma(0.5 * (n + 1))
        / math.gamma(0.5 * n + 1)
    )


def _a1_discrete(profile: Profile, s: np.ndarray) -> float:
    """a_1 of the classical slope by the same DCT as the solver (so the discrete b0 is consistent)."""
    return float(_coeffs(profile.lam * _slope(s, profile.n))[1])


def _classical_unit(profile: Profile, theta: np.ndarray, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Classical w0 = A p0 and W0 = int_0^s w0 at half-width b0 = 1 (closed form for wedge and parabola)."""
    lam = profile.lam
    if profile.kind == "wedge":
        u = np.abs(s)
        w0 = (2.0 * lam / math.pi) * np.arccosh(1.0 / u)
        W0 = np.sign(s) * (2.0 * lam / math.pi) * (u * np.arccosh(1.0 / u) + np.arcsin(u))
        return w0, W0
    if profile.kind == "parabola":
        root = np.sqrt(1.0 - s * s)
        return lam * root, 0.5 * lam * (s * root + np.arcsin(s))
    a = _coeffs(lam * _slope(s, profile.n))
    return _sine_series(a), _cumulative(a, theta)


def _classical_funcs(profile: Profile, N: int) -> tuple[Callable[[float], float], Callable[[float], float]]:
    """w0(x), W0(x) for any x (b0 = 1): closed forms, or interpolation of the spectral values (power)."""
    lam = profile.lam
    if profile.kind == "wedge":

        def w0(x: float) -> float:
            u = abs(x)
            if u == 0.0:
                return math.inf
            return (2.0 * lam / math.pi) * math.acosh(1.0 / u) if u < 1.0 else 0.0

        def W0(x: float) -> float:
            u = min(abs(x), 1.0)
            val = u * math.acosh(1.0 / u) + math.asin(u) if u > 0.0 else 0.0
            return math.copysign((2.0 * lam / math.pi) * val, x)

        return w0, W0
    if profile.kind == "parabola":

        def w0(x: float) -> float:
            return lam * math.sqrt(1.0 - x * x) if abs(x) < 1.0 else 0.0

        def W0(x: float) -> float:
            u = min(abs(x), 1.0)
            return math.copysign(0.5 * lam * (u * math.sqrt(1.0 - u * u) + math.asin(u)), x)

        return w0, W0
    theta, s = _nodes(N)
    w_nodes, W_nodes = _classical_unit(profile, theta, s)
    pos = s[::-1] > 0.0  # ascending positive nodes
    sa = np.concatenate(([0.0], s[::-1][pos], [1.0]))
    wa = np.concatenate(([np.interp(0.0, s[::-1], w_nodes[::-1])], w_nodes[::-1][pos], [0.0]))
    # W0(0) = 0 and W0(1) = P/2 = (pi/4) a_1 exactly (A = 1, b0 = 1)
    Wa = np.concatenate(([0.0], W_nodes[::-1][pos], [0.25 * math.pi * _a1_classical(profile)]))

    def w0(x: float) -> float:
        return float(np.interp(abs(x), sa, wa, right=0.0))

    def W0(x: float) -> float:
        return math.copysign(float(np.interp(abs(x), sa, Wa, right=Wa[-1])), x)

    return w0, W0


# --- solution ------------------------------------------------------------------------------------


class ConvectiveSolution(NamedTuple):
    """Result of :func:`solve` (dimensionless: x in units of b0, pressure in units of P/b0).

    The load P is fixed; b0 is the classical half-width at that load; b is the half-width in material
    (undeformed) coordinates of the flat elastic body. Physical values: b = (b/b0) b0 and
    p = (p b0/P) P/b0.

    Attributes:
        profile: The profile solved.
        beta: Dundurs beta.
        b_over_b0_first_order: Closed form (wedge, parabola) or, for the power profile, the linearised
            solver value.
        b_over_b0_first_order_numeric: Solver with beta^2 terms dropped (checks the closed form).
        b_over_b0_first_iterate: Exact solution for the effective profile h(x - g0(x)), g0 from p0.
        b_over_b0_converged: Fixed point of the full nonlinear equations.
        x: Plot grid (units of b0), symmetric, covering every contact.
        p_classical, p_first_order, p_first_iterate, p_converged: Pressures on ``x`` (units of P/b0).
        iterations: Fixed-point iterations used.
        residual: Last change of b/b0 in the fixed-point iteration.
        n_nodes: Gauss-Chebyshev nodes.
    """

    profile: Profile
    beta: float
    b_over_b0_first_order: float
    b_over_b0_first_order_numeric: float
    b_over_b0_first_iterate: float
    b_over_b0_converged: float
    x: np.ndarray
    p_classical: np.ndarray
    p_first_order: np.ndarray
    p_first_iterate: np.ndarray
    p_converged: np.ndarray
    iterations: int
    residual: float
    n_nodes: int


def _on_grid(x: np.ndarray, r: float, s: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Interpolate nodal values w(s) of a contact of half-width r onto x (zero outside)."""
    sa, wa = s[::-1], w[::-1]
    return np.interp(
        x / r, np.concatenate(([-1.0], sa, [1.0])), np.concatenate(([0.0], wa, [0.0])), left=0.0, right=0.0
    )


def _first_order_numeric(
    profile: Profile, beta: float, theta: np.ndarray, s: np.ndarray, a10: float
) -> tuple[float, np.ndarray]:
    """Solver with beta^2 dropped: H' = h'(x)(1 + beta A p0_b) - h''(x) g0_b, p0_b classical at the current b."""
    n, lam = profile.n, profile.lam
    w_u, W_u = _classical_unit(profile, theta, s)
    corr = lam * _slope(s, n) * w_u
    if n != 1.0:
        corr = corr + lam * (n - 1.0) * np.abs(s) ** (n - 2.0) * W_u
    ac = _coeffs(corr)
    a0 = _coeffs(lam * _slope(s, n))
    c = ac[1]
    # load: r^n (a10 + beta c r^(n-1)) = a10
    r = _root_near_one(lambda q: q**n * (a10 + beta * c * q ** (n - 1.0)) - a10)
    a = r ** (n - 1.0) * (a0 + beta * r ** (n - 1.0) * ac)
    return r, _sine_series(a)


def _first_iterate(profile: Profile, beta: float, a10: float, N: int) -> float:
    """b1/b0 of the classical problem for H1(x) = h(x - g0(x)), g0 = -beta A int_0^x p0 (physical x)."""
    from scipy import integrate  # imported here: a run that never integrates skips its ~20 ms import

    n, lam = profile.n, profile.lam
    w0, W0 = _classical_funcs(profile, N)
    P = 0.5 * math.pi * a10

    def phi(x: float) -> float:
        return x + beta * W0(x)

    # sign change of x - g0(x) near the apex (wedge: exponentially small, may underflow to none)
    breaks = [1.0]
    if beta < 0.0 and phi(1e-300) < 0.0 < phi(1.0):
        # root of phi(x)/x = 1 + beta W0(x)/x, found in t = ln x (the root can be ~exp(-100))
        t_root = optimize.brentq(
            lambda t: 1.0 + beta * W0(math.exp(t)) / math.exp(t), math.log(1e-300), 0.0, xtol=1e-13
        )
        breaks.append(math.exp(t_root))

    def load(b1: float) -> float:
        def integrand(u: float) -> float:
            x = b1 * math.sin(u)
            y = phi(x)
            sl = math.copysign(abs(y) ** (n - 1.0), y) if n != 1.0 else math.copysign(1.0, y)
            return b1 * math.sin(u) * lam * sl * (1.0 + beta * w0(x))

        pts = sorted(math.asin(min(xb / b1, 1.0)) for xb in breaks if xb < b1)
        with warnings.catch_warnings():
            # the power profile's p0 is an interpolant: quad may warn about its kinks; b/b0 is then
            # limited by the interpolation (O(N^-2)), not by quad
            warnings.simplefilter("ignore", integrate.IntegrationWarning)
            val, _ = integrate.quad(
                integrand, 0.0, 0.5 * math.pi, points=pts or None, limit=400, epsabs=1e-14, epsrel=1e-13
            )
        return 2.0 * val - P

    return _root_near_one(load)


def _first_iterate_pressure(
    profile: Profile, beta: float, r1: float, theta: np.ndarray, s: np.ndarray, N: int
) -> np.ndarray:
    """A p1 at the nodes of the first-iterate contact (half-width r1)."""
    w0, W0 = _classical_funcs(profile, N)
    x = r1 * s
    w0x = np.array([w0(v) for v in x]) if profile.kind == "power" else _vec(w0)(x)
    W0x = np.array([W0(v) for v in x]) if profile.kind == "power" else _vec(W0)(x)
    F = profile.lam * _slope(x + beta * W0x, profile.n) * (1.0 + beta * w0x)
    return _sine_series(_coeffs(F))


def _vec(f: Callable[[float], float]) -> Callable[[np.ndarray], np.ndarray]:
    return np.vectorize(f, otypes=[float])


def _fixed_point(
    profile: Profile, beta: float, theta: np.ndarray, s: np.ndarray, a10: float, tol: float, max_iter: int
) -> tuple[float, np.ndarray, int, float]:
    """Fixed point of the full equations, iterated self-similarly (state: b and the series of A p)."""
    n, lam = profile.n, profile.lam
    a = _coeffs(lam * _slope(s, n))
    r, change = 1.0, math.inf
    for it in range(1, max_iter + 1):
        w = _sine_series(a)
        W = _cumulative(a, theta)
        at = _coeffs(lam * _slope(s + beta * W, n) * (1.0 + beta * w))
        if not at[1] > 0.0:
            raise RuntimeError(f"convective iteration lost the load (a_1 = {at[1]:.3g}) at iteration {it}")
        r_new = (a10 / at[1]) ** (1.0 / n)
        a = r_new ** (n - 1.0) * at
        change, r = abs(r_new - r), r_new
        if change < tol:
            return r, _sine_series(a), it, change
    raise RuntimeError(
        f"convective iteration did not converge in {max_iter} iterations (last change {change:.3g})"
    )


def solve(
    profile: Profile,
    *,
    beta: float,
    n_nodes: int = 65536,
    tol: float = 1e-14,
    max_iter: int = 200,
    n_plot: int = 801,
) -> ConvectiveSolution:
    """Solve the convective contact problem at fixed load (first order, first iterate, fixed point).

    Args:
        profile: From :func:`wedge_profile`, :func:`parabola_profile` or :func:`power_profile`.
        beta: Dundurs beta, -0.5 <= beta <= 0.5, either sign (:func:`analytic.materials.bimaterial`; rigid
            indenter: -(1 - 2 nu2)/(2 (1 - nu2)) <= 0).
        n_nodes: Gauss-Chebyshev nodes N (even, >= 64); error in b/b0 is O(N^-2).
        tol: Stop when b/b0 changes by less than this between iterations.
        max_iter: Iteration cap (RuntimeError beyond).
        n_plot: Points of the output grid ``x``.

    Returns:
        :class:`ConvectiveSolution` (dimensionless, see there).
    """
    beta = _check_beta(beta)
    N = int(n_nodes)
    if N < 64 or N % 2:
        raise ValueError(f"n_nodes = {n_nodes!r} out of range: need an even integer >= 64")
    theta, s = _nodes(N)
    a10 = _a1_discrete(profile, s)  # b0 from the same quadrature: b/b0 = 1 exactly at beta = 0
    P = 0.5 * math.pi * a10  # load with A = 1, b0 = 1

    w_cl, _ = _classical_unit(profile, theta, s)
    r_lin, w_lin = _first_order_numeric(profile, beta, theta, s, a10)
    if profile.kind == "wedge":
        r_fo = wedge_first_order(profile.lam, beta) if beta != 0.0 else 1.0
    elif profile.kind == "parabola":
        r_fo = parabola_first_order_from_b0(profile.lam, beta) if beta != 0.0 else 1.0
    else:
        r_fo = r_lin
    r_it1 = _first_iterate(profile, beta, _a1_classical(profile), N) if beta != 0.0 else 1.0
    w_it1 = _first_iterate_pressure(profile, beta, r_it1, theta, s, N)
    r_conv, w_conv, its, change = _fixed_point(profile, beta, theta, s, a10, tol, max_iter)

    xmax = 1.05 * max(1.0, r_lin, r_it1, r_conv)
    x = np.linspace(-xmax, xmax, int(n_plot))
    return ConvectiveSolution(
        profile=profile,
        beta=beta,
        b_over_b0_first_order=r_fo,
        b_over_b0_first_order_numeric=r_lin,
        b_over_b0_first_iterate=r_it1,
        b_over_b0_converged=r_conv,
        x=x,
        p_classical=_on_grid(x, 1.0, s, w_cl) / P,
        p_first_order=_on_grid(x, r_lin, s, w_lin) / P,
        p_first_iterate=_on_grid(x, r_it1, s, w_it1) / P,
        p_converged=_on_grid(x, r_conv, s, w_conv) / P,
        iterations=its,
        residual=change,
        n_nodes=N,
    )


def converged_b_over_b0(
    profile: Profile, *, beta: float, n_nodes: int = 65536, tol: float = 1e-14, max_iter: int = 200
) -> float:
    """Only the fixed-point b/b0 (cheaper than :func:`solve`)."""
    beta = _check_beta(beta)
    theta, s = _nodes(int(n_nodes))
    return _fixed_point(profile, beta, theta, s, _a1_discrete(profile, s), tol, max_iter)[0]


# --- self-convergence -------------------------------------------------------------------------------


class SelfConvergenceRow(NamedTuple):
    """b/b0 at one resolution and its change from the previous (coarser) one."""

    n_nodes: int
    b_over_b0_converged: float
    change: float
    iterations: int


def self_convergence(
    profile: Profile, *, beta: float, n_nodes: Sequence[int] = (1024, 4096, 16384, 65536)
) -> list[SelfConvergenceRow]:
    """Fixed-point b/b0 for increasing N; ``change`` is |b/b0(N) - b/b0(N_prev)| (nan for the first)."""
    beta = _check_beta(beta)
    rows: list[SelfConvergenceRow] = []
    prev = math.nan
    for N in n_nodes:
        theta, s = _nodes(int(N))
        r, _, its, _ = _fixed_point(profile, beta, theta, s, _a1_discrete(profile, s), 1e-14, 200)
        rows.append(SelfConvergenceRow(int(N), r, abs(r - prev), its))
        prev = r
    return rows

