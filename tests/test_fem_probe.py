"""fem.probe.stress_at_points on the flat-punch patch test: the uniform stress (exact in the FE space), the
plane-strain out-of-plane stress included, to round-off; NaN outside the body."""

import dolfinx_solver  # noqa: F401

import numpy as np
import pytest
from test_fem_patch import NU, TOL_ROUNDOFF, D, E, H, W, structured_block

from fem.elasticity import lame
from fem.obstacles import PlaneObstacle
from fem.probe import stress_at_points
from fem.solver import solve_contact


@pytest.mark.parametrize("degree", [1, 2])
def test_probe_reads_the_uniform_patch_stress(degree):
    res = solve_contact(structured_block(), PlaneObstacle(height=0.0), E=E, nu=NU, degree=degree, method="nitsche",
                        control="displacement", target=D, n_steps=1,
                        supports={"clamped": "roller_y", "sides": "roller_x"})
    lm = lame(E=E, nu=NU)
    syy, sxx = -(lm.lmbda + 2 * lm.mu) * D / H, -lm.lmbda * D / H
    pts = np.array([[0.1, -0.1], [1.0, -0.5], [W, 0.0], [0.37, -0.91], [5.0, 5.0]])  # the last is outside
    st = stress_at_points(res, pts)
    tol = TOL_ROUNDOFF * abs(syy)
    assert np.allclose(st.syy[:4], syy, atol=tol) and np.allclose(st.sxx[:4], sxx, atol=tol)
    assert np.allclose(st.sxy[:4], 0.0, atol=tol)
    assert np.allclose(st.szz[:4], NU * (sxx + syy), atol=tol)  # plane strain: s_zz = nu (s_xx + s_yy)
    assert np.all(np.isnan([st.sxx[4], st.vm[4]]))
