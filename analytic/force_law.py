"""A force law for multibody users (issue 40, item 4): P(d), the patch positions and sizes of a design, from the
interacting-patch model (:mod:`analytic.interacting_patches`), inside the model's analytic validity limit.

The design (:mod:`analytic.design_family`) is a rigid particle moved by d (mm) along its direction (straight
down) onto an elastic concave body of depth H. The half-plane of the model is the body's surface flattened to
the horizontal line; x is the horizontal abscissa; the real gap g(x) is the vertical distance from the concave
surface up to the particle's lower surface at d = 0 (both surfaces are graphs y(x) near the pairs), so the
model's approach delta IS the particle's displacement d (Flamant's depth convention with r_ref = H, the body's
depth, and nu of the body: :mod:`analytic.interacting_patches`). P (N/mm) is the vertical load per unit thickness.

Validity (the model's analytic limit, :func:`validity`; refused outside it): at every tabulated state,
    |slope of the concave surface| <= MAX_SURFACE_SLOPE over the patches (the half-plane is horizontal),
    b_k <= MAX_PATCH_OVER_RADIUS * min(|R_concave(c_k)|, R_particle(c_k)) at every patch,
    span of the patches <= MAX_SPAN_OVER_DEPTH * H.
The region the concave FEM map measured (issue 40, item 3) comes from above: ``approach_max`` (mm past first
touch), which ``workbench forcelaw`` reads from the map's region file; without it a table states this analytic
validity limit only.

Which limit refuses (explicit): WITHOUT ``approach_max`` the analytic limit refuses (the static tilt of the pairs
before solving; a state past it ends the rows, or refuses a d_max). WITH ``approach_max`` (a region the map
measured against the FEM) the measured region is the refusal, and the analytic limit is a warning
(:attr:`ForceLawTable.warnings`, written into the table): the map evaluated the model past the analytic limit and
validated it there, so the analytic limit is conservative where the map says so, and a design beyond it is
accepted only inside the measured region.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from analytic.design_family import DesignMeasure, FamilyMember, build
from analytic.designs import POISSON_RATIO, YOUNGS_MODULUS, ConcaveDesign
from analytic.interacting_patches import (
    MAX_PATCH_OVER_RADIUS,
    MAX_SPAN_OVER_DEPTH,
    MAX_SURFACE_SLOPE,
    Gap,
    PatchSolution,
    solve_patches,
)

__all__ = ["ForceLawRow", "ForceLawTable", "VALIDITY_NOTE", "design_gap", "force_law", "pair_tilts", "validity"]

VALIDITY_NOTE = ("region = the interacting-patch model's analytic validity limit (surface slope, patch size against "
                 "the radii, span against the depth) only; workbench forcelaw narrows it to the region the concave "
                 "FEM map validated")


class _Graph:
    """y(x), y'(x) and the Hertz radius (convex > 0) of a curve piece that is a graph over [x_lo, x_hi]."""

    def __init__(self, curve, *, outward_up: bool):
        t = np.linspace(curve.t_min, curve.t_max, 20001)
        x = curve.point(t)[:, 0]
        if x[-1] < x[0]:
            t, x = t[::-1], x[::-1]
        if np.any(np.diff(x) <= 0):
            raise ValueError("design out of range: a surface is not a graph y(x) near the pairs")
        self.curve, self.t, self.x, self.sign = curve, t, x, (1.0 if outward_up else -1.0)

    def _param(self, xq: np.ndarray) -> np.ndarray:
        tq = np.interp(xq, self.x, self.t)
        for _ in range(4):  # Newton on x(t) = xq
            tq = tq - (self.curve.point(tq)[:, 0] - xq) / self.curve.derivative(tq, 1)[:, 0]
        return tq

    def y(self, xq) -> tuple[np.ndarray, np.ndarray]:
        xq = np.atleast_1d(np.asarray(xq, dtype=float))
        tq = self._param(xq)
        d1 = self.curve.derivative(tq, 1)
        return self.curve.point(tq)[:, 1], d1[:, 1] / d1[:, 0]

    def radius(self, xq: float) -> float:
        """Hertz radius of the body bounded by this surface at x (convex > 0, concave < 0; inf when flat)."""
        tq = self._param(np.array([float(xq)]))
        k = float(self.curve.curvature(tq)[0])
        return math.inf if k == 0.0 else -1.0 / k


class DesignGap(NamedTuple):
    """The model's gap of a design and the surfaces it came from."""

    gap: Gap
    concave: _Graph
    particle: _Graph


def design_gap(des: ConcaveDesign, m: DesignMeasure) -> DesignGap:
    """g(x) = y_particle(x) - y_concave(x) at d = 0 on the domain around the pairs (module docstring)."""
    if not np.allclose(des.direction, (0.0, -1.0)):
        raise ValueError(f"design {des.name!r} out of range: the force law needs a vertical path")
    concave = _Graph(des.concave, outward_up=True)
    lower = des.particle.pieces[0]  # the particle's lower spline (the closing arc is its top)
    particle = _Graph(lower, outward_up=False)
    xs = sorted([float(m.primary.point_a[0]), float(m.secondary.point_a[0])])
    sep = max(xs[1] - xs[0], 1.0)
    lo = max(xs[0] - sep, concave.x[0], particle.x[0])
    hi = min(xs[1] + sep, concave.x[-1], particle.x[-1])

    def value(x):
        return particle.y(x)[0] - concave.y(x)[0]

    def slope(x):
        return particle.y(x)[1] - concave.y(x)[1]

    def shaped(f):
        return lambda x: f(x).reshape(np.shape(x))

    return DesignGap(Gap(shaped(value), shaped(slope), (lo, hi)), concave, particle)


def validity(sol: PatchSolution, dg: DesignGap, *, depth: float) -> str | None:
    """None inside the model's analytic validity limit, else one phrase naming the quantity and its limit."""
    if not sol.patches:
        return None
    lo = min(pt.centre - pt.half_width for pt in sol.patches)
    hi = max(pt.centre + pt.half_width for pt in sol.patches)
    slope = float(np.max(np.abs(dg.concave.y(np.linspace(lo, hi, 65))[1])))
    if slope > MAX_SURFACE_SLOPE:
        return f"the concave surface's slope reaches {slope:.3g} over the patches (limit {MAX_SURFACE_SLOPE})"
    for pt in sol.patches:
        radius = min(abs(dg.concave.radius(pt.centre)), abs(dg.particle.radius(pt.centre)))
        if pt.half_width > MAX_PATCH_OVER_RADIUS * radius:
            return (f"the patch at x = {pt.centre:.4g} mm is {pt.half_width:.4g} mm wide (half), "
                    f"{pt.half_width / radius:.3g} of the smaller radius {radius:.4g} mm "
                    f"(limit {MAX_PATCH_OVER_RADIUS})")
    if hi - lo > MAX_SPAN_OVER_DEPTH * depth:
        return f"the patches span {hi - lo:.4g} mm, {(hi - lo) / depth:.3g} of the depth (limit {MAX_SPAN_OVER_DEPTH})"
    return None


class ForceLawRow(NamedTuple):
    """One state: displacement d (mm), load P (N/mm), patches (centre x, half-width b (mm), p0 (MPa), share)."""

    d: float
    P: float
    patches: tuple[tuple[float, float, float, float], ...]


class ForceLawTable(NamedTuple):
    """The force law of a design: its numbers, the touch displacement, the rows, the model's constants."""

    member: FamilyMember
    d_touch: float
    rows: tuple[ForceLawRow, ...]
    E_star: float
    nu: float
    depth: float
    note: str
    warnings: tuple[str, ...] = ()  # the analytic limit passed inside a measured region (module docstring)


def pair_tilts(m: DesignMeasure) -> tuple[tuple[str, float], ...]:
    """The surface slope at each pair against the path (|n_x| / |n_y| of the pair's normal; 0: the surface faces
    the path, as the horizontal half-plane assumes): ``(("primary", t1), ("secondary", t2))``."""
    return tuple((label, abs(p.normal[0]) / max(abs(p.normal[1]), 1e-300))
                 for label, p in (("primary", m.primary), ("secondary", m.secondary)))


def _static_validity(m: DesignMeasure) -> str | None:
    """Before solving: the surfaces at the pairs must face the path (the half-plane is horizontal)."""
    for label, tilt in pair_tilts(m):
        if tilt > MAX_SURFACE_SLOPE:
            return (f"the {label} pair's surface slope is {tilt:.3g} (limit {MAX_SURFACE_SLOPE}): its normal is "
                    f"{math.degrees(math.atan(tilt)):.3g} deg off the path, the patches do not share one half-plane")
    return None


def force_law(mem: FamilyMember, *, d_max: float | None = None, n_rows: int = 41, step: float = 0.002,
              n_terms: int = 32, approach_max: float | None = None) -> ForceLawTable:
    """The table of a member from first touch: to ``d_max`` (mm along the path) in ``n_rows`` rows (>= 2), or,
    with d_max None, in steps of ``step`` (mm) up to the last row inside the validity limit (at most 0.5 mm).
    ``approach_max`` (mm past first touch, > 0): a region measured elsewhere (the concave map,
    ``workbench.forcelaw_region``); without d_max the rows stop there too, and a d_max beyond it is refused. With
    it the analytic limit warns instead of refusing (module docstring; :attr:`ForceLawTable.warnings`).

    Raises:
        ValueError: one line: a bad value, a d_max beyond ``approach_max``, or (without ``approach_max``) the design
            outside the analytic validity limit, or (d_max given) a state up to d_max outside it.
    """
    if not (isinstance(n_rows, int) and 2 <= n_rows <= 1000):
        raise ValueError(f"n_rows = {n_rows!r} out of range: need an integer 2 <= n_rows <= 1000")
    if not (math.isfinite(step) and 1e-5 <= step <= 0.1):
        raise ValueError(f"step = {step!r} out of range: need 1e-5 <= step <= 0.1 mm")
    des, m = build(mem)
    measured = approach_max is not None  # the measured region refuses; the analytic limit only warns
    warnings: list[str] = []
    why = _static_validity(m)
    if why and not measured:
        raise ValueError(f"design {mem.name!r} out of range: outside the interacting-patch model's validity "
                         f"limit: {why}")
    if why:
        warnings.append(f"past the model's analytic limit before solving ({why}); inside the region the concave "
                        "map validated")
    if d_max is not None and not (math.isfinite(d_max) and m.d_touch < d_max <= m.d_touch + 0.5):
        raise ValueError(f"d_max = {d_max!r} out of range: need {m.d_touch:.6g} < d_max <= {m.d_touch + 0.5:.6g} mm "
                         "(from first touch to 0.5 mm beyond)")
    limit = 0.5 if approach_max is None else approach_max
    if d_max is not None and d_max > m.d_touch + limit * (1.0 + 1e-12):
        raise ValueError(f"d_max = {d_max!r} out of range: beyond the region the concave map validated for this "
                         f"design, d <= {m.d_touch + limit:.6g} mm ({limit:.4g} mm past first touch at "
                         f"{m.d_touch:.6g} mm)")
    E_star = YOUNGS_MODULUS / (1.0 - POISSON_RATIO**2)
    dg = design_gap(des, m)
    if d_max is not None:
        ds = m.d_touch + (d_max - m.d_touch) * np.linspace(0.0, 1.0, n_rows)[1:]
    else:
        ds = m.d_touch + step * np.arange(1, int(limit / step + 1e-9) + 1)
        if approach_max is not None and (not len(ds) or ds[-1] < m.d_touch + limit * (1.0 - 1e-12)):
            ds = np.append(ds, m.d_touch + limit)  # the region's last map load is a row
    rows = [ForceLawRow(float(m.d_touch), 0.0, ())]
    prev: PatchSolution | None = None
    for d in ds:
        sol = _continued(dg, prev, float(d), d0=rows[-1].d, E_star=E_star, depth=mem.depth, n_terms=n_terms)
        why = validity(sol, dg, depth=mem.depth)
        if why and measured:
            if not any(w.startswith("from d = ") for w in warnings):
                warnings.append(f"from d = {d:.6g} mm past the model's analytic limit ({why}); inside the region "
                                "the concave map validated")
            why = None
        if why and d_max is None:
            if len(rows) < 2:
                raise ValueError(f"design {mem.name!r} out of range: already at d = {d:.6g} mm {why} "
                                 f"(first touch at {m.d_touch:.6g} mm); try a smaller step")
            break
        if why:
            raise ValueError(f"d_max = {d_max!r} out of range: at d = {d:.6g} mm {why}; the model's validity limit "
                             f"is below this d_max (first touch at {m.d_touch:.6g} mm, last valid row "
                             f"d = {rows[-1].d:.6g} mm)")
        rows.append(ForceLawRow(float(d), sol.P, tuple((pt.centre, pt.half_width, pt.p0, pt.share)
                                                       for pt in sol.patches)))
        prev = sol
    return ForceLawTable(mem, float(m.d_touch), tuple(rows), E_star, POISSON_RATIO, mem.depth, VALIDITY_NOTE,
                         tuple(warnings))


def _continued(dg: DesignGap, prev: PatchSolution | None, d: float, *, d0: float, E_star: float, depth: float,
               n_terms: int, level: int = 0) -> PatchSolution:
    """The state at d, continued from ``prev`` (at d0); on a failed solve, through the midpoint (up to 5 halvings)."""
    start = None if prev is None else [(pt.centre, pt.half_width) for pt in prev.patches]
    try:
        return solve_patches(dg.gap, E_star=E_star, r_ref=depth, delta=d, nu=POISSON_RATIO, n_terms=n_terms,
                             start=start)
    except RuntimeError as exc:
        if level >= 5:
            raise ValueError(f"d = {d:.6g} mm out of range: the interacting-patch model finds no consistent "
                             f"contact state there ({' '.join(str(exc).split())})") from None
    mid = _continued(dg, prev, 0.5 * (d0 + d), d0=d0, E_star=E_star, depth=depth, n_terms=n_terms, level=level + 1)
    return _continued(dg, mid, d, d0=0.5 * (d0 + d), E_star=E_star, depth=depth, n_terms=n_terms, level=level + 1)
