"""The weighted gap of two meshed bodies: one sparse matrix, from the paired points (numpy/scipy only).

Units mm, N, MPa. Slave node i (a Lagrange node on the slave contact surface) has the scalar contact basis
function ``phi_i`` (:func:`fem.two_body.geometry.multiplier_basis`: linear for P1, piecewise linear hats on the
half facets for P2; >= 0, a partition of unity); its weighted gap and weight are

    W_i g~_i = int_Gs phi_i g ds = G0_i + (D u)_i ,      W_i = int_Gs phi_i ds   (mm^2 and mm)

with the gap ``g = g0 + (u_m(X_m) - u_s(X_s)) . nu_s`` of :mod:`fem.two_body.geometry` (> 0 open). The integral
is the pairing's rule: the mortar Gauss points (exact for the polynomial products), or for node-to-segment the
slave nodes themselves (``phi_i(X_node) = delta``): then ``g~_i`` is the gap collocated at node i.

D (rows: contact nodes, columns: displacement dofs ``2 node + component``) holds both bodies' dofs, so the
contact terms couple dofs across the non-matching meshes:

    D_i . u = sum_points w phi_i(X_s) [ sum_b N^m_b(X_m) u_b - sum_b N^s_b(X_s) u_b ] . nu_s

A contact law ``p_i = p(g~_i)`` (MPa, >= 0 compressive; :mod:`fem.two_body.laws`) then gives the contact part of
the residual and its exact Jacobian (the pairing is fixed: small kinematics):

    F_c(u) = -D^T p ,        dF_c/du = D^T diag(-dp_i/dg~_i / W_i) D

(the virtual work of the nodal forces ``p_i W_i`` on the weighted gap variations; for the penalty law
``p = kappa [-g~]_+`` this is the gradient of ``sum_i W_i kappa/2 [-g~_i]_+^2``). A uniform pressure is carried
exactly by mortar, so the contact patch test passes.

Nodes whose paired weight is below ``MIN_PAIRED_FRACTION`` of their full weight ``int_facets phi_i ds`` (the
slave surface runs past the master's end) are dropped: their gap is not defined.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from fem.two_body.geometry import PairedPoints, SurfaceGeometry, facet_node_params, multiplier_basis

__all__ = ["MIN_PAIRED_FRACTION", "CellData", "PointBases", "WeightedGap", "assemble_weighted_gap", "point_bases",
           "reference_coordinates"]

MIN_PAIRED_FRACTION = 0.25


class CellData(NamedTuple):
    """The cells of one body's contact facets (per facet of a :class:`SurfaceGeometry`).

    Attributes:
        vertices: (n, 3, 2) affine triangle vertices (mm), in the element's reference order.
        nodes: (n, k) the cell's displacement nodes (blocked dof indices; component c is ``2 node + c``).
        node_x: (n, k, 2) reference coordinates of those nodes (mm).
        tabulate: ``tabulate(xi) -> (m, k)`` basis values at reference points ``xi`` (m, 2).
    """

    vertices: np.ndarray
    nodes: np.ndarray
    node_x: np.ndarray
    tabulate: Callable[[np.ndarray], np.ndarray]


class WeightedGap(NamedTuple):
    """``W g~ = G0 + D u`` on the contact nodes (module docstring).

    Attributes:
        nodes: (m,) slave node indices (blocked dof index of the displacement space).
        X: (m, 2) reference coordinates of the nodes (mm).
        W: (m,) nodal weights ``int phi_i ds`` over the paired part (mm).
        G0: (m,) ``int phi_i g0 ds`` (mm^2).
        D: (m, n_dofs) sparse CSR (mm).
        normal: (m, 2) nodal unit normal of the slave surface (the weighted mean of nu_s).
        dropped: slave nodes without a partner (paired fraction below MIN_PAIRED_FRACTION).
    """

    nodes: np.ndarray
    X: np.ndarray
    W: np.ndarray
    G0: np.ndarray
    D: sp.csr_matrix
    normal: np.ndarray
    dropped: int

    def gap(self, u: np.ndarray) -> np.ndarray:
        """Weighted gaps g~ (mm) of the displacement dof array u."""
        return (self.G0 + self.D @ u) / self.W


def reference_coordinates(vertices: np.ndarray, X: np.ndarray) -> np.ndarray:
    """Reference coordinates of points X (n, 2) in affine triangles ``vertices`` (n, 3, 2)."""
    J = np.stack([vertices[:, 1] - vertices[:, 0], vertices[:, 2] - vertices[:, 0]], axis=2)
    return np.linalg.solve(J, (X - vertices[:, 0])[..., None])[..., 0]


def _facet_nodes(geom: SurfaceGeometry, cells: CellData, degree: int) -> tuple[np.ndarray, np.ndarray]:
    """(n_facets, n_facet_nodes) node indices of each slave facet's Lagrange nodes, in the order of
    :func:`fem.two_body.geometry.facet_node_params`, and their full weights ``L int_0^1 N_i dt``."""
    t, w = facet_node_params(degree)
    P = geom.a[:, None, :] + t[None, :, None] * (geom.b - geom.a)[:, None, :]
    dist = np.linalg.norm(cells.node_x[:, None, :, :] - P[:, :, None, :], axis=3)  # (n, nt, k)
    pick = np.argmin(dist, axis=2)
    L = geom.length
    if np.any(np.take_along_axis(dist, pick[..., None], axis=2)[..., 0] > 1e-8 * L[:, None]):
        raise ValueError("a contact facet's Lagrange nodes were not found in its cell")
    return np.take_along_axis(cells.nodes, pick, axis=1), L[:, None] * w[None, :]


class PointBases(NamedTuple):
    """The bases at the paired points (n points; k nodes per cell, nt contact nodes per slave facet).

    Attributes:
        rows_node: (n, nt) the slave facet's contact nodes (blocked dof indices) each point contributes to.
        wphi: (n, nt) ``w phi_i(X_s)``: the point's weight times the contact basis (mm).
        N_s, N_m: (n, k) the slave and master cells' displacement basis at X_s and X_m.
        nodes_s, nodes_m: (n, k) those cells' nodes.
        facet_nodes, full_w: (n_facets, nt) every slave facet's contact nodes and their full weights (mm).
    """

    rows_node: np.ndarray
    wphi: np.ndarray
    N_s: np.ndarray
    N_m: np.ndarray
    nodes_s: np.ndarray
    nodes_m: np.ndarray
    facet_nodes: np.ndarray
    full_w: np.ndarray


def point_bases(pts: PairedPoints, *, slave: SurfaceGeometry, slave_cells: CellData, master_cells: CellData,
                degree: int) -> PointBases:
    """The contact basis and both cells' displacement bases at the paired points (reference configuration)."""
    facet_nodes, full_w = _facet_nodes(slave, slave_cells, degree)
    fs, fm = pts.slave_facet, pts.master_facet
    N_s = slave_cells.tabulate(reference_coordinates(slave_cells.vertices[fs], pts.X_s))  # (n, k)
    N_m = master_cells.tabulate(reference_coordinates(master_cells.vertices[fm], pts.X_m))
    # phi_i(X_s) for the facet's own nodes: the contact basis at the point's facet parameter
    e = slave.b[fs] - slave.a[fs]
    t = np.clip(np.einsum("ij,ij->i", pts.X_s - slave.a[fs], e) / np.einsum("ij,ij->i", e, e), 0.0, 1.0)
    phi = multiplier_basis(t, degree)  # (n, nt)
    return PointBases(facet_nodes[fs], pts.weight[:, None] * phi, N_s, N_m, slave_cells.nodes[fs],
                      master_cells.nodes[fm], facet_nodes, full_w)


def assemble_weighted_gap(pts: PairedPoints, *, slave: SurfaceGeometry, slave_cells: CellData,
                          master_cells: CellData, n_dofs: int, degree: int) -> WeightedGap:
    """The weighted gap of the paired points (module docstring); ``n_dofs`` = 2 x the number of nodes."""
    pb = point_bases(pts, slave=slave, slave_cells=slave_cells, master_cells=master_cells, degree=degree)
    facet_nodes, full_w, rows_node, wphi = pb.facet_nodes, pb.full_w, pb.rows_node, pb.wphi
    N_s, N_m, nodes_s, nodes_m = pb.N_s, pb.N_m, pb.nodes_s, pb.nodes_m
    nu = pts.normal
    # D entries: for each point, row = each facet node, col = (node, component) of master (+) and slave (-)
    coef = np.concatenate([N_m, -N_s], axis=1)  # (n, 2k)
    cols_node = np.concatenate([nodes_m, nodes_s], axis=1)
    vals = wphi[:, :, None, None] * coef[:, None, :, None] * nu[:, None, None, :]  # (n, nt, 2k, 2)
    rows = np.broadcast_to(rows_node[:, :, None, None], vals.shape)
    cols = np.broadcast_to(2 * cols_node[:, None, :, None] + np.arange(2)[None, None, None, :], vals.shape)
    W_all = np.bincount(rows_node.ravel(), weights=wphi.ravel(), minlength=n_dofs // 2)
    G0_all = np.bincount(rows_node.ravel(), weights=(wphi * pts.g0[:, None]).ravel(), minlength=n_dofs // 2)
    nrm = np.stack([np.bincount(rows_node.ravel(), weights=(wphi * nu[:, c:c + 1]).ravel(), minlength=n_dofs // 2)
                    for c in range(2)], axis=1)
    full = np.bincount(facet_nodes.ravel(), weights=full_w.ravel(), minlength=n_dofs // 2)
    candidates = np.unique(facet_nodes)
    keep = candidates[W_all[candidates] >= MIN_PAIRED_FRACTION * full[candidates]]
    row_of = np.full(n_dofs // 2, -1)
    row_of[keep] = np.arange(keep.size)
    r = row_of[rows.ravel()]
    ok = r >= 0
    D = sp.csr_matrix((vals.ravel()[ok], (r[ok], cols.ravel()[ok])), shape=(keep.size, n_dofs))
    D.sum_duplicates()
    X = _node_positions(keep, facet_nodes, slave)
    normal = nrm[keep] / np.linalg.norm(nrm[keep], axis=1)[:, None]
    return WeightedGap(nodes=keep, X=X, W=W_all[keep], G0=G0_all[keep], D=D, normal=normal,
                       dropped=int(candidates.size - keep.size))


def _node_positions(keep: np.ndarray, facet_nodes: np.ndarray, slave: SurfaceGeometry) -> np.ndarray:
    """Reference positions of the slave facet nodes ``keep`` (from the facet parameters)."""
    nt = facet_nodes.shape[1]
    t = np.linspace(0.0, 1.0, nt)
    P = slave.a[:, None, :] + t[None, :, None] * (slave.b - slave.a)[:, None, :]
    pos = np.zeros((int(facet_nodes.max()) + 1, 2))
    pos[facet_nodes.ravel()] = P.reshape(-1, 2)
    return pos[keep]
