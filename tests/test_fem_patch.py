"""Flat frictionless rigid punch patch test: uniform uniaxial strain, to round-off (Nitsche) / penalty size.

Block [0, W] x [-H, 0] (structured triangles, all cells the same diameter h), roller bottom (u_y = 0), roller
sides (u_x = 0), a rigid half-plane wider than the block pressed down by d. Exact solution (plane strain):
u_y = -d (1 + y / H), u_x = 0, sigma_yy = -M d / H, sigma_xx = -lambda d / H, M = lambda + 2 mu; it lies in
the P1/P2 space, so Nitsche (consistent) reproduces it to round-off. Penalty with kappa = kappa0 E / h leaves a
penetration g = -p / kappa, so p = M d / H / (1 + M / (kappa H)) exactly (also linear, also round-off).
"""

import dolfinx_solver  # noqa: F401

import dolfinx
import numpy as np
import pytest
from dolfinx.io.gmsh import MeshData, PhysicalGroup
from mpi4py import MPI

from fem.elasticity import lame, sigma
from fem.obstacles import PlaneObstacle
from fem.solver import solve_contact

E, NU, W, H, D = 1000.0, 0.3, 2.0, 1.0, 1e-3
# Round-off tolerance: relative errors of an exact discrete solution are ~ cond * eps; 1e-9 leaves margin.
TOL_ROUNDOFF = 1e-9


def structured_block(nx=8, ny=4):
    mesh = dolfinx.mesh.create_rectangle(MPI.COMM_WORLD, [[0.0, -H], [W, 0.0]], [nx, ny],
                                         dolfinx.mesh.CellType.triangle)
    fdim = 1
    groups = {"contact": (1, lambda x: np.isclose(x[1], 0.0)), "clamped": (2, lambda x: np.isclose(x[1], -H)),
              "sides": (3, lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], W))}
    idx, val = [], []
    for tag, marker in groups.values():
        f = dolfinx.mesh.locate_entities_boundary(mesh, fdim, marker)
        idx.append(f)
        val.append(np.full(f.size, tag, dtype=np.int32))
    idx, val = np.concatenate(idx), np.concatenate(val)
    # a corner facet belongs to one group only (locate returns facets, corners are vertices): no duplicates
    order = np.argsort(idx)
    tags = dolfinx.mesh.meshtags(mesh, fdim, idx[order], val[order])
    pg = {name: PhysicalGroup(1, tag) for name, (tag, _) in groups.items()}
    return MeshData(mesh, None, tags, None, None, pg)


def _stresses(res):
    lm = lame(E=E, nu=NU)
    mesh = res.u.function_space.mesh
    Q = dolfinx.fem.functionspace(mesh, ("DG", 1, (2, 2)))
    s = dolfinx.fem.Function(Q)
    s.interpolate(dolfinx.fem.Expression(sigma(res.u, lm), Q.element.interpolation_points))
    return s.x.array.reshape(-1, 2, 2), lm


@pytest.mark.parametrize("degree", [1, 2])
def test_nitsche_flat_punch_exact(degree):
    md = structured_block()
    res = solve_contact(md, PlaneObstacle(height=0.0), E=E, nu=NU, degree=degree, method="nitsche",
                        control="displacement", target=D, n_steps=1,
                        supports={"clamped": "roller_y", "sides": "roller_x"})
    s, lm = _stresses(res)
    M = lm.lmbda + 2 * lm.mu
    syy, sxx = -M * D / H, -lm.lmbda * D / H
    assert np.max(np.abs(s[:, 1, 1] - syy)) <= TOL_ROUNDOFF * abs(syy)
    assert np.max(np.abs(s[:, 0, 0] - sxx)) <= TOL_ROUNDOFF * abs(syy)
    assert np.max(np.abs(s[:, 0, 1])) <= TOL_ROUNDOFF * abs(syy)
    assert np.max(np.abs(res.samples.p + syy)) <= TOL_ROUNDOFF * abs(syy)  # contact law pressure = -sigma_yy
    assert abs(res.P - (-syy) * W) <= TOL_ROUNDOFF * abs(syy) * W
    assert abs(res.P_pressure - res.P) <= TOL_ROUNDOFF * res.P


@pytest.mark.parametrize("kappa0", [10.0, 1e3])
def test_penalty_flat_punch_predicted_penetration(kappa0):
    md = structured_block()
    res = solve_contact(md, PlaneObstacle(height=0.0), E=E, nu=NU, degree=2, method="penalty", kappa0=kappa0,
                        control="displacement", target=D, n_steps=1,
                        supports={"clamped": "roller_y", "sides": "roller_x"})
    s, lm = _stresses(res)
    M = lm.lmbda + 2 * lm.mu
    h = np.hypot(W / 8, H / 4)  # ufl.CellDiameter of the structured right triangles
    kappa = kappa0 * E / (1.0 - NU**2) / h  # kappa0 E* / h, E* = E/(1 - nu^2) (issue 37: as for two bodies)
    p_pred = M * D / H / (1.0 + M / (kappa * H))
    assert np.max(np.abs(s[:, 1, 1] + p_pred)) <= TOL_ROUNDOFF * p_pred
    assert np.max(np.abs(res.samples.p - p_pred)) <= TOL_ROUNDOFF * p_pred
    # the penalty error itself: relative size M / (kappa H), as predicted
    assert abs((M * D / H - p_pred) / (M * D / H) - M / (kappa * H + M)) <= 1e-12


def test_bad_arguments_raise_value_error():
    md = structured_block(2, 1)
    with pytest.raises(ValueError, match="method"):
        solve_contact(md, PlaneObstacle(), E=E, nu=NU, method="mortar", target=D)
    with pytest.raises(ValueError, match="nu"):
        solve_contact(md, PlaneObstacle(), E=E, nu=0.5, target=D)
    with pytest.raises(ValueError, match="supports"):
        solve_contact(md, PlaneObstacle(), E=E, nu=NU, target=D, supports={"nowhere": "clamped"})
