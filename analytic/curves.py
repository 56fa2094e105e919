"""Parametric planar curves with closest-point projection (shared by ``meshes/`` and ``fem/``).

Conventions (units: mm):

* A curve ``C(t)``, ``t`` in ``[t_min, t_max]``, has the unit tangent ``T = C'/|C'|`` and the unit LEFT normal
  ``N = (-T_y, T_x)`` (tangent rotated by +90 deg).
* Signed curvature ``kappa = (x' y'' - y' x'') / |C'|^3`` is > 0 when the curve turns left, i.e. towards
  ``N``; ``radius = 1 / kappa`` (``inf`` on straight parts).
* A body's boundary is oriented so that ``N`` is the body's OUTWARD normal (elastic concave body: top spline
  runs left to right; closed rigid particle: clockwise). Then ``project(x).distance`` is > 0 outside the body
  and < 0 inside it: against the rigid particle it is the signed gap.
* With that orientation the Hertz radius of the body (convex > 0, concave < 0) is ``-radius(t)``
  (see :func:`analytic.lcp.hertz_radius`).

Projection (:meth:`Curve.project`) is global: the squared distance is sampled on a parameter grid fine
enough to resolve every local minimum, the few best sampled local minima are refined by a safeguarded Newton
method on ``f(t) = (C(t) - x) . C'(t) = 0`` (bracketed by the neighbouring samples); the closest is kept.
"""

from __future__ import annotations

import abc
from typing import NamedTuple

import numpy as np
from scipy.interpolate import BSpline as _ScipyBSpline

__all__ = [
    "Projection",
    "Curve",
    "BSpline",
    "CircleArc",
    "Line",
    "Ellipse",
    "CompositeCurve",
    "clamped_uniform_knots",
]

_CHUNK_ENTRIES = 2_000_000  # points x samples per vectorised projection chunk (memory bound)


class Projection(NamedTuple):
    """Closest point of a set of points on a curve.

    Attributes:
        t: (n,) curve parameter of the foot point.
        foot: (n, 2) closest point on the curve.
        distance: (n,) signed distance, > 0 on the side the left normal points to.
        normal: (n, 2) unit left normal at the foot.
    """

    t: np.ndarray
    foot: np.ndarray
    distance: np.ndarray
    normal: np.ndarray


def _as_t(t) -> np.ndarray:
    return np.atleast_1d(np.asarray(t, dtype=float))


def _as_points(points) -> np.ndarray:
    p = np.asarray(points, dtype=float)
    if p.ndim == 1:
        p = p.reshape(1, 2)
    if p.ndim != 2 or p.shape[1] != 2:
        raise ValueError(f"points must have shape (n, 2), got {p.shape}")
    return p


class Curve(abc.ABC):
    """Abstract parametric planar curve ``C(t)``, ``t`` in ``[t_min, t_max]``."""

    t_min: float = 0.0
    t_max: float = 1.0

    # -- to implement -------------------------------------------------------------------------------------
    @abc.abstractmethod
    def point(self, t) -> np.ndarray:
        """Return C(t), shape (n, 2)."""

    @abc.abstractmethod
    def derivative(self, t, order: int = 1) -> np.ndarray:
        """Return d^order C / dt^order, shape (n, 2) (order 1 or 2 at least)."""

    @abc.abstractmethod
    def translated(self, shift) -> Curve:
        """Return the curve rigidly translated by ``shift`` (2,) (mm)."""

    @abc.abstractmethod
    def sample_parameters(self) -> np.ndarray:
        """Increasing parameter grid (including both ends) fine enough to separate all local minima of the
        distance to any point (used as the coarse stage of :meth:`project`)."""

    # -- derived quantities -------------------------------------------------------------------------------
    def _samples(self) -> tuple[np.ndarray, np.ndarray]:
        """(parameters, points) of the coarse projection grid, computed once per (immutable) curve."""
        cache = self.__dict__.get("_sample_cache")
        if cache is None:
            ts = self.sample_parameters()
            cache = (ts, self.point(ts))
            self.__dict__["_sample_cache"] = cache
        return cache

    @property
    def is_closed(self) -> bool:
        """True when C(t_min) == C(t_max) (to 1e-12 relative to the curve size)."""
        ends = self.point([self.t_min, self.t_max])
        scale = max(1.0, float(np.ptp(self._samples()[1], axis=0).max()))
        return bool(np.linalg.norm(ends[0] - ends[1]) <= 1e-12 * scale)

    def tangent(self, t) -> np.ndarray:
        """Unit tangent C'/|C'|, shape (n, 2)."""
        d = self.derivative(t, 1)
        return d / np.linalg.norm(d, axis=1)[:, None]

    def normal(self, t) -> np.ndarray:
        """Unit LEFT normal (tangent rotated by +90 deg), shape (n, 2)."""
        tg = self.tangent(t)
        return np.column_stack([-tg[:, 1], tg[:, 0]])

    def curvature(self, t) -> np.ndarray:
        """Signed curvature (x'y'' - y'x'')/|C'|^3 (1/mm), > 0 when turning left (towards the normal)."""
        d1 = self.derivative(t, 1)
        d2 = self.derivative(t, 2)
        cross = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
        return cross / np.linalg.norm(d1, axis=1) ** 3

    def radius(self, t) -> np.ndarray:
        """Signed radius of curvature 1/curvature (mm); ``inf`` where the curvature vanishes."""
        k = self.curvature(t)
        with np.errstate(divide="ignore"):
            return np.where(k == 0.0, np.inf, 1.0 / np.where(k == 0.0, 1.0, k))

    def sample(self, n: int) -> np.ndarray:
        """Return n points at uniformly spaced parameters, shape (n, 2)."""
        return self.point(np.linspace(self.t_min, self.t_max, n))

    def length(self, *, n: int = 4001) -> float:
        """Arc length (mm) by composite Simpson on |C'| over each sample interval."""
        return float(self.arc_length(np.array([self.t_max]), n=n)[0])

    def arc_length(self, t, *, n: int = 4001) -> np.ndarray:
        """Arc length s(t) from t_min (mm), by trapezoidal integration of |C'| on a fine grid + interpolation.

        Accuracy ~ (dt)^2 |C'''|; with the default 4001 points it is ~1e-8 relative for smooth curves.
        """
        tt = np.unique(np.concatenate([np.linspace(self.t_min, self.t_max, n), self.sample_parameters()]))
        speed = np.linalg.norm(self.derivative(tt, 1), axis=1)
        s = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(tt))])
        return np.interp(_as_t(t), tt, s)

    # -- projection ---------------------------------------------------------------------------------------
    def _f(self, t, x):
        """f = (C - x).C' and f' = |C'|^2 + (C - x).C''  (half the derivatives of the squared distance)."""
        c = self.point(t)
        d1 = self.derivative(t, 1)
        d2 = self.derivative(t, 2)
        r = c - x
        return np.einsum("ij,ij->i", r, d1), np.einsum("ij,ij->i", d1, d1) + np.einsum("ij,ij->i", r, d2)

    def _refine(self, x: np.ndarray, lo: np.ndarray, hi: np.ndarray, t0: np.ndarray) -> np.ndarray:
        """Safeguarded Newton for the local minimiser of |C(t) - x|^2 in [lo, hi] (vectorised)."""
        lo = lo.copy()
        hi = hi.copy()
        flo, _ = self._f(lo, x)
        fhi, _ = self._f(hi, x)
        t = np.clip(t0, lo, hi)
        done = np.zeros(len(t), dtype=bool)
        # minimiser at a bracket end when the squared distance is monotone on the bracket
        at_lo = flo >= 0.0
        at_hi = (fhi <= 0.0) & ~at_lo
        t[at_lo] = lo[at_lo]
        t[at_hi] = hi[at_hi]
        done |= at_lo | at_hi
        scale = max(1.0, abs(self.t_max - self.t_min))
        for _ in range(100):
            act = ~done
            if not act.any():
                break
            ta, xa = t[act], x[act]
            f, fp = self._f(ta, xa)
            # keep the sign-change bracket: f(lo) < 0 < f(hi)
            la, ha = lo[act], hi[act]
            la = np.where(f < 0.0, ta, la)
            ha = np.where(f > 0.0, ta, ha)
            with np.errstate(divide="ignore", invalid="ignore"):
                tn = ta - f / fp
            bad = ~np.isfinite(tn) | (fp <= 0.0) | (tn <= la) | (tn >= ha)
            tn = np.where(bad, 0.5 * (la + ha), tn)
            step = np.abs(tn - ta)
            lo[act], hi[act], t[act] = la, ha, tn
            conv = (step <= 4e-16 * scale) | (f == 0.0) | ((ha - la) <= 4e-16 * scale)
            idx = np.flatnonzero(act)
            done[idx[conv]] = True
        return t

    def _projection(self, x: np.ndarray, t: np.ndarray) -> Projection:
        """The :class:`Projection` of points ``x`` whose foot parameters are ``t`` (distance signed by the normal)."""
        foot = self.point(t)
        nrm = self.normal(t)
        r = x - foot
        side = np.einsum("ij,ij->i", r, nrm)
        dist = np.linalg.norm(r, axis=1) * np.where(side < 0.0, -1.0, 1.0)
        return Projection(t=t, foot=foot, distance=dist, normal=nrm)

    def project(self, points, *, t_guess=None, n_candidates: int = 3) -> Projection:
        """Global closest point on the curve of each point (coarse sampling + safeguarded Newton).

        Args:
            points: (n, 2) points (mm).
            t_guess: optional (n,) parameters (e.g. from the previous call) refined as extra candidates.
            n_candidates: number of best sampled local minima refined per point.

        Returns:
            Projection(t, foot, distance, normal); ``distance`` is signed, > 0 on the normal side. When the
            foot is an end point of an open curve the sign is that of (x - foot).normal.
        """
        x_all = _as_points(points)
        n = len(x_all)
        ts, cs = self._samples()
        chord = float(np.linalg.norm(np.diff(cs, axis=0), axis=1).max())
        c2 = (cs * cs).sum(axis=1)
        t_out = np.empty(n)
        closed = self.is_closed
        chunk = max(16, _CHUNK_ENTRIES // len(ts))
        for start in range(0, n, chunk):
            x = x_all[start : start + chunk]
            m = len(x)
            # squared distances to the samples by |x|^2 + |c|^2 - 2 x.c (BLAS); the ~eps |x|^2 round-off
            # only affects the coarse choice of candidates, which the bracketed Newton then refines
            d2 = (x * x).sum(axis=1)[:, None] + c2[None, :] - 2.0 * (x @ cs.T)  # (m, N)
            is_min = np.ones(d2.shape, dtype=bool)
            is_min[:, 1:] &= d2[:, 1:] <= d2[:, :-1]
            is_min[:, :-1] &= d2[:, :-1] <= d2[:, 1:]
            if closed:  # wrap-around neighbours (first and last samples coincide)
                is_min[:, 0] &= d2[:, 0] <= d2[:, -2]
                is_min[:, -1] &= d2[:, -1] <= d2[:, 1]
            score = np.where(is_min, np.maximum(d2, 0.0), np.inf)
            k = min(n_candidates, score.shape[1])
            if k < score.shape[1]:
                cand = np.argpartition(score, k - 1, axis=1)[:, :k]
            else:
                cand = np.argsort(score, axis=1)
            rows = np.arange(m)
            cand_d = np.sqrt(score[rows[:, None], cand])
            # a sampled local minimum can hold the global one only if its sampled distance is within one
            # sample chord of the best sampled distance: refine only those
            keep = np.isfinite(cand_d) & (cand_d <= cand_d.min(axis=1, keepdims=True) + chord)
            best_t = np.full(m, np.nan)
            best_d = np.full(m, np.inf)
            nsamp = len(ts)
            for j in range(k):
                sel = np.flatnonzero(keep[:, j])
                if not len(sel):
                    continue
                i = cand[sel, j]
                lo = ts[np.maximum(i - 1, 0)]
                hi = ts[np.minimum(i + 1, nsamp - 1)]
                tj = self._refine(x[sel], lo, hi, ts[i])
                dj = ((self.point(tj) - x[sel]) ** 2).sum(axis=1)
                take = dj < best_d[sel]
                best_t[sel[take]], best_d[sel[take]] = tj[take], dj[take]
            if t_guess is not None:
                tg = np.clip(_as_t(t_guess)[start : start + chunk], self.t_min, self.t_max)
                tj = self._refine(x, np.full(m, self.t_min), np.full(m, self.t_max), tg)
                # the global bracket may not hold a sign change; only accept a true improvement
                dj = ((self.point(tj) - x) ** 2).sum(axis=1)
                take = dj < best_d
                best_t[take], best_d[take] = tj[take], dj[take]
            t_out[start : start + m] = best_t
        return self._projection(x_all, t_out)


def clamped_uniform_knots(n_control: int, degree: int) -> np.ndarray:
    """Open uniform (clamped) knot vector on [0, 1]: degree+1 repeated end knots, uniform interior knots."""
    if n_control < degree + 1:
        raise ValueError(f"n_control must be >= degree + 1 = {degree + 1}, got {n_control}")
    n_inner = n_control - degree - 1
    inner = np.linspace(0.0, 1.0, n_inner + 2)[1:-1]
    return np.concatenate([np.zeros(degree + 1), inner, np.ones(degree + 1)])


class BSpline(Curve):
    """Clamped (open uniform knots) B-spline on t in [0, 1]; passes through the first/last control points,
    tangent there to the control polygon.

    Args:
        control_points: (m, 2) control points (mm), m >= degree + 1.
        degree: polynomial degree (3 = cubic).
    """

    def __init__(self, control_points, *, degree: int = 3):
        cp = np.asarray(control_points, dtype=float)
        if cp.ndim != 2 or cp.shape[1] != 2:
            raise ValueError(f"control_points must have shape (m, 2), got {cp.shape}")
        if degree < 1:
            raise ValueError(f"degree must be >= 1, got {degree}")
        if len(cp) < degree + 1:
            raise ValueError(f"control_points needs >= degree + 1 = {degree + 1} rows, got {len(cp)}")
        self.control_points = cp
        self.degree = int(degree)
        self.knots = clamped_uniform_knots(len(cp), degree)
        self.t_min, self.t_max = 0.0, 1.0
        self._spl = [_ScipyBSpline(self.knots, cp, degree, extrapolate=True)]
        for k in range(1, 3):
            self._spl.append(self._spl[0].derivative(k) if k <= degree else None)

    def __repr__(self) -> str:
        return f"BSpline(n_control={len(self.control_points)}, degree={self.degree})"

    def point(self, t) -> np.ndarray:
        return self._spl[0](np.clip(_as_t(t), 0.0, 1.0))

    def derivative(self, t, order: int = 1) -> np.ndarray:
        tt = np.clip(_as_t(t), 0.0, 1.0)
        if order == 0:
            return self.point(tt)
        if order > self.degree:
            return np.zeros((len(tt), 2))
        if order < len(self._spl) and self._spl[order] is not None:
            return self._spl[order](tt)
        return self._spl[0].derivative(order)(tt)

    def translated(self, shift) -> BSpline:
        return BSpline(self.control_points + np.asarray(shift, dtype=float).reshape(1, 2), degree=self.degree)

    def sample_parameters(self) -> np.ndarray:
        spans = np.unique(self.knots)
        # >= 4 samples per knot span (a cubic span has at most 2 distance minima), ~1000 samples in all
        per_span = int(np.clip(1024 // (len(spans) - 1), 4, 24))
        grids = [np.linspace(a, b, per_span + 1) for a, b in zip(spans[:-1], spans[1:], strict=True)]
        return np.unique(np.concatenate(grids))


class CircleArc(Curve):
    """Circular arc C(t) = c + r (cos phi, sin phi), phi = angle_start + t (angle_end - angle_start).

    The parameter is t in [0, 1].

    Counter-clockwise when angle_end > angle_start (left normal points to the centre, curvature +1/r),
    clockwise otherwise (left normal points outwards, curvature -1/r). A span of 2*pi is a full circle.
    """

    def __init__(self, center, radius: float, angle_start: float, angle_end: float):
        if not radius > 0.0:
            raise ValueError(f"radius must be > 0 (mm), got {radius}")
        if angle_end == angle_start:
            raise ValueError("angle_end must differ from angle_start")
        if abs(angle_end - angle_start) > 2.0 * np.pi * (1.0 + 1e-14):
            raise ValueError(f"|angle_end - angle_start| must be <= 2*pi, got {abs(angle_end - angle_start)}")
        self.center = np.asarray(center, dtype=float).reshape(2)
        self.r = float(radius)
        self.angle_start = float(angle_start)
        self.angle_end = float(angle_end)
        self.t_min, self.t_max = 0.0, 1.0

    def __repr__(self) -> str:
        return f"CircleArc({self.center.tolist()}, {self.r}, {self.angle_start}, {self.angle_end})"

    @property
    def span(self) -> float:
        return self.angle_end - self.angle_start

    def angle(self, t) -> np.ndarray:
        return self.angle_start + np.clip(_as_t(t), 0.0, 1.0) * self.span

    def point(self, t) -> np.ndarray:
        phi = self.angle(t)
        return self.center + self.r * np.column_stack([np.cos(phi), np.sin(phi)])

    def derivative(self, t, order: int = 1) -> np.ndarray:
        phi = self.angle(t)
        # d^k/dphi^k (cos, sin) = (cos(phi + k pi/2), sin(phi + k pi/2))
        s = self.r * self.span**order
        return s * np.column_stack([np.cos(phi + order * np.pi / 2), np.sin(phi + order * np.pi / 2)])

    def translated(self, shift) -> CircleArc:
        c = self.center + np.asarray(shift, dtype=float)
        return CircleArc(c, self.r, self.angle_start, self.angle_end)

    def sample_parameters(self) -> np.ndarray:
        n = max(8, int(np.ceil(abs(self.span) / (np.pi / 32))))
        return np.linspace(0.0, 1.0, n + 1)

    def project(self, points, *, t_guess=None, n_candidates: int = 3) -> Projection:  # noqa: ARG002
        """Closed-form projection: the radial foot inside the arc's angular range, else the nearer end."""
        x = _as_points(points)
        rel = x - self.center
        phi = np.arctan2(rel[:, 1], rel[:, 0])
        lo, hi = min(self.angle_start, self.angle_end), max(self.angle_start, self.angle_end)
        # shift phi into [lo, lo + 2 pi)
        phi = lo + np.mod(phi - lo, 2.0 * np.pi)
        inside = phi <= hi
        t_rad = (phi - self.angle_start) / self.span
        ends = self.point([0.0, 1.0])
        d0 = np.linalg.norm(x - ends[0], axis=1)
        d1 = np.linalg.norm(x - ends[1], axis=1)
        t = np.where(inside, t_rad, np.where(d0 <= d1, 0.0, 1.0))
        at_center = np.linalg.norm(rel, axis=1) == 0.0
        t = np.where(at_center, 0.0, np.clip(t, 0.0, 1.0))
        return self._projection(x, t)


class Line(Curve):
    """Straight segment C(t) = p0 + t (p1 - p0), t in [0, 1]; curvature 0."""

    def __init__(self, p0, p1):
        self.p0 = np.asarray(p0, dtype=float).reshape(2)
        self.p1 = np.asarray(p1, dtype=float).reshape(2)
        if np.allclose(self.p0, self.p1, rtol=0.0, atol=0.0):
            raise ValueError("Line needs p0 != p1")
        self.t_min, self.t_max = 0.0, 1.0

    def __repr__(self) -> str:
        return f"Line({self.p0.tolist()}, {self.p1.tolist()})"

    def point(self, t) -> np.ndarray:
        tt = np.clip(_as_t(t), 0.0, 1.0)
        return self.p0 + tt[:, None] * (self.p1 - self.p0)

    def derivative(self, t, order: int = 1) -> np.ndarray:
        tt = _as_t(t)
        if order == 1:
            return np.tile(self.p1 - self.p0, (len(tt), 1))
        return np.zeros((len(tt), 2))

    def translated(self, shift) -> Line:
        s = np.asarray(shift, dtype=float)
        return Line(self.p0 + s, self.p1 + s)

    def sample_parameters(self) -> np.ndarray:
        return np.array([0.0, 0.5, 1.0])

    def project(self, points, *, t_guess=None, n_candidates: int = 3) -> Projection:  # noqa: ARG002
        """Closed-form projection onto the segment."""
        x = _as_points(points)
        e = self.p1 - self.p0
        t = np.clip((x - self.p0) @ e / (e @ e), 0.0, 1.0)
        return self._projection(x, t)


class Ellipse(Curve):
    """Ellipse (arc) C(t) = c + Rot (a cos phi, b sin phi), phi = angle_start + t (angle_end - angle_start).

    Counter-clockwise (normal inwards) when angle_end > angle_start. Curvature at phi:
    a b / (a^2 sin^2 phi + b^2 cos^2 phi)^{3/2} (sign as for :class:`CircleArc`).
    """

    def __init__(self, center, a: float, b: float, *, rotation: float = 0.0, angle_start: float = 0.0,
                 angle_end: float = 2.0 * np.pi):
        if not (a > 0.0 and b > 0.0):
            raise ValueError(f"semi-axes a, b must be > 0 (mm), got {a}, {b}")
        self.center = np.asarray(center, dtype=float).reshape(2)
        self.a, self.b, self.rotation = float(a), float(b), float(rotation)
        self.angle_start, self.angle_end = float(angle_start), float(angle_end)
        c, s = np.cos(rotation), np.sin(rotation)
        self._rot = np.array([[c, -s], [s, c]])
        self.t_min, self.t_max = 0.0, 1.0

    @property
    def span(self) -> float:
        return self.angle_end - self.angle_start

    def point(self, t) -> np.ndarray:
        phi = self.angle_start + np.clip(_as_t(t), 0.0, 1.0) * self.span
        loc = np.column_stack([self.a * np.cos(phi), self.b * np.sin(phi)])
        return self.center + loc @ self._rot.T

    def derivative(self, t, order: int = 1) -> np.ndarray:
        phi = self.angle_start + np.clip(_as_t(t), 0.0, 1.0) * self.span
        sh = order * np.pi / 2
        loc = self.span**order * np.column_stack([self.a * np.cos(phi + sh), self.b * np.sin(phi + sh)])
        return loc @ self._rot.T

    def translated(self, shift) -> Ellipse:
        return Ellipse(self.center + np.asarray(shift, dtype=float), self.a, self.b, rotation=self.rotation,
                       angle_start=self.angle_start, angle_end=self.angle_end)

    def sample_parameters(self) -> np.ndarray:
        ecc = max(self.a, self.b) / min(self.a, self.b)
        n = max(16, int(np.ceil(abs(self.span) / (np.pi / 32) * min(ecc, 8.0))))
        return np.linspace(0.0, 1.0, n + 1)


class CompositeCurve(Curve):
    """Continuous chain of curves; global parameter s in [0, n_pieces], piece k = floor(s) (the last piece
    owns s = n_pieces), local parameter = piece.t_min + (s - k) (piece.t_max - piece.t_min).

    Derivatives are with respect to s (chain rule: local derivative times (t_max - t_min)^order). Tangent and
    normal may jump at the joints unless the pieces are tangent there (they are in the designs).
    """

    def __init__(self, pieces, *, tol: float = 1e-9):
        pieces = list(pieces)
        if not pieces:
            raise ValueError("pieces must be a non-empty sequence of Curve")
        for k in range(len(pieces) - 1):
            a = pieces[k].point([pieces[k].t_max])[0]
            b = pieces[k + 1].point([pieces[k + 1].t_min])[0]
            if np.linalg.norm(a - b) > tol * max(1.0, np.abs(a).max()):
                gap = np.linalg.norm(a - b)
                raise ValueError(f"pieces must be continuous: gap {gap:.3e} mm after piece {k}")
        self.pieces = pieces
        self.t_min, self.t_max = 0.0, float(len(pieces))

    def __repr__(self) -> str:
        return f"CompositeCurve({self.pieces!r})"

    def _split(self, s):
        ss = np.clip(_as_t(s), self.t_min, self.t_max)
        k = np.minimum(np.floor(ss).astype(int), len(self.pieces) - 1)
        return k, ss - k

    def _eval(self, s, order: int) -> np.ndarray:
        k, u = self._split(s)
        out = np.empty((len(u), 2))
        for j, pc in enumerate(self.pieces):
            m = k == j
            if m.any():
                span = pc.t_max - pc.t_min
                tl = pc.t_min + u[m] * span
                out[m] = pc.point(tl) if order == 0 else pc.derivative(tl, order) * span**order
        return out

    def point(self, t) -> np.ndarray:
        return self._eval(t, 0)

    def derivative(self, t, order: int = 1) -> np.ndarray:
        return self._eval(t, order)

    def translated(self, shift) -> CompositeCurve:
        return CompositeCurve([p.translated(shift) for p in self.pieces])

    def sample_parameters(self) -> np.ndarray:
        parts = []
        for j, pc in enumerate(self.pieces):
            tp = pc.sample_parameters()
            parts.append(j + (tp - pc.t_min) / (pc.t_max - pc.t_min))
        return np.unique(np.concatenate(parts))

    def piece_of(self, s) -> np.ndarray:
        """Index of the piece owning each global parameter s."""
        return self._split(s)[0]
