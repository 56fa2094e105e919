"""Local contact problem (LCP) between two planar curves: all contact candidates, classified.

Eq. (2) of the close-to-conformal paper (Gay Neto & Wriggers master-master pairs): find (zeta, theta) with

    F1 = (A(zeta) - B(theta)) . A'(zeta) = 0,      F2 = -(A(zeta) - B(theta)) . B'(theta) = 0.

F is the gradient of phi = |A - B|^2 / 2, with Hessian
H = [[|A'|^2 + (A - B).A'', -A'.B'], [-A'.B', |B'|^2 - (A - B).B'']].

Sign conventions (see :mod:`analytic.curves`): both curves are oriented so that their LEFT normal is the
OUTWARD normal of their body (elastic concave body A: left to right; rigid particle B: clockwise).
The signed gap of a candidate is g = (A - B) . n_B (> 0 separated, < 0 overlapping: indentation delta = -g).

Classification of a solution (re-derived from "plausible = local minimiser of the distance when separated,
local maximiser of the penetration when overlapping"): reduce phi over zeta (the foot of B(theta) on A, a
minimum: H11 > 0); the reduced signed gap g(theta) must have a local MINIMUM, i.e.

* separated (g > 0): H positive definite (H11 > 0, det H > 0);
* overlapping (g < 0): H11 > 0, H22 > 0 and det H < 0 (both feet are closest points, the reduced
  squared distance is maximal);
* and the normals are opposite (n_A . n_B < 0), otherwise the pair faces away from each other.

Everything else is non-plausible. Intersections (A = B) are reported separately.

Hertz radii: with the outward orientation, a body's Hertz radius (convex > 0, concave < 0) is
R = -1 / kappa, kappa the signed curvature of its curve; the relative radius is 1/R = 1/R_A + 1/R_B (eq. 7).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from typing import NamedTuple

import numpy as np

from analytic.curves import Curve

__all__ = ["ContactPair", "Intersection", "LCPResult", "find_contact_pairs", "hertz_radius",
           "relative_radius", "cli"]


class ContactPair(NamedTuple):
    """One solution of eq. (2) that is not an intersection (units mm).

    Attributes:
        t_a, t_b: parameters zeta (curve A) and theta (curve B).
        point_a, point_b: (2,) the two points.
        normal: (2,) unit common normal, the outward normal of A at point_a (points from A towards B).
        gap: signed gap (A - B) . n_B, > 0 separated, < 0 overlapping.
        delta: indentation max(-gap, 0).
        radius_a, radius_b: Hertz radii (convex > 0, concave < 0; inf when straight).
        relative_radius: R with 1/R = 1/R_a + 1/R_b (inf for parallel flat faces; negative means the
            concave surface is more curved than the convex one: no Hertz contact there).
        plausible: classification (see the module docstring).
        hessian_eigs: (2,) eigenvalues of the Hessian of |A - B|^2 / 2 in (zeta, theta).
    """

    t_a: float
    t_b: float
    point_a: np.ndarray
    point_b: np.ndarray
    normal: np.ndarray
    gap: float
    delta: float
    radius_a: float
    radius_b: float
    relative_radius: float
    plausible: bool
    hessian_eigs: np.ndarray

    def as_dict(self) -> dict:
        d = self._asdict()
        return {k: (v.tolist() if isinstance(v, np.ndarray) else _num(v)) for k, v in d.items()}


class Intersection(NamedTuple):
    """A crossing A(t_a) = B(t_b) of the two curves."""

    t_a: float
    t_b: float
    point: np.ndarray
    radius_a: float
    radius_b: float
    relative_radius: float
    angle_deg: float  # angle between the tangents at the crossing

    def as_dict(self) -> dict:
        d = self._asdict()
        return {k: (v.tolist() if isinstance(v, np.ndarray) else _num(v)) for k, v in d.items()}


class LCPResult(NamedTuple):
    """All solutions of eq. (2): plausible pairs (sorted by gap), non-plausible ones (by |gap|), and
    intersections (by x)."""

    pairs: list[ContactPair]
    non_plausible: list[ContactPair]
    intersections: list[Intersection]

    def as_dict(self) -> dict:
        return {"pairs": [p.as_dict() for p in self.pairs],
                "non_plausible": [p.as_dict() for p in self.non_plausible],
                "intersections": [p.as_dict() for p in self.intersections]}


def _num(v):
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    v = float(v)
    return v if math.isfinite(v) else (None if math.isnan(v) else ("inf" if v > 0 else "-inf"))


def hertz_radius(curve: Curve, t) -> np.ndarray:
    """Hertz radius (mm) of the body bounded by ``curve`` (outward-oriented): -1/curvature, convex > 0."""
    k = np.asarray(curve.curvature(t))
    with np.errstate(divide="ignore"):
        return np.where(k == 0.0, np.inf, -1.0 / np.where(k == 0.0, 1.0, k))


def relative_radius(r1, r2):
    """Relative radius R, 1/R = 1/R1 + 1/R2 (eq. 7); inf when both curvatures cancel."""
    inv = 1.0 / np.asarray(r1, dtype=float) + 1.0 / np.asarray(r2, dtype=float)
    with np.errstate(divide="ignore"):
        return np.where(inv == 0.0, np.inf, 1.0 / np.where(inv == 0.0, 1.0, inv))


def _residual(ca: Curve, cb: Curve, za, tb):
    a, a1, a2 = ca.point(za), ca.derivative(za, 1), ca.derivative(za, 2)
    b, b1, b2 = cb.point(tb), cb.derivative(tb, 1), cb.derivative(tb, 2)
    r = a - b
    f = np.column_stack([np.einsum("ij,ij->i", r, a1), -np.einsum("ij,ij->i", r, b1)])
    h11 = np.einsum("ij,ij->i", a1, a1) + np.einsum("ij,ij->i", r, a2)
    h22 = np.einsum("ij,ij->i", b1, b1) - np.einsum("ij,ij->i", r, b2)
    h12 = -np.einsum("ij,ij->i", a1, b1)
    return f, h11, h12, h22, r, a1, b1


def _newton(ca, cb, z, t, box, step_cap, tol, solve_intersection=False, max_iter=60):
    """Vectorised trust-region Newton on F = grad phi (or on A - B); returns (z, t, converged)."""
    (za0, za1), (tb0, tb1) = box
    conv = np.zeros(len(z), dtype=bool)
    for _ in range(max_iter):
        act = ~conv
        if not act.any():
            break
        zi, ti = z[act], t[act]
        f, h11, h12, h22, r, a1, b1 = _residual(ca, cb, zi, ti)
        if solve_intersection:
            # G = A - B, J = [A', -B']
            j11, j12, j21, j22 = a1[:, 0], -b1[:, 0], a1[:, 1], -b1[:, 1]
            g1, g2 = r[:, 0], r[:, 1]
        else:
            j11, j12, j21, j22 = h11, h12, h12, h22
            g1, g2 = f[:, 0], f[:, 1]
        det = j11 * j22 - j12 * j21
        with np.errstate(divide="ignore", invalid="ignore"):
            dz = -(j22 * g1 - j12 * g2) / det
            dt = -(-j21 * g1 + j11 * g2) / det
        ok = np.isfinite(dz) & np.isfinite(dt)
        dz, dt = np.where(ok, dz, 0.0), np.where(ok, dt, 0.0)
        scale = np.maximum(1.0, np.maximum(np.abs(dz) / step_cap[0], np.abs(dt) / step_cap[1]))
        zn = np.clip(zi + dz / scale, za0, za1)
        tn = np.clip(ti + dt / scale, tb0, tb1)
        moved = np.abs(zn - zi) + np.abs(tn - ti)
        z[act], t[act] = zn, tn
        idx = np.flatnonzero(act)
        conv[idx[(moved <= tol) & ok]] = True
        conv[idx[~ok]] = True  # singular: stop, residual check below rejects it
    return z, t


def find_contact_pairs(curve_a: Curve, curve_b: Curve, *, t_range_a=None, t_range_b=None,
                       n_samples: int = 400, residual_tol: float = 1e-11) -> LCPResult:
    """Find and classify all solutions of eq. (2) in the given parameter ranges.

    Method: sample the normalised residual F/(|A'|, |B'|) and |A - B| on an n_samples x n_samples grid;
    start a trust-region Newton (steps capped at 2 grid cells) from every grid cell where both components of
    F change sign and from every local minimum of |F| and of |A - B|; keep the converged roots (|F| /
    (|A'| |B'|)^(1/2) <= residual_tol, in mm) and remove duplicates.

    Args:
        curve_a: body A boundary (e.g. the concave elastic surface), outward-oriented.
        curve_b: body B boundary (e.g. the rigid particle), outward-oriented.
        t_range_a, t_range_b: (lo, hi) parameter ranges; default the whole curves.
        n_samples: grid points per parameter (>= 16).
        residual_tol: acceptance tolerance on the normalised residual (mm).

    Returns:
        LCPResult(pairs, non_plausible, intersections); pairs sorted by gap.
    """
    if int(n_samples) < 16:
        raise ValueError(f"n_samples must be >= 16, got {n_samples}")
    ra = (curve_a.t_min, curve_a.t_max) if t_range_a is None else tuple(map(float, t_range_a))
    rb = (curve_b.t_min, curve_b.t_max) if t_range_b is None else tuple(map(float, t_range_b))
    for name, (lo, hi), c in (("t_range_a", ra, curve_a), ("t_range_b", rb, curve_b)):
        if not (c.t_min <= lo < hi <= c.t_max):
            raise ValueError(f"{name} must satisfy {c.t_min} <= lo < hi <= {c.t_max}, got {(lo, hi)}")
    n = int(n_samples)
    zs = np.linspace(*ra, n)
    ts = np.linspace(*rb, n)
    A, A1 = curve_a.point(zs), curve_a.derivative(zs, 1)
    B, B1 = curve_b.point(ts), curve_b.derivative(ts, 1)
    R = A[:, None, :] - B[None, :, :]  # (n, n, 2)
    sa = np.linalg.norm(A1, axis=1)
    sb = np.linalg.norm(B1, axis=1)
    F1 = np.einsum("ijk,ik->ij", R, A1) / sa[:, None]
    F2 = -np.einsum("ijk,jk->ij", R, B1) / sb[None, :]
    dist = np.linalg.norm(R, axis=2)

    def sign_change(F):
        c = np.stack([F[:-1, :-1], F[1:, :-1], F[:-1, 1:], F[1:, 1:]])
        return (c.min(axis=0) <= 0.0) & (c.max(axis=0) >= 0.0)

    def local_min(V):
        P = np.pad(V, 1, constant_values=np.inf)
        m = np.ones_like(V, dtype=bool)
        for di in (-1, 0, 1):
            for dj in (-1, 0, 1):
                if di or dj:
                    m &= V <= P[1 + di: 1 + di + n, 1 + dj: 1 + dj + n]
        return m

    cells = np.argwhere(sign_change(F1) & sign_change(F2))
    half = (0.5 * (zs[1] - zs[0]), 0.5 * (ts[1] - ts[0]))
    starts = [np.column_stack([zs[cells[:, 0]] + half[0], ts[cells[:, 1]] + half[1]])]
    fm = np.argwhere(local_min(np.hypot(F1, F2)))
    starts.append(np.column_stack([zs[fm[:, 0]], ts[fm[:, 1]]]))
    starts = np.unique(np.concatenate(starts), axis=0)
    cap = (2.0 * (zs[1] - zs[0]), 2.0 * (ts[1] - ts[0]))
    box = (ra, rb)
    z, t = _newton(curve_a, curve_b, starts[:, 0].copy(), starts[:, 1].copy(), box, cap, 1e-15)
    # polish with full Newton steps (the capped iteration may stop early in flat, near-conformal valleys)
    z, t = _newton(curve_a, curve_b, z, t, box, (np.inf, np.inf), 1e-15, max_iter=12)
    # intersections: Newton on A - B from the local minima of the distance
    dm = np.argwhere(local_min(dist))
    zi, ti = _newton(curve_a, curve_b, zs[dm[:, 0]].astype(float), ts[dm[:, 1]].astype(float), box, cap,
                     1e-15, solve_intersection=True)

    length_scale = max(1.0, float(np.ptp(np.concatenate([A, B]), axis=0).max()))
    # Newton on F converges only linearly to a shallow crossing (det H ~ sin^2 of the crossing angle):
    # starts that ended near A = B are also re-solved as intersections (Newton on A - B)
    near = np.linalg.norm(curve_a.point(z) - curve_b.point(t), axis=1) <= 1e-4 * length_scale
    if near.any():
        z2, t2 = _newton(curve_a, curve_b, z[near].copy(), t[near].copy(), box, cap, 1e-15,
                         solve_intersection=True)
        hit = np.linalg.norm(curve_a.point(z2) - curve_b.point(t2), axis=1) <= 1e-12 * length_scale
        zi, ti = np.concatenate([zi, z2[hit]]), np.concatenate([ti, t2[hit]])
    roots = []
    for zz, tt in zip(np.concatenate([z, zi]), np.concatenate([t, ti]), strict=True):
        f, h11, h12, h22, r, a1, b1 = _residual(curve_a, curve_b, [zz], [tt])
        res = np.hypot(f[0, 0] / np.linalg.norm(a1), f[0, 1] / np.linalg.norm(b1))
        if res <= residual_tol * length_scale:
            roots.append((zz, tt))
    # de-duplicate by the two points (closed curves repeat at the parameter ends)
    uniq: list[tuple[float, float]] = []
    pts_a, pts_b = [], []
    dup_tol = 1e-7 * length_scale
    for zz, tt in roots:
        pa, pb = curve_a.point([zz])[0], curve_b.point([tt])[0]
        if any(np.linalg.norm(pa - qa) < dup_tol and np.linalg.norm(pb - qb) < dup_tol
               for qa, qb in zip(pts_a, pts_b, strict=True)):
            continue
        uniq.append((zz, tt))
        pts_a.append(pa)
        pts_b.append(pb)

    pairs, non_plausible, crossings = [], [], []
    inter_tol = 1e-10 * length_scale
    touch_tol = 1e-7 * length_scale  # closer pairs are treated as crossings (|gap| < ~1e-6 mm)
    for zz, tt in uniq:
        f, h11, h12, h22, r, a1, b1 = _residual(curve_a, curve_b, [zz], [tt])
        pa, pb = curve_a.point([zz])[0], curve_b.point([tt])[0]
        rad_a = float(hertz_radius(curve_a, [zz])[0])
        rad_b = float(hertz_radius(curve_b, [tt])[0])
        rel = float(relative_radius(rad_a, rad_b))
        if np.linalg.norm(pa - pb) <= touch_tol:
            # a crossing (or a root of F left ~1e-6 mm off a very shallow crossing: polish it on A - B)
            if np.linalg.norm(pa - pb) > inter_tol:
                z2, t2 = _newton(curve_a, curve_b, np.array([zz]), np.array([tt]), box, cap, 1e-15,
                                 solve_intersection=True)
                q_a, q_b = curve_a.point(z2)[0], curve_b.point(t2)[0]
                if np.linalg.norm(q_a - q_b) > inter_tol:
                    continue  # neither a converged pair nor a crossing
                zz, tt, pa, pb = float(z2[0]), float(t2[0]), q_a, q_b
                rad_a = float(hertz_radius(curve_a, [zz])[0])
                rad_b = float(hertz_radius(curve_b, [tt])[0])
                rel = float(relative_radius(rad_a, rad_b))
            if any(np.linalg.norm(pa - c.point) < dup_tol for c in crossings):
                continue
            ta, tb = curve_a.tangent([zz])[0], curve_b.tangent([tt])[0]
            ang = math.degrees(math.acos(min(1.0, abs(float(ta @ tb)))))
            crossings.append(Intersection(float(zz), float(tt), 0.5 * (pa + pb), rad_a, rad_b, rel, ang))
            continue
        na, nb = curve_a.normal([zz])[0], curve_b.normal([tt])[0]
        gap = float((pa - pb) @ nb)
        H = np.array([[h11[0], h12[0]], [h12[0], h22[0]]])
        det = float(np.linalg.det(H))
        if gap > 0.0:
            plausible = h11[0] > 0.0 and det > 0.0
        else:
            plausible = h11[0] > 0.0 and h22[0] > 0.0 and det < 0.0
        plausible = bool(plausible and float(na @ nb) < 0.0)
        pair = ContactPair(float(zz), float(tt), pa, pb, na, gap, max(-gap, 0.0), rad_a, rad_b, rel,
                           plausible, np.linalg.eigvalsh(H))
        (pairs if plausible else non_plausible).append(pair)
    pairs.sort(key=lambda p: p.gap)
    non_plausible.sort(key=lambda p: abs(p.gap))  # the relevant (near) ones first
    crossings.sort(key=lambda c: c.point[0])
    return LCPResult(pairs, non_plausible, crossings)


def _print_text(res: LCPResult, out) -> None:
    for label, items in (("plausible", res.pairs), ("non-plausible", res.non_plausible)):
        for p in items:
            print(f"{label:13s} A{p.point_a.round(5).tolist()} B{p.point_b.round(5).tolist()} "
                  f"gap={p.gap:+.6g} R_a={p.radius_a:.6g} R_b={p.radius_b:.6g} R={p.relative_radius:.6g}",
                  file=out)
    for c in res.intersections:
        print(f"{'intersection':13s} {c.point.round(5).tolist()} R_a={c.radius_a:.6g} R_b={c.radius_b:.6g} "
              f"R={c.relative_radius:.6g} angle={c.angle_deg:.4g} deg", file=out)


def cli(argv: list[str], *, parser_class=argparse.ArgumentParser) -> int:
    """``lcp --config {symmetric,close_to_conformal} --d D [--json] [--n-samples N]``: solve eq. (2) between
    the design's concave surface (A) and its particle moved by d along the design direction (B). ``parser_class``:
    the command line's (``python -m analytic``: one ``error:`` line)."""
    from analytic.designs import DESIGN_NAMES, design, particle_at

    parser = parser_class(prog="python -m analytic lcp", description=cli.__doc__)
    parser.add_argument("--config", required=True, help=f"one of {', '.join(DESIGN_NAMES)}")
    parser.add_argument("--d", type=float, default=0.0,
                        help="particle displacement along the path (mm), [0, 2]")
    parser.add_argument("--n-samples", type=int, default=400, help="grid points per parameter, >= 16")
    parser.add_argument("--json", action="store_true", help="print JSON")
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return int(exc.code or 0)
    if args.config not in DESIGN_NAMES:
        print(f"error: config must be one of {list(DESIGN_NAMES)}, got {args.config!r}", file=sys.stderr)
        return 2
    if not (math.isfinite(args.d) and 0.0 <= args.d <= 2.0):
        print(f"error: d must be in [0, 2] (mm), got {args.d}", file=sys.stderr)
        return 2
    try:
        des = design(args.config)
        res = find_contact_pairs(des.concave, particle_at(des, args.d), n_samples=args.n_samples)
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    if args.json:
        print(json.dumps({"config": args.config, "d": args.d, **res.as_dict()}, indent=2))
    else:
        _print_text(res, sys.stdout)
    return 0
