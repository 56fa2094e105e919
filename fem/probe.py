"""Stresses of a converged contact state at given material points (MPI-safe), e.g. down the symmetry axis.

The Cauchy stress of a P_k displacement on affine triangles is a polynomial of degree k - 1 per cell, so it is
interpolated exactly into a discontinuous ``DG(k - 1)`` tensor space and evaluated there (at a point on a cell
boundary, dolfinx picks one of the cells). Units: mm and MPa, tension positive; ``szz`` is the plane-strain
out-of-plane stress ``lambda tr(eps)`` (``-p`` in the mixed formulation), ``vm`` the von Mises stress with it.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

from typing import NamedTuple

import dolfinx
import numpy as np
import ufl
from mpi4py import MPI

from fem.elasticity import epsilon, sigma, sigma_mixed, von_mises

__all__ = ["StressSamples", "stress_at_points"]


class StressSamples(NamedTuple):
    """Stress components (MPa) at the probe points, in the order given; NaN where no cell holds a point."""

    sxx: np.ndarray
    syy: np.ndarray
    sxy: np.ndarray
    szz: np.ndarray
    vm: np.ndarray


def stress_at_points(result, points: np.ndarray) -> StressSamples:
    """Evaluate the stress of ``result`` (a :class:`fem.solver.ContactResult`) at (n, 2) material points (mm).

    Every rank passes the same points and gets the same values (each point is evaluated by the lowest rank
    whose cells hold it).
    """
    u, ph, lm = result.u, result.pressure_field, result.lame
    mesh = u.function_space.mesh
    comm = mesh.comm
    deg = max(u.function_space.ufl_element().embedded_superdegree - 1, 0)
    stress = sigma(u, lm) if ph is None else sigma_mixed(u, ph, lm)
    szz = lm.lmbda * ufl.tr(epsilon(u)) if ph is None else -ph
    comps = (stress[0, 0], stress[1, 1], stress[0, 1], szz, von_mises(u, lm, ph))
    Q = dolfinx.fem.functionspace(mesh, ("DG", deg, (len(comps),)))
    f = dolfinx.fem.Function(Q)
    f.interpolate(dolfinx.fem.Expression(ufl.as_vector(comps), Q.element.interpolation_points))

    pts = np.zeros((len(points), 3))
    pts[:, :2] = np.asarray(points, dtype=float)
    tree = dolfinx.geometry.bb_tree(mesh, mesh.topology.dim)
    hits = dolfinx.geometry.compute_colliding_cells(mesh, dolfinx.geometry.compute_collisions_points(tree, pts), pts)
    local = np.full((len(pts), len(comps)), np.nan)
    idx = [i for i in range(len(pts)) if len(hits.links(i)) > 0]
    if idx:
        cells = np.array([hits.links(i)[0] for i in idx], dtype=np.int32)
        local[idx] = f.eval(pts[idx], cells)
    owner = np.where(np.isnan(local[:, 0]), comm.size, comm.rank).astype(np.int64)
    comm.Allreduce(MPI.IN_PLACE, owner, op=MPI.MIN)
    values = np.where((owner == comm.rank)[:, None], np.nan_to_num(local), 0.0)
    comm.Allreduce(MPI.IN_PLACE, values, op=MPI.SUM)
    values[owner == comm.size] = np.nan
    return StressSamples(*values.T)
