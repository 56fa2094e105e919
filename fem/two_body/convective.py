"""Convective kinematics of two meshed bodies: the pairing follows the relative tangential displacement (numpy).

Units mm, N, MPa. Flat slave surface along ``tau = e1`` with outward normal ``nu = e2`` (the shipped two-body
scenes: the lower block's top), master above it. A slave integration point X (fixed on its slave segment, weight
w, contact basis ``phi_i``) is at ``x_s = X + u_s(X)``. Its partner is the master MATERIAL point whose current
abscissa is the same (the Ciavarella-Hills pairing: the particles that touch in the deformed state):

    C(r, u) = x_m1(r) - x_s1 = 0 ,   x_m(r) = X_m(r) + u_m(X_m(r)) ,   X_m(r) = a_j + r (b_j - a_j)

on the master facet j that holds the root, and the gap is the height of the deformed master above the slave point

    G(r, u) = x_m2(r) + delta(X_m1(r)) - x_s2 ,      g = G(r(u), u)                      (> 0 open)

with ``delta = h_exact - chord`` the master body's exact surface above its chord (zero for a flat master). To first
order in u, ``g = g_small + s (u_s1 - u_m1)`` with s the master's slope: the relative tangential displacement of
dissimilar materials enters the gap, which is what small kinematics leaves out.

Derivatives (``G_u``, ``C_u``: the u-gradients at fixed r; ``s = G_r / C_r``):

    dg/du = G_u - s C_u ,   r_u = -C_u / C_r
    d2g/du2 = a x r_u + r_u x a + (G_rr - s C_rr) r_u x r_u ,   a = G_ur - s C_ur      (G_uu = C_uu = 0)

The weighted gaps ``W_i g~_i = sum_points w phi_i g`` and the nodal law are those of small kinematics
(:mod:`fem.two_body.weighted_gap`, :mod:`fem.two_body.laws`). Two tractions (:data:`TRACTIONS`):

* ``"halfplane"`` (Ciavarella-Hills: the half-plane theory's frictionless surfaces carry no shear): the traction
  acts along the slave normal e2 on both bodies, at the points that touch now. The contact residual is
  ``F_c = -T(u)^T p`` with ``T_i = sum w phi_i G_u`` (the vertical virtual displacement jump, at fixed r), and its
  exact Jacobian ``T^T diag(-dp/dg~ / W) D - sum_i p_i sum w phi_i G_ur x r_u`` (not symmetric: the residual is
  not the gradient of an energy). G_u is continuous where a cut moves (both facets give the master node's own
  value there), so the cuts add nothing to it.
* ``"master_normal"`` (the energy's gradient): ``F_c = -D(u)^T p`` with ``D_i = sum w phi_i dg/du``; since
  ``dg/du = G_u - s C_u``, the traction is along the deformed master's normal (-s, 1): the slave carries the
  shear ``s p`` the inclined master face transmits (as the rigid solver's ``traction = "obstacle"``). Exact
  Jacobian ``D^T diag(-dp/dg~ / W) D - sum_i p_i sum w phi_i d2g/du2``, symmetric.

Measured (stiff cylinder E ratio 1e6 on a nu = 0 block, beta = -1/2, a/R = 0.05, h = a/10, node-to-segment,
augmented Lagrangian): ``"master_normal"`` narrowed the contact against small kinematics where the rigid
half-plane convective solver (validated against Ciavarella-Hills) widens it; ``"halfplane"`` reproduces the rigid
solver node for node (tests/test_two_body_convective.py).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from fem.two_body.geometry import FACING_COS, PairedPoints, SurfaceGeometry, gauss_legendre_01, multiplier_basis
from fem.two_body.weighted_gap import CellData, WeightedGap, reference_coordinates
from vocabulary import HALFPLANE, TWO_BODY_TRACTIONS

__all__ = ["ConvectiveGap", "MasterCells", "NEWTON_R_TOL", "TRACTIONS"]

TRACTIONS = TWO_BODY_TRACTIONS
NEWTON_R_TOL = 1e-14  # the pairing's Newton iteration in the facet parameter r
_MAX_R_ITERATIONS = 30


class MasterCells(NamedTuple):
    """The master surface's cells with second-derivative tabulation (per facet of its :class:`SurfaceGeometry`).

    Attributes:
        cells: :class:`fem.two_body.weighted_gap.CellData` of the master facets.
        tabulate2: ``tabulate2(xi) -> (values (m, k), first derivatives (m, k, 2), second (m, k, 3): xx, xy, yy)``
            in reference coordinates.
        surface: the exact master surface (``height(x1) -> (h, h', h'')``), or None (its chords).
    """

    cells: CellData
    tabulate2: Callable
    surface: object | None


class ConvectiveGap:
    """The weighted gaps of convective kinematics (module docstring) for fixed slave points.

    Args:
        pts: the slave points (mortar Gauss points, or the slave nodes), paired once in the reference configuration.
        small: the small-kinematics :class:`WeightedGap` of the same points (its nodes, weights and X).
        slave, master: the two surfaces; slave_cells, master: their cells.
        degree: displacement degree (1 or 2).  n_dofs: size of the displacement array.
        traction: ``"halfplane"`` or ``"master_normal"`` (module docstring).
    """

    def __init__(self, pts: PairedPoints, small: WeightedGap, *, slave: SurfaceGeometry, slave_cells: CellData,
                 master_geom: SurfaceGeometry, master: MasterCells, degree: int, n_dofs: int,
                 traction: str = "halfplane"):
        if not np.allclose(slave.normal, [0.0, 1.0], atol=1e-12):
            raise ValueError("kinematics='convective' for two bodies needs a flat slave surface with normal (0, 1)")
        if traction not in TRACTIONS:
            raise ValueError(f"traction must be one of {TRACTIONS}, got {traction!r}")
        self.traction = traction
        self.small, self.n_dofs, self.degree = small, n_dofs, degree
        self.master_geom, self.master = master_geom, master
        fs = pts.slave_facet
        self.w = pts.weight
        e = slave.b[fs] - slave.a[fs]
        t = np.clip(np.einsum("ij,ij->i", pts.X_s - slave.a[fs], e) / np.einsum("ij,ij->i", e, e), 0.0, 1.0)
        phi = multiplier_basis(t, degree)  # (n, nt)
        rows_node = _facet_node_rows(slave, slave_cells, degree)[fs]
        row_of = np.full(n_dofs // 2, -1)
        row_of[small.nodes] = np.arange(small.nodes.size)
        self.rows = row_of[rows_node]  # (n, nt) contact-node row, -1 where dropped
        self.wphi = np.where(self.rows >= 0, self.w[:, None] * phi, 0.0)
        self.X_s = pts.X_s
        N_s = slave_cells.tabulate(reference_coordinates(slave_cells.vertices[fs], pts.X_s))
        self.N_s, self.nodes_s = N_s, slave_cells.nodes[fs]
        self.facet0 = pts.master_facet.copy()  # the reference partner facet: the root search starts there
        order = np.argsort(0.5 * (master_geom.a[:, 0] + master_geom.b[:, 0]))
        self.rank = np.empty_like(order)
        self.rank[order] = np.arange(order.size)
        self.by_rank = order
        self.facet = self.facet0.copy()
        # what the segmentation in the current configuration needs
        self.slave, self.slave_cells = slave, slave_cells
        self.facet_nodes = _facet_node_rows(slave, slave_cells, degree)  # (n_f, nt) nodes at t = 0, (1/2,) 1
        self.row_of = row_of
        self.t_nodes = np.linspace(0.0, 1.0, self.facet_nodes.shape[1])
        self.cand = [np.flatnonzero(slave.normal[k] @ master_geom.normal.T < -FACING_COS)
                     for k in range(slave.a.shape[0])]
        mc = master.cells
        self.m_ends = np.stack([_node_at(mc, master_geom.a), _node_at(mc, master_geom.b)], axis=1)  # (n_m, 2)
        self.n_gauss = degree + 1
        self.cuts = _NO_CUTS

    # -- the pairing ----------------------------------------------------------------------------------------
    def _master_at(self, j: np.ndarray, r: np.ndarray, u: np.ndarray):
        """x_m(r), x_m'(r), x_m''(r) (n, 2) on facets j, and the basis with its r-derivatives and nodes."""
        g, mc = self.master_geom, self.master.cells
        e = g.b[j] - g.a[j]
        X = g.a[j] + r[:, None] * e
        xi = reference_coordinates(mc.vertices[j], X)
        N, dN, d2N = self.master.tabulate2(xi)
        Jinv = np.linalg.inv(np.stack([mc.vertices[j][:, 1] - mc.vertices[j][:, 0],
                                       mc.vertices[j][:, 2] - mc.vertices[j][:, 0]], axis=2))
        dxi = np.einsum("nab,nb->na", Jinv, e)  # d xi / dr
        Nr = np.einsum("nka,na->nk", dN, dxi)
        Nrr = (d2N[..., 0] * dxi[:, None, 0] ** 2 + 2 * d2N[..., 1] * dxi[:, None, 0] * dxi[:, None, 1]
               + d2N[..., 2] * dxi[:, None, 1] ** 2)
        nodes = mc.nodes[j]
        um = u.reshape(-1, 2)[nodes]  # (n, k, 2)
        x = X + np.einsum("nk,nkc->nc", N, um)
        x1 = e + np.einsum("nk,nkc->nc", Nr, um)
        x2 = np.einsum("nk,nkc->nc", Nrr, um)
        return x, x1, x2, N, Nr, Nrr, nodes

    def segment(self, u: np.ndarray) -> None:
        """Cut every slave facet where its CURRENT abscissa meets a master node's current abscissa, pair each
        segment with the master facet above it, and put ``n_gauss`` Gauss points on it (the mortar segments of
        the current configuration: the integrands are polynomials on each segment when the strain is uniform,
        so the patch test holds with slip). Sets the per-point arrays and the cuts (for the Hessian)."""
        um = u.reshape(-1, 2)
        tg, wg = gauss_legendre_01(self.n_gauss)
        sl, ms = self.slave, self.master_geom
        x_end = np.stack([ms.a[:, 0], ms.b[:, 0]], axis=1) + um[self.m_ends, 0]
        pts_k, pts_j, pts_t, pts_w = [], [], [], []
        cuts = []
        for k in range(sl.a.shape[0]):
            cand = self.cand[k]
            if cand.size == 0:
                continue
            L = float(np.linalg.norm(sl.b[k] - sl.a[k]))
            xs = sl.a[k, 0] + self.t_nodes * (sl.b[k, 0] - sl.a[k, 0]) + um[self.facet_nodes[k], 0]
            coef = np.polynomial.polynomial.polyfit(self.t_nodes, xs, self.t_nodes.size - 1)
            lo, hi = min(xs[0], xs[-1]), max(xs[0], xs[-1])
            breaks = [0.0, 1.0] + ([0.5] if self.degree == 2 else [])
            vert = {}
            for jj in cand:
                for e in (0, 1):
                    c = x_end[jj, e]
                    if lo < c < hi:
                        t_c = _root_in_01(coef, c)
                        if t_c is not None:
                            breaks.append(t_c)
                            vert[t_c] = self.m_ends[jj, e]
            br = np.unique(np.array(breaks))
            seg_j = []
            for t0, t1 in zip(br[:-1], br[1:], strict=True):
                if t1 - t0 <= 1e-14:
                    seg_j.append(-1)
                    continue
                xm = np.polynomial.polynomial.polyval(0.5 * (t0 + t1), coef)
                xa, xb = x_end[cand, 0], x_end[cand, 1]
                inside = (np.minimum(xa, xb) <= xm) & (xm <= np.maximum(xa, xb))
                if not inside.any():
                    seg_j.append(-1)
                    continue
                # several facets above (a fold): the one nearest the slave in the reference configuration
                near = cand[inside][np.argmin(np.abs(0.5 * (ms.a[cand[inside], 1] + ms.b[cand[inside], 1])))]
                seg_j.append(int(near))
                t = t0 + (t1 - t0) * tg
                pts_k.append(np.full(t.size, k))
                pts_j.append(np.full(t.size, near))
                pts_t.append(t)
                pts_w.append((t1 - t0) * L * wg)
            for i, t_c in enumerate(br[1:-1], start=1):
                if t_c in vert and seg_j[i - 1] >= 0 and seg_j[i] >= 0 and seg_j[i - 1] != seg_j[i]:
                    dxs = np.polynomial.polynomial.polyval(t_c, np.polynomial.polynomial.polyder(coef))
                    cuts.append((k, t_c, seg_j[i - 1], seg_j[i], int(vert[t_c]), L, dxs))
        k = np.concatenate(pts_k).astype(np.int64)
        self.facet = np.concatenate(pts_j).astype(np.int64)
        t = np.concatenate(pts_t)
        self.w = np.concatenate(pts_w)
        self.X_s = sl.a[k] + t[:, None] * (sl.b[k] - sl.a[k])
        phi = multiplier_basis(t, self.degree)
        self.rows = self.row_of[self.facet_nodes[k]]
        self.wphi = np.where(self.rows >= 0, self.w[:, None] * phi, 0.0)
        sc = self.slave_cells
        self.N_s = sc.tabulate(reference_coordinates(sc.vertices[k], self.X_s))
        self.nodes_s = sc.nodes[k]
        self.cuts = cuts

    def pair(self, u: np.ndarray):
        """Solve ``C(r, u) = 0`` for every point (Newton in r, hopping to the neighbouring facet when r leaves
        [0, 1]); returns the per-point state."""
        us = u.reshape(-1, 2)[self.nodes_s]
        x_s = self.X_s + np.einsum("nk,nkc->nc", self.N_s, us)
        j = self.facet.copy()
        r = np.full(j.size, 0.5)
        nf = self.rank.size
        for _ in range(_MAX_R_ITERATIONS):
            x, x1, _, *_ = self._master_at(j, r, u)
            dr = -(x[:, 0] - x_s[:, 0]) / x1[:, 0]
            r = r + dr
            left, right = r < -1e-12, r > 1.0 + 1e-12
            step = np.where(left, -1, np.where(right, 1, 0))
            # a facet hop: the neighbour along x1 (facets ordered by their midpoints' abscissa)
            sgn = np.sign(self.master_geom.b[j, 0] - self.master_geom.a[j, 0])
            k = np.clip(self.rank[j] + step * sgn.astype(int), 0, nf - 1)
            hop = step != 0
            j = np.where(hop, self.by_rank[k], j)
            r = np.where(hop, 0.5, r)
            if not hop.any() and np.max(np.abs(dr)) <= NEWTON_R_TOL:
                break
        self.facet = j
        return x_s, j, np.clip(r, 0.0, 1.0)

    # -- gap, gradient, Hessian ----------------------------------------------------------------------------
    def linearise(self, u: np.ndarray, *, hessian_weights: Callable[[np.ndarray], np.ndarray] | None = None):
        """(g~ (m,), D (m x n_dofs) CSR, H (n_dofs x n_dofs) CSR or None, T (m x n_dofs) CSR): the weighted gaps,
        their gradient D, the traction's virtual-work matrix T (``F_c = -T^T p``; T = D for ``"master_normal"``)
        and ``sum_i c_i d(T_i)/du`` for the nodal weights ``c = hessian_weights(g~)`` (minus the law's pressures
        at these gaps: one pass of the pairing for the whole Jacobian; ``d(T_i)/du = d2(W_i g~_i)/du2`` for
        ``"master_normal"``)."""
        self.segment(u)
        x_s, j, r = self.pair(u)
        x, x1, x2, N_m, Nr, Nrr, nodes_m = self._master_at(j, r, u)
        d0 = d1 = d2 = 0.0
        if self.master.surface is not None:
            h, hp, hpp = self.master.surface.height(x[:, 0] - np.einsum("nk,nk->n", N_m, u.reshape(-1, 2)[nodes_m, 0]))
            chord_x = self.master_geom.a[j] + r[:, None] * (self.master_geom.b[j] - self.master_geom.a[j])
            e = self.master_geom.b[j] - self.master_geom.a[j]
            d0 = h - chord_x[:, 1]
            d1 = hp * e[:, 0] - e[:, 1]  # d delta / dr (X_m1' = e1)
            d2 = hpp * e[:, 0] ** 2
        g = x[:, 1] + d0 - x_s[:, 1]
        G_r, C_r = x1[:, 1] + d1, x1[:, 0]
        G_rr, C_rr = x2[:, 1] + d2, x2[:, 0]
        s = G_r / C_r
        n = g.size
        k_s = self.nodes_s.shape[1]
        # local dof vector per point: [slave nodes x (c = 0, 1)], [master nodes x (c = 0, 1)]
        dofs = np.concatenate([2 * self.nodes_s[:, :, None] + np.arange(2), 2 * nodes_m[:, :, None] + np.arange(2)],
                              axis=1).reshape(n, -1)
        L = dofs.shape[1]
        G_u, C_u = np.zeros((n, L)), np.zeros((n, L))
        G_ur, C_ur = np.zeros((n, L)), np.zeros((n, L))
        G_u[:, 1:2 * k_s:2], C_u[:, 0:2 * k_s:2] = -self.N_s, -self.N_s
        G_u[:, 2 * k_s + 1::2], C_u[:, 2 * k_s::2] = N_m, N_m
        G_ur[:, 2 * k_s + 1::2], C_ur[:, 2 * k_s::2] = Nr, Nr
        grad = G_u - s[:, None] * C_u
        rows = self.rows
        wphi = self.wphi
        m = self.small.nodes.size
        valid = rows >= 0
        gt = np.bincount(rows[valid], weights=(wphi * g[:, None])[valid], minlength=m) / self.small.W
        ri = np.broadcast_to(rows[:, :, None], (n, rows.shape[1], L))
        vals = wphi[:, :, None] * grad[:, None, :]
        ci = np.broadcast_to(dofs[:, None, :], vals.shape)
        D = sp.csr_matrix((vals[valid].ravel(), (ri[valid].ravel(), ci[valid].ravel())), shape=(m, self.n_dofs))
        D.sum_duplicates()
        T = D
        if self.traction == HALFPLANE:
            tv = wphi[:, :, None] * G_u[:, None, :]
            T = sp.csr_matrix((tv[valid].ravel(), (ri[valid].ravel(), ci[valid].ravel())), shape=(m, self.n_dofs))
            T.sum_duplicates()
        H = None
        if hessian_weights is not None:
            c = hessian_weights(gt)
            c_pt = np.einsum("np,np->n", wphi, np.where(valid, c[np.maximum(rows, 0)], 0.0))
            r_u = -C_u / C_r[:, None]
            if self.traction == HALFPLANE:
                hess = G_ur[:, :, None] * r_u[:, None, :]
            else:
                a = G_ur - s[:, None] * C_ur
                hess = (a[:, :, None] * r_u[:, None, :] + r_u[:, :, None] * a[:, None, :]
                        + (G_rr - s * C_rr)[:, None, None] * r_u[:, :, None] * r_u[:, None, :])
            hess = c_pt[:, None, None] * hess
            Hi = np.broadcast_to(dofs[:, :, None], hess.shape)
            Hj = np.broadcast_to(dofs[:, None, :], hess.shape)
            H = sp.csr_matrix((hess.ravel(), (Hi.ravel(), Hj.ravel())), shape=(self.n_dofs, self.n_dofs))
            if self.traction == "master_normal":
                H = H + self._cut_hessian(u, c)
            H.sum_duplicates()
        return gt, D, H, T


    def _cut_hessian(self, u: np.ndarray, c: np.ndarray) -> sp.csr_matrix:
        """The moving cuts' part of ``sum_i c_i d2(W_i g~_i)/du2``: at a cut t_c, where the slave's current abscissa
        meets master node v, dg/du jumps by ``-(s- - s+) C_u`` (the deformed master's slope s jumps at v) and
        ``dt_c/du = C_u / x_s1'(t_c)`` with ``C_u = e_(v,x) - N_s(t_c) e_x``, so the segments' Leibniz terms add
        ``-L phi_i(t_c) (s- - s+) / x_s1'(t_c) C_u x C_u`` (symmetric)."""
        if not self.cuts:
            return sp.csr_matrix((self.n_dofs, self.n_dofs))
        k = np.array([cu[0] for cu in self.cuts])
        t_c = np.array([cu[1] for cu in self.cuts])
        jl = np.array([cu[2] for cu in self.cuts])
        jr = np.array([cu[3] for cu in self.cuts])
        v = np.array([cu[4] for cu in self.cuts])
        L = np.array([cu[5] for cu in self.cuts])
        dxs = np.array([cu[6] for cu in self.cuts])
        ms = self.master_geom
        slopes = []
        for j in (jl, jr):  # the slope of the deformed master at v on each side's facet
            at_b = self.m_ends[j, 1] == v
            r = np.where(at_b, 1.0, 0.0)
            x, x1, *_ = self._master_at(j, r, u)
            d1 = 0.0
            if self.master.surface is not None:
                e = ms.b[j] - ms.a[j]
                X1 = ms.a[j, 0] + r * e[:, 0]
                _, hp, _ = self.master.surface.height(X1)
                d1 = hp * e[:, 0] - e[:, 1]
            slopes.append((x1[:, 1] + d1) / x1[:, 0])
        jump = slopes[0] - slopes[1]
        sl, sc = self.slave, self.slave_cells
        X = sl.a[k] + t_c[:, None] * (sl.b[k] - sl.a[k])
        N_s = sc.tabulate(reference_coordinates(sc.vertices[k], X))
        phi = multiplier_basis(t_c, self.degree)
        rows = self.row_of[self.facet_nodes[k]]
        cw = np.einsum("np,np->n", phi, np.where(rows >= 0, c[np.maximum(rows, 0)], 0.0))
        scale = -cw * L * jump / dxs
        n_s = sc.nodes[k]
        dofs = np.concatenate([2 * n_s, 2 * v[:, None]], axis=1)  # x-dofs
        Cu = np.concatenate([-N_s, np.ones((k.size, 1))], axis=1)
        vals = scale[:, None, None] * Cu[:, :, None] * Cu[:, None, :]
        Hi = np.broadcast_to(dofs[:, :, None], vals.shape)
        Hj = np.broadcast_to(dofs[:, None, :], vals.shape)
        return sp.csr_matrix((vals.ravel(), (Hi.ravel(), Hj.ravel())), shape=(self.n_dofs, self.n_dofs))

    def pattern(self, *, window: int) -> sp.csr_matrix:
        """A 0/1 matrix (contact nodes x dofs) whose rows' column sets cover every pair the convective Jacobian can
        couple while each point's partner stays within ``window`` master facets of its reference partner."""
        n = self.facet0.size
        ranks = self.rank[self.facet0][:, None] + np.arange(-window, window + 1)[None, :]
        facets = self.by_rank[np.clip(ranks, 0, self.rank.size - 1)]  # (n, 2 window + 1)
        m_nodes = self.master.cells.nodes[facets].reshape(n, -1)
        nodes = np.concatenate([self.nodes_s, m_nodes], axis=1)
        cols = (2 * nodes[:, :, None] + np.arange(2)).reshape(n, -1)
        rows = self.rows
        valid = rows >= 0
        ri = np.broadcast_to(rows[:, :, None], (n, rows.shape[1], cols.shape[1]))[valid]
        ci = np.broadcast_to(cols[:, None, :], (n, rows.shape[1], cols.shape[1]))[valid]
        M = sp.csr_matrix((np.ones(ri.size), (ri.ravel(), ci.ravel())), shape=(self.small.nodes.size, self.n_dofs))
        M.sum_duplicates()
        return M


def _facet_node_rows(slave: SurfaceGeometry, cells: CellData, degree: int) -> np.ndarray:
    """(n_facets, n_facet_nodes) node indices of each slave facet's Lagrange nodes (as the weighted gap's)."""
    from fem.two_body.weighted_gap import _facet_nodes

    return _facet_nodes(slave, cells, degree)[0]


_NO_CUTS: list = []


def _node_at(cells: CellData, P: np.ndarray) -> np.ndarray:
    """The node of each facet's cell that sits at the point P (n, 2) (a facet end)."""
    d = np.linalg.norm(cells.node_x - P[:, None, :], axis=2)
    return cells.nodes[np.arange(P.shape[0]), np.argmin(d, axis=1)]


def _root_in_01(coef: np.ndarray, c: float) -> float | None:
    """The root t in (0, 1) of ``polyval(t, coef) = c`` for a monotone, nearly linear polynomial on [0, 1] (the
    current abscissa along a facet): Newton from the linear root (a companion-matrix solve loses the root when the
    quadratic coefficient is round-off small)."""
    P = np.polynomial.polynomial
    d = P.polyder(coef)
    t = (c - coef[0]) / (P.polyval(1.0, coef) - coef[0])
    for _ in range(20):
        step = (P.polyval(t, coef) - c) / P.polyval(t, d)
        t -= step
        if abs(step) <= 1e-15:
            break
    return float(t) if 1e-13 < t < 1.0 - 1e-13 else None
