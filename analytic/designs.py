"""Default geometries of the close-to-conformal paper's two configurations (units: mm).

The paper does not publish its splines; these are designed to reproduce what it reports (see
``docs/concave_design.md`` for the achieved numbers):

* ``symmetric``: two far-apart symmetric pairs, Hertz radii 2.96 (convex) and -6.81 (concave), relative
  radius 5.23; the particle moves straight down and the Table 1 steps d = 0.60, 0.80, 1.00 give indentations
  close to 0.086, 0.27, 0.46.
* ``close_to_conformal``: a primary pair with radii 41 / -50 (relative ~228), a secondary pair 1.2 mm to its
  right behind a non-plausible pair, the left intersection near radii 23 / -44 once the particle touches
  (d ~ 0.46), Table 1 steps d = 0.46 ... 1.00.

Construction: every target curve is built from a prescribed, smooth curvature profile (a piecewise constant
curvature convolved with a Gaussian, or a graph y = f(x) with a prescribed f''), sampled densely and fitted by
a clamped cubic B-spline (linear least squares in the control points, arc-length parameter, end points and end
tangent directions imposed). The rigid particle is that spline closed by a circular arc tangent to both ends.
Orientation: concave surface left to right, particle clockwise (left normals = outward normals).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy import sparse
from scipy.interpolate import BSpline as _ScipyBSpline
from scipy.sparse.linalg import spsolve

from analytic.curves import BSpline, CircleArc, CompositeCurve, Curve, clamped_uniform_knots

__all__ = ["ConcaveDesign", "ConformalKnobs", "DESIGN_NAMES", "SymmetricKnobs", "build_design", "design",
           "particle_at", "fit_clamped_bspline", "closing_arc",
           "close_particle",
           "YOUNGS_MODULUS", "POISSON_RATIO"]

YOUNGS_MODULUS = 214000.0  # MPa (paper: E = 214 GPa)
POISSON_RATIO = 0.3

DESIGN_NAMES = ("symmetric", "close_to_conformal")


class ConcaveDesign(NamedTuple):
    """One configuration: elastic concave body + rigid particle.

    Attributes:
        name: configuration name.
        concave: top boundary of the elastic body (clamped cubic B-spline, left to right).
        particle: rigid particle at d = 0 (CompositeCurve[BSpline, CircleArc], clockwise).
        direction: unit displacement direction of the particle (straight path).
        body_box: (x_min, x_max, y_bottom) of the elastic body: vertical sides at x_min / x_max from the
            spline ends down to the horizontal bottom y = y_bottom.
        table1_d: the paper's Table 1 displacements d (mm).
        table1_delta: the paper's Table 1 indentations (mm), for comparison only.
        targets: the paper's reported radii (mm), for comparison only.
    """

    name: str
    concave: Curve
    particle: Curve
    direction: np.ndarray
    body_box: tuple[float, float, float]
    table1_d: tuple[float, ...]
    table1_delta: tuple[float, ...]
    targets: dict


def particle_at(design: ConcaveDesign, d: float) -> Curve:
    """The rigid particle translated by d (mm) along the design direction."""
    return design.particle.translated(float(d) * np.asarray(design.direction, dtype=float))


# ----------------------------------------------------------------------------------------------------------
# fitting helpers
def fit_clamped_bspline(points: np.ndarray, n_control: int, *, degree: int = 3) -> BSpline:
    """Least-squares clamped uniform B-spline through dense ordered ``points`` (m, 2).

    The parameter of each point is its normalised arc length; the end control points are the end points and
    the second / second-last control points lie on the end tangents of the point set (so a closing arc
    tangent to the target is tangent to the spline).
    """
    pts = np.asarray(points, dtype=float)
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    u = np.concatenate([[0.0], np.cumsum(seg)]) / seg.sum()
    t0 = pts[1] - pts[0]
    t0 /= np.linalg.norm(t0)
    t1 = pts[-1] - pts[-2]
    t1 /= np.linalg.norm(t1)
    # ~12 fitting points per knot span (uniform in arc length) are plenty for a smooth target
    m_fit = 12 * n_control
    if len(pts) > m_fit:
        uf = np.linspace(0.0, 1.0, m_fit)
        pts = np.column_stack([np.interp(uf, u, pts[:, 0]), np.interp(uf, u, pts[:, 1])])
        u = uf
    knots = clamped_uniform_knots(n_control, degree)
    M = _ScipyBSpline.design_matrix(np.clip(u, 0.0, 1.0), knots, degree).tocsc()
    p0, p1 = pts[0], pts[-1]
    # unknowns: alpha0, alpha1 (scalars), interior control points 2..n-3 (x and y)
    c0, c1 = M[:, [1]].toarray()[:, 0], M[:, [n_control - 2]].toarray()[:, 0]
    e0, e1 = M[:, [0]].toarray()[:, 0], M[:, [n_control - 1]].toarray()[:, 0]
    rhs = pts - np.outer(e0 + c0, p0) - np.outer(e1 + c1, p1)
    inner = M[:, 2: n_control - 2]
    zero = sparse.csc_matrix(inner.shape)
    A = sparse.hstack([
        sparse.csc_matrix(np.column_stack([np.concatenate([c0 * t0[0], c0 * t0[1]]),
                                           np.concatenate([-c1 * t1[0], -c1 * t1[1]])])),
        sparse.vstack([sparse.hstack([inner, zero]), sparse.hstack([zero, inner])]),
    ]).tocsc()
    # normal equations of the (banded, well-conditioned) B-spline least-squares problem
    sol = spsolve((A.T @ A).tocsc(), A.T @ np.concatenate([rhs[:, 0], rhs[:, 1]]))
    n_in = n_control - 4
    cp = np.empty((n_control, 2))
    cp[0], cp[-1] = p0, p1
    cp[1] = p0 + sol[0] * t0
    cp[-2] = p1 - sol[1] * t1
    cp[2:-2, 0] = sol[2: 2 + n_in]
    cp[2:-2, 1] = sol[2 + n_in:]
    return BSpline(cp, degree=degree)


def closing_arc(spline: Curve) -> CircleArc:
    """Clockwise circular arc from the end of ``spline`` back to its start, tangent to the spline's end.

    The circle tangent to the end tangent line and passing through the start point has radius
    r = -|w|^2 / (2 w . r1), w = end - start, r1 the right normal at the end. It is also tangent at the start
    only when the end tangents make equal angles with the chord; :func:`close_particle` enforces that.
    """
    e0, e1 = spline.point([spline.t_min])[0], spline.point([spline.t_max])[0]
    t1 = spline.tangent([spline.t_max])[0]
    r1 = np.array([t1[1], -t1[0]])  # right normal: the centre of a clockwise arc
    w = e1 - e0
    den = 2.0 * float(w @ r1)
    if not den < 0.0:
        raise ValueError("no clockwise closing arc: the spline start lies left of its end tangent")
    r = -float(w @ w) / den
    c = e1 + r * r1
    a_start = float(np.arctan2(*(e1 - c)[::-1]))
    a_end = float(np.arctan2(*(e0 - c)[::-1]))
    span = np.mod(a_start - a_end, 2.0 * np.pi)
    return CircleArc(c, r, a_start, a_start - span)


def close_particle(spline: BSpline) -> CompositeCurve:
    """Close ``spline`` (clockwise lower part of a particle) by :func:`closing_arc`; the spline's second
    control point is re-aligned with the arc tangent at the start (a change of the order of the fit error)."""
    arc = closing_arc(spline)
    t_arc = arc.tangent([1.0])[0]
    cp = spline.control_points.copy()
    cp[1] = cp[0] + np.linalg.norm(cp[1] - cp[0]) * t_arc
    spline = BSpline(cp, degree=spline.degree)
    return CompositeCurve([spline, arc], tol=1e-9)


def _curve_from_curvature(lengths, curvatures, *, start, theta0, sigma, ds=0.002) -> np.ndarray:
    """Points of the curve with piecewise constant curvature (segments of given lengths and curvatures)
    smoothed by a Gaussian of standard deviation ``sigma`` (mm) in arc length (total turning preserved)."""
    total = float(np.sum(lengths))
    n = int(np.ceil(total / ds))
    s = np.linspace(0.0, total, n + 1)
    edges = np.concatenate([[0.0], np.cumsum(lengths)])
    idx = np.clip(np.searchsorted(edges, s, side="right") - 1, 0, len(lengths) - 1)
    k = np.asarray(curvatures, dtype=float)[idx]
    if sigma > 0:
        h = s[1] - s[0]
        half = int(np.ceil(4 * sigma / h))
        ker = np.exp(-0.5 * (np.arange(-half, half + 1) * h / sigma) ** 2)
        ker /= ker.sum()
        k = np.convolve(np.pad(k, half, mode="edge"), ker, mode="valid")
    theta = theta0 + np.concatenate([[0.0], np.cumsum(0.5 * (k[1:] + k[:-1]) * np.diff(s))])
    xy = np.column_stack([np.cos(theta), np.sin(theta)])
    pos = np.concatenate([[[0.0, 0.0]], np.cumsum(0.5 * (xy[1:] + xy[:-1]) * np.diff(s)[:, None], axis=0)])
    return np.asarray(start, dtype=float) + pos


def _smootherstep(u):
    u = np.clip(u, 0.0, 1.0)
    return u**3 * (10.0 - 15.0 * u + 6.0 * u**2)


def _bump(x, c, w):
    """C2 compact bump (1 - ((x - c)/w)^2)^3 on |x - c| < w."""
    u = (np.asarray(x) - c) / w
    return np.where(np.abs(u) < 1.0, (1.0 - u**2) ** 3, 0.0)


def _integrate2(x, f2):
    """f with f(0) = f'(0) = 0 and f'' = f2 on the grid x (containing 0), trapezoidal rule."""
    i0 = int(np.argmin(np.abs(x)))
    dx = np.diff(x)
    f1 = np.concatenate([[0.0], np.cumsum(0.5 * (f2[1:] + f2[:-1]) * dx)])
    f1 -= f1[i0]
    f0 = np.concatenate([[0.0], np.cumsum(0.5 * (f1[1:] + f1[:-1]) * dx)])
    return f0 - f0[i0], f1


# ----------------------------------------------------------------------------------------------------------
# symmetric configuration
_SYM_R_CONVEX = 2.96
_SYM_R_CONCAVE = 6.81
# Line of centres (particle shoulder centre minus concave flank centre) at d = 0, (horizontal, downward),
# least-squares fit of |v + d e| - (R2 - R1) = delta to Table 1 (0.60, 0.086), (0.80, 0.27), (1.00, 0.46)
# for two circles: residuals -0.0008, +0.0016, -0.0008 mm, i.e. within the 2-digit rounding of the table.
_SYM_V = (1.46216665, 3.05351646)


class SymmetricKnobs(NamedTuple):
    """What the symmetric construction takes (mm); the defaults are the paper's design.

    r_convex, r_concave: the particle shoulder and the concave flank radii (the pair's Hertz radii);
    v: the line of centres (shoulder centre minus flank centre) at d = 0, (horizontal, downward);
    centre_flat: a flat inserted at the bottom of the groove (moves both flanks apart by 2 centre_flat);
    groove_extra: length added to the groove's 45-degree straight (deepens the groove by groove_extra/sqrt 2 and
    moves the flanks apart by sqrt 2 groove_extra); depth: the body's depth below the groove bottom.
    """

    r_convex: float = _SYM_R_CONVEX
    r_concave: float = _SYM_R_CONCAVE
    v: tuple[float, float] = _SYM_V
    centre_flat: float = 0.0
    groove_extra: float = 0.0
    depth: float = 20.0


def _symmetric_concave(half_width: float, knobs: SymmetricKnobs | None = None) -> np.ndarray:
    """Right half of the cup (from the centre, left to right): a central groove (fillet R 0.6 turning 0 -> 45
    deg, straight, convex R 2 back to 8 deg) that keeps the particle bottom > 1.2 mm away, a straight flank,
    the concave contact arc R 6.81 (8 -> 55 deg), a convex rim R 3 (55 -> 0 deg) and the flat top (the
    radius, the groove and a central flat from ``knobs``, :class:`SymmetricKnobs`)."""
    k = knobs or SymmetricKnobs()
    rf, rg, rc, rr = 0.6, 2.0, k.r_concave, 3.0
    a0, a1, a2 = np.radians(45.0), np.radians(8.0), np.radians(55.0)
    lengths = [rf * a0, 0.6 + k.groove_extra, rg * (a0 - a1), 0.5, rc * (a2 - a1), rr * a2, 40.0]
    curv = [1.0 / rf, 0.0, -1.0 / rg, 0.0, 1.0 / rc, -1.0 / rr, 0.0]
    if k.centre_flat > 0.0:
        lengths, curv = [k.centre_flat, *lengths], [0.0, *curv]
    pts = _curve_from_curvature(lengths, curv, start=(0.0, 0.0), theta0=0.0, sigma=0.15)
    pts = pts[pts[:, 0] <= half_width]
    return pts


def _symmetric_particle(shoulder_x: float, r_convex: float = _SYM_R_CONVEX) -> np.ndarray:
    """Lower part of the particle, clockwise from the right side (heading down) to the left side (heading
    up): shoulder arc R 2.96 (90 deg -> 5 deg normal), flat bottom arc, symmetric left shoulder."""
    r1, beta = r_convex, np.radians(5.0)
    rb = r1 + shoulder_x / np.sin(beta)
    lengths = [r1 * (np.pi / 2 - beta), rb * 2 * beta, r1 * (np.pi / 2 - beta)]
    curv = [-1.0 / r1, -1.0 / rb, -1.0 / r1]
    return _curve_from_curvature(lengths, curv, start=(shoulder_x + r1, 0.0), theta0=-np.pi / 2, sigma=0.1)


def _mirror_symmetric(spl: BSpline) -> BSpline:
    """Exact mirror symmetry about x = 0 of a spline traversed across the axis: with symmetric (uniform)
    knots, cp[i] and the mirror image of cp[n-1-i] are averaged."""
    cp = spl.control_points
    mirrored = cp[::-1] * np.array([-1.0, 1.0])
    return BSpline(0.5 * (cp + mirrored), degree=spl.degree)


def _center_of_curvature(curve: Curve, t: float) -> np.ndarray:
    return curve.point([t])[0] + curve.normal([t])[0] / curve.curvature([t])[0]


def _middle_half(points: np.ndarray, s_start: float, length: float) -> np.ndarray:
    """The raw points of the middle half of a segment [s_start, s_start + length] (arc length along ``points``)."""
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    keep = (s >= s_start + 0.25 * length) & (s <= s_start + 0.75 * length)
    return points[keep]


def _arc_centre(points: np.ndarray) -> np.ndarray:
    """Centre of the least-squares circle through ``points`` (Kasa's linear fit)."""
    x, y = points[:, 0], points[:, 1]
    A = np.column_stack([2.0 * x, 2.0 * y, np.ones_like(x)])
    sol = np.linalg.lstsq(A, x * x + y * y, rcond=None)[0]
    return sol[:2]


def _symmetric(knobs: SymmetricKnobs | None = None, *, name: str = "symmetric") -> ConcaveDesign:
    k = knobs or SymmetricKnobs()
    half_width = 15.0
    right = _symmetric_concave(half_width, k)
    paper = k == SymmetricKnobs()
    a0, a1, a2 = np.radians(45.0), np.radians(8.0), np.radians(55.0)
    flank_start = k.centre_flat + 0.6 * a0 + 0.6 + k.groove_extra + 2.0 * (a0 - a1) + 0.5
    flank = _middle_half(right, flank_start, k.r_concave * (a2 - a1))
    right = np.vstack([right, [[half_width, right[-1, 1]]]]) if right[-1, 0] < half_width else right
    left = right[::-1].copy()
    left[:, 0] *= -1.0
    pts = np.vstack([left[:-1], right])
    concave = _mirror_symmetric(fit_clamped_bspline(pts, 240))
    # flank centre of curvature (right side): at the flank arc mid-point (35 deg normal)
    # (a family member: the centre of the raw flank arc's middle half, smooth in the knobs; the spline's local
    # curvature carries the fit's ripple)
    if paper:
        pr = concave.project(np.array([[3.6, -0.5]]))
        c2 = _center_of_curvature(concave, pr.t[0])
    else:
        c2 = _arc_centre(flank)
    # particle: shoulder centre x = c2x + v_x (two passes correct the smoothing shift), then translate
    v = k.v
    sx = c2[0] + v[0]
    for _ in range(3):
        lower = _symmetric_particle(sx, k.r_convex)
        spl = _mirror_symmetric(fit_clamped_bspline(lower, 120))
        if paper:
            q = spl.project(np.array([[sx + 2.0, -2.0]]))
            c1 = _center_of_curvature(spl, q.t[0])
        else:
            c1 = _arc_centre(_middle_half(lower, 0.0, k.r_convex * (0.5 * np.pi - np.radians(5.0))))
        sx += (c2[0] + v[0]) - c1[0]
    shift = np.array([0.0, (c2[1] - v[1]) - c1[1]])
    spl = spl.translated(shift)
    particle = close_particle(spl)
    return ConcaveDesign(
        name=name, concave=concave, particle=particle, direction=np.array([0.0, -1.0]),
        body_box=(-half_width, half_width, -k.depth), table1_d=(0.60, 0.80, 1.00),
        table1_delta=(0.086, 0.27, 0.46),
        targets={"radius_convex": 2.96, "radius_concave": -6.81, "relative_radius": 5.23})


# ----------------------------------------------------------------------------------------------------------
# close-to-conformal configuration
_CC_R_CONVEX, _CC_R_CONCAVE = 41.0, 50.0  # primary pair
_CC_R_CONVEX_I, _CC_R_CONCAVE_I = 23.0, 44.0  # left intersection
_CC_D0 = 0.45957  # initial vertical gap at the primary pair: delta(0.46) = 0.00043 as in Table 1
_CC_X2 = 2.4  # secondary pair abscissa
_CC_XM = 1.3  # where the non-plausible maximum height is imposed
_CC_EPS = 0.006  # secondary gap once the primary touches (relative height of the secondary minimum)
_CC_HM = 0.015  # height of the non-plausible maximum between the pairs (above the primary)
_CC_RAMP = 0.25  # length of the curvature ramp to the left of the primary
_CC_INFO: dict = {}


class ConformalKnobs(NamedTuple):
    """What the close-to-conformal construction takes (mm); the defaults are the paper's design.

    r_convex, r_concave: the primary pair's radii (the concave one as a magnitude); x2: the secondary pair's
    abscissa (the bumps between the pairs and the far ramp scale with x2/2.4); eps: the secondary gap once the
    primary touches; d0: the initial vertical gap at the primary; depth: the body's depth below the primary.
    """

    r_convex: float = _CC_R_CONVEX
    r_concave: float = _CC_R_CONCAVE
    x2: float = _CC_X2
    eps: float = _CC_EPS
    d0: float = _CC_D0
    depth: float = 20.0


def _cc_profiles(x: np.ndarray, knobs: ConformalKnobs | None = None):
    """Graph second derivatives f'' (concave surface) and q'' (particle lower surface).

    f'' = 1/50 at the primary (x = 0), ramping to 1/44 over 0.25 mm on the left, plus a concave bump
    between the pairs (where the concave side is more curved: the non-plausible pair). q'' = f'' + G'' with
    the relative curvature G'' = 1/41 - 1/50 at x = 0 ramping on the left to 1/23 - 1/44, and on the right
    three compact bumps whose amplitudes solve G'(x2) = 0, G(x2) = eps, G(x_m) = h_m (linear system),
    then ramping to 1/23 - 1/50 beyond x = 3 (so that the far gap opens like a relative radius ~ 40 mm).
    """
    k = knobs or ConformalKnobs()
    sc = k.x2 / _CC_X2  # 1.0 exactly for the paper's design
    g0 = 1.0 / k.r_convex - 1.0 / k.r_concave
    g1 = 1.0 / _CC_R_CONVEX_I - 1.0 / _CC_R_CONCAVE_I
    ramp_l = _smootherstep(-x / _CC_RAMP)
    f2 = 1.0 / k.r_concave + (1.0 / _CC_R_CONCAVE_I - 1.0 / k.r_concave) * ramp_l
    g_far = 1.0 / 23.0 - 1.0 / 50.0
    ramp_r = _smootherstep((x - 3.0 * sc) / (1.5 * sc))
    base = g0 + (g1 - g0) * ramp_l + (g_far - g0) * ramp_r
    bumps = [_bump(x, 0.6 * sc, 0.6 * sc), _bump(x, _CC_XM * sc, 0.6 * sc), _bump(x, k.x2, 0.6 * sc)]
    # linear conditions on the amplitudes
    i2 = int(np.argmin(np.abs(x - k.x2)))
    im = int(np.argmin(np.abs(x - _CC_XM * sc)))
    G_base, G1_base = _integrate2(x, base)
    cols = [_integrate2(x, b) for b in bumps]
    A = np.array([[c[1][i2] for c in cols], [c[0][i2] for c in cols], [c[0][im] for c in cols]])
    rhs = np.array([-G1_base[i2], k.eps - G_base[i2], _CC_HM - G_base[im]])
    amp = np.linalg.solve(A, rhs)
    if k == ConformalKnobs():  # the paper's design only (a family member does not overwrite it)
        _CC_INFO["bump_amplitudes"] = amp.tolist()
    g2 = base + sum(a * b for a, b in zip(amp, bumps, strict=True))
    neg = -amp[1] * bumps[1] if amp[1] < 0 else 0.0 * x  # concave side takes the negative bump
    f2 = f2 + neg
    q2 = f2 + g2
    return f2, q2


def _close_to_conformal(knobs: ConformalKnobs | None = None, *, name: str = "close_to_conformal") -> ConcaveDesign:
    k = knobs or ConformalKnobs()
    half_width = 15.0
    x = np.linspace(-half_width, half_width, 30001)
    f2, q2 = _cc_profiles(x, k)
    f, _ = _integrate2(x, f2)
    q, q1 = _integrate2(x, q2)
    concave = fit_clamped_bspline(np.column_stack([x, f]), 400)
    # particle lower part on [xa, xb]: choose xb so the end tangents are symmetric about the chord
    xa = -10.0
    ia = int(np.argmin(np.abs(x - xa)))
    ang = np.arctan(q1)
    ib_range = np.flatnonzero(x > 5.0)
    chord = np.arctan2(q[ib_range] - q[ia], x[ib_range] - x[ia])
    mis = (ang[ib_range] - chord) - (chord - ang[ia])
    j = ib_range[int(np.argmin(np.abs(mis)))]
    # refine xb to the exact root of the mismatch by linear interpolation on a fine local grid
    xs = np.linspace(x[j - 1], x[j + 1], 2001)
    qs = np.interp(xs, x, q)
    q1s = np.interp(xs, x, q1)
    chord_s = np.arctan2(qs - q[ia], xs - x[ia])
    ms = (np.arctan(q1s) - chord_s) - (chord_s - ang[ia])
    xb = float(xs[int(np.argmin(np.abs(ms)))])
    xp = np.linspace(xb, xa, 20001)  # clockwise: bottom runs right to left
    yp = np.interp(xp, x, q) + k.d0
    # the fit imposes the end tangents of the point set: use the exact graph tangents there
    spl = fit_clamped_bspline(np.column_stack([xp, yp]), 300)
    spl = _with_end_tangents(spl, np.interp(xb, x, q1), np.interp(xa, x, q1))
    particle = close_particle(spl)
    return ConcaveDesign(
        name=name, concave=concave, particle=particle, direction=np.array([0.0, -1.0]),
        body_box=(-half_width, half_width, -k.depth), table1_d=(0.46, 0.47, 0.48, 0.50, 0.70, 1.00),
        table1_delta=(0.00043, 0.010, 0.020, 0.040, 0.24, 0.54),
        targets={"radius_convex": 41.0, "radius_concave": -50.0, "relative_radius": 233.0,
                 "intersection_radius_convex": 23.0, "intersection_radius_concave": -44.0,
                 "intersection_relative_radius": 50.0})


def _with_end_tangents(spl: BSpline, slope_start: float, slope_end: float) -> BSpline:
    """Re-align the 2nd and 2nd-last control points with exact end tangents (travel right to left)."""
    cp = spl.control_points.copy()
    for i_end, i_in, slope in ((0, 1, slope_start), (-1, -2, slope_end)):
        t = -np.array([1.0, slope]) / np.hypot(1.0, slope)  # direction of travel (decreasing x)
        dist = np.linalg.norm(cp[i_in] - cp[i_end])
        cp[i_in] = cp[i_end] + (dist if i_end == 0 else -dist) * t
    return BSpline(cp, degree=spl.degree)


_CACHE: dict[str, ConcaveDesign] = {}


def build_design(knobs: SymmetricKnobs | ConformalKnobs, *, name: str) -> ConcaveDesign:
    """A family member built by the construction of its kind (:mod:`analytic.design_family` chooses the knobs);
    the default knobs give the paper's design, float for float."""
    if isinstance(knobs, SymmetricKnobs):
        return _symmetric(knobs, name=name)
    return _close_to_conformal(knobs, name=name)


def design(name: str) -> ConcaveDesign:
    """The default design ``name`` in DESIGN_NAMES (built once per process, then cached)."""
    if name not in DESIGN_NAMES:
        raise ValueError(f"name must be one of {list(DESIGN_NAMES)}, got {name!r}")
    if name not in _CACHE:
        _CACHE[name] = _symmetric() if name == "symmetric" else _close_to_conformal()
    return _CACHE[name]
