"""A rigid indenter meshed as a band of triangles along its contact surface (numpy only: no mesher involved).

A code without analytic rigid surfaces models the indenter as a meshed body every node of which moves with the
rigid body (CalculiX, Kratos: ``docs/external.md``). Only the band's contact surface matters, so the band is one
layer of triangles between the exact surface and a copy of it moved into the indenter by ``thickness``.

The surface nodes are the exact surface evaluated at chosen abscissae or curve parameters, so they lie on it to
round-off (checked by ``tests/test_export_benchmarks.py`` to 1e-9 mm):

* circle of radius R touching y = 0 at the origin: ``(R sin phi, R (1 - cos phi))``, phi uniform (arc spacing h);
* parabola ``y = x^2 / (2 R)`` and wedge ``y = m |x|``: ``(x, f(x))``, x spaced uniformly in arc length per segment,
  the wedge's apex (0, 0) a node (the segments meet there);
* a parametric curve C(t) (the concave scenes' B-spline particle, :mod:`analytic.curves`): ``C(t)``, t spaced
  uniformly in arc length.

No mesher is used: the band is structured (node i of the surface, node i of the offset copy, two triangles per
segment), so there is nothing a machine's last bits could change. Graphs y = f(x) are offset vertically (+y, into
the indenter above the body); a curve along its inward normal ``-N`` (``N`` its outward left normal,
:mod:`analytic.curves`), which is valid while ``thickness`` stays below the smallest radius of curvature (checked:
every triangle must keep a positive area).

Orientation (the contract of :mod:`workbench.external.mesh_model`): triangles counter-clockwise; the surface facets
``(i, i + 1)`` run with the band on their left, so the band's outward normal is the facet direction turned by -90
degrees (towards the body it touches). Units mm.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

__all__ = ["RigidBand", "circle_band", "parabola_band", "wedge_band", "curve_band", "arc_parameters", "band_of"]

FINE = 4000  # samples per segment of the arc-length table that spaces the nodes (the nodes are exact either way)


class RigidBand(NamedTuple):
    """One layer of triangles along a rigid surface.

    Attributes:
        nodes: (2 n, 2) mm: the n surface nodes first (in surface order), then their n offset copies.
        triangles: (2 (n - 1), 3) node indices, counter-clockwise.
        surface: (n - 1, 2) the surface facets (node i, node i + 1), the band on their left.
        params: (n,) the parameter of each surface node (x, the angle phi, or the curve parameter t).
        thickness: the offset (mm).
    """

    nodes: np.ndarray
    triangles: np.ndarray
    surface: np.ndarray
    params: np.ndarray
    thickness: float


def arc_parameters(point: Callable[[np.ndarray], np.ndarray], breaks, h: float) -> np.ndarray:
    """Parameters u_0 < ... < u_n of ``point(u)`` (a vectorised curve, (k,) -> (k, 2)) with every value of ``breaks``
    among them (its ends included) and, between two breaks, equal arc lengths of at most ``h`` (mm): the arc length
    of each segment is tabulated on ``FINE`` samples and inverted by interpolation (only the spacing depends on the
    table: every node is ``point(u)`` itself)."""
    if not (h > 0 and math.isfinite(h)):
        raise ValueError(f"h must be a finite length > 0 (mm), got {h!r}")
    breaks = np.unique(np.asarray(breaks, dtype=float))
    if breaks.size < 2:
        raise ValueError(f"breaks must hold at least two distinct parameters, got {breaks.tolist()}")
    out = [breaks[:1]]
    for lo, hi in zip(breaks[:-1], breaks[1:], strict=True):
        u = np.linspace(lo, hi, FINE + 1)
        s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(point(u), axis=0), axis=1))])
        n = max(1, math.ceil(s[-1] / h - 1e-9))
        inner = np.interp(np.linspace(0.0, s[-1], n + 1)[1:-1], s, u)
        out += [inner, [hi]]
    return np.concatenate(out)


def band_of(surface: np.ndarray, inner: np.ndarray, params: np.ndarray, thickness: float) -> RigidBand:
    """The band between the ordered surface nodes and their offset copies (ValueError if it folds)."""
    n = len(surface)
    i = np.arange(n - 1)
    s0, s1, q0, q1 = i, i + 1, n + i, n + i + 1
    tri = np.concatenate([np.column_stack([s0, s1, q1]), np.column_stack([s0, q1, q0])])
    nodes = np.vstack([surface, inner])
    p = nodes[tri]
    area = 0.5 * ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
                  - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1]))
    if not np.all(area > 0):
        raise ValueError(f"the rigid band folds ({int(np.sum(area <= 0))} of {len(area)} triangles not "
                         f"counter-clockwise): thickness {thickness:g} mm against the surface's curvature, or the "
                         "surface nodes are not ordered with the band on their left")
    return RigidBand(nodes, tri, np.column_stack([s0, s1]), np.asarray(params, dtype=float), float(thickness))


def _graph_band(f: Callable[[np.ndarray], np.ndarray], x: np.ndarray, thickness: float) -> RigidBand:
    """A band above the graph y = f(x) at the increasing abscissae x (the band, above, is left of increasing x)."""
    surface = np.column_stack([x, f(x)])
    return band_of(surface, surface + np.array([0.0, thickness]), x, thickness)


def _span(x_max: float, half: bool) -> list[float]:
    if not (x_max > 0 and math.isfinite(x_max)):
        raise ValueError(f"x_max must be a finite length > 0 (mm), got {x_max!r}")
    return [0.0, x_max] if half else [-x_max, 0.0, x_max]


def circle_band(*, radius: float, x_max: float, h: float, thickness: float, half: bool) -> RigidBand:
    """The lower arc of the circle of centre (0, R) over |x| <= x_max < R (x >= 0: ``half``), nodes
    ``(R sin phi, R (1 - cos phi))`` at equal angles (arc spacing <= h), phi = 0 among them."""
    if not x_max < radius:
        raise ValueError(f"x_max = {x_max!r} must be below the radius {radius!r} (mm)")
    phi_max = math.asin(x_max / radius)
    phi = arc_parameters(lambda t: np.column_stack([radius * np.sin(t), radius * (1.0 - np.cos(t))]),
                         [v * phi_max / x_max for v in _span(x_max, half)], h)
    surface = np.column_stack([radius * np.sin(phi), radius * (1.0 - np.cos(phi))])
    return band_of(surface, surface + np.array([0.0, thickness]), phi, thickness)


def parabola_band(*, radius: float, x_max: float, h: float, thickness: float, half: bool) -> RigidBand:
    """The parabola ``y = x^2 / (2 R)`` over |x| <= x_max (x >= 0: ``half``), x = 0 a node."""
    def f(x):
        return x * x / (2.0 * radius)

    x = arc_parameters(lambda t: np.column_stack([t, f(t)]), _span(x_max, half), h)
    return _graph_band(f, x, thickness)


def wedge_band(*, slope: float, x_max: float, h: float, thickness: float, half: bool) -> RigidBand:
    """The wedge ``y = m |x|`` over |x| <= x_max (x >= 0: ``half``), its apex (0, 0) a node (a corner of the band)."""
    def f(x):
        return slope * np.abs(x)

    x = arc_parameters(lambda t: np.column_stack([t, f(t)]), _span(x_max, half), h)
    return _graph_band(f, x, thickness)


def curve_band(curve, *, t_lo: float, t_hi: float, h: float, thickness: float) -> RigidBand:
    """The part t_lo <= t <= t_hi of a curve of :mod:`analytic.curves` whose left normal is the indenter's outward
    normal (a clockwise particle), nodes ``curve.point(t)``; the offset copy lies at ``-thickness N``. The nodes run
    with decreasing t, which puts the band on their left."""
    t = arc_parameters(curve.point, [t_lo, t_hi], h)[::-1]
    surface = curve.point(t)
    return band_of(surface, surface - thickness * curve.normal(t), t, thickness)
