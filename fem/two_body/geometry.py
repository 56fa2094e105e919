"""Pairing of two meshed contact surfaces in 2D (numpy only): mortar segments and node-to-segment points.

Units mm. Both surfaces are chains of straight facets (the meshes have affine triangles). The *slave* surface
carries the integration; every slave point ``X_s`` is paired with the master point ``X_m`` where the ray
``X_s + s nu_s`` along the slave facet's outward unit normal ``nu_s`` meets a master facet. The signed distance
``g0 = (X_m - X_s) . nu_s`` is the initial gap (> 0 open, < 0 overlap). With ``small`` kinematics the pairing is
made once, in the reference configuration, and the gap of a displacement u is

    g(u) = g0 + (u_m(X_m) - u_s(X_s)) . nu_s                                  (mm, > 0 open)

Two pairings (:class:`PairedPoints`, one row per point):

* **mortar** (segment-to-segment, :func:`mortar_points`): each slave facet is cut at the projections of the
  master facet ends into segments, each segment paired with one master facet; ``n_gauss`` Gauss points per
  segment. A product of a slave and a master polynomial of degree p is integrated exactly with
  ``n_gauss = p + 1``; that is what makes the contact patch test pass on non-matching meshes.
* **node-to-segment** (:func:`node_points`): one point per slave facet node (P1: the two ends, P2: also the
  midpoint) with the nodal weight ``int_facet N_i ds`` of its Lagrange function on that facet (P1: L/2, L/2;
  P2: L/6, 2L/3, L/6; :func:`lagrange_node_weights`). The
  gap is collocated at the nodes and the force of node i goes to the master nodes by the master shape
  functions at its projection, which is not the consistent load of a uniform pressure on a non-matching
  master mesh: node-to-segment fails the patch test (Taylor and Papadopoulos 1991).

A master facet is a candidate for a slave facet only if the two face each other
(``nu_s . nu_m < -FACING_COS``); where several candidates cover a slave sub-interval the nearest one (smallest
``|g0|``) is taken.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["FACING_COS", "SurfaceGeometry", "PairedPoints", "mortar_points", "node_points", "gauss_legendre_01",
           "facet_node_params", "multiplier_basis", "CircleSurface", "ProfileSurface", "exact_master_gaps"]

# A master facet faces a slave facet when the angle between nu_s and -nu_m is below acos(FACING_COS) = 78.5 deg.
FACING_COS = 0.2
_EPS = 1e-12  # relative length below which a segment is dropped (facet-parameter units)


class SurfaceGeometry(NamedTuple):
    """The straight facets of one contact surface (n facets; mm).

    Attributes:
        a, b: (n, 2) facet end points (reference configuration).
        normal: (n, 2) outward unit normal of the body.
        cell: (n,) index of the cell that owns the facet (local to the mesh).
    """

    a: np.ndarray
    b: np.ndarray
    normal: np.ndarray
    cell: np.ndarray

    @property
    def length(self) -> np.ndarray:
        return np.linalg.norm(self.b - self.a, axis=1)


class PairedPoints(NamedTuple):
    """Paired slave/master points (one row each; mm).

    Attributes:
        slave_facet, master_facet: (n,) facet indices into the slave and master :class:`SurfaceGeometry`.
        X_s, X_m: (n, 2) slave and master points (reference configuration).
        normal: (n, 2) slave outward unit normal ``nu_s`` at the point.
        weight: (n,) integration weight (mm): Gauss weight times segment length (mortar) or the nodal weight
            ``int N_i ds`` on its facet (node-to-segment).
        g0: (n,) initial gap ``(X_m - X_s) . nu_s`` (mm).
    """

    slave_facet: np.ndarray
    master_facet: np.ndarray
    X_s: np.ndarray
    X_m: np.ndarray
    normal: np.ndarray
    weight: np.ndarray
    g0: np.ndarray


def gauss_legendre_01(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre points and weights on [0, 1] (weights sum to 1)."""
    x, w = np.polynomial.legendre.leggauss(int(n))
    return 0.5 * (x + 1.0), 0.5 * w


def facet_node_params(degree: int) -> tuple[np.ndarray, np.ndarray]:
    """Parameters in [0, 1] of the Lagrange nodes on a facet and their weights ``int_0^1 phi_i dt`` with the
    contact basis :func:`multiplier_basis`."""
    if degree == 1:
        return np.array([0.0, 1.0]), np.array([0.5, 0.5])
    if degree == 2:
        return np.array([0.0, 0.5, 1.0]), np.array([0.25, 0.5, 0.25])
    raise ValueError(f"degree must be 1 or 2 for meshed contact surfaces, got {degree}")


def lagrange_node_weights(degree: int) -> np.ndarray:
    """``int_0^1 N_i dt`` of the Lagrange functions of a facet's nodes (P1: 1/2, 1/2; P2: Simpson 1/6, 2/3, 1/6):
    the consistent nodal loads of a uniform pressure on the slave side, the node-to-segment weights."""
    if degree == 1:
        return np.array([0.5, 0.5])
    if degree == 2:
        return np.array([1.0, 4.0, 1.0]) / 6.0
    raise ValueError(f"degree must be 1 or 2 for meshed contact surfaces, got {degree}")


def _ray_hits(X: np.ndarray, nu: np.ndarray, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For rays ``X + s nu`` and segments ``a + r (b - a)`` (broadcast): (s, r); nan where parallel."""
    e = b - a
    det = nu[..., 0] * (-e[..., 1]) - nu[..., 1] * (-e[..., 0])
    rhs = a - X
    with np.errstate(divide="ignore", invalid="ignore"):
        s = (rhs[..., 0] * (-e[..., 1]) - rhs[..., 1] * (-e[..., 0])) / det
        r = (nu[..., 0] * rhs[..., 1] - nu[..., 1] * rhs[..., 0]) / det
    return s, r


def _candidates(slave: SurfaceGeometry, master: SurfaceGeometry, k: int) -> np.ndarray:
    """Indices of the master facets that face slave facet k."""
    facing = slave.normal[k] @ master.normal.T < -FACING_COS
    return np.flatnonzero(facing)


def _project_params(slave: SurfaceGeometry, k: int, P: np.ndarray) -> np.ndarray:
    """Parameters t in the slave facet k of the projections of points P (along the slave normal)."""
    a, b = slave.a[k], slave.b[k]
    e = b - a
    return (P - a) @ e / (e @ e)


def multiplier_basis(t: np.ndarray, degree: int) -> np.ndarray:
    """(n, k) values at facet parameters t of the contact (multiplier) basis of a facet's k Lagrange nodes.

    Degree 1: the linear Lagrange functions (1 - t, t). Degree 2: piecewise linear hats on the facet split at
    its midpoint, ``(max(0, 1 - 2t), 1 - |2t - 1|, max(0, 2t - 1))``: one function per displacement node, all
    >= 0 with a partition of unity. The quadratic Lagrange functions would not do: the corner ones are negative
    on half the facet, and the nodal pressures then oscillate from corner to midside node (measured on the
    elastic cylinder, h = a/10: 1294, 1107, 1596, 1627 MPa across the edge where the theory rises smoothly
    859 to 1832 MPa).
    """
    t = np.asarray(t, dtype=float)
    if degree == 1:
        return np.stack([1.0 - t, t], axis=1)
    if degree == 2:
        return np.stack([np.maximum(0.0, 1.0 - 2.0 * t), 1.0 - np.abs(2.0 * t - 1.0), np.maximum(0.0, 2.0 * t - 1.0)],
                        axis=1)
    raise ValueError(f"degree must be 1 or 2 for meshed contact surfaces, got {degree}")


def mortar_points(slave: SurfaceGeometry, master: SurfaceGeometry, *, n_gauss: int,
                  cuts: tuple[float, ...] = (), kinks: np.ndarray | None = None) -> PairedPoints:
    """Mortar segments of every slave facet and ``n_gauss`` Gauss points on each (module docstring); ``cuts``:
    extra facet parameters where the segments are cut (the kinks of the multiplier basis); ``kinks``: (k, 2)
    master points (mm) whose projections cut the slave facets as the master facet ends do (the kinks of the
    master's exact profile, e.g. a wedge's apex: no Gauss segment straddles them)."""
    tg, wg = gauss_legendre_01(n_gauss)
    kinks = np.zeros((0, 2)) if kinks is None else np.asarray(kinks, dtype=float).reshape(-1, 2)
    rows = []
    for k in range(slave.a.shape[0]):
        cand = _candidates(slave, master, k)
        if cand.size == 0:
            continue
        ta = _project_params(slave, k, master.a[cand])
        tb = _project_params(slave, k, master.b[cand])
        lo, hi = np.minimum(ta, tb), np.maximum(ta, tb)
        keep = (hi > _EPS) & (lo < 1.0 - _EPS)
        cand, lo, hi = cand[keep], lo[keep], hi[keep]
        if cand.size == 0:
            continue
        tk = _project_params(slave, k, kinks)
        breaks = np.unique(np.clip(np.concatenate([[0.0, 1.0], list(cuts), lo, hi, tk]), 0.0, 1.0))
        L = np.linalg.norm(slave.b[k] - slave.a[k])
        nu = slave.normal[k]
        for t0, t1 in zip(breaks[:-1], breaks[1:], strict=True):
            if t1 - t0 <= _EPS:
                continue
            mid = 0.5 * (t0 + t1)
            cover = (lo <= mid) & (mid <= hi)
            if not cover.any():
                continue
            Xmid = slave.a[k] + mid * (slave.b[k] - slave.a[k])
            s, _ = _ray_hits(Xmid, nu, master.a[cand[cover]], master.b[cand[cover]])
            j = cand[cover][int(np.nanargmin(np.abs(s)))]
            t = t0 + (t1 - t0) * tg
            X = slave.a[k] + t[:, None] * (slave.b[k] - slave.a[k])
            s, r = _ray_hits(X, nu, master.a[j], master.b[j])
            Xm = master.a[j] + r[:, None] * (master.b[j] - master.a[j])
            rows.append((np.full(t.size, k), np.full(t.size, j), X, Xm, np.tile(nu, (t.size, 1)),
                         (t1 - t0) * L * wg, s))
    return _stack(rows)


def node_points(slave: SurfaceGeometry, master: SurfaceGeometry, *, degree: int) -> PairedPoints:
    """Node-to-segment points: the Lagrange nodes of every slave facet with their nodal weights, each paired
    with the nearest facing master facet its normal ray hits (module docstring)."""
    tn, _ = facet_node_params(degree)
    wn = lagrange_node_weights(degree)
    rows = []
    for k in range(slave.a.shape[0]):
        cand = _candidates(slave, master, k)
        if cand.size == 0:
            continue
        L = np.linalg.norm(slave.b[k] - slave.a[k])
        nu = slave.normal[k]
        for t, w in zip(tn, wn, strict=True):
            X = slave.a[k] + t * (slave.b[k] - slave.a[k])
            s, r = _ray_hits(X, nu, master.a[cand], master.b[cand])
            ok = (r >= -1e-9) & (r <= 1.0 + 1e-9) & np.isfinite(s)
            if not ok.any():
                continue
            i = np.flatnonzero(ok)[int(np.argmin(np.abs(s[ok])))]
            j, rr = cand[i], float(np.clip(r[i], 0.0, 1.0))
            Xm = master.a[j] + rr * (master.b[j] - master.a[j])
            rows.append((np.array([k]), np.array([j]), X[None, :], Xm[None, :], nu[None, :], np.array([w * L]),
                         np.array([s[i]])))
    return _stack(rows)


class CircleSurface(NamedTuple):
    """The exact reference surface of a meshed circular body (centre (mm), radius R (mm)): the mesh's facets are
    its chords, and a chord lies up to ``h^2 / (8 R)`` inside the circle."""

    center: tuple[float, float]
    radius: float

    def height(self, x1: np.ndarray):
        """(h, h', h'') of the circle's lower arc at abscissae x1 (mm): ``h = c2 - sqrt(R^2 - (x1 - c1)^2)``."""
        dx = np.asarray(x1, dtype=float) - self.center[0]
        root = np.sqrt(np.maximum(self.radius**2 - dx * dx, 1e-300))
        return self.center[1] - root, dx / root, self.radius**2 / root**3

    def kinks(self) -> np.ndarray:
        """(0, 2): a circle has no kink."""
        return np.zeros((0, 2))

    def ray_distance(self, X: np.ndarray, nu: np.ndarray, s_near: np.ndarray) -> np.ndarray:
        """Signed distances s along the rays ``X + s nu`` to the circle, the root nearest to ``s_near``."""
        c = np.asarray(self.center, dtype=float)
        d = X - c
        b = np.einsum("ij,ij->i", d, nu)
        disc = b * b - (np.einsum("ij,ij->i", d, d) - self.radius ** 2)
        root = np.sqrt(np.maximum(disc, 0.0))
        s1, s2 = -b - root, -b + root
        return np.where(np.abs(s1 - s_near) <= np.abs(s2 - s_near), s1, s2)


class ProfileSurface(NamedTuple):
    """The reference surface of a flat-faced master body that carries a gap profile (two half-planes with a
    profile, issue 25): the master's facets lie on ``y = 0``, and its reference surface is ``y = h(X1)`` above
    them, a parabola ``h = X1^2 / (2 R)`` (``kind = "parabola"``, ``size = R`` in mm) or a wedge
    ``h = m |X1|`` (``kind = "wedge"``, ``size = m``, the face slope). The profile travels with the master's
    material points (it is evaluated at the master abscissa X1 that a slave point meets), as the indenter's profile
    in Ciavarella and Hills's half-plane theory."""

    kind: str
    size: float

    def height(self, x1: np.ndarray):
        """(h, h', h'') at material abscissae x1 (mm): h'' of the wedge is 0 off its apex."""
        x = np.asarray(x1, dtype=float)
        if self.kind == "parabola":
            return 0.5 * x * x / self.size, x / self.size, np.full_like(x, 1.0 / self.size)
        return self.size * np.abs(x), self.size * np.sign(x), np.zeros_like(x)

    def kinks(self) -> np.ndarray:
        """(k, 2) points of the master's flat face (mm) where h' jumps: the wedge's apex (0, 0); none for the
        parabola. The mortar segments are cut at their projections (:func:`mortar_points`)."""
        return np.array([[0.0, 0.0]]) if self.kind == "wedge" else np.zeros((0, 2))

    def ray_distance(self, X: np.ndarray, nu: np.ndarray, s_near: np.ndarray) -> np.ndarray:
        """Signed distances s along the rays ``X + s nu`` to ``y = h(x)`` (Newton from ``s_near``; exact in one
        step for the vertical rays of a flat slave)."""
        s = np.asarray(s_near, dtype=float).copy()
        for _ in range(50):
            h, hp, _ = self.height(X[:, 0] + s * nu[:, 0])
            f = h - (X[:, 1] + s * nu[:, 1])
            df = hp * nu[:, 0] - nu[:, 1]
            step = f / df
            s -= step
            if np.all(np.abs(step) <= 1e-15 * (1.0 + np.abs(s))):
                break
        return s


def exact_master_gaps(pts: PairedPoints, surface) -> PairedPoints:
    """The paired points with the initial gap ``g0`` measured to the master body's exact reference surface
    (``surface.ray_distance``) instead of its chords. The gap profile's curvature is what sets a contact
    pressure: against the chords it is zero on each facet and concentrated at the nodes, and the pressure of a
    meshed cylinder then oscillates from node to node (measured, elastic cylinder h = a/10: p_max +0.9 % with
    chords). The master point ``X_m`` where u_m is interpolated stays on the chord (inside its cell)."""
    if surface is None or pts.g0.size == 0:
        return pts
    return pts._replace(g0=surface.ray_distance(pts.X_s, pts.normal, pts.g0))


def _stack(rows) -> PairedPoints:
    if not rows:
        z = np.zeros(0)
        return PairedPoints(z.astype(int), z.astype(int), np.zeros((0, 2)), np.zeros((0, 2)), np.zeros((0, 2)), z, z)
    cols = list(zip(*rows, strict=True))
    return PairedPoints(np.concatenate(cols[0]).astype(np.int64), np.concatenate(cols[1]).astype(np.int64),
                        np.vstack(cols[2]), np.vstack(cols[3]), np.vstack(cols[4]), np.concatenate(cols[5]),
                        np.concatenate(cols[6]))
