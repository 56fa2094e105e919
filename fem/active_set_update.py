"""Active-set update by edge extrapolation: the next prescribed contact runs from the pressure of an iterate.

Semismooth Newton (and a primal-dual active-set step, its equivalent for a fixed linearisation) moves a contact
edge to the sign change of the pressure argument q of the last iterate. Near a too-small prescribed set the
penetration just outside grows like dist^(3/2), near a too-large one the tension is confined to the last samples,
so the sign change lies about one contact quadrature point beyond the prescribed edge: one point per iteration.

Here the edge of each run is instead the zero crossing of the smooth pressure extrapolated from inside the run:
near a smooth incomplete-contact edge ``p ~ sqrt(b - x)``, so ``q |q|`` is linear in the surface coordinate X1;
it is fitted (least squares) through the :data:`FIT_POINTS` samples next to the edge, leaving out the
:data:`SKIP_POINTS` outermost ones (they carry the local error of a wrongly placed edge), and its root is the new
edge. A fit with the wrong slope sign, or a root further than :data:`MAX_MOVE` run half-widths away, falls back
to the sign change (:func:`fem.postprocess.contact_edges`).

Units: mm (X1), MPa (q). Pure numpy: no mesh, no PETSc.
"""

from __future__ import annotations

import numpy as np

from fem.postprocess import contact_edges

__all__ = ["extrapolated_runs", "safeguarded_runs", "merged_runs", "accelerated_runs", "same_active_points",
           "sign_runs", "MERGE_POINTS", "SECANT_POINTS", "SECANT_REACH", "FIT_POINTS", "SKIP_POINTS",
           "MAX_MOVE"]

FIT_POINTS = 4
SKIP_POINTS = 1
MAX_MOVE = 0.5
# accelerated_runs: a secant step moves an edge at most this many times the last sign-change step (e -> m)
SECANT_REACH = 3.0
# merged_runs: runs closer than this many sample spacings are one run (the sign of tiny gaps fragments a run)
MERGE_POINTS = 4
# accelerated_runs: an edge that moved by more than this many sample spacings in each of the last two updates
# (the same way, less the second time) takes the secant step; closer, the quadrature grain makes it noise
SECANT_POINTS = 3


def _fit_edge(s: np.ndarray, q: np.ndarray, fallback: float, half: float) -> float:
    """Root of the least-squares line ``q |q| = c0 + c1 s`` through the samples (s, q); ``fallback`` when the
    slope does not point towards an edge at ``fallback`` or the root moves more than ``MAX_MOVE half``."""
    if s.size < 2:
        return fallback
    y = q * np.abs(q)
    c1, c0 = np.polyfit(s, y, 1)
    if c1 == 0.0:
        return fallback
    root = -c0 / c1
    inside = float(np.mean(s))
    # the pressure must fall towards the edge: y decreases from the run's inside to the root
    if (root - inside) * c1 >= 0.0 or not np.isfinite(root) or abs(root - fallback) > MAX_MOVE * half:
        return fallback
    return float(root)


def extrapolated_runs(s: np.ndarray, q: np.ndarray, *, zone: tuple | None = None) -> tuple[tuple[float, float], ...]:
    """Contact runs ((lo, hi), ...) of the samples (s sorted, q the pressure argument) with each edge at the zero
    crossing of the fitted ``q |q|`` (module docstring); lo = -inf for a run from the first sample.

    ``zone``: the prescribed runs the iterate was solved with. Outside them no contact law acted, so a positive
    q there is a penetration, not a pressure: those samples are taken as open, and the fit extrapolates the
    pressure of the prescribed set alone. (Fitted through the penetration beyond a slightly small set, the root
    overshot the edge: measured on the elastic cylinder, a/R = 0.0125, h = a/20, a prescribed edge 0.466 mm went
    to 0.608 mm for a true edge of 0.56 mm, and the set then came back one node per iteration: 5 iterations for
    the step instead of 3.)"""
    if zone is not None:
        inside = np.zeros(len(s), dtype=bool)
        for lo, hi in zone:
            inside |= (s > lo) & (s < hi)
        q = np.where(inside, q, -np.abs(q))
    out = []
    n = len(s)
    for left, right, i, j in contact_edges(s, q):
        half = 0.5 * (right - left) if i > 0 else right - s[0]
        lo = -np.inf
        if i > 0:
            a, b = i + SKIP_POINTS, min(i + SKIP_POINTS + FIT_POINTS, j + 1)
            lo = _fit_edge(s[a:b], q[a:b], left, half) if b - a >= 2 else left
        hi = right
        if j < n - 1:
            a, b = max(j + 1 - SKIP_POINTS - FIT_POINTS, i), j + 1 - SKIP_POINTS
            hi = _fit_edge(s[a:b], q[a:b], right, half) if b - a >= 2 else right
        out.append((float(lo), float(hi)))
    return tuple(out)


def same_active_points(s: np.ndarray, runs_a, runs_b) -> bool:
    """True when the runs select the same samples ``lo < s < hi`` (the prescribed active sets are equal)."""
    def mask(runs):
        m = np.zeros(len(s), dtype=bool)
        for lo, hi in runs:
            m |= (s > lo) & (s < hi)
        return m
    return bool(np.array_equal(mask(runs_a), mask(runs_b)))


def sign_runs(s: np.ndarray, q: np.ndarray) -> tuple[tuple[float, float], ...]:
    """Contact runs ((lo, hi), ...) at the sign changes of q (square-root edge model between samples,
    :func:`fem.postprocess.contact_edges`); lo = -inf for a run from the first sample."""
    return tuple(((-np.inf if i == 0 else float(a)), float(b)) for a, b, i, _ in contact_edges(s, q))


def _secant_edge(e0: float, m0: float, e1: float, m1: float) -> float:
    """Next prescribed edge from two (prescribed e, sign-change m) pairs: the root of f(e) = m(e) - e by the
    secant, limited to :data:`SECANT_REACH` times the sign-change step of the last pair; m1 without a slope."""
    if not (np.isfinite(e1) and np.isfinite(m1)):
        return m1
    f0, f1 = m0 - e0, m1 - e1
    if f1 == 0.0 or f1 == f0 or not np.isfinite(e0):
        return m1
    e = e1 - f1 * (e1 - e0) / (f1 - f0)
    step = e - e1
    if step * f1 <= 0.0 or abs(step) > SECANT_REACH * abs(f1):  # against the sign change, or too far
        return m1 if step * f1 <= 0.0 else e1 + SECANT_REACH * f1
    return float(e)


def _toward(e: float, m: float, f: float) -> float:
    """The fitted edge f when it moves from the prescribed edge e the way the sign change m does, else m."""
    if not (np.isfinite(e) and np.isfinite(f)):
        return m
    return f if (f - e) * (m - e) > 0.0 else m


def safeguarded_runs(zone: tuple, sign: tuple, fit: tuple) -> tuple:
    """The fitted runs ``fit`` with each edge checked against the prescribed runs ``zone`` and the sign-change
    runs ``sign`` of the iterate (one fitted run per sign run): an edge whose fit moves against the sign change
    (the pressure near a wrongly placed edge bends the fit) takes the sign change. Runs that do not correspond
    one to one to the prescribed ones (or whose fit has another number of runs) are taken as fitted."""
    if not len(zone) == len(sign) == len(fit):
        return fit
    out = []
    for (a, b), (ma, mb), (fa, fb) in zip(zone, sign, fit, strict=True):
        if not (ma < b and a < mb):
            return fit
        out.append((fa if np.isinf(fa) else _toward(a, ma, fa), _toward(b, mb, fb)))
    return tuple(out)


def merged_runs(runs: tuple, gap: float) -> tuple:
    """Runs with the ones closer than ``gap`` (mm) merged into their envelope."""
    out: list = []
    for lo, hi in runs:
        if out and lo - out[-1][1] < gap:
            out[-1] = (out[-1][0], max(out[-1][1], hi))
        else:
            out.append((lo, hi))
    return tuple(out)


def accelerated_runs(prev: tuple, prev_sign: tuple, cur: tuple, cur_sign: tuple, fit: tuple, h: float) -> tuple:
    """The runs ``fit`` with each edge replaced by the secant step (:func:`_secant_edge`) where the sign-change
    edge moved by more than :data:`SECANT_POINTS` sample spacings ``h`` (mm) in both of the last two updates, the
    same way and less the second time (a linearly converging edge, e.g. a too-large set that halves its excess
    per iteration); unchanged when the runs do not correspond one to one."""
    if not (len(prev) == len(prev_sign) == len(cur) == len(cur_sign) == len(fit)):
        return fit
    lim = SECANT_POINTS * h

    def edge(e0, m0, e1, m1, f):
        d0, d1 = m0 - e0, m1 - e1
        if not all(np.isfinite(v) for v in (e0, m0, e1, m1)) or abs(d1) <= lim or abs(d0) <= lim:
            return f
        if d0 * d1 <= 0.0 or abs(d1) >= abs(d0):
            return f
        return _secant_edge(e0, m0, e1, m1)

    out = []
    for (a0, b0), (ma0, mb0), (a1, b1), (ma1, mb1), (fa, fb) in zip(prev, prev_sign, cur, cur_sign, fit,
                                                                        strict=True):
        if not (ma1 < b1 and a1 < mb1):
            return fit
        out.append((fa if np.isinf(fa) else edge(a0, ma0, a1, ma1, fa), edge(b0, mb0, b1, mb1, fb)))
    return tuple(out)
