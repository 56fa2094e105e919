"""The force-controlled Newton (:mod:`fem.force_newton`, issue 38): d an unknown of every Newton iteration.

* The bordered Krylov solve (:mod:`fem.bordered_krylov`) solves ``[[J, g], [p^T, 0]] [du, dd] = [r_u, r_d]``: on a
  small matrix against numpy's dense solve, with an exact preconditioner (one Krylov iteration: the block
  factorisation is the inverse) and with an inexact one (Jacobi: more iterations, the same answer).
* On the Hertz scene of :mod:`tests.test_fem_linear_solver` (force control, one level from the Hertz zone): one
  Newton iteration, one factorisation and (with a factor) two triangular solves, the load equal to the target to
  round-off, and the same P, d and peak pressure as the SNES's own path (``predictor="hertz"``: the Hertz
  predictor, then Newton and force corrections) with every linear solver, GAMG's bordered solve included.
"""

import dolfinx_solver  # noqa: F401

import numpy as np
import pytest
from mpi4py import MPI
from petsc4py import PETSc
from test_fem_linear_solver import P_TARGET, A, _solve, build_block_mesh, dgmsh

from fem.bordered_krylov import BorderedSystem


def _system(n=40, seed=3):
    rng = np.random.default_rng(seed)
    J = np.diag(4.0 + rng.random(n)) + np.diag(-np.ones(n - 1), 1) + np.diag(-np.ones(n - 1), -1)
    g, p, r_u = rng.standard_normal(n), rng.standard_normal(n), rng.standard_normal(n)
    return J, g, p, r_u, float(rng.standard_normal())


def _petsc(J, g, p, r_u):
    A = PETSc.Mat().createAIJ(J.shape, comm=MPI.COMM_SELF)
    A.setUp()
    for i, row in enumerate(J):
        cols = np.nonzero(row)[0].astype(PETSc.IntType)
        A.setValues(i, cols, row[cols])
    A.assemble()
    vecs = []
    for arr in (g, p, r_u):
        v = A.createVecLeft()
        v.getArray()[:] = arr
        vecs.append(v)
    return A, vecs


@pytest.mark.parametrize("pc_type, max_its", [("lu", 1), ("jacobi", 60)])
def test_bordered_solve_matches_the_dense_solve(pc_type, max_its):
    J, g, p, r_u, r_d = _system()
    n = J.shape[0]
    B = np.zeros((n + 1, n + 1))
    B[:n, :n], B[:n, n], B[n, :n] = J, g, p
    want = np.linalg.solve(B, np.append(r_u, r_d))
    A, (gv, pv, rv) = _petsc(J, g, p, r_u)
    ksp = PETSc.KSP().create(MPI.COMM_SELF)
    ksp.setOperators(A)
    ksp.setType("preonly")
    ksp.getPC().setType(pc_type)
    ksp.setUp()
    system = BorderedSystem(A=A, pc=ksp.getPC(), rtol=1e-13, max_it=100)
    its, dd = system.solve(r_u=rv, r_d=r_d, g=gv, p=pv, atol=0.0)
    assert 1 <= its <= max_its
    assert np.allclose(rv.getArray(), want[:n], rtol=0, atol=1e-10 * np.abs(want).max())
    assert abs(dd - want[n]) <= 1e-10 * np.abs(want).max()
    # g_scale: the border -g gives the solution of that system
    B[:n, n] = -g
    want = np.linalg.solve(B, np.append(r_u, r_d))
    rv.getArray()[:] = r_u
    its, dd = system.solve(r_u=rv, r_d=r_d, g=gv, p=pv, atol=0.0, g_scale=-1.0)
    assert abs(dd - want[n]) <= 1e-10 * np.abs(want).max()
    system.destroy()


@pytest.fixture(scope="module")
def hertz_mesh(tmp_path_factory):
    mf = build_block_mesh(width=40 * A, height=40 * A, contact_half_width=A, h_contact=A / 10, half_model=True,
                          out_dir=tmp_path_factory.mktemp("force_newton"), name="hertz_force_newton")
    return dgmsh.read_from_msh(str(mf.msh), MPI.COMM_WORLD, 0, gdim=2)


@pytest.mark.parametrize("linear_solver", ["lu", "lu_reuse", "gamg"])
def test_one_newton_iteration_from_the_hertz_zone(hertz_mesh, linear_solver):
    PETSc.Log.begin()
    events = [PETSc.Log.Event(name) for name in ("MatLUFactorNum", "MatSolve", "MatMatSolve")]
    before = [e.getPerfInfo()["count"] for e in events]
    res = _solve(hertz_mesh, predictor="hertz_zone", linear_solver=linear_solver)
    factors, solves, two_column_solves = (e.getPerfInfo()["count"] - b for e, b in zip(events, before, strict=True))
    ref = _solve(hertz_mesh, predictor="hertz", linear_solver="lu")
    assert res.newton_iterations == [1] and [s["kind"] for s in res.load_steps] == ["step"], res.load_steps
    assert factors == 1, factors  # the Jacobian's (GAMG: its coarsest level's)
    if linear_solver != "gamg":  # z and w in one solve with the factor; the step meets snes_atol without a
        # refinement solve (dF/dd's round-off)
        assert (solves, two_column_solves) == (0, 1), (solves, two_column_solves)
    assert abs(res.P - P_TARGET) <= 1e-12 * P_TARGET
    assert len(ref.newton_iterations) > 1 or ref.newton_iterations[0] > 1  # the SNES's path differs (can fail)
    for got, want in ((res.P, ref.P), (res.d, ref.d), (res.patches[0].p_max, ref.patches[0].p_max)):
        assert abs(got - want) <= 1e-8 * abs(want), (linear_solver, got, want)


def test_the_zone_is_the_obstacles_own_half_plane_width():
    """The predicted zone of a circle is the exact circle's half-width (smaller than Hertz's by about 3 k^2 / 16,
    k = a/R), of a parabola Hertz's."""
    from analytic.hertz import hertz
    from fem.obstacles import CircleObstacle, ParabolaObstacle

    E_star, R = 2.2e5, 10.0
    a = hertz(P_TARGET, R, E_star).half_width
    b = CircleObstacle(center=(0.0, R), radius=R).half_plane_half_width(P_TARGET, E_star)
    k = a / R
    assert b < a and abs((a - b) / a - 3 * k**2 / 16) <= 0.1 * 3 * k**2 / 16, (a, b)
    assert ParabolaObstacle(radius=R, vertex=(0.0, 0.0)).half_plane_half_width(P_TARGET, E_star) == a
