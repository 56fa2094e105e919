"""Mortar contact of two meshed bodies in the current configuration (finite kinematics, P1; numpy/scipy only).

Units mm, N, MPa. Both contact surfaces move with the displacement: ``x = X + u``. A slave facet k (P1: straight
in the current configuration too, ends x_A, x_B, current length ``l_s = |x_B - x_A|``) carries points at fixed
facet parameters t, ``x_s = (1 - t) x_A + t x_B``, with the contact basis ``phi_A = 1 - t``, ``phi_B = t``
(:func:`fem.two_body.geometry.multiplier_basis`). The gap of a slave point is its signed distance to the deformed
master polyline along the deformed master normal (> 0 open, on the master's outward side):

* **facet** j (ends x_a, x_b; current unit normal n_j, outward of the master): where the foot of the
  perpendicular falls on the facet (``0 <= r <= 1``, ``r = (x_s - x_a) . e / |e|^2``, ``e = x_b - x_a``):
  ``g = (x_s - x_a) . n_j``; where the feet fall within two facets (the overlap at the other side of a corner:
  inside the master at a convex corner), the nearer one, i.e. the facet whose side of the corner's bisector the
  point is on;
* **vertex** v shared by facets j, j': where the feet on both facets fall beyond v (the fan of normals at a
  convex corner): ``g = +-|x_s - x_v|`` (sign of ``(x_s - x_v) . (n_j + n_j')``).

So g is the signed distance to the polyline everywhere: C^1 across the fans, with a kink at each bisector of an
overlap (the normal turns from n_j to n_j' there, the way the surface turns). An earlier version took
``-|x_s - x_v|`` in the overlap as well: that turns the normal back across the overlap (a concave corner where the
master is convex), with jumps of the angle between the facets at the overlap's edges. Linearised exactly (the
moving bounds below), its discrete problem lost positive compliance at a contact-edge node: the node's own pressure
closed its gap (``dg~_i/dp_i = -1.1e-6`` mm/MPa, measured on the two-half-planes case at W = 640 b0, h = b0/10),
Newton cycled between the node on and off, and the load stepper stopped at P = 2726 of 3299 N/mm.

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
meets a master facet end (``r_c(t) = rho``, rho = 0 or 1, linear in t) and where they cross the bisector of two
neighbouring candidate facets within the overlap (``(x_s(t) - x_v) . (n_j - n_j') = 0`` with both feet within
their facets; none where the facets turn by less than :data:`_KINK`), and carry two Gauss points per piece: the
integrands are polynomials of t on the facet pieces (2-point Gauss is exact there), so a uniform pressure is carried
exactly on non-matching meshes (the patch test); only the vertex pieces (width ~ |g| times the angle between
neighbouring facets) are integrated inexactly. The cuts move with u, and the integrands jump across the bisectors
(and change their master nodes across every cut), so every derivative carries the moving bounds (Leibniz's
rule, per piece [t0, t1]):

    d/du int_t0^t1 f dt = int_t0^t1 df/du dt + f(t1) dt1/du - f(t0) dt0/du ,   dt_c/du = -(d phi/du) / (d phi/dt) ,
    phi = (x_s(t) - x_a) . e_c - rho |e_c|^2  (a foot at an end of e_c = x_b - x_a) ,
    phi = (x_s(t) - x_v) . (n_j - n_j')       (a bisector; n = sigma rot(e) / |e| turns with its facet's nodes)

(the ends t = 0, 1 do not move). Without them the Newton direction of a penetrating contact was wrong by a few
per cent in the traction's geometric term (measured 2.35e-2 relative against central differences along a Newton
direction of the two-half-planes case, the same with 8 Gauss points per piece), and Newton converged linearly
there (a factor 0.85 per iteration for 40 iterations).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from fem.two_body.geometry import FACING_COS, PairedPoints, SurfaceGeometry, gauss_legendre_01
from fem.two_body.weighted_gap import CellData, WeightedGap

__all__ = ["FiniteContact", "facet_gap", "vertex_gap"]

_KINK = 1e-10  # radians: neighbouring master facets that turn by less carry no bisector cut (the kink's share of
# the integrals is below 1e-10 of a piece's, and the bisector of two facets in line is round-off)
_FAR = 1e6  # the weighted gap (times the slave size) of a contact node without a partner now: open


def _rot(e: np.ndarray) -> np.ndarray:
    """``(e1, -e0)``: e turned by -90 degrees (as :func:`fem.two_body.surfaces.surface_of_group`)."""
    return np.stack([e[..., 1], -e[..., 0]], axis=-1)


def facet_gap(x: np.ndarray, xa: np.ndarray, xb: np.ndarray, sigma: np.ndarray, *, hessian: bool = True):
    """Signed distance of points x (n, 2) to the lines through facets (xa, xb) with normal ``sigma rot(e)/|e|``:
    (g (n,), gradient (n, 6), Hessian (n, 6, 6) or None without ``hessian``) with respect to ``z = (x, xa, xb)``."""
    d, e = x - xa, xb - xa
    ell = np.linalg.norm(e, axis=1)
    c = sigma * (d[:, 0] * e[:, 1] - d[:, 1] * e[:, 0])
    n = x.shape[0]
    # in the variables y = (d0, d1, e0, e1)
    dc = sigma[:, None] * np.stack([e[:, 1], -e[:, 0], -d[:, 1], d[:, 0]], axis=1)
    dl = np.zeros((n, 4))
    dl[:, 2:] = e / ell[:, None]
    g = c / ell
    grad = dc / ell[:, None] - c[:, None] * dl / ell[:, None] ** 2
    # y = M z: d = x - xa, e = xb - xa
    grad_z = np.concatenate([grad[:, 0:2], -grad[:, 0:2] - grad[:, 2:4], grad[:, 2:4]], axis=1)
    if not hessian:
        return g, grad_z, None
    d2c = np.zeros((n, 4, 4))
    d2c[:, 0, 3] = d2c[:, 3, 0] = sigma
    d2c[:, 1, 2] = d2c[:, 2, 1] = -sigma
    d2l = np.zeros((n, 4, 4))
    eh = e / ell[:, None]
    d2l[:, 2:, 2:] = (np.eye(2)[None] - eh[:, :, None] * eh[:, None, :]) / ell[:, None, None]
    outer = dc[:, :, None] * dl[:, None, :]
    hess = (d2c / ell[:, None, None] - (outer + outer.transpose(0, 2, 1)) / ell[:, None, None] ** 2
            - c[:, None, None] * d2l / ell[:, None, None] ** 2
            + 2 * c[:, None, None] * dl[:, :, None] * dl[:, None, :] / ell[:, None, None] ** 3)
    eye = np.eye(2)
    M = np.zeros((4, 6))
    M[0:2, 0:2], M[0:2, 2:4] = eye, -eye
    M[2:4, 2:4], M[2:4, 4:6] = -eye, eye
    return g, grad_z, np.einsum("ai,nab,bj->nij", M, hess, M)


def vertex_gap(x: np.ndarray, xv: np.ndarray, sign: np.ndarray, *, hessian: bool = True):
    """``g = sign |x - xv|`` with its gradient (n, 6) and Hessian (n, 6, 6) (None without ``hessian``) in
    ``z = (x, xv, unused)``."""
    q = x - xv
    rho = np.linalg.norm(q, axis=1)
    qh = q / rho[:, None]
    n = x.shape[0]
    grad = np.zeros((n, 6))
    grad[:, 0:2], grad[:, 2:4] = sign[:, None] * qh, -sign[:, None] * qh
    if not hessian:
        return sign * rho, grad, None
    K = sign[:, None, None] * (np.eye(2)[None] - qh[:, :, None] * qh[:, None, :]) / rho[:, None, None]
    hess = np.zeros((n, 6, 6))
    hess[:, 0:2, 0:2], hess[:, 2:4, 2:4] = K, K
    hess[:, 0:2, 2:4], hess[:, 2:4, 0:2] = -K, -K
    return sign * rho, grad, hess


class _Integrand(NamedTuple):
    """The factors of the integrands at n slave points: the gap g (n,), its gradient gz (n, 6) in (x_s, master
    nodes) and Hessian hz (n, 6, 6) or None, its gradient gy (n, 8) in the local variables (x_A, x_B, master node 1,
    master node 2), the current slave length ls (n,) and its gradient ly (n, 8), those 8 variables' dofs (n, 8),
    the contact basis phi (n, 2), the contact rows of A and B (n, 2; -1: not a contact node) and rows >= 0."""

    g: np.ndarray
    gz: np.ndarray
    hz: np.ndarray | None
    gy: np.ndarray
    ls: np.ndarray
    ly: np.ndarray
    dofs: np.ndarray
    phi: np.ndarray
    rows: np.ndarray
    valid: np.ndarray


class Pieces(NamedTuple):
    """The current segmentation of the slave facets, one row per piece [t0, t1] of slave facet k (in order of k,
    then t0) with its master feature: kind (0 facet, 1 vertex), nodes n1, n2 (the vertex twice), the sign of the
    gap formula; and the cut at each end: the master facet whose end the foot meets there (-1: the facet end
    t = 0 or 1, which does not move) and which of its ends (rho = 0 or 1), or (rho = 2) the bisector of that facet
    and its neighbour ``other`` (-1 for the other cuts)."""

    k: np.ndarray
    t0: np.ndarray
    t1: np.ndarray
    kind: np.ndarray
    n1: np.ndarray
    n2: np.ndarray
    sgn: np.ndarray
    cut0: np.ndarray
    rho0: np.ndarray
    other0: np.ndarray
    cut1: np.ndarray
    rho1: np.ndarray
    other1: np.ndarray


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
        self.facing = slave.normal @ master.normal.T < -FACING_COS  # (n_s, n_m): the pairs that can touch
        self.pts = pts
        self.tg, self.wg = gauss_legendre_01(2)

    # -- the current segmentation ---------------------------------------------------------------------------
    def _points(self, u: np.ndarray) -> Pieces | None:
        """The current :class:`Pieces` of every slave facet (None: no piece).

        Every slave facet at once (no loop over facets): the near master facets of each (:func:`_near`), then the
        facets in groups of similar candidate counts (padded to the group's power of 4), each group's cuts,
        pieces and features as arrays."""
        x = u.reshape(-1, 2) + self._X
        xA, xB = x[self.s_ends[:, 0]], x[self.s_ends[:, 1]]
        near = _near(self.facing, 0.5 * (xA + xB), np.linalg.norm(xB - xA, axis=1), x[self.m_ends[:, 0]],
                     x[self.m_ends[:, 1]])
        count = near.sum(axis=1)
        width = np.where(count > 0, 4 ** np.ceil(np.log(np.maximum(count, 2)) / np.log(4) - 1e-9).astype(int), 0)
        # (groups by powers of 4: measured 2.5 ms per call at 71 slave facets, against 3.0 by powers of 2 and 5.7
        # in one group: numpy's per-call overhead against the padding)
        out = []
        for C in np.unique(width[width > 0]):
            ks = np.flatnonzero(width == C)
            kk, jj = np.nonzero(near[ks])  # row-major: each facet's candidates in ascending order (as before)
            valid, cand = _padded(kk, (ks.size, C), jj)
            piece = self._pieces(ks, cand, valid, x, xA[ks], xB[ks])
            if piece is not None:
                out.append(piece)
        if not out:
            return None
        cols = [np.concatenate(c) for c in zip(*out, strict=True)]
        order = np.lexsort((cols[1], cols[0]))
        return Pieces(*(c[order] for c in cols))

    def _gauss(self, pc: Pieces) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The Gauss points of the pieces: (piece of each point, t, dt-weight), in order of piece."""
        ng = self.tg.size
        ip = np.repeat(np.arange(pc.k.size), ng)
        span = (pc.t1 - pc.t0)[ip]
        return ip, pc.t0[ip] + span * np.tile(self.tg, pc.k.size), span * np.tile(self.wg, pc.k.size)

    def _pieces(self, ks, cand, valid, x, xA, xB):
        """The pieces of the slave facets ``ks`` (module docstring: cut where a foot meets a master facet end),
        with their candidate master facets ``cand`` (K, C; ``valid`` marks the padding's complement): the columns
        of :class:`Pieces` in order of facet, then t (None: no piece)."""
        K, C = cand.shape
        xa, xb = x[self.m_ends[cand, 0]], x[self.m_ends[cand, 1]]  # (K, C, 2)
        e = xb - xa
        ee = np.where(valid, np.einsum("kcj,kcj->kc", e, e), 1.0)
        r0 = np.einsum("kcj,kcj->kc", xA[:, None, :] - xa, e) / ee
        r1 = np.einsum("kcj,kj->kc", e, xB - xA) / ee
        with np.errstate(divide="ignore", invalid="ignore"):
            tc = np.concatenate([-r0 / r1, (1.0 - r0) / r1], axis=1)  # slot c: rho = 0; slot C + c: rho = 1
        vv = np.concatenate([valid, valid], axis=1)
        tc = np.where(vv & np.isfinite(tc) & (tc > 1e-13) & (tc < 1 - 1e-13), tc, np.inf)
        # the bisectors of neighbouring candidates (the kink of the distance where both feet fall inside)
        ends_c = self.m_ends[cand]
        pk, i1, i2 = _shared_node_pairs(ends_c, valid)
        Pm = int(np.bincount(pk, minlength=K).max(initial=0))
        pv, I1, I2 = _padded(pk, (K, max(Pm, 1)), i1, i2)
        kr = np.arange(K)[:, None]
        nrm = self.sigma[cand][:, :, None] * _rot(e) / np.sqrt(ee)[:, :, None]  # (K, C, 2): outward, unit
        dn = nrm[kr, I1] - nrm[kr, I2]  # (K, Pm, 2)
        xv = x[_shared_node(ends_c[kr, I1], ends_c[kr, I2])]
        with np.errstate(divide="ignore", invalid="ignore"):
            tb = -np.einsum("kpj,kpj->kp", xA[:, None, :] - xv, dn) / np.einsum("kj,kpj->kp", xB - xA, dn)
        kinked = np.linalg.norm(dn, axis=2) > _KINK  # (a straight master: no kink, and dn is round-off)
        with np.errstate(invalid="ignore"):  # only where both feet fall within their facets (an overlap's kink)
            rb1, rb2 = r0[kr, I1] + tb * r1[kr, I1], r0[kr, I2] + tb * r1[kr, I2]
            both = (rb1 >= -1e-12) & (rb1 <= 1 + 1e-12) & (rb2 >= -1e-12) & (rb2 <= 1 + 1e-12)
        tb = np.where(pv & kinked & both & np.isfinite(tb) & (tb > 1e-13) & (tb < 1 - 1e-13), tb, np.inf)
        allc = np.concatenate([np.zeros((K, 1)), np.ones((K, 1)), tc, tb], axis=1)
        src = np.argsort(allc, axis=1, kind="stable")  # 0, 1: the facet's ends; 2 + slot: a cut; 2 + 2C + p: pair p
        br = np.take_along_axis(allc, src, axis=1)
        S = int(np.max(np.sum(np.isfinite(br), axis=1))) - 1  # the cuts inside (0, 1) lead; the padding (inf) trails
        t0, t1 = br[:, :S], br[:, 1:S + 1]
        with np.errstate(invalid="ignore"):
            seg = np.isfinite(t1) & (t1 - t0 > 1e-14)
        tm = np.where(seg, 0.5 * (t0 + t1), 0.5)  # (K, S)
        xs = xA[:, None, :] + tm[:, :, None] * (xB - xA)[:, None, :]
        r = r0[:, None, :] + tm[:, :, None] * r1[:, None, :]  # (K, S, C)
        kind, n1, n2, sgn = self._features(xs, cand, valid, xa, nrm, r, x, (Pm, pv, I1, I2))
        ok = seg & (kind >= 0)
        if not ok.any():
            return None
        kf = np.broadcast_to(ks[:, None], ok.shape)[ok]
        ends = []
        for s_end in (src[:, :S], src[:, 1:S + 1]):
            cut, bis = (s_end >= 2) & (s_end < 2 + 2 * C), s_end >= 2 + 2 * C
            slot = np.clip(s_end - 2, 0, 2 * C - 1)
            pair = np.clip(s_end - 2 - 2 * C, 0, I1.shape[1] - 1)
            facet = np.where(cut, np.take_along_axis(cand, slot % C, axis=1),
                             np.where(bis, np.take_along_axis(cand, np.take_along_axis(I1, pair, axis=1), axis=1), -1))
            other = np.where(bis, np.take_along_axis(cand, np.take_along_axis(I2, pair, axis=1), axis=1), -1)
            ends += [facet[ok], np.where(cut, slot // C, np.where(bis, 2, 0))[ok], other[ok]]
        return (kf, t0[ok], t1[ok], kind[ok], n1[ok], n2[ok], sgn[ok], *ends)

    def _features(self, xs, cand, valid, xa, nrm, r, x, pairs):
        """The master feature of each slave point xs (K, S, 2) among its facet's candidate facets ``cand`` (K, C)
        (module docstring): arrays (K, S) of kind (0 facet, 1 vertex, -1 none), node 1, node 2 and the sign of the
        gap formula. nrm: (K, C, 2) the candidates' outward unit normals; r: (K, S, C) foot parameters; pairs:
        (Pm, pv, I1, I2), the candidates that share a node (:func:`_shared_node_pairs`, padded to (K, max(Pm, 1))).
        Ties go to the first facet, then the first vertex, in the order of the candidates."""
        K, S, C = r.shape
        sig = self.sigma[cand]
        dist = np.einsum("ksj,kcj->ksc", xs, nrm) - np.einsum("kcj,kcj->kc", xa, nrm)[:, None, :]
        inside = (r >= 0.0) & (r <= 1.0) & valid[:, None, :]
        ends = self.m_ends[cand]  # (K, C, 2)
        Pm, pv, I1, I2 = pairs
        kr = np.arange(K)[:, None]
        score_v = np.full((K, S, max(Pm, 1)), np.inf)
        V = np.zeros((K, max(Pm, 1)), dtype=np.int64)
        vsign = np.ones((K, S, max(Pm, 1)))
        if Pm:
            e1, e2 = ends[kr, I1], ends[kr, I2]  # (K, Pm, 2)
            V = _shared_node(e1, e2)
            ra, rb = _per_point(r, I1), _per_point(r, I2)
            b1 = np.where((e1[..., 1] == V)[:, None, :], ra - 1.0, -ra)  # (K, S, Pm): the foot beyond v
            b2 = np.where((e2[..., 1] == V)[:, None, :], rb - 1.0, -rb)
            active = (b1 > 0) & (b2 > 0) & pv[:, None, :]
            q = xs[:, :, None, :] - x[V][:, None, :, :]  # (K, S, Pm, 2)
            rho = np.linalg.norm(q, axis=3)
            nsum = nrm[kr, I1] + nrm[kr, I2]
            vsign = np.where(np.einsum("kspj,kpj->ksp", q, nsum) >= 0, 1.0, -1.0)
            score_v = np.where(active, rho, np.inf)
        score = np.concatenate([np.where(inside, np.abs(dist), np.inf), score_v], axis=2)
        best = np.argmin(score, axis=2)
        none = ~np.isfinite(np.min(score, axis=2))
        is_v = best >= C
        fi = np.minimum(best, C - 1)
        pi = np.maximum(best - C, 0)
        kind = np.where(none, -1, np.where(is_v, 1, 0))
        fe = ends[kr, fi]  # (K, S, 2)
        vv = V[kr, pi]
        n1 = np.where(is_v, vv, fe[..., 0])
        n2 = np.where(is_v, vv, fe[..., 1])
        sgn = np.where(is_v, vsign[kr, np.arange(S)[None, :], pi], sig[kr, fi])
        return kind, n1, n2, sgn

    # -- gap, gradient, Hessian ----------------------------------------------------------------------------
    def bind_reference(self, X_nodes: np.ndarray) -> None:
        """The reference node coordinates (n_nodes, 2), needed to form x = X + u."""
        self._X = X_nodes

    def _integrand(self, x: np.ndarray, k, t, kind, n1, n2, sgn, *, hessian: bool) -> _Integrand:
        """The integrands' factors at slave points (facet k, parameter t) with their master features (the
        :class:`Pieces` columns per point), x the current node coordinates."""
        A, B = self.s_ends[k, 0], self.s_ends[k, 1]
        xA, xB = x[A], x[B]
        xs = xA + t[:, None] * (xB - xA)
        g = np.zeros(t.size)
        gz = np.zeros((t.size, 6))
        hz = np.zeros((t.size, 6, 6)) if hessian else None
        f, v = kind == 0, kind == 1
        for sel, fn, args in ((f, facet_gap, (x[n1[f]], x[n2[f]], sgn[f])), (v, vertex_gap, (x[n1[v]], sgn[v]))):
            if sel.any():
                gi, gzi, hzi = fn(xs[sel], *args, hessian=hessian)
                g[sel], gz[sel] = gi, gzi
                if hessian:
                    hz[sel] = hzi
        # local variables y = (x_A, x_B, master node 1, master node 2); x_s = (1 - t) x_A + t x_B: y = P z
        gy = np.concatenate([(1 - t)[:, None] * gz[:, 0:2], t[:, None] * gz[:, 0:2], gz[:, 2:6]], axis=1)
        es = xB - xA
        ls = np.linalg.norm(es, axis=1)
        eh = es / ls[:, None]
        ly = np.zeros((t.size, 8))
        ly[:, 0:2], ly[:, 2:4] = -eh, eh
        dofs = (2 * np.stack([A, B, n1, n2], axis=1)[:, :, None] + np.arange(2)).reshape(t.size, 8)
        rows = self.row_of[np.stack([A, B], axis=1)]  # (n, 2)
        return _Integrand(g, gz, hz, gy, ls, ly, dofs, np.stack([1 - t, t], axis=1), rows, rows >= 0)

    def _moving_bounds(self, pc: Pieces, x: np.ndarray):
        """The pieces' ends that move (a cut, not t = 0 or 1): (their integrand factors (:meth:`_integrand`), the
        sign of the bound (-1 at t0, +1 at t1), dt/du (n, 14) and its dofs (n, 14): x_A, x_B and the cut's master
        nodes); module docstring. None: no moving end."""
        parts = []
        for tb, cut, rho, other, sign in ((pc.t0, pc.cut0, pc.rho0, pc.other0, -1.0),
                                          (pc.t1, pc.cut1, pc.rho1, pc.other1, 1.0)):
            i = np.flatnonzero(cut >= 0)
            parts.append((i, tb[i], cut[i], rho[i], other[i], np.full(i.size, sign)))
        i, t, cut, rho, other, sign = (np.concatenate(c) for c in zip(*parts, strict=True))
        if i.size == 0:
            return None
        k = pc.k[i]
        it = self._integrand(x, k, t, pc.kind[i], pc.n1[i], pc.n2[i], pc.sgn[i], hessian=False)
        A, B = self.s_ends[k, 0], self.s_ends[k, 1]
        a, b = self.m_ends[cut, 0], self.m_ends[cut, 1]
        bis = rho == 2
        rho = np.where(bis, 0, rho)  # (a bisector has no end)
        oth = np.where(bis, other, cut)
        a2, b2 = self.m_ends[oth, 0], self.m_ends[oth, 1]
        xs = x[A] + t[:, None] * (x[B] - x[A])
        e, e2 = x[b] - x[a], x[b2] - x[a2]
        # phi = (x_s - x_a) . e - rho |e|^2 (a foot at an end) or (x_s - x_v) . (n - n2) (a bisector): linear in
        # x_s along c = e or n - n2, so d phi/dx_A = (1 - t) c, d phi/dx_B = t c, d phi/dt = (x_B - x_A) . c
        c = e.copy()
        dphi = np.zeros((i.size, 7, 2))  # in (x_A, x_B, x_a, x_b, x_a2, x_b2, x_v)
        d = xs - x[a]
        dphi[:, 2], dphi[:, 3] = (2 * rho - 1)[:, None] * e - d, d - 2 * rho[:, None] * e
        v_col = A.copy()  # the bisector's vertex (a zero column elsewhere)
        j = np.flatnonzero(bis)
        if j.size:  # the facets' normals n = sigma rot(e) / |e| turn with their nodes: w = d(q . n)/de, q = x_s - x_v
            v_col[j] = _shared_node(np.stack([a[j], b[j]], axis=1), np.stack([a2[j], b2[j]], axis=1))
            q = xs[j] - x[v_col[j]]
            grads = []
            for ee, sg in ((e[j], self.sigma[cut[j]]), (e2[j], self.sigma[oth[j]])):
                ell = np.linalg.norm(ee, axis=1)
                n = sg[:, None] * _rot(ee) / ell[:, None]
                grads.append((n, sg[:, None] * np.stack([-q[:, 1], q[:, 0]], axis=1) / ell[:, None]
                              - np.einsum("nj,nj->n", q, n)[:, None] * ee / ell[:, None] ** 2))
            (n_1, w1), (n_2, w2) = grads
            c[j] = n_1 - n_2
            dphi[j, 2], dphi[j, 3], dphi[j, 4], dphi[j, 5], dphi[j, 6] = -w1, w1, w2, -w2, -c[j]
        dphi[:, 0], dphi[:, 1] = (1 - t)[:, None] * c, t[:, None] * c
        dphidt = np.einsum("nj,nj->n", x[B] - x[A], c)
        dt = -dphi.reshape(i.size, 14) / dphidt[:, None]
        cols = (2 * np.stack([A, B, a, b, a2, b2, v_col], axis=1)[:, :, None] + np.arange(2)).reshape(i.size, 14)
        return it, sign, dt, cols

    def linearise(self, u: np.ndarray, *, hessian_weights: Callable[[np.ndarray], np.ndarray] | None = None,
                  derivatives: bool = True):
        """(g~ (m,), D (m x n) CSR, H (n x n) CSR or None, T (m x n) CSR): the weighted gaps, ``D = W_ref dg~/du``
        (row-scaled so that the problem's ``T^T diag(-dp/dg~ / W_ref) D`` is the exact term), the
        sum ``sum_i c_i dT_i/du`` for ``c = hessian_weights(g~)``, and the traction's virtual-work matrix T
        (``F_c = -T^T p``; module docstring). ``derivatives=False``: g~ and T only (D and H None; what the
        residual needs). The derivatives carry the cuts' motion (the moving bounds of the module docstring)."""
        m, nd = self.small.nodes.size, self.n_dofs
        pc = self._points(u)
        if pc is None:
            z = sp.csr_matrix((m, nd))
            return np.full(m, _FAR), z, (None if hessian_weights is None else sp.csr_matrix((nd, nd))), z
        ip, t, wt = self._gauss(pc)
        x = u.reshape(-1, 2) + self._X
        want_h = hessian_weights is not None
        it = self._integrand(x, pc.k[ip], t, pc.kind[ip], pc.n1[ip], pc.n2[ip], pc.sgn[ip], hessian=want_h)
        g, gy, ls, ly = it.g, it.gy, it.ls, it.ly
        wphi = np.where(it.valid, wt[:, None] * it.phi, 0.0)
        rr = np.maximum(it.rows, 0)
        G = np.bincount(rr.ravel(), weights=(wphi * (g * ls)[:, None]).ravel(), minlength=m)
        W = _nodal_weights(wphi, it.rows, ls, m)
        paired = W > 0
        gt = np.where(paired, G / np.where(paired, W, 1.0), _FAR * float(np.max(ls)))

        def rowmat(vals, rows, valid, cols):  # (n, 2, 8) on the rows (n, 2) and the columns (n, 8) -> (m x nd)
            ri = np.broadcast_to(rows[:, :, None], vals.shape)[valid]
            ci = np.broadcast_to(cols[:, None, :], vals.shape)[valid]
            M = sp.csr_matrix((vals[valid].ravel(), (ri.ravel(), ci.ravel())), shape=(m, nd))
            M.sum_duplicates()
            return M

        T = rowmat(wphi[:, :, None] * (ls[:, None] * gy)[:, None, :], it.rows, it.valid, it.dofs)
        if not derivatives:
            return gt, None, None, T
        dG = rowmat(wphi[:, :, None] * (ls[:, None] * gy + g[:, None] * ly)[:, None, :], it.rows, it.valid, it.dofs)
        dW = rowmat(wphi[:, :, None] * ly[:, None, :], it.rows, it.valid, it.dofs)
        bounds = self._moving_bounds(pc, x)
        if bounds is not None:  # + f(t1) dt1/du - f(t0) dt0/du, f = phi_i l_s g (G) and phi_i l_s (W)
            bt, sign, dt, cols = bounds
            fw = np.where(bt.valid, sign[:, None] * bt.phi * bt.ls[:, None], 0.0)  # (n, 2)
            dG = dG + rowmat((fw * bt.g[:, None])[:, :, None] * dt[:, None, :], bt.rows, bt.valid, cols)
            dW = dW + rowmat(fw[:, :, None] * dt[:, None, :], bt.rows, bt.valid, cols)
        scale = np.where(paired, self.small.W / np.where(paired, W, 1.0), 0.0)
        D = (sp.diags(scale) @ (dG - sp.diags(gt * paired) @ dW)).tocsr()
        H = None
        if want_h:
            n = t.size
            P = np.zeros((n, 6, 8))
            eye = np.eye(2)
            P[:, 0:2, 0:2] = (1 - t)[:, None, None] * eye
            P[:, 0:2, 2:4] = t[:, None, None] * eye
            P[:, 2:4, 4:6] = eye
            P[:, 4:6, 6:8] = eye
            hy = np.einsum("nzy,nzw,nwx->nyx", P, it.hz, P, optimize=True)
            c = hessian_weights(gt)
            c_pt = np.einsum("np,np->n", wphi, np.where(it.valid, c[rr], 0.0))
            hess = c_pt[:, None, None] * (ls[:, None, None] * hy + gy[:, :, None] * ly[:, None, :])
            Hi = np.broadcast_to(it.dofs[:, :, None], hess.shape)
            Hj = np.broadcast_to(it.dofs[:, None, :], hess.shape)
            vals, Ri, Cj = [hess.ravel()], [Hi.ravel()], [Hj.ravel()]
            if bounds is not None:  # sum_i c_i (f_T,i(t1) dt1/du - f_T,i(t0) dt0/du), f_T,i = phi_i l_s dg/dy
                cb = np.einsum("np,np->n", fw, np.where(bt.valid, c[np.maximum(bt.rows, 0)], 0.0))
                hb = (cb[:, None] * bt.gy)[:, :, None] * dt[:, None, :]
                vals.append(hb.ravel())
                Ri.append(np.broadcast_to(bt.dofs[:, :, None], hb.shape).ravel())
                Cj.append(np.broadcast_to(cols[:, None, :], hb.shape).ravel())
            H = sp.csr_matrix((np.concatenate(vals), (np.concatenate(Ri), np.concatenate(Cj))), shape=(nd, nd))
            H.sum_duplicates()
        return gt, D, H, T

    def current_weights(self, u: np.ndarray) -> np.ndarray:
        """The nodal weights on the CURRENT slave length, ``W_i = int phi_i dgamma`` (mm; 0 for a contact node
        without a partner now): ``p_i W_i`` is the node's contact force (N/mm), the pressure being per deformed
        length."""
        m = self.small.nodes.size
        pc = self._points(u)
        if pc is None:
            return np.zeros(m)
        ip, t, wt = self._gauss(pc)
        k = pc.k[ip]
        x = u.reshape(-1, 2) + self._X
        A, B = self.s_ends[k, 0], self.s_ends[k, 1]
        ls = np.linalg.norm(x[B] - x[A], axis=1)
        rows = self.row_of[np.stack([A, B], axis=1)]
        valid = rows >= 0
        wphi = np.where(valid, wt[:, None] * np.stack([1 - t, t], axis=1), 0.0)
        return _nodal_weights(wphi, rows, ls, m)

    def gaps(self, u: np.ndarray) -> np.ndarray:
        """The nodal weighted gaps g~ (mm) of the dof array u."""
        return self.linearise(u, derivatives=False)[0]

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


def _near(facing: np.ndarray, xm: np.ndarray, ls: np.ndarray, xa: np.ndarray, xb: np.ndarray) -> np.ndarray:
    """(n_s, n_m) True for the facing master facets (``facing``) that can hold the nearest feature of some point of
    a slave facet (midpoints xm, lengths ls; master facet ends xa, xb): those within ``ls`` (plus round-off) of the
    nearest facing facet's distance to xm (a point of the facet is within ls/2 of xm, so a farther facet is never
    the nearest to it)."""
    e = xb - xa
    d = xm[:, None, :] - xa[None, :, :]  # (n_s, n_m, 2)
    r = np.clip(np.einsum("smj,mj->sm", d, e) / np.einsum("mj,mj->m", e, e)[None, :], 0.0, 1.0)
    dist = np.linalg.norm(d - r[:, :, None] * e[None, :, :], axis=2)
    dist = np.where(facing, dist, np.inf)
    return facing & (dist <= dist.min(axis=1, initial=np.inf)[:, None] + 1.01 * ls[:, None])


def _shared_node_pairs(ends: np.ndarray, valid: np.ndarray):
    """The pairs of candidate facets that share a node, per slave facet: (k, i1, i2) with i1 < i2 slots of
    ``ends`` (K, C, 2; ``valid`` (K, C)), in the order of ``np.nonzero(np.triu(shares, 1))`` (k, then i1, then i2).
    A node of a polyline joins at most two facets; a node held by more gives every pair."""
    K, C = valid.shape
    k, slot = np.nonzero(valid)
    k, slot = np.repeat(k, 2), np.repeat(slot, 2)
    node = ends[valid].ravel()
    order = np.lexsort((slot, node, k))
    k, node, slot = k[order], node[order], slot[order]
    out = []
    for lag in range(1, 1 + max(C - 1, 0)):
        same = (k[lag:] == k[:-lag]) & (node[lag:] == node[:-lag])
        if not same.any():
            break
        out.append((k[lag:][same], slot[:-lag][same], slot[lag:][same]))
    if not out:
        empty = np.zeros(0, dtype=np.int64)
        return empty, empty, empty
    pk, i1, i2 = (np.concatenate(c) for c in zip(*out, strict=True))
    keep = i1 != i2  # a facet with both ends at one node (degenerate) is not a pair with itself
    pk, i1, i2 = pk[keep], i1[keep], i2[keep]
    key = (pk * C + i1) * C + i2
    key, first = np.unique(key, return_index=True)  # two facets sharing both ends: one pair, sorted
    return pk[first], i1[first], i2[first]


def _padded(row: np.ndarray, shape: tuple[int, int], *values: np.ndarray) -> tuple[np.ndarray, ...]:
    """Ragged rows as padded arrays: entry i of each of ``values`` goes to row ``row[i]`` (sorted), in the next free
    slot of that row; (valid (shape, bool), then one int64 array per value, 0 in the padding)."""
    slot = np.arange(row.size) - np.searchsorted(row, row)
    valid = np.zeros(shape, dtype=bool)
    valid[row, slot] = True
    out = []
    for v in values:
        a = np.zeros(shape, dtype=np.int64)
        a[row, slot] = v
        out.append(a)
    return (valid, *out)


def _shared_node(e1: np.ndarray, e2: np.ndarray) -> np.ndarray:
    """The node that the facets with ends e1 and e2 (..., 2) share (the first end of e1 if it is one of e2's)."""
    return np.where((e1[..., 0] == e2[..., 0]) | (e1[..., 0] == e2[..., 1]), e1[..., 0], e1[..., 1])


def _per_point(a: np.ndarray, idx: np.ndarray) -> np.ndarray:
    """``a[k, s, idx[k, p]]``: (K, S, P) from a (K, S, C) and idx (K, P)."""
    K, S = a.shape[:2]
    return a[np.arange(K)[:, None, None], np.arange(S)[None, :, None], idx[:, None, :]]


def _node_at(cells: CellData, P: np.ndarray) -> np.ndarray:
    """The node of each facet's cell that sits at the point P (n, 2) (a facet end)."""
    d = np.linalg.norm(cells.node_x - P[:, None, :], axis=2)
    return cells.nodes[np.arange(P.shape[0]), np.argmin(d, axis=1)]


def _nodal_weights(wphi: np.ndarray, rows: np.ndarray, ls: np.ndarray, m: int) -> np.ndarray:
    """``W_i = int phi_i dgamma`` (mm) of the m contact nodes from the Gauss points' weighted shape values ``wphi``
    (n, 2; 0 where the row is invalid), their rows (n, 2; -1: not a contact node) and the current slave facet
    lengths ``ls`` (n,): the weights of :meth:`FiniteContact.linearise`'s weighted gap and of
    :meth:`FiniteContact.current_weights`."""
    return np.bincount(np.maximum(rows, 0).ravel(), weights=(wphi * ls[:, None]).ravel(), minlength=m)
