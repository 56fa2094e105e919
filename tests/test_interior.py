"""Interior stress error (fem/interior.py) and its use on the Hertz scene.

Requirements: the error integral is exact for a field the FEM represents exactly (a uniform stress: round-off),
its box area is the box's; on the Hertz cylinder (a/R = 0.05, P2 Nitsche, W = 20 a with the half-plane far field)
the L2 stress error against McEwen's field over |x|, z <= 4 a falls when h_c halves (measured in make run at
a/20, a/40, a/80: 3.0e-3, 9.4e-4, 2.6e-4 p0, rate 1.78), and the largest von Mises stress is within 1 % of McEwen's
0.5575 p0, at the depth 0.70 a within a tenth of a.
"""

import dolfinx_solver  # noqa: F401

from typing import NamedTuple

import dolfinx
import numpy as np
import pytest
from dolfinx.io import gmsh as dgmsh
from mpi4py import MPI

from analytic.hertz import hertz, hertz_load_from_half_width
from fem.elasticity import lame, plane_strain_modulus
from fem.far_field import far_field_supports
from fem.interior import interior_stress_error
from fem.obstacles import CircleObstacle
from fem.solver import solve_contact
from meshes.block import build_block_mesh
from workbench.scenes.block_budget import _exact_hertz_field, _vm_max_exact

R, E, NU = 10.0, 200e3, 0.3
A = 0.05 * R
E_STAR = plane_strain_modulus(E=E, nu=NU)
P_TARGET = hertz_load_from_half_width(A, R, E_STAR)


@pytest.fixture(scope="module")
def meshes(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("interior")
    out = {}
    for n in (5, 10):
        mf = build_block_mesh(width=20 * A, height=20 * A, contact_half_width=A, h_contact=A / n, half_model=True,
                              out_dir=tmp, name=f"int{n}")
        out[n] = dgmsh.read_from_msh(str(mf.msh), MPI.COMM_WORLD, 0, gdim=2)
    return out


class _State(NamedTuple):
    u: dolfinx.fem.Function
    pressure_field: None
    lame: object


def test_uniform_stress_is_integrated_exactly(meshes):
    mesh = meshes[5].mesh
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 2, (2,)))
    u = dolfinx.fem.Function(V)
    ex, ey, gxy = 1e-3, -2e-3, 5e-4  # u = (ex x + gxy y, ey y): eps_xy = gxy / 2
    u.interpolate(lambda X: np.vstack([ex * X[0] + gxy * X[1], ey * X[1]]))
    lm = lame(E=E, nu=NU)
    tr = ex + ey
    s = (lm.lmbda * tr + 2 * lm.mu * ex, lm.lmbda * tr + 2 * lm.mu * ey, lm.mu * gxy, lm.lmbda * tr)
    res = interior_stress_error(_State(u, None, lm), lambda x, y: tuple(np.full_like(x, v) for v in s),
                                x_max=4 * A, z_max=4 * A)
    assert res.l2 < 1e-9 * abs(s[0])
    assert abs(res.area / (4 * A * 4 * A) - 1.0) < 0.02  # half model: 0 <= x <= 4a, the box edge to the cell size


def test_hertz_interior_error_falls_and_the_von_mises_maximum_is_in_place(meshes):
    errors = {}
    for n, mesh in meshes.items():
        res = solve_contact(mesh, CircleObstacle(center=(0.0, R), radius=R), E=E, nu=NU, degree=2,
                            traction="halfplane", control="force", target=P_TARGET, n_steps=1, symmetric_half=True,
                            supports=far_field_supports(far_field="halfplane", symmetric_half=True))
        th = hertz(res.P, R, E_STAR)
        theory = type("T", (), {"half_width": th.half_width, "p_ref": th.p0})
        e = interior_stress_error(res, _exact_hertz_field(theory, NU), x_max=4 * th.half_width,
                                  z_max=4 * th.half_width)
        errors[n] = e.l2 / th.p0
    vm_exact, z_exact = _vm_max_exact(NU)
    assert abs(vm_exact - 0.5575) < 1e-4 and abs(z_exact - 0.704) < 1e-3
    assert e.vm_max_fem / th.p0 == pytest.approx(vm_exact, rel=1e-2)
    assert abs(-e.at_fem[1] / th.half_width - z_exact) < 0.1
    assert errors[10] < 0.5 * errors[5], errors
    assert errors[10] < 0.02, errors
