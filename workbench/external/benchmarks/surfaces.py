"""The exact curved surfaces of a benchmark, described in its geometry (``Benchmark.geometry["surfaces"]``: facet
group -> description), and a quadratic mesh whose mid-edge nodes on those surfaces lie on them.

The meshes are straight-sided 3-node triangles (:mod:`workbench.external.benchmarks.base`): a code with 6-node
triangles that puts its mid-edge nodes at the middle of the straight edges (:meth:`MeshModel.quadratic`) meshes a
curved surface as chords, off by h^2 / (8 R) at the middle of a facet of length h on a radius R (3.1e-5 mm for the
rigid circle of hertz_cylinder at h_c = a/10 with facets of h_c: a quarter of a percent of the approach there).
:func:`quadratic` moves the mid-edge nodes of the curved groups onto the surface instead (the facets then follow
it to O(h^3)). The descriptions:

* ``{"kind": "circle", "center": [x, y], "radius": R}``: radial projection;
* ``{"kind": "parabola", "radius": R}``: ``y = x^2 / (2 R)``, the node moved vertically onto it;
* ``{"kind": "bspline", "degree": 3, "control_points": [[x, y], ...]}``: a clamped uniform B-spline
  (:class:`analytic.curves.BSpline`), the closest point.

Straight surfaces (the wedge's faces, the blocks' sides) need none. Units mm.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from workbench.external.mesh_model import MeshModel

__all__ = ["circle", "parabola", "bspline", "projector", "quadratic"]


def circle(center, radius: float) -> dict:
    """A circle of ``radius`` about ``center``."""
    return {"kind": "circle", "center": [float(c) for c in center], "radius": float(radius)}


def parabola(radius: float, *, cap: float | None = None) -> dict:
    """The parabola ``y = x^2 / (2 R)``; with ``cap`` x_c (mm) the parabola over |x| <= x_c and flat beyond,
    ``y = min(|x|, x_c)^2 / (2 R)`` (the finite-strain runs' upper body, :mod:`workbench.scenes.halfplanes`)."""
    if cap is None:
        return {"kind": "parabola", "radius": float(radius), "equation": "y = x^2 / (2 R)"}
    return {"kind": "parabola", "radius": float(radius), "cap": float(cap),
            "equation": "y = min(|x|, x_c)^2 / (2 R), x_c = cap (the parabola, flat beyond)"}


def bspline(curve) -> dict:
    """A clamped uniform B-spline of :mod:`analytic.curves` (its control points as they are)."""
    return {"kind": "bspline", "degree": int(curve.degree), "knots": "clamped uniform on [0, 1] (end multiplicity "
            "degree + 1, interior knots equally spaced)", "control_points": np.asarray(curve.control_points).tolist()}


def projector(desc: dict) -> Callable[[np.ndarray], np.ndarray]:
    """The map of points (n, 2) onto the surface ``desc`` (module docstring)."""
    kind = desc["kind"]
    if kind == "circle":
        c, R = np.asarray(desc["center"], dtype=float), float(desc["radius"])

        def onto(p):
            v = p - c
            return c + R * v / np.linalg.norm(v, axis=1, keepdims=True)
        return onto
    if kind == "parabola":
        R, cap = float(desc["radius"]), float(desc.get("cap", np.inf))
        return lambda p: np.column_stack([p[:, 0], np.minimum(np.abs(p[:, 0]), cap) ** 2 / (2.0 * R)])
    if kind == "bspline":
        from analytic.curves import BSpline

        curve = BSpline(np.asarray(desc["control_points"], dtype=float), degree=int(desc["degree"]))
        return lambda p: curve.project(p).foot
    raise ValueError(f"surface kind {kind!r}; allowed: circle, parabola, bspline")


def quadratic(model: MeshModel, surfaces: dict) -> MeshModel:
    """``model`` with 6-node triangles and 3-node facets (:meth:`MeshModel.quadratic`), the mid-edge nodes of the
    facets of every group of ``surfaces`` moved onto that surface."""
    q = model.quadratic()
    nodes = q.nodes.copy()
    for group, desc in surfaces.items():
        if group in q.facets:
            mid = q.facets[group][:, 2]
            nodes[mid] = projector(desc)(nodes[mid])
    return MeshModel(nodes, q.cells, q.facets)
