"""Mortar contact of two meshed bodies in the current configuration (finite kinematics, P1; numpy/scipy only).

Units mm, N, MPa. Both contact surfaces move with the displacement: ``x = X + u``. A slave facet k (P1: straight
in the current configuration too, ends x_A, x_B, current length ``l_s = |x_B - x_A|``) carries points at fixed
facet parameters t, ``x_s = (1 - t) x_A + t x_B``, with the contact basis ``phi_A = 1 - t``, ``phi_B = t``
(:func:`fem.two_body.geometry.multiplier_basis`). The gap of a slave point is its signed distance to the deformed
master polyline along the deformed master normal (> 0 open, on the master's outward side):

* **facet** j (ends x_a, x_b; current unit normal n_j, outward of the master): where the foot of the
  perpendicular falls on the facet (``0 <= r <= 1``, ``r = (x_s - x_a) . e / |e|^2``, ``e = x_b - x_a``):
  ``g = (x_s - x_a) . n_j``;
* **vertex** v shared by facets j, j': where the feet on both facets fall beyond v (the fan of normals at a
  convex corner) or within both (the overlap at the other side of the corner): ``g = +-|x_s - x_v|`` (sign of
  ``(x_s - x_v) . (n_j + n_j')``). On the outside this is the true distance; on the other side a smooth
  continuation. Both pieces meet the facets' distances with the same value and gradient, so g is C^1 in the
  slave point and the master nodes.

The nodal weighted gaps and weights are integrals over the CURRENT slave length (the pressure per deformed length):

    G_i = int phi_i g dgamma ,   W_i = int phi_i dgamma ,   g~_i = G_i / W_i ,   dgamma = l_s dt

and the contact residual is the virtual work of the nodal pressures ``p_i = p(g~_i)`` (:mod:`fem.two_body.laws`)
acting along the deformed master normal on the current length:

    F_c = -sum_i p_i T_i ,      T_i = int phi_i dg/du dgamma

(``dg/du``: the normal on the slave point, minus the normal times the master shape functions at the foot, on
the master nodes: the gradient of the distance, whose foot-variation vanishes). Its exact Jacobian:

    dF_c/du = -sum_i [ p_i'(g~_i) T_i (x) dg~_i/du + p_i dT_i/du ] ,
    dg~_i/du = (dG_i/du - g~_i dW_i/du) / W_i ,   dT_i/du = int phi_i (d2g/du2 l_s + dg/du (x) dl_s/du) dt

The slave facets are cut (in the current configuration, every evaluation) where the foot of the perpendicular
meets a master facet end (``r_j(t) = 0`` or 1, linear in t), and carry two Gauss points per segment: the
integrands are polynomials of t on the facet pieces (2-point Gauss is exact there), so a uniform pressure is
carried exactly on non-matching meshes (the patch test). Since g and dg/du are continuous across the cuts, the
cuts' motion adds nothing to the derivatives of the integrals; only the vertex pieces (width ~ |g| times the
angle between neighbouring facets) are integrated inexactly.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.sparse as sp

from fem.two_body.geometry import FACING_COS, PairedPoints, SurfaceGeometry, gauss_legendre_01
from fem.two_body.weighted_gap import CellData, WeightedGap

__all__ = ["FiniteContact", "facet_gap", "vertex_gap"]

_FAR = 1e6  # the weighted gap (times the slave size) of a contact node without a partner now: open


def _rot(e: np.ndarray) -> np.ndarray:
    """``(e1, -e0)``: e turned by -90 degrees (as :func:`fem.two_body.surfaces.surface_of_group`)."""
    return np.stack([e[..., 1], -e[..., 0]], axis=-1)


def facet_gap(x: np.ndarray, xa: np.ndarray, xb: np.ndarray, sigma: np.ndarray):
    """Signed distance of points x (n, 2) to the lines through facets (xa, xb) with normal ``sigma rot(e)/|e|``:
    (g (n,), gradient (n, 6), Hessian (n, 6, 6)) with respect to ``z = (x, xa, xb)``."""
    d, e = x - xa, xb - xa
    ell = np.linalg.norm(e, axis=1)
    c = sigma * (d[:, 0] * e[:, 1] - d[:, 1] * e[:, 0])
    n = x.shape[0]
    # in the variables y = (d0, d1, e0, e1)
    dc = sigma[:, None] * np.stack([e[:, 1], -e[:, 0], -d[:, 1], d[:, 0]], axis=1)
    d2c = np.zeros((n, 4, 4))
    d2c[:, 0, 3] = d2c[:, 3, 0] = sigma
    d2c[:, 1, 2] = d2c[:, 2, 1] = -sigma
    dl = np.zeros((n, 4))
    dl[:, 2:] = e / ell[:, None]
    d2l = np.zeros((n, 4, 4))
    eh = e / ell[:, None]
    d2l[:, 2:, 2:] = (np.eye(2)[None] - eh[:, :, None] * eh[:, None, :]) / ell[:, None, None]
    g = c / ell
    grad = dc / ell[:, None] - c[:, None] * dl / ell[:, None] ** 2
    outer = dc[:, :, None] * dl[:, None, :]
    hess = (d2c / ell[:, None, None] - (outer + outer.transpose(0, 2, 1)) / ell[:, None, None] ** 2
            - c[:, None, None] * d2l / ell[:, None, None] ** 2
            + 2 * c[:, None, None] * dl[:, :, None] * dl[:, None, :] / ell[:, None, None] ** 3)
    # y = M z: d = x - xa, e = xb - xa
    eye = np.eye(2)
    M = np.zeros((4, 6))
    M[0:2, 0:2], M[0:2, 2:4] = eye, -eye
    M[2:4, 2:4], M[2:4, 4:6] = -eye, eye
    return g, grad @ M, np.einsum("ai,nab,bj->nij", M, hess, M)


def vertex_gap(x: np.ndarray, xv: np.ndarray, sign: np.ndarray):
    """``g = sign |x - xv|`` with its gradient (n, 6) and Hessian (n, 6, 6) in ``z = (x, xv, unused)``."""
    q = x - xv
    rho = np.linalg.norm(q, axis=1)
    qh = q / rho[:, None]
    n = x.shape[0]
    grad = np.zeros((n, 6))
    grad[:, 0:2], grad[:, 2:4] = sign[:, None] * qh, -sign[:, None] * qh
    K = sign[:, None, None] * (np.eye(2)[None] - qh[:, :, None] * qh[:, None, :]) / rho[:, None, None]
    hess = np.zeros((n, 6, 6))
    hess[:, 0:2, 0:2], hess[:, 2:4, 2:4] = K, K
    hess[:, 0:2, 2:4], hess[:, 2:4, 0:2] = -K, -K
    return sign * rho, grad, hess


class FiniteContact:
    """The current-configuration mortar terms (module docstring) for P1 surfaces.

    Args:
        pts: the reference mortar pairing (its master facets seed the Jacobian's pattern).
        small: the reference :class:`WeightedGap` (its contact nodes are the law's nodes, its W the scale the
            problem divides by).
        slave, master: the two surfaces; slave_cells, master_cells: their cells (P1).
        n_dofs: size of the displacement array.
    """

    def __init__(self, pts: PairedPoints, small: WeightedGap, *, slave: SurfaceGeometry, slave_cells: CellData,
                 master: SurfaceGeometry, master_cells: CellData, n_dofs: int):
        from fem.two_body.weighted_gap import _facet_nodes

        self.small, self.n_dofs = small, n_dofs
        self.slave, self.master = slave, master
        self.s_ends = _facet_nodes(slave, slave_cells, 1)[0]  # (n_s, 2): nodes at t = 0, 1
        self.m_ends = np.stack([_node_at(master_cells, master.a), _node_at(master_cells, master.b)], axis=1)
        self.sigma = np.sign(np.einsum("ij,ij->i", master.normal, _rot(master.b - master.a)))
        self.row_of = np.full(n_dofs // 2, -1)
        self.row_of[small.nodes] = np.arange(small.nodes.size)
        self.cand = [np.flatnonzero(slave.normal[k] @ master.normal.T < -FACING_COS) for k in range(slave.a.shape[0])]
        self.pts = pts
        self.tg, self.wg = gauss_legendre_01(2)

    # -- the current segmentation ---------------------------------------------------------------------------
    def _points(self, u: np.ndarray):
        """Per point: slave facet k, t, dt-weight, kind (0 facet, 1 vertex), master nodes (2), sign; or None."""
        x = u.reshape(-1, 2) + self._X
        out = []
        for k, cand in enumerate(self.cand):
            if cand.size == 0:
                continue
            xA, xB = x[self.s_ends[k, 0]], x[self.s_ends[k, 1]]
            cand = _near(cand, 0.5 * (xA + xB), float(np.linalg.norm(xB - xA)), x[self.m_ends[cand, 0]],
                         x[self.m_ends[cand, 1]])
            xa, xb = x[self.m_ends[cand, 0]], x[self.m_ends[cand, 1]]
            e = xb - xa
            ee = np.einsum("ij,ij->i", e, e)
            r0 = np.einsum("ij,ij->i", xA - xa, e) / ee
            r1 = (e @ (xB - xA)) / ee
            with np.errstate(divide="ignore", invalid="ignore"):
                tc = np.concatenate([-r0 / r1, (1.0 - r0) / r1])
            tc = tc[np.isfinite(tc) & (tc > 1e-13) & (tc < 1 - 1e-13)]
            br = np.unique(np.concatenate([[0.0, 1.0], tc]))
            t0, t1 = br[:-1], br[1:]
            keep = t1 - t0 > 1e-14
            t0, t1 = t0[keep], t1[keep]
            tm = 0.5 * (t0 + t1)
            kind, n1, n2, sgn = self._features(xA + tm[:, None] * (xB - xA), cand, xa, e,
                                               r0[None, :] + tm[:, None] * r1[None, :], x)
            ok = kind >= 0
            if not ok.any():
                continue
            t0, t1, kind, n1, n2, sgn = t0[ok], t1[ok], kind[ok], n1[ok], n2[ok], sgn[ok]
            ng = self.tg.size
            out.append((np.full(t0.size * ng, k), (t0[:, None] + (t1 - t0)[:, None] * self.tg[None, :]).ravel(),
                        ((t1 - t0)[:, None] * self.wg[None, :]).ravel(),
                        *(np.repeat(a, ng) for a in (kind, n1, n2, sgn))))
        if not out:
            return None
        cols = list(zip(*out, strict=True))
        return (np.concatenate(cols[0]).astype(np.int64), np.concatenate(cols[1]), np.concatenate(cols[2]),
                np.concatenate(cols[3]).astype(np.int64), np.concatenate(cols[4]).astype(np.int64),
                np.concatenate(cols[5]).astype(np.int64), np.concatenate(cols[6]))

    def _features(self, xs, cand, xa, e, r, x):
        """The master feature of each slave point xs (n, 2) among the candidate facets (module docstring): arrays
        (kind: 0 facet, 1 vertex, -1 none; node 1; node 2; sign of the gap formula). r: (n, n_c) foot parameters."""
        sig = self.sigma[cand]
        nrm = sig[:, None] * _rot(e) / np.linalg.norm(e, axis=1)[:, None]  # (n_c, 2)
        dist = np.einsum("nc,kc->nk", xs, nrm) - np.einsum("kc,kc->k", xa, nrm)[None, :]  # (n, n_c)
        inside = (r >= 0.0) & (r <= 1.0)
        ends = self.m_ends[cand]
        n, nc = r.shape
        excluded = np.zeros((n, nc), dtype=bool)
        i1, i2 = np.nonzero(np.triu(_shares(ends), 1))
        v = np.where((ends[i1, 0] == ends[i2, 0]) | (ends[i1, 0] == ends[i2, 1]), ends[i1, 0], ends[i1, 1])
        b1 = np.where(ends[i1, 1] == v, r[:, i1] - 1.0, -r[:, i1])  # (n, n_pairs): the foot beyond v
        b2 = np.where(ends[i2, 1] == v, r[:, i2] - 1.0, -r[:, i2])
        both_in = inside[:, i1] & inside[:, i2]
        active = ((b1 > 0) & (b2 > 0)) | both_in
        for p in range(i1.size):
            excluded[:, i1[p]] |= both_in[:, p]
            excluded[:, i2[p]] |= both_in[:, p]
        q = xs[:, None, :] - x[v][None, :, :]  # (n, n_pairs, 2)
        rho = np.linalg.norm(q, axis=2)
        vsign = np.where(np.einsum("npc,pc->np", q, nrm[i1] + nrm[i2]) >= 0, 1.0, -1.0)
        score = np.concatenate([np.where(inside & ~excluded, np.abs(dist), np.inf), np.where(active, rho, np.inf)],
                               axis=1)
        best = np.argmin(score, axis=1)
        none = ~np.isfinite(score[np.arange(n), best])
        is_v = best >= nc
        fi = np.minimum(best, nc - 1)
        pi = np.maximum(best - nc, 0)
        kind = np.where(none, -1, np.where(is_v, 1, 0))
        vv = v[pi] if v.size else np.zeros(n, dtype=np.int64)
        n1 = np.where(is_v, vv, ends[fi, 0])
        n2 = np.where(is_v, vv, ends[fi, 1])
        sgn = np.where(is_v, vsign[np.arange(n), pi] if v.size else 1.0, sig[fi])
        return kind, n1, n2, sgn

    # -- gap, gradient, Hessian ----------------------------------------------------------------------------
    def bind_reference(self, X_nodes: np.ndarray) -> None:
        """The reference node coordinates (n_nodes, 2), needed to form x = X + u."""
        self._X = X_nodes

    def linearise(self, u: np.ndarray, *, hessian_weights: Callable[[np.ndarray], np.ndarray] | None = None):
        """(g~ (m,), D (m x n) CSR, H (n x n) CSR or None, T (m x n) CSR): the weighted gaps, ``D = W_ref dg~/du``
        (row-scaled so that the problem's ``T^T diag(-dp/dg~ / W_ref) D`` is the exact term), the
        sum ``sum_i c_i dT_i/du`` for ``c = hessian_weights(g~)``, and the traction's virtual-work matrix T
        (``F_c = -T^T p``; module docstring)."""
        m, nd = self.small.nodes.size, self.n_dofs
        pts = self._points(u)
        if pts is None:
            z = sp.csr_matrix((m, nd))
            return np.full(m, _FAR), z, (None if hessian_weights is None else sp.csr_matrix((nd, nd))), z
        k, t, wt, kind, n1, n2, sgn = pts
        x = u.reshape(-1, 2) + self._X
        A, B = self.s_ends[k, 0], self.s_ends[k, 1]
        xA, xB = x[A], x[B]
        xs = xA + t[:, None] * (xB - xA)
        g = np.zeros(t.size)
        gz = np.zeros((t.size, 6))
        hz = np.zeros((t.size, 6, 6))
        f, v = kind == 0, kind == 1
        if f.any():
            g[f], gz[f], hz[f] = facet_gap(xs[f], x[n1[f]], x[n2[f]], sgn[f])
        if v.any():
            g[v], gz[v], hz[v] = vertex_gap(xs[v], x[n1[v]], sgn[v])
        # local variables y = (x_A, x_B, master node 1, master node 2); x_s = (1 - t) x_A + t x_B
        P = np.zeros((t.size, 6, 8))
        eye = np.eye(2)
        P[:, 0:2, 0:2] = (1 - t)[:, None, None] * eye
        P[:, 0:2, 2:4] = t[:, None, None] * eye
        P[:, 2:4, 4:6] = eye
        P[:, 4:6, 6:8] = eye
        gy = np.einsum("nz,nzy->ny", gz, P)
        hy = np.einsum("nzy,nzw,nwx->nyx", P, hz, P)
        es = xB - xA
        ls = np.linalg.norm(es, axis=1)
        eh = es / ls[:, None]
        ly = np.zeros((t.size, 8))
        ly[:, 0:2], ly[:, 2:4] = -eh, eh
        dofs = np.concatenate([2 * np.stack([A, B, n1, n2], axis=1)[:, :, None] + np.arange(2)], axis=1)
        dofs = dofs.reshape(t.size, 8)
        phi = np.stack([1 - t, t], axis=1)
        rows = self.row_of[np.stack([A, B], axis=1)]  # (n, 2)
        valid = rows >= 0
        wphi = np.where(valid, wt[:, None] * phi, 0.0)
        rr = np.maximum(rows, 0)
        G = np.bincount(rr.ravel(), weights=(wphi * (g * ls)[:, None]).ravel(), minlength=m)
        W = np.bincount(rr.ravel(), weights=(wphi * ls[:, None]).ravel(), minlength=m)
        paired = W > 0
        gt = np.where(paired, G / np.where(paired, W, 1.0), _FAR * float(np.max(ls)))

        def rowmat(vals):  # (n, 2, 8) -> (m x nd)
            ri = np.broadcast_to(rows[:, :, None], vals.shape)[valid]
            ci = np.broadcast_to(dofs[:, None, :], vals.shape)[valid]
            M = sp.csr_matrix((vals[valid].ravel(), (ri.ravel(), ci.ravel())), shape=(m, nd))
            M.sum_duplicates()
            return M

        T = rowmat(wphi[:, :, None] * (ls[:, None] * gy)[:, None, :])
        dG = rowmat(wphi[:, :, None] * (ls[:, None] * gy + g[:, None] * ly)[:, None, :])
        dW = rowmat(wphi[:, :, None] * ly[:, None, :])
        scale = np.where(paired, self.small.W / np.where(paired, W, 1.0), 0.0)
        D = (sp.diags(scale) @ (dG - sp.diags(gt * paired) @ dW)).tocsr()
        H = None
        if hessian_weights is not None:
            c = hessian_weights(gt)
            c_pt = np.einsum("np,np->n", wphi, np.where(valid, c[rr], 0.0))
            hess = c_pt[:, None, None] * (ls[:, None, None] * hy + gy[:, :, None] * ly[:, None, :])
            Hi = np.broadcast_to(dofs[:, :, None], hess.shape)
            Hj = np.broadcast_to(dofs[:, None, :], hess.shape)
            H = sp.csr_matrix((hess.ravel(), (Hi.ravel(), Hj.ravel())), shape=(nd, nd))
            H.sum_duplicates()
        return gt, D, H, T

    def current_weights(self, u: np.ndarray) -> np.ndarray:
        """The nodal weights on the CURRENT slave length, ``W_i = int phi_i dgamma`` (mm; 0 for a contact node
        without a partner now): ``p_i W_i`` is the node's contact force (N/mm), the pressure being per deformed
        length."""
        m = self.small.nodes.size
        pts = self._points(u)
        if pts is None:
            return np.zeros(m)
        k, t, wt = pts[0], pts[1], pts[2]
        x = u.reshape(-1, 2) + self._X
        A, B = self.s_ends[k, 0], self.s_ends[k, 1]
        ls = np.linalg.norm(x[B] - x[A], axis=1)
        rows = self.row_of[np.stack([A, B], axis=1)]
        valid = rows >= 0
        wphi = np.where(valid, wt[:, None] * np.stack([1 - t, t], axis=1), 0.0)
        return np.bincount(np.maximum(rows, 0).ravel(), weights=(wphi * ls[:, None]).ravel(), minlength=m)

    def gaps(self, u: np.ndarray) -> np.ndarray:
        """The nodal weighted gaps g~ (mm) of the dof array u."""
        return self.linearise(u)[0]

    def pattern(self, *, window: int) -> sp.csr_matrix:
        """A 0/1 matrix (contact nodes x dofs) covering the couplings while each slave facet's partners stay within
        ``window`` master facets (ordered by abscissa) of its reference partners; PETSc allocates the rest."""
        order = np.argsort(0.5 * (self.master.a[:, 0] + self.master.b[:, 0]))
        rank = np.empty_like(order)
        rank[order] = np.arange(order.size)
        fs, fm = self.pts.slave_facet, self.pts.master_facet
        ranks = rank[fm][:, None] + np.arange(-window, window + 1)[None, :]
        facets = order[np.clip(ranks, 0, order.size - 1)]
        nodes = np.concatenate([self.s_ends[fs], self.m_ends[facets].reshape(fs.size, -1)], axis=1)
        cols = (2 * nodes[:, :, None] + np.arange(2)).reshape(fs.size, -1)
        rows = self.row_of[self.s_ends[fs]]
        valid = rows >= 0
        ri = np.broadcast_to(rows[:, :, None], (fs.size, 2, cols.shape[1]))[valid]
        ci = np.broadcast_to(cols[:, None, :], (fs.size, 2, cols.shape[1]))[valid]
        M = sp.csr_matrix((np.ones(ri.size), (ri.ravel(), ci.ravel())), shape=(self.small.nodes.size, self.n_dofs))
        M.sum_duplicates()
        return M


def _near(cand: np.ndarray, xm: np.ndarray, ls: float, xa: np.ndarray, xb: np.ndarray) -> np.ndarray:
    """The candidate master facets that can hold the nearest feature of some point of a slave facet (midpoint xm,
    length ls): those within ``ls`` (plus round-off) of the nearest facet's distance to xm (a point of the facet is
    within ls/2 of xm, so a farther facet is never the nearest to it)."""
    e = xb - xa
    r = np.clip(np.einsum("ij,ij->i", xm - xa, e) / np.einsum("ij,ij->i", e, e), 0.0, 1.0)
    dist = np.linalg.norm(xm - (xa + r[:, None] * e), axis=1)
    return cand[dist <= dist.min() + 1.01 * ls]


def _shares(ends: np.ndarray) -> np.ndarray:
    """(n_c, n_c) True where two facets (end nodes ``ends``) share a node."""
    return (ends[:, None, :, None] == ends[None, :, None, :]).any(axis=(2, 3))


def _node_at(cells: CellData, P: np.ndarray) -> np.ndarray:
    """The node of each facet's cell that sits at the point P (n, 2) (a facet end)."""
    d = np.linalg.norm(cells.node_x - P[:, None, :], axis=2)
    return cells.nodes[np.arange(P.shape[0]), np.argmin(d, axis=1)]
