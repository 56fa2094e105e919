"""A meshed contact surface read from a dolfinx mesh: its straight facets and their cells (numpy records).

The records are those of :mod:`fem.two_body.geometry` and :mod:`fem.two_body.weighted_gap`; this is the only
module of the pairing that touches dolfinx. Serial meshes only (every facet and its cell on this process).
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

import dolfinx
import numpy as np

from fem.two_body.geometry import SurfaceGeometry
from fem.two_body.weighted_gap import CellData

__all__ = ["surface_of_group", "cell_data", "tabulate2"]


def surface_of_group(mesh_data, group: str) -> SurfaceGeometry:
    """The facets of the facet group ``group`` as a :class:`SurfaceGeometry` (outward normals of their body)."""
    mesh = mesh_data.mesh
    tdim = mesh.topology.dim
    facets = mesh_data.facet_tags.find(mesh_data.physical_groups[group].tag)
    mesh.topology.create_connectivity(tdim - 1, tdim)
    f2c = mesh.topology.connectivity(tdim - 1, tdim)
    cells = np.array([f2c.links(f)[0] for f in facets], dtype=np.int32)
    fx = mesh.geometry.x[dolfinx.mesh.entities_to_geometry(mesh, tdim - 1, facets)][:, :, :2]  # (n, 2, 2)
    cx = mesh.geometry.x[mesh.geometry.dofmaps[0][cells]][:, :, :2]
    a, b = fx[:, 0], fx[:, 1]
    e = b - a
    n = np.stack([e[:, 1], -e[:, 0]], axis=1) / np.linalg.norm(e, axis=1)[:, None]
    away = np.einsum("ij,ij->i", n, 0.5 * (a + b) - cx.mean(axis=1))
    n[away < 0] *= -1.0
    return SurfaceGeometry(a=a, b=b, normal=n, cell=cells)


def cell_data(V, geom: SurfaceGeometry) -> CellData:
    """The cells of ``geom``'s facets in the vector Lagrange space ``V`` (degree 1 or 2)."""
    mesh = V.mesh
    element = V.ufl_element().sub_elements[0].basix_element
    vertices = mesh.geometry.x[mesh.geometry.dofmaps[0][geom.cell]][:, :, :2]
    nodes = V.dofmap.list[geom.cell]
    node_x = V.tabulate_dof_coordinates()[:, :2][nodes]

    def tabulate(xi: np.ndarray) -> np.ndarray:
        return element.tabulate(0, np.ascontiguousarray(xi, dtype=np.float64))[0, :, :, 0]

    return CellData(vertices=vertices, nodes=nodes.astype(np.int64), node_x=node_x, tabulate=tabulate)


def tabulate2(V):
    """``tabulate2(xi) -> (values (m, k), first (m, k, 2), second derivatives (m, k, 3): xx, xy, yy)`` of the
    scalar basis of ``V`` at reference points (for :mod:`fem.two_body.convective`)."""
    element = V.ufl_element().sub_elements[0].basix_element

    def tab(xi: np.ndarray):
        t = element.tabulate(2, np.ascontiguousarray(xi, dtype=np.float64))[..., 0]  # (6, m, k)
        return t[0], np.stack([t[1], t[2]], axis=2), np.stack([t[3], t[4], t[5]], axis=2)

    return tab
