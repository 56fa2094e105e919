"""Contact post-processing: surface samples at quadrature points, contact edges, patches, loads.

Conventions (units: mm, N/mm, MPa): pressure p >= 0 compressive, from the contact law (penalty
``kappa [-g]_+``, Nitsche ``[-P_gamma]_+``) at the facet quadrature points of Gamma_c; the pressure argument
``q`` (``p = [q]_+``) locates the contact edges by zero-crossing interpolation between neighbouring samples.
All samples are gathered to every rank (MPI-safe) and sorted by the surface coordinate ``s`` (the material
abscissa X1 on the block top).

Half models: samples live on x >= 0; :func:`find_patches` mirrors patches touching ``s = 0`` (full-body centre,
half-width, peak) and doubles their load when ``half=True``.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

import basix
import dolfinx
import numpy as np
import ufl

from measures.contact import Patch, SurfaceSamples, contact_edges, find_patches

__all__ = ["SurfaceSamples", "SurfaceSampler", "Patch", "sample_surface", "find_patches", "contact_edges",
           "integration_entities", "facets_across", "resolution_warnings", "penetration_warning",
           "oscillation_warnings", "LOCKING_NU"]

# Displacement-formulation runs at nu >= LOCKING_NU get a "near-incompressible" warning. Measured on the Hertz
# scene (P2, h = a/10, Nitsche): peak error 0.02 % at nu = 0.3, 2.8 % at nu = 0.45, 8 % RMS and an oscillating
# pressure at nu = 0.499, divergence at 0.4999; P1 (h = a/40) is worse. The mixed formulation holds 0.1 %.
LOCKING_NU = 0.45


def integration_entities(mesh, facets) -> np.ndarray:
    """(n, 2) owned (cell, local facet) pairs of the given exterior facets."""
    tdim = mesh.topology.dim
    mesh.topology.create_connectivity(tdim - 1, tdim)
    mesh.topology.create_connectivity(tdim, tdim - 1)
    ent = dolfinx.fem.compute_integration_domains(dolfinx.fem.IntegralType.exterior_facet, mesh.topology,
                                                  np.asarray(facets, dtype=np.int32))
    return np.asarray(ent, dtype=np.int32).reshape(-1, 2)


class SurfaceSampler:
    """:func:`sample_surface` with its set-up done once: ``SurfaceSampler(u=..., forms=..., facets=...,
    quadrature_degree=...)()`` returns the samples of the current ``u`` (and the current values of the
    Constants in ``forms``).

    The dolfinx Expression (FFCx JIT lookup), the integration entities and the quadrature weights times facet
    lengths depend only on the forms, the mesh and the facets, so a solver that samples the surface after
    every load step builds one sampler per solve.

    ``rule`` (points (n, 1) on the reference facet and weights summing to 1, e.g. a
    :class:`fem.methods.base.SampleRule`) replaces the Gauss points of ``quadrature_degree``; samples at the same
    material point (a facet end point seen from both facets) are then merged (weight-averaged values, summed
    weights).
    """

    def __init__(self, *, u, forms, facets, quadrature_degree: int | None = None, rule=None,
                 compiled: dict | None = None):
        mesh = u.function_space.mesh
        self._mesh = mesh
        self._ent = integration_entities(mesh, facets)
        _, wts = _points(quadrature_degree, rule)
        self._merge = rule is not None
        self._nq = len(wts)
        # built on every rank: an Expression is compiled collectively (dolfinx's mpi_jit), so a rank without
        # contact facets must build it too, or the ranks that have some wait for it forever (a hang under mpiexec)
        if compiled is None:
            compiled = {name: dolfinx.fem.Expression(e, X) for name, (e, X) in
                        self.expressions(u=u, forms=forms, quadrature_degree=quadrature_degree, rule=rule).items()}
        self._expr, ends = compiled["fields"], compiled["ends"]
        if self._ent.shape[0]:
            xe = ends.eval(mesh, self._ent).reshape(self._ent.shape[0], 2, 2)
            length = np.linalg.norm(xe[:, 1] - xe[:, 0], axis=1)
            w = (length[:, None] * wts[None, :]).reshape(-1)
        else:
            w = np.zeros(0)
        self._w = np.concatenate(mesh.comm.allgather(w))

    @staticmethod
    def expressions(*, u, forms, quadrature_degree: int | None = None, rule=None) -> dict:
        """The sampler's UFL expressions with their reference points on the facet: ``fields`` (X, u, p, q,
        sigma_nn, gap at the sample points) and ``ends`` (X at the facet's ends), to compile with the problem's
        forms (:mod:`fem.compiled_forms`) and hand back as ``compiled``."""
        X = ufl.SpatialCoordinate(u.function_space.mesh)
        fields = ufl.as_vector([X[0], X[1], u[0], u[1], forms.pressure, forms.argument, forms.sigma_nn,
                                forms.gap])
        return {"fields": (fields, _points(quadrature_degree, rule)[0]), "ends": (X, np.array([[0.0], [1.0]]))}

    def __call__(self) -> SurfaceSamples:
        """The samples of the current state, gathered to every rank and sorted by ``s``."""
        ent, mesh = self._ent, self._mesh
        if ent.shape[0]:
            vals = self._expr.eval(mesh, ent).reshape(-1, 8)
        else:
            vals = np.zeros((0, 8))
        vals = np.concatenate(mesh.comm.allgather(vals), axis=0)
        order = np.lexsort((vals[:, 1], vals[:, 0]))
        vals, w = vals[order], self._w[order]
        if self._merge:
            vals, w = _merge_coincident(vals, w)
        Xs = vals[:, 0:2]
        return SurfaceSamples(s=Xs[:, 0].copy(), X=Xs, x=Xs + vals[:, 2:4], p=vals[:, 4], q=vals[:, 5],
                              sigma_nn=vals[:, 6], gap=vals[:, 7], weight=w)


def _points(quadrature_degree: int | None, rule) -> tuple[np.ndarray, np.ndarray]:
    """Sample points (n, 1) on the reference facet and weights (sum 1): ``rule``'s, else the Gauss rule of
    ``quadrature_degree``."""
    if rule is None:
        return basix.make_quadrature(basix.CellType.interval, quadrature_degree)
    return np.asarray(rule.points, dtype=float), np.asarray(rule.weights, dtype=float)


def _merge_coincident(vals: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Merge samples at the same material point (a facet end point sampled from both of its facets).

    ``vals`` sorted by (X1, X2); merged rows are the weight-averaged values with the summed weight, so
    ``sum(weight * p)`` is unchanged.
    """
    if vals.shape[0] < 2:
        return vals, w
    tol = 1e-12 * max(1.0, float(np.max(np.abs(vals[:, 0:2]))))
    new = np.ones(vals.shape[0], dtype=bool)
    new[1:] = np.any(np.abs(np.diff(vals[:, 0:2], axis=0)) > tol, axis=1)
    group = np.cumsum(new) - 1
    wsum = np.bincount(group, weights=w)
    merged = np.column_stack([np.bincount(group, weights=w * vals[:, k]) for k in range(vals.shape[1])])
    safe = np.where(wsum > 0, wsum, 1.0)
    merged /= safe[:, None]
    return merged, wsum


def sample_surface(*, u, forms, facets, quadrature_degree: int) -> SurfaceSamples:
    """Evaluate p, q, sigma_nn, gap and positions at the Gauss points of the contact facets (all ranks).

    One-off use; repeated sampling of the same problem should keep a :class:`SurfaceSampler`. A
    :class:`SurfaceSampler` built with a ``rule`` (points and weights on the reference facet, e.g. the nodal rule
    of the augmented Lagrangian method) samples there instead and merges the points shared by two facets.
    """
    return SurfaceSampler(u=u, forms=forms, facets=facets, quadrature_degree=quadrature_degree)()


def facets_across(samples: SurfaceSamples, *, quadrature_degree: int, half: bool = False,
                  points_per_facet: int | None = None) -> list[float]:
    """Number of contact facets spanned by each patch (same order as :func:`find_patches`).

    ``(right - left) / h`` with ``h`` the mean length of the facets holding the patch's active samples (the
    sample weights of one facet sum to its length; ``quadrature_degree`` gives the points per facet, or
    ``points_per_facet`` for samples at a method's own points). A half model's patch at ``s = 0`` counts its
    mirror image too.
    """
    n_q = (len(basix.make_quadrature(basix.CellType.interval, quadrature_degree)[1]) if points_per_facet is None
           else int(points_per_facet))
    out = []
    for left, right, i, j in contact_edges(samples.s, samples.q):
        n = j - i + 1
        h = float(np.sum(samples.weight[i:j + 1])) * n_q / n
        width = 2.0 * right if (half and i == 0) else right - left
        out.append(width / h if h > 0 else 0.0)
    return out


def resolution_warnings(samples: SurfaceSamples, *, quadrature_degree: int, half: bool = False,
                        min_facets_across: int = 8, points_per_facet: int | None = None) -> list[str]:
    """Named warnings about whether the contact is resolved by the mesh (empty list: none).

    * ``"no contact: ..."``: no sample is active.
    * ``"contact unresolved: ..."``: a patch spans fewer than ``min_facets_across`` contact facets, so its
      half-width and peak are set by where the nodes fall rather than by the solution (refine h_contact).
    * ``"contact truncated: ..."``: a patch reaches the end of the candidate contact boundary (the contact
      group is too short; the symmetry end of a half model does not count).
    """
    runs = contact_edges(samples.s, samples.q)
    if not runs:
        return ["no contact: no active contact sample (the obstacle does not touch the body)"]
    out = []
    n = len(samples.s)
    across = facets_across(samples, quadrature_degree=quadrature_degree, half=half,
                           points_per_facet=points_per_facet)
    for (left, right, i, j), k in zip(runs, across, strict=True):
        if k < min_facets_across:
            where = 0.0 if (half and i == 0) else 0.5 * (left + right)
            out.append(f"contact unresolved: the patch at X1 = {where:.6g} mm spans {k:.2f} contact facets "
                       f"(< {min_facets_across}); refine h_contact")
        if j == n - 1 or (i == 0 and not half):
            out.append(f"contact truncated: the patch [{left:.6g}, {right:.6g}] mm reaches the end of the "
                       "candidate contact boundary")
    return out


def penetration_warning(samples: SurfaceSamples, *, d: float, rtol: float = 1e-3) -> str | None:
    """``"penetration: ..."`` when the largest penetration ``max(-g)`` exceeds ``rtol |d|`` (else None).

    Penalty (and Nitsche with a small gamma0) lets the body penetrate the obstacle by about ``p / kappa``; that
    penetration is lost from the elastic approach ``d``, so ``max(-g) / |d|`` is the relative error it puts
    into the load-approach relation and, through it, into the half-width and the peak. Measured on the Hertz
    scene (h = a/10, P2): 3e-5 with the defaults (Nitsche gamma0 = 10; penalty kappa0 = 1e3), 2.7e-2 with
    penalty kappa0 = 1 (peak 10 % off).
    """
    pen = float(max(0.0, -np.min(samples.gap))) if samples.gap.size else 0.0
    if d != 0 and pen > rtol * abs(d):
        return (f"penetration: max(-g) = {pen:.3g} mm is {pen / abs(d):.2g} of the rigid displacement d "
                f"(> {rtol:g}); raise kappa0 / gamma0")
    return None


def oscillation_warnings(samples: SurfaceSamples) -> list[str]:
    """``"pressure oscillation: ..."`` for each patch whose contact pressure zig-zags between samples.

    For a patch with samples ``p_i..p_j`` and peak ``p_m``, the excess variation
    ``e = (sum |p_{k+1} - p_k| - (2 p_m - p_i - p_j)) / p_m`` is 0 for a single-peaked profile. A patch is
    flagged when ``e > 0.1`` AND it has at least 3 local maxima, more than one per 10 samples (so a genuine
    two- or three-peaked patch resolved by many samples is not flagged). Measured on the Hertz scene (24
    samples): e = 0 with the default Nitsche gamma0 = 10; e = 0.26, 9 maxima with penalty kappa0 = 1e3 and
    e = 0.36 with Nitsche gamma0 = 1e4 (the constraint over-enforced at the Gauss points: RMS/p0 2.0-2.3 %
    against 0.4 %); e = 2.2 at nu = 0.499 with the displacement formulation (locking).
    """
    out = []
    for left, right, i, j in contact_edges(samples.s, samples.q):
        p = samples.p[i:j + 1]
        if p.size < 4:
            continue
        pm = float(p.max())
        excess = (float(np.sum(np.abs(np.diff(p)))) - (2.0 * pm - p[0] - p[-1])) / pm
        n_max = int(np.sum((p[1:-1] > p[:-2]) & (p[1:-1] > p[2:])))
        if excess > 0.1 and n_max >= 3 and n_max > 0.1 * p.size:
            out.append(f"pressure oscillation: the patch [{left:.6g}, {right:.6g}] mm has {n_max} local maxima in "
                       f"{p.size} samples, excess variation {excess:.2f} p_max (> 0.1): lower kappa0 / gamma0, or "
                       "use formulation='mixed' near nu = 0.5")
    return out
