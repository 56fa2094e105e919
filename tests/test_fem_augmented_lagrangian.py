"""Augmented Lagrangian (Uzawa, nodal multiplier): exact constraint without an infinite penalty.

Requirements:
1. Flat-punch patch test (tests/test_fem_patch.py's block and supports): the exact uniform stress
   ``sigma_yy = -M d / H`` to round-off for P1 and P2, at kappa0 = 1 (where the penalty method is off by
   ``M / (kappa H + M)`` = 43 %) and at kappa0 = 1e3. Tolerance 1e-9 as the Nitsche patch test: the Uzawa loop
   stops at a nodal gap violation of 1e-10 max|u| (uzawa_rtol), which puts ~5e-11 into the stress (measured).
2. Hertz cylinder (tests/test_fem_hertz.py's scene: P2, h = a/20, half model, half-plane traction, force control
   with the Hertz predictor) within the Nitsche tolerances: peak and half-width 0.5 %, RMS(p - p_H)/p0 1 %,
   load balance P_pressure/P 1e-3 (measured +0.06 %, +0.003 %, 0.14 %, 4e-11).
3. Stiffness sweep kappa0 = 1e1 ... 1e5 (five values, four decades apart at the ends): every run converges,
   with no warning, and gives the same d, peak and half-width within 1e-8 relative (measured 2e-10: the answer
   is the kappa-independent fixed point ``g_i = 0`` at the active nodes, reached to uzawa_rtol); the Uzawa
   iterations fall as kappa0 grows (the multiplier error contracts by about 1 / (1 + c kappa0) per update).
   The penalty method at kappa0 = 1e1 misses the same d by more than 1e-4 (measured 7e-4: its penetration
   p / kappa), 1e4 times the sweep tolerance.
"""

import dolfinx_solver  # noqa: F401

import numpy as np
import pytest
from dolfinx.io import gmsh as dgmsh
from mpi4py import MPI
from test_fem_hertz import NU, P_TARGET, A, E, R, hertz_errors
from test_fem_patch import TOL_ROUNDOFF, H, W, _stresses, structured_block

from fem.obstacles import CircleObstacle, PlaneObstacle
from fem.solver import solve_contact
from meshes.block import build_block_mesh

AL = "augmented_lagrangian"
E_PATCH, NU_PATCH, D_PATCH = 1000.0, 0.3, 1e-3
SWEEP = (1e1, 1e2, 1e3, 1e4, 1e5)
TOL_SWEEP = 1e-8  # same answer over the sweep: 100 x the Uzawa gap tolerance (uzawa_rtol = 1e-10)


@pytest.fixture(scope="module")
def mesh20(tmp_path_factory):
    mf = build_block_mesh(width=40 * A, height=40 * A, contact_half_width=A, h_contact=A / 20, half_model=True,
                          out_dir=tmp_path_factory.mktemp("fem_al"), name="hertz20")
    return dgmsh.read_from_msh(str(mf.msh), MPI.COMM_WORLD, 0, gdim=2)


def _hertz(mesh, **kw):
    return solve_contact(mesh, CircleObstacle(center=(0.0, R), radius=R), E=E, nu=NU, degree=2, method=AL,
                         kinematics="small", traction="halfplane", control="force", target=P_TARGET, n_steps=4,
                         symmetric_half=True, **kw)


@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize("kappa0", [1.0, 1e3])
def test_flat_punch_exact_without_penalty_error(degree, kappa0):
    res = solve_contact(structured_block(), PlaneObstacle(height=0.0), E=E_PATCH, nu=NU_PATCH, degree=degree,
                        method=AL, kappa0=kappa0, control="displacement", target=D_PATCH, n_steps=1,
                        supports={"clamped": "roller_y", "sides": "roller_x"})
    s, lm = _stresses(res)
    M = lm.lmbda + 2 * lm.mu
    syy, sxx = -M * D_PATCH / H, -lm.lmbda * D_PATCH / H
    err = np.max(np.abs(s[:, 1, 1] - syy)) / abs(syy)
    h = np.hypot(W / 8, H / 4)
    penalty_error = M / (kappa0 * E_PATCH / h * H + M)  # what the penalty method leaves at this kappa0
    print(f"\nAL patch P{degree} kappa0={kappa0:g}: stress error {err:.2e} (penalty would leave {penalty_error:.2e}), "
          f"uzawa {[r['uzawa'] for r in res.load_steps]}")
    assert err <= TOL_ROUNDOFF, err
    assert np.max(np.abs(s[:, 0, 0] - sxx)) <= TOL_ROUNDOFF * abs(syy)
    assert np.max(np.abs(s[:, 0, 1])) <= TOL_ROUNDOFF * abs(syy)
    assert np.max(np.abs(res.samples.p + syy)) <= TOL_ROUNDOFF * abs(syy)  # nodal pressure = -sigma_yy
    assert abs(res.P - (-syy) * W) <= TOL_ROUNDOFF * abs(syy) * W
    assert abs(res.P_pressure - res.P) <= TOL_ROUNDOFF * res.P
    assert penalty_error > 1e-4  # the error the multiplier removed is far above round-off


def test_hertz_cylinder_within_nitsche_tolerances(mesh20):
    res = _hertz(mesh20)
    err_a, err_p0, rms = hertz_errors(res)
    print(f"\nHertz AL P2: err_a={err_a:.2e} err_p0={err_p0:.2e} rms={rms:.2e} "
          f"balance={res.P_pressure / res.P - 1:.1e} its={res.newton_iterations} "
          f"uzawa={[r['uzawa'] for r in res.load_steps]} wall={res.wall_time_s:.2f}s")
    assert len(res.patches) == 1 and not res.warnings, res.warnings
    assert abs(res.P / P_TARGET - 1.0) <= 1e-9  # force_rtol = 1e-10
    assert abs(err_a) <= 5e-3, err_a
    assert abs(err_p0) <= 5e-3, err_p0
    assert rms <= 1e-2, rms
    assert abs(res.P_pressure / res.P - 1.0) <= 1e-3
    assert all(r["uzawa_gap"] <= 1e-10 for r in res.load_steps)
    assert res.options["uzawa_rtol"] == 1e-10


def test_stiffness_sweep_same_answer(mesh20):
    runs = {k: _hertz(mesh20, kappa0=k) for k in SWEEP}
    ref = runs[1e3]
    rows = []
    for k, res in runs.items():
        dev = max(abs(res.d / ref.d - 1), abs(res.patches[0].p_max / ref.patches[0].p_max - 1),
                  abs(res.patches[0].half_width / ref.patches[0].half_width - 1))
        uz = sum(r["uzawa"] for r in res.load_steps)
        rows.append((k, dev, uz, res.wall_time_s))
        assert not res.warnings, (k, res.warnings)
        assert dev <= TOL_SWEEP, (k, dev)
    print("\nAL sweep (kappa0, max rel. deviation from kappa0=1e3, Uzawa solves, wall s):")
    for row in rows:
        print(f"  {row[0]:8.0e}  {row[1]:.1e}  {row[2]:3d}  {row[3]:.2f}")
    uzawa = [r[2] for r in rows]
    assert all(a >= b for a, b in zip(uzawa, uzawa[1:], strict=False)), uzawa
    pen = solve_contact(mesh20, CircleObstacle(center=(0.0, R), radius=R), E=E, nu=NU, method="penalty",
                        kappa0=SWEEP[0], traction="halfplane", control="force", target=P_TARGET, n_steps=4,
                        symmetric_half=True)
    print(f"  penalty kappa0={SWEEP[0]:g}: d / d_AL - 1 = {pen.d / ref.d - 1:.2e}")
    assert abs(pen.d / ref.d - 1) > 1e4 * TOL_SWEEP, pen.d / ref.d - 1  # penetration p / kappa, ~1e-3 of d
