"""Convective kinematics of two meshed bodies, Ciavarella and Hills's model: only the master's profile is convected.

Units mm, N, MPa. Flat slave surface along ``e1`` with outward normal ``e2`` (the lower body's top), a master body
with an exact reference surface ``y = H(X1)`` (:class:`fem.two_body.geometry.ProfileSurface`,
:class:`fem.two_body.geometry.CircleSurface`). Each slave point X_s keeps its reference partner X_m (the pairing of
small kinematics) for the displacements and the forces; what moves is the place where the master's profile is read:
the slave point now faces the master material point whose abscissa is ``X_m1 + delta``, with the relative
tangential displacement

    delta(u) = u_s1(X_s) - u_m1(X_m)                                                       (mm, linear in u)

so that the gap is

    g(u) = g_small(u) + H(X_m1 + delta(u)) - H(X_m1)                                      (> 0 open)

with ``g_small = g0 + (u_m(X_m) - u_s(X_s)) . e2`` of :mod:`fem.two_body.weighted_gap`. This is Ciavarella and
Hills's eq. (8): Hertz's boundary conditions, the normal displacements of both bodies at the points that were
opposite in the undeformed state, and the profile's slope read at the convected point. (The full pairing of
:mod:`fem.two_body.convective` moves the displacements and the forces with the particles too; for two elastic
bodies the two models differ at the order of the effect itself: docs/models.md.) For a rigid master (u_m = 0)
the two coincide with the rigid solver's convective gap.

Weighted gaps ``W_i g~_i = G0_i + (D u)_i + sum_points w phi_i (H(X_m1 + delta) - H(X_m1))``; with ``delta = C u``
(C: a constant sparse matrix) and the constant scatter B (``B[i, point] = w phi_i``):

    dg~/du = (D + B diag(H'(X_m1 + C u)) C) / W

The traction acts along e2 on both bodies at the reference-paired points (``traction = "halfplane"``): the contact
residual is small kinematics' ``F_c = -D^T p`` and its exact Jacobian ``D^T diag(-dp/dg~ / W) dg~/du`` (not
symmetric: the residual is not the gradient of an energy). No re-pairing, no re-segmentation: the cost of an
iteration is that of small kinematics.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from fem.two_body.geometry import PairedPoints, SurfaceGeometry
from fem.two_body.weighted_gap import CellData, WeightedGap, point_bases

__all__ = ["ProfileConvection"]


class ProfileConvection:
    """The weighted gaps of Ciavarella-Hills's convective model (module docstring).

    Args:
        pts: the paired points (reference configuration); ``small``: their :class:`WeightedGap`.
        slave, slave_cells, master_cells: the slave surface and both surfaces' cells.
        surface: the master's exact reference surface (``height(x1) -> (H, H', H'')``).
        degree: displacement degree.  n_dofs: size of the displacement array.
    """

    def __init__(self, pts: PairedPoints, small: WeightedGap, *, slave: SurfaceGeometry, slave_cells: CellData,
                 master_cells: CellData, surface, degree: int, n_dofs: int):
        if surface is None:
            raise ValueError("convection='profile' needs the master's exact reference surface (master_surface)")
        if not np.allclose(slave.normal, [0.0, 1.0], atol=1e-12):
            raise ValueError("kinematics='convective' for two bodies needs a flat slave surface with normal (0, 1)")
        self.small, self.surface = small, surface
        pb = point_bases(pts, slave=slave, slave_cells=slave_cells, master_cells=master_cells, degree=degree)
        n = pts.X_s.shape[0]
        row_of = np.full(n_dofs // 2, -1)
        row_of[small.nodes] = np.arange(small.nodes.size)
        rows = row_of[pb.rows_node]
        ok = rows >= 0
        pid = np.broadcast_to(np.arange(n)[:, None], rows.shape)
        self.B = sp.csr_matrix((pb.wphi[ok], (rows[ok], pid[ok])), shape=(small.nodes.size, n))
        k = pb.N_s.shape[1]
        cols = np.concatenate([2 * pb.nodes_s, 2 * pb.nodes_m], axis=1)  # x components
        vals = np.concatenate([pb.N_s, -pb.N_m], axis=1)
        self.C = sp.csr_matrix((vals.ravel(), (np.repeat(np.arange(n), 2 * k), cols.ravel())), shape=(n, n_dofs))
        self.C.sum_duplicates()
        self.X_m1 = pts.X_m[:, 0].copy()
        self.H_ref = surface.height(self.X_m1)[0]

    def pattern(self, window: int = 0) -> sp.csr_matrix:
        """The sparsity of the Jacobian's contact rows: small kinematics' D and the profile term's B C."""
        return (abs(self.small.D) + abs(self.B) @ abs(self.C)).tocsr()

    def gaps(self, u: np.ndarray) -> np.ndarray:
        """The weighted gaps g~ (mm) of the dof array u."""
        H = self.surface.height(self.X_m1 + self.C @ u)[0]
        return (self.small.G0 + self.small.D @ u + self.B @ (H - self.H_ref)) / self.small.W

    def linearise(self, u: np.ndarray, *, hessian_weights=None):
        """(g~, dW g~/du, None, D): the weighted gaps, their gradient (times W, as small kinematics' D), no
        second-derivative term (the residual's force matrix D is constant), and the force matrix."""
        H, Hp, _ = self.surface.height(self.X_m1 + self.C @ u)
        g = (self.small.G0 + self.small.D @ u + self.B @ (H - self.H_ref)) / self.small.W
        grad = (self.small.D + self.B @ sp.diags(Hp) @ self.C).tocsr()
        return g, grad, None, self.small.D
