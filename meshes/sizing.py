"""gmsh mesh-size fields with geometric growth away from the contact zone.

A Threshold field on a Distance field gives h(d) = h0 + (growth - 1) d, capped at h_max: the size grows
linearly with the distance d, i.e. geometrically from element to element (h_{k+1} = growth * h_k).
"""

from __future__ import annotations

import math

__all__ = ["growth_field", "apply_background", "validate_common", "graded_triangles", "TRI_PER_H2"]


def validate_common(*, h_contact: float, h_far: float, growth: float) -> None:
    """Raise ValueError (one line naming the argument) on bad sizes."""
    if not (h_contact > 0.0 and math.isfinite(h_contact)):
        raise ValueError(f"h_contact must be > 0 (mm), got {h_contact}")
    if not (h_far >= h_contact and math.isfinite(h_far)):
        raise ValueError(f"h_far must be >= h_contact = {h_contact} (mm), got {h_far}")
    if not (1.0 < growth <= 3.0):
        raise ValueError(f"growth must be in (1, 3], got {growth}")


def growth_field(gmsh, *, h0: float, h_max: float, growth: float, curves=(), points=(),
                 sampling_size: float | None = None, curve_length: float | None = None) -> int:
    """Add Distance(curves/points) + Threshold fields: h = min(h_max, h0 + (growth - 1) d). Returns the tag.

    Args:
        gmsh: the gmsh module (current model, synchronised).
        h0: size on the entities (mm).
        h_max: cap (mm).
        growth: element-to-element size ratio (> 1).
        curves / points: entity tags the distance is measured to.
        sampling_size: spacing of the Distance-field samples along the curves (default h0 / 4).
        curve_length: longest curve length (mm), to set the number of samples per curve.
    """
    fd = gmsh.model.mesh.field.add("Distance")
    if curves:
        gmsh.model.mesh.field.setNumbers(fd, "CurvesList", list(curves))
        spacing = sampling_size if sampling_size is not None else h0 / 4.0
        n = 20 if curve_length is None else max(20, int(math.ceil(curve_length / spacing)) + 1)
        gmsh.model.mesh.field.setNumber(fd, "Sampling", n)
    if points:
        gmsh.model.mesh.field.setNumbers(fd, "PointsList", list(points))
    ft = gmsh.model.mesh.field.add("Threshold")
    gmsh.model.mesh.field.setNumber(ft, "InField", fd)
    gmsh.model.mesh.field.setNumber(ft, "SizeMin", h0)
    gmsh.model.mesh.field.setNumber(ft, "SizeMax", h_max)
    gmsh.model.mesh.field.setNumber(ft, "DistMin", 0.0)
    gmsh.model.mesh.field.setNumber(ft, "DistMax", max((h_max - h0) / (growth - 1.0), 1e-12))
    return ft


def apply_background(gmsh, fields, *, h_max: float, algorithm: int = 6) -> None:
    """Use Min(fields) as the only size source (no point/curvature/boundary sizes) with Frontal-Delaunay.

    The mesher's own choices are pinned (one thread, fixed algorithm and random seed), so the mesh is a function
    of the gmsh input alone (which :mod:`meshes.portable` makes a function of the case).
    """
    fm = gmsh.model.mesh.field.add("Min")
    gmsh.model.mesh.field.setNumbers(fm, "FieldsList", list(fields))
    gmsh.model.mesh.field.setAsBackgroundMesh(fm)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Mesh.MeshSizeMax", h_max)
    gmsh.option.setNumber("Mesh.Algorithm", algorithm)
    gmsh.option.setNumber("Mesh.ElementOrder", 1)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.MaxNumThreads1D", 1)
    gmsh.option.setNumber("Mesh.MaxNumThreads2D", 1)
    gmsh.option.setNumber("Mesh.RandomSeed", 1)
    gmsh.option.setNumber("Mesh.RandomFactor", 1e-9)


TRI_PER_H2 = 4.0 / math.sqrt(3.0)  # triangles per h^2 of area (equilateral, side h)


def graded_triangles(*, L: float, h0: float, h_far: float, growth: float, area: float, c: float) -> float:
    """The model count of triangles (see the module docstring), before the fitted factor; inf if unbounded."""
    k = growth - 1.0
    if not (h0 > 0 and math.isfinite(h0)) or not math.isfinite(L):
        return math.inf
    h_far = max(h_far, h0)
    with_inv = L / k * (1.0 / h0 - 1.0 / h_far)
    logs = c / k**2 * (math.log(h_far / h0) + h0 / h_far - 1.0)
    D = (h_far - h0) / k
    a_far = max(area - (L * D + 0.5 * c * D * D), 0.0)
    return TRI_PER_H2 * (with_inv + logs + a_far / h_far**2)
