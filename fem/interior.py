"""Interior stress error of a converged contact state against a closed-form field, over a box of the body.

    e_L2 = sqrt( int_B |sigma_h - sigma|^2 dx / |B| ),   |s|^2 = s_xx^2 + s_yy^2 + 2 s_xy^2 + s_zz^2

with ``s_zz`` the plane-strain out-of-plane stress (``lambda tr eps``, ``-p`` in the mixed formulation), over the
part B of the body inside the box ``|x| <= x_max``, ``-z_max <= y <= 0`` (mm; B's area |B| is integrated with the
same rule, so e_L2 is an RMS in MPa). Integration: Gauss points of degree ``quadrature_degree`` on every cell with
a vertex in the box, each point weighted by the indicator of the box (so B's boundary is resolved to the cell
size; the rule is the same on every grid). The largest von Mises stress over the same points is returned with its
place, for the FEM and the closed form.

Units: mm, MPa, tension positive. ``exact(x, y)`` returns ``(sxx, syy, sxy, szz)`` (MPa) at arrays of points in
the mesh frame.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

from collections.abc import Callable
from typing import NamedTuple

import basix
import dolfinx
import numpy as np
import ufl
from mpi4py import MPI

from fem.elasticity import epsilon, sigma, sigma_mixed, von_mises

__all__ = ["InteriorError", "interior_stress_error"]


class InteriorError(NamedTuple):
    """L2 (RMS) stress error over the box (MPa), the box area (mm^2) and the largest von Mises stresses.

    ``vm_max_fem`` / ``vm_max_exact`` (MPa) at ``(x, y)`` (mm) of the quadrature point where each is largest.
    """

    l2: float
    area: float
    vm_max_fem: float
    at_fem: tuple[float, float]
    vm_max_exact: float
    at_exact: tuple[float, float]


def interior_stress_error(result, exact: Callable, *, x_max: float, z_max: float,
                          quadrature_degree: int = 6) -> InteriorError:
    """The interior error of ``result`` (a :class:`fem.solver.ContactResult`) against ``exact`` (module docstring).

    For a half model (the mesh holds x >= 0 only) the box is its part in the mesh; the RMS is the same by symmetry.
    """
    u, ph, lm = result.u, result.pressure_field, result.lame
    mesh = u.function_space.mesh
    comm = mesh.comm
    s = sigma(u, lm) if ph is None else sigma_mixed(u, ph, lm)
    szz = lm.lmbda * ufl.tr(epsilon(u)) if ph is None else -ph
    comps = ufl.as_vector((s[0, 0], s[1, 1], s[0, 1], szz, von_mises(u, lm, ph)))
    pts_ref, wts = basix.make_quadrature(basix.CellType.triangle, quadrature_degree)
    n_local = mesh.topology.index_map(mesh.topology.dim).size_local
    # cells with a vertex in the box (owned cells only: each cell counted once over the ranks)
    cells = np.arange(n_local, dtype=np.int32)
    geom = mesh.geometry.x
    dofs = mesh.geometry.dofmaps[0][:n_local]
    vx, vy = geom[dofs, 0], geom[dofs, 1]
    inside_v = (np.abs(vx) <= x_max) & (vy >= -z_max)
    cells = cells[np.any(inside_v, axis=1)]
    X = ufl.SpatialCoordinate(mesh)
    everything = ufl.as_vector([*comps, X[0], X[1], ufl.JacobianDeterminant(mesh)])  # one Expression, one module
    vals = dolfinx.fem.Expression(everything, pts_ref).eval(mesh, cells).reshape(len(cells), len(wts), 8)
    fem_vals, xq, detj = vals[..., :5], vals[..., 5:7], np.abs(vals[..., 7])
    x, y = xq[..., 0].ravel(), xq[..., 1].ravel()
    ind = ((np.abs(x) <= x_max) & (y >= -z_max)).astype(float)
    w = (detj * wts[None, :]).ravel() * ind
    ex = np.array(exact(x, y))  # (4, n)
    fe = fem_vals.reshape(-1, 5).T
    d = fe[:4] - ex
    sq = d[0] ** 2 + d[1] ** 2 + 2.0 * d[2] ** 2 + d[3] ** 2
    num = comm.allreduce(float(np.sum(w * sq)), op=MPI.SUM)
    area = comm.allreduce(float(np.sum(w)), op=MPI.SUM)
    vm_ex = np.sqrt(0.5 * ((ex[0] - ex[1]) ** 2 + (ex[1] - ex[3]) ** 2 + (ex[3] - ex[0]) ** 2) + 3.0 * ex[2] ** 2)

    def largest(values):
        v = np.where(ind > 0, values, -np.inf)
        i = int(np.argmax(v)) if v.size else -1
        local = (float(v[i]), float(x[i]), float(y[i])) if i >= 0 else (-np.inf, 0.0, 0.0)
        return max(comm.allgather(local))

    vf, vfx, vfy = largest(fe[4])
    ve, vex, vey = largest(vm_ex)
    return InteriorError(l2=float(np.sqrt(num / area)), area=area, vm_max_fem=vf, at_fem=(vfx, vfy),
                         vm_max_exact=ve, at_exact=(vex, vey))
