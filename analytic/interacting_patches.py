"""Interacting contact patches on an elastic half-plane: every patch solved together, with the real gap and the
half-plane (logarithmic) coupling between them (plane strain, frictionless; pure numpy/scipy).

Problem. A rigid (or, through the composite modulus E*, elastic) indenter approaches an elastic half-plane. The
real gap g(x) (mm) is the separation of the two surfaces before loading, measured along the half-plane normal,
at abscissa x along the half-plane surface; the indenter moves by delta (mm) towards the half-plane. The
surface displacement v(x) (mm, positive INTO the half-plane) under the pressure p >= 0 (MPa, compression
positive) is Flamant's field summed over the load (:mod:`analytic.flamant`, the workbench's half-plane
convention):

    v(x) = (1 / (pi E*)) int p(s) [2 ln(r_ref / |x - s|) - kappa] ds,   kappa = 1 / (1 - nu)  (0 if nu is None)

i.e. v(x) = -(2/(pi E*)) int p ln|x - s| ds + const with the constant fixed by the DEPTH convention of
:func:`analytic.flamant.flamant_displacement` and ``fem.far_field``: the half-plane does not move at the depth
r_ref below each load point (kappa = 1/(1 - nu) is Flamant's surface term -(1 + nu) P/(pi E) written with
E* = E/(1 - nu^2) of the elastic half-plane, a rigid indenter; ``nu=None`` drops it: v = 0 at the surface
distance r_ref). In 2D a half-plane's displacement grows like ln r, so delta has a meaning only with r_ref (the
body's depth; the FEM far field takes the block height). Contact conditions (complementarity):

    h(x) := g(x) + v(x) - delta >= 0,   p(x) >= 0,   p h = 0.

On each patch k, |x - c_k| < b_k, h = 0; differentiated, (2/(pi E*)) PV int p(s) / (x - s) ds = g'(x), the
whole pressure (all patches) inside the integral: that is the coupling.

Method (Gauss-Chebyshev collocation per patch, exact kernel integrals, :mod:`analytic.chebyshev_kernels`).
On patch k, x = c_k + b_k t, p = sqrt(1 - t^2) sum_n alpha_{k,n} U_n(t) (bounded at both ends: the edges are
found by the condition that p be bounded there). The slope equation on patch k reads

    (2/E*) sum_n alpha_{k,n} T_{n+1}(t) = F_k(t) := g'(x) - (2/E*) sum_{j != k} sum_n alpha_{j,n} Lambda'_n(t_j(x)),

so with f_{k,m} the Chebyshev coefficients of F_k at N Gauss-Chebyshev nodes: alpha_{k,n} = (E*/2) f_{k,n+1}
(a linear system for all alpha at once, given the patches) and the solvability condition f_{k,0} = 0 (one
equation per patch). The last equation per patch is h(c_k) = 0 at the patch centre (delta given) or, for a
given total load P = sum_k (pi/2) b_k alpha_{k,0}, the same h(c_k) - h(c_1) = 0 for k > 1 and the load. The
2K unknowns (c_k, ln b_k) are found by scipy's hybrid Powell root. The active set: patches start at the local
minima of g that the approach reaches, patches with a non-positive load are dropped, a minimum where h < 0 is
added, overlapping patches are merged, and the final solution is checked (p >= 0 on every patch, h >= 0 on a
grid outside them). For one patch on g = x^2/(2R) the series is alpha = (E* b/(2R), 0, ...): Hertz, exactly.

Validity (what the model leaves out). The half-plane idealisation of the elastic body: every patch half-width
b_k small against the radii of both surfaces there (b/|R| <= :data:`MAX_PATCH_OVER_RADIUS`), the patches'
span small against the body depth r_ref (span/r_ref <= :data:`MAX_SPAN_OVER_DEPTH`), and the surfaces nearly
parallel to the half-plane across the whole span (|slope of the elastic surface| <= :data:`MAX_SURFACE_SLOPE`:
beyond it the normals of the patches differ and the coupling through a flat surface is no longer the body's;
for patches separated by s on an elastic surface of radius R the slope is about s/|R|, so this is the limit of
the separation against the radius). The model's error inside these limits is of the order of (b/R) and of the
slope squared (a few per cent at the limits). Those limits are the model's analytic validity limit; the concave
map measured the model against the FEM (issue 40, item 3; docs/concave_map.md), past the slope limit too: with
pairs tilted 0.10 to 0.14 it stayed within 5 % at 124 of 125 points (median 1.9 %, the P(d) part, not the tilt),
so the slope limit is conservative there. Units: mm, N/mm, MPa.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import NamedTuple

import numpy as np
from scipy import optimize

from analytic.chebyshev_kernels import (
    cauchy_matrix,
    chebyshev_coefficients,
    gauss_chebyshev_nodes,
    log_matrix,
    series_pressure,
)
from analytic.materials import validate_positive as _positive

__all__ = ["Gap", "Patch", "PatchSolution", "MAX_PATCH_OVER_RADIUS", "MAX_SPAN_OVER_DEPTH", "MAX_SURFACE_SLOPE",
           "N_TERMS", "hertz_approach", "parabola_gap", "solve_patches", "load_curve"]

N_TERMS = 48  # Gauss-Chebyshev nodes per patch: Hertz is exact with any; a smooth real gap converges geometrically
MAX_PATCH_OVER_RADIUS = 0.1
MAX_SPAN_OVER_DEPTH = 0.25
MAX_SURFACE_SLOPE = 0.1


class Gap(NamedTuple):
    """The real gap g(x) >= 0 before loading (mm) and its slope g'(x), along the half-plane surface x (mm).

    ``domain`` (x_lo, x_hi) is where the gap is defined and searched for contact; ``curvature_radii`` optional
    callable x -> (R_indenter, R_elastic) (mm, convex > 0, concave < 0) for the validity check.
    """

    value: Callable[[np.ndarray], np.ndarray]
    slope: Callable[[np.ndarray], np.ndarray]
    domain: tuple[float, float]
    curvature_radii: Callable[[float], tuple[float, float]] | None = None
    surface_slope: Callable[[np.ndarray], np.ndarray] | None = None


def parabola_gap(*, R: float, centre: float = 0.0, half_range: float | None = None) -> Gap:
    """Hertz's gap g = (x - c)^2 / (2R) of a cylinder of relative radius R (mm) on the half-plane."""
    R = _positive(R, "R", "mm")
    span = 0.5 * R if half_range is None else float(half_range)
    return Gap(lambda x: (np.asarray(x, dtype=float) - centre) ** 2 / (2.0 * R),
               lambda x: (np.asarray(x, dtype=float) - centre) / R, (centre - span, centre + span),
               lambda x: (R, math.inf))


class Patch(NamedTuple):
    """One contact patch (mm, MPa, N/mm): centre c, half-width b, peak pressure p0, load, load share (of the total),
    and the series alpha of p = sqrt(1 - t^2) sum alpha_n U_n(t), t = (x - c)/b."""

    centre: float
    half_width: float
    p0: float
    load: float
    share: float
    alpha: np.ndarray

    def pressure(self, x) -> np.ndarray:
        return series_pressure((np.asarray(x, dtype=float) - self.centre) / self.half_width, self.alpha)


class PatchSolution(NamedTuple):
    """All patches at one state: the approach delta (mm, depth convention of the module), the total load P (N/mm)."""

    delta: float
    P: float
    patches: tuple[Patch, ...]
    E_star: float
    r_ref: float
    nu: float | None

    def pressure(self, x) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        return sum((pt.pressure(x) for pt in self.patches), np.zeros_like(x))

    def displacement(self, x) -> np.ndarray:
        """v(x) (mm, into the half-plane) of the module docstring."""
        return _displacement(np.asarray(x, dtype=float), self.patches, E_star=self.E_star, r_ref=self.r_ref,
                             nu=self.nu)


def _displacement(x, patches, *, E_star, r_ref, nu) -> np.ndarray:
    kappa = 0.0 if nu is None else 1.0 / (1.0 - nu)
    total = np.zeros_like(x)
    for pt in patches:
        t = (x - pt.centre) / pt.half_width
        ln_int = pt.half_width * (0.5 * math.pi * pt.alpha[0] * math.log(pt.half_width)
                                  + math.pi * (log_matrix(t, pt.alpha.size) @ pt.alpha))  # int p ln|x - s| ds
        total += (2.0 * math.log(r_ref) - kappa) * pt.load - 2.0 * ln_int
    return total / (math.pi * E_star)


class _Assembly:
    """The linear collocation system of all patches for given (c_k, b_k), and the residuals of the 2K equations."""

    def __init__(self, gap: Gap, *, E_star: float, r_ref: float, nu: float | None, n: int):
        self.gap, self.E, self.r_ref, self.nu, self.n = gap, E_star, r_ref, nu, n
        self.C = chebyshev_coefficients(n)
        _, self.t = gauss_chebyshev_nodes(n)

    def alphas(self, c: np.ndarray, b: np.ndarray) -> tuple[list[np.ndarray], np.ndarray]:
        """alpha_k (n - 1 terms each) and f_{k,0} (the solvability residuals, dimensionless)."""
        K, n, m = c.size, self.n, self.n - 1
        xs = [c[k] + b[k] * self.t for k in range(K)]
        M = [[None if j == k else cauchy_matrix((xs[k] - c[j]) / b[j], m) for j in range(K)] for k in range(K)]
        A = np.eye(K * m)
        rhs = np.empty(K * m)
        S = self.C[1:]  # f_1 .. f_{n-1}
        for k in range(K):
            rhs[k * m:(k + 1) * m] = 0.5 * self.E * (S @ self.gap.slope(xs[k]))
            for j in range(K):
                if j != k:
                    A[k * m:(k + 1) * m, j * m:(j + 1) * m] += S @ M[k][j]
        al = np.linalg.solve(A, rhs) if K > 1 else rhs
        alpha = [al[k * m:(k + 1) * m] for k in range(K)]
        f0 = np.empty(K)
        for k in range(K):
            F = self.gap.slope(xs[k]) - (2.0 / self.E) * sum((M[k][j] @ alpha[j] for j in range(K) if j != k),
                                                           np.zeros(n))
            f0[k] = self.C[0] @ F
        return alpha, f0

    def patches(self, c, b, alpha) -> tuple[Patch, ...]:
        loads = [0.5 * math.pi * b[k] * alpha[k][0] for k in range(c.size)]
        total = sum(loads)
        return tuple(Patch(float(c[k]), float(b[k]), _peak(alpha[k], b[k]), float(loads[k]),
                           float(loads[k] / total) if total else math.nan, alpha[k]) for k in range(c.size))

    def h_centres(self, pts: tuple[Patch, ...]) -> np.ndarray:
        """g(c_k) + v(c_k): equal to delta at every patch centre in contact."""
        c = np.array([pt.centre for pt in pts])
        return self.gap.value(c) + _displacement(c, pts, E_star=self.E, r_ref=self.r_ref, nu=self.nu)


def _peak(alpha: np.ndarray, b: float) -> float:
    """max of sum alpha_n sin((n + 1) phi) over phi: a grid then a bounded scalar search."""
    phi = np.linspace(0.0, math.pi, 2049)
    k = np.arange(1, alpha.size + 1)
    w = np.sin(np.multiply.outer(phi, k)) @ alpha
    j = int(np.argmax(w))
    lo, hi = phi[max(j - 1, 0)], phi[min(j + 1, phi.size - 1)]
    best = optimize.minimize_scalar(lambda f: -float(np.sin(k * f) @ alpha), bounds=(lo, hi), method="bounded",
                                    options={"xatol": 1e-13})
    return float(max(w[j], -best.fun))


def _hertz_b(approach: float, R: float, *, r_ref: float, nu: float | None) -> float:
    """Half-width b of one isolated Hertz patch at the approach (module convention): the root of
    approach = (b^2 / (4R)) [2 ln(2 r_ref / b) + 1 - kappa] (:func:`hertz_approach`), on 0 < b < r_ref."""
    def f(b):
        return hertz_approach(b, R, r_ref=r_ref, nu=nu) - approach

    hi = min(r_ref, math.sqrt(4.0 * R * max(approach, 1e-300)))
    lo = hi
    while f(lo) > 0.0 and lo > 1e-12 * hi:
        lo *= 0.5
    if f(lo) > 0.0 or f(hi) < 0.0:
        return 0.5 * hi
    return optimize.brentq(f, lo, hi, xtol=1e-300, rtol=1e-15)


def hertz_approach(b: float, R: float, *, r_ref: float, nu: float | None) -> float:
    """Approach (mm) of one isolated Hertz patch of half-width b on g = x^2/(2R), module convention:
    delta = (P / (pi E*)) [2 ln(2 r_ref / b) + 1 - kappa], P = pi E* b^2 / (4 R)
    (from v(0) with int_{-1}^{1} sqrt(1 - u^2) ln|u| du = -(pi/4)(1 + 2 ln 2))."""
    kappa = 0.0 if nu is None else 1.0 / (1.0 - nu)
    return b * b / (4.0 * R) * (2.0 * math.log(2.0 * r_ref / b) + 1.0 - kappa)


def _solve_fixed_set(asm: _Assembly, c0, b0, *, delta, P) -> tuple[Patch, ...]:
    """Root of the 2K equations for a given set of patches (starting at c0, b0)."""
    K = len(c0)
    scale = float(np.mean(b0))

    lo, hi = math.log(1e-8 * scale), math.log(1e4 * scale)  # keeps a wild trial step of the root finite

    def unpack(y):
        return y[:K] * scale, np.exp(np.clip(y[K:], lo, hi))

    def residual(y):
        c, b = unpack(y)
        alpha, f0 = asm.alphas(c, b)
        pts = asm.patches(c, b, alpha)
        h = asm.h_centres(pts)
        if delta is not None:
            second = (h - delta) / scale
        else:
            second = np.concatenate([[(sum(pt.load for pt in pts) - P) / P], (h[1:] - h[0]) / scale])
        return np.concatenate([f0, second])

    y0 = np.concatenate([np.asarray(c0, dtype=float) / scale, np.log(np.asarray(b0, dtype=float))])
    sol = optimize.root(residual, y0, method="hybr", options={"xtol": 1e-15, "maxfev": 400 * (2 * K + 1)})
    c, b = unpack(sol.x)
    if not np.all(np.isfinite(sol.x)) or np.max(np.abs(residual(sol.x))) > 1e-9:
        raise RuntimeError(f"interacting patches: the root did not converge ({sol.message}; "
                           f"residual {np.max(np.abs(residual(sol.x))):.3g})")
    alpha, _ = asm.alphas(c, b)
    return asm.patches(c, b, alpha)


def _solve_with_retries(asm: _Assembly, cs, bs, *, delta, P) -> tuple[Patch, ...]:
    """:func:`_solve_fixed_set`, started again from halved half-widths when the root fails or lands on a patch
    with tensile pressure (a too wide start can converge to one patch spanning a hump of the gap)."""
    bs = list(bs)
    for attempt in range(4):
        try:
            pts = _solve_fixed_set(asm, cs, bs, delta=delta, P=P)
        except RuntimeError:
            if attempt == 3:
                raise
        else:
            if attempt == 3 or all(np.min(series_pressure(np.linspace(-0.99, 0.99, 199), pt.alpha)) >= -1e-8 * pt.p0
                                   for pt in pts):
                return pts
        bs = [0.5 * b for b in bs]
    return pts


def _minima(gap: Gap, n: int = 4001) -> tuple[np.ndarray, np.ndarray]:
    """Abscissae and local curvatures of the interior local minima of g on its domain (grid then polished)."""
    x = np.linspace(*gap.domain, n)
    g = gap.value(x)
    idx = [i for i in range(1, n - 1) if g[i] <= g[i - 1] and g[i] < g[i + 1]]
    xs, curv = [], []
    for i in idx:
        try:
            xm = optimize.brentq(gap.slope, x[i - 1], x[i + 1], xtol=1e-15)
        except ValueError:
            xm = x[i]
        h = 1e-4 * (x[1] - x[0])
        xs.append(xm)
        curv.append(max(float(gap.slope(xm + h) - gap.slope(xm - h)) / (2 * h), 1e-12))
    return np.array(xs), np.array(curv)


def solve_patches(gap: Gap, *, E_star: float, r_ref: float, delta: float | None = None, P: float | None = None,
                  nu: float | None = None, n_terms: int = N_TERMS,
                  start: Sequence[tuple[float, float]] | None = None) -> PatchSolution:
    """All contact patches at the approach ``delta`` (mm) or the total load ``P`` (N/mm), exactly one of them.

    Args:
        gap: The real gap (:class:`Gap`), min g = 0 not required (the approach is measured from g = 0).
        E_star: Composite plane-strain modulus (MPa).
        r_ref: Reference depth (mm), the body's depth (module docstring).
        nu: Poisson's ratio of the elastic half-plane (Flamant's surface term), or None.
        n_terms: Gauss-Chebyshev nodes per patch (>= 8).
        start: Optional (centre, half-width) of each patch to start from (continuation); default: the minima.

    Raises:
        ValueError: a bad value (one line); RuntimeError: no consistent active set.
    """
    E_star = _positive(E_star, "E_star", "MPa")
    r_ref = _positive(r_ref, "r_ref", "mm")
    if (delta is None) == (P is None):
        raise ValueError("delta, P = both or neither given out of range: give exactly one of them")
    if P is not None:
        P = _positive(P, "P", "N/mm")
    if nu is not None and not (-1.0 < float(nu) < 0.5):
        raise ValueError(f"nu = {nu!r} out of range: need -1 < nu < 0.5")
    if int(n_terms) < 8:
        raise ValueError(f"n_terms = {n_terms!r} out of range: need an integer >= 8")
    asm = _Assembly(gap, E_star=E_star, r_ref=r_ref, nu=nu, n=int(n_terms))
    xm, km = _minima(gap)
    if xm.size == 0:
        raise ValueError("gap out of range: g has no interior local minimum on its domain")
    if delta is not None and delta <= float(np.min(gap.value(xm))):
        return PatchSolution(float(delta), 0.0, (), E_star, r_ref, nu)
    if start is not None and len(start):
        cs = [float(c) for c, _ in start]
        bs = [float(b) for _, b in start]
    else:
        order = np.argsort(gap.value(xm))
        reach = [order[0]]  # the lowest minimum; the others join where the solution interpenetrates them
        cs = [float(xm[i]) for i in reach]
        if delta is not None:
            bs = [_hertz_b(delta - float(gap.value(xm[i])), 1.0 / km[i], r_ref=r_ref, nu=nu) for i in reach]
        else:
            bs = [math.sqrt(4.0 * P / (len(reach) * math.pi * E_star * km[i])) for i in reach]
    for _ in range(4 * xm.size + 4):
        pts = _solve_with_retries(asm, cs, bs, delta=delta, P=P)
        keep = [pt for pt in pts if pt.load > 0.0]
        if len(keep) < len(pts):
            if not keep:
                raise RuntimeError("interacting patches: no patch carries a positive load")
            cs, bs = [pt.centre for pt in keep], [pt.half_width for pt in keep]
            continue
        merged = _merge(pts)
        if merged is not None:
            cs, bs = merged
            continue
        d = float(asm.h_centres(pts)[0]) if delta is None else float(delta)
        sol = PatchSolution(d, float(sum(pt.load for pt in pts)), pts, E_star, r_ref, None if nu is None else nu)
        new = [(x, k, d - float(gap.value(x) + sol.displacement(np.array([x]))[0])) for x, k in zip(xm, km, strict=True)
               if not any(abs(x - pt.centre) < pt.half_width for pt in pts)]
        new = [(x, k, over) for x, k, over in new if over > 0.0]
        if new:
            cs = cs + [float(x) for x, _, _ in new]
            bs = bs + [_hertz_b(over, 1.0 / k, r_ref=r_ref, nu=nu) for _, k, over in new]
            continue
        _check(sol, gap)
        return sol
    raise RuntimeError("interacting patches: the active set did not settle")


def _merge(pts: tuple[Patch, ...]):
    """(centres, half-widths) after merging overlapping patches, or None if none overlap."""
    spans = sorted((pt.centre - pt.half_width, pt.centre + pt.half_width) for pt in pts)
    out = [list(spans[0])]
    hit = False
    for lo, hi in spans[1:]:
        if lo <= out[-1][1]:
            out[-1][1] = max(out[-1][1], hi)
            hit = True
        else:
            out.append([lo, hi])
    if not hit:
        return None
    return [0.5 * (lo + hi) for lo, hi in out], [0.5 * (hi - lo) for lo, hi in out]


def _check(sol: PatchSolution, gap: Gap) -> None:
    """p >= 0 on every patch and h >= 0 outside them (relative tolerances stated in the message)."""
    for pt in sol.patches:
        t = np.linspace(-1.0, 1.0, 801)[1:-1]
        if np.min(series_pressure(t, pt.alpha)) < -1e-8 * pt.p0:
            raise RuntimeError(f"interacting patches: tensile pressure in the patch at x = {pt.centre:.6g} mm "
                               "(the patch should split)")
    x = np.linspace(*gap.domain, 4001)
    # outside every patch by more than 1 % of its half-width (h ~ distance^1.5 at an edge: the series' truncation
    # error dominates there); h is measured against the interference delta - min g
    outside = np.all([np.abs(x - pt.centre) > 1.01 * pt.half_width for pt in sol.patches], axis=0)
    h = gap.value(x) + sol.displacement(x) - sol.delta
    scale = sol.delta - float(np.min(gap.value(x)))
    if np.any(h[outside] < -1e-6 * max(scale, 1e-300)):
        i = int(np.argmin(np.where(outside, h, np.inf)))
        raise RuntimeError(f"interacting patches: interpenetration h = {h[i]:.3g} mm at x = {x[i]:.6g} mm")


def load_curve(gap: Gap, deltas: Sequence[float], *, E_star: float, r_ref: float, nu: float | None = None,
               n_terms: int = N_TERMS) -> tuple[PatchSolution, ...]:
    """Solutions at increasing approaches (continuation from the previous state): P(delta), patches."""
    out, start = [], None
    for d in deltas:
        try:
            s = solve_patches(gap, E_star=E_star, r_ref=r_ref, delta=float(d), nu=nu, n_terms=n_terms, start=start)
        except RuntimeError:
            s = solve_patches(gap, E_star=E_star, r_ref=r_ref, delta=float(d), nu=nu, n_terms=n_terms)
        out.append(s)
        start = [(pt.centre, pt.half_width) for pt in s.patches]
    return tuple(out)
