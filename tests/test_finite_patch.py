"""Finite-strain patch test: a homogeneous finite deformation is reproduced to round-off.

Block [0, W] x [-H, 0] (structured triangles), roller bottom (u_y = 0), roller left side (u_x = 0), free right
side, a frictionless rigid half-plane pressed down by d = 0.1 H (10 % compression). The exact solution is the
homogeneous plane-strain deformation ``F = diag(l1, s)``, ``s = 1 - d/H``, with the lateral stretch l1 from the
free side, ``P_xx(l1, s) = 0`` (uniaxial stress in plane strain): ``u = ((l1 - 1) x, (s - 1)(y + H))``, in the
P1/P2 space (no active-set predictor: the contact reaches the block corners, whose edge the predictor
extrapolates inwards). Nitsche is consistent, so it reproduces u, the contact pressure ``p = -sigma_yy = -P_yy / l1``
(current configuration), and the load ``P = -P_yy W`` (= p times the current width l1 W: the surface Jacobian
ds/dS = l1 of the top enters the pressure resultant) to round-off.
"""

import dolfinx_solver  # noqa: F401

import dolfinx
import numpy as np
import pytest
from dolfinx.io.gmsh import MeshData, PhysicalGroup
from mpi4py import MPI
from scipy.optimize import brentq

from fem.elasticity import lame
from fem.obstacles import PlaneObstacle
from fem.solver import solve_contact

E, NU, W, H = 1000.0, 0.3, 2.0, 1.0
D = 0.1 * H
TOL = 1e-9  # relative; measured ~1e-13


def block(nx=8, ny=4):
    mesh = dolfinx.mesh.create_rectangle(MPI.COMM_WORLD, [[0.0, -H], [W, 0.0]], [nx, ny],
                                         dolfinx.mesh.CellType.triangle)
    groups = {"contact": (1, lambda x: np.isclose(x[1], 0.0)), "clamped": (2, lambda x: np.isclose(x[1], -H)),
              "left": (3, lambda x: np.isclose(x[0], 0.0)), "right": (4, lambda x: np.isclose(x[0], W))}
    idx, val = [], []
    for tag, marker in groups.values():
        f = dolfinx.mesh.locate_entities_boundary(mesh, 1, marker)
        idx.append(f)
        val.append(np.full(f.size, tag, dtype=np.int32))
    idx, val = np.concatenate(idx), np.concatenate(val)
    order = np.argsort(idx)
    tags = dolfinx.mesh.meshtags(mesh, 1, idx[order], val[order])
    return MeshData(mesh, None, tags, None, None, {n: PhysicalGroup(1, t) for n, (t, _) in groups.items()})


def exact_piola(model: str, l1: float, s: float) -> tuple[float, float]:
    """(P_xx, P_yy) (MPa) of the homogeneous plane-strain deformation F = diag(l1, s)."""
    lm = lame(E=E, nu=NU)
    if model == "saint_venant_kirchhoff":
        exx, eyy = 0.5 * (l1**2 - 1), 0.5 * (s**2 - 1)
        tr = exx + eyy
        return l1 * (lm.lmbda * tr + 2 * lm.mu * exx), s * (lm.lmbda * tr + 2 * lm.mu * eyy)
    lnJ = np.log(l1 * s)
    return lm.mu * (l1 - 1 / l1) + lm.lmbda * lnJ / l1, lm.mu * (s - 1 / s) + lm.lmbda * lnJ / s


@pytest.mark.parametrize("model", ["saint_venant_kirchhoff", "neo_hookean"])
def test_finite_homogeneous_compression_exact(model):
    s = 1.0 - D / H
    l1 = brentq(lambda x: exact_piola(model, x, s)[0], 0.5, 2.0, xtol=1e-15, rtol=1e-15)
    assert l1 > 1.0 + 1e-3  # the lateral expansion is finite, so ds/dS = l1 is tested
    Pyy = exact_piola(model, l1, s)[1]
    p_exact = -Pyy / l1
    res = solve_contact(block(), PlaneObstacle(height=0.0), E=E, nu=NU, degree=2, method="nitsche",
                        kinematics="finite", material_model=model, control="displacement", target=D, n_steps=2,
                        active_set_predictor=False, supports={"clamped": "roller_y", "left": "roller_x"})
    X = res.u.function_space.tabulate_dof_coordinates()[:, :2]
    u_exact = np.column_stack([(l1 - 1) * X[:, 0], (s - 1) * (X[:, 1] + H)])
    assert np.max(np.abs(res.u.x.array.reshape(-1, 2) - u_exact)) <= TOL * D
    assert np.max(np.abs(res.samples.p - p_exact)) <= TOL * p_exact
    assert np.max(np.abs(res.samples.sigma_nn - p_exact)) <= TOL * p_exact
    assert abs(res.P - (-Pyy) * W) <= TOL * p_exact * W
    assert abs(res.P_pressure - res.P) <= TOL * res.P
    # the finite answer differs from the linear one by far more than round-off (the test can tell them apart)
    lm = lame(E=E, nu=NU)
    p_linear = (lm.lmbda + 2 * lm.mu - lm.lmbda**2 / (lm.lmbda + 2 * lm.mu)) * D / H
    assert abs(p_exact - p_linear) > 1e-3 * p_linear
