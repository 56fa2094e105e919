"""Solver options of issue 16 that change only the cost: ``linear_solver`` (``lu``, ``lu_reuse``, ``gamg``, ``auto``),
``split_jacobian`` (K assembled once) and ``predictor="hertz_zone"`` (no stiffness solve). Each gives the same
answer as the default path (P, peak pressure and half-width to 1e-8 relative); bad values are refused with a
ValueError naming the option.

Scene: the Hertz scene of :mod:`tests.test_fem_active_set` (exact circle R = 10 mm, a = 0.5 mm, half model, P2,
h_contact = a/10, E = 200 GPa, nu = 0.3), force control to the Hertz load of a, one load step.
"""

import dolfinx_solver  # noqa: F401

import pytest
from dolfinx.io import gmsh as dgmsh
from mpi4py import MPI

from analytic.hertz import hertz_load_from_half_width
from fem.elasticity import plane_strain_modulus
from fem.obstacles import CircleObstacle
from fem.solver import solve_contact
from meshes.block import build_block_mesh

R, E, NU = 10.0, 200e3, 0.3
A = 0.05 * R
P_TARGET = hertz_load_from_half_width(A, R, plane_strain_modulus(E=E, nu=NU))


@pytest.fixture(scope="module")
def mesh10(tmp_path_factory):
    mf = build_block_mesh(width=40 * A, height=40 * A, contact_half_width=A, h_contact=A / 10, half_model=True,
                          out_dir=tmp_path_factory.mktemp("linear_solver"), name="hertz_linear_solver")
    return dgmsh.read_from_msh(str(mf.msh), MPI.COMM_WORLD, 0, gdim=2)


def _solve(mesh, **kw):
    return solve_contact(mesh, CircleObstacle(center=(0.0, R), radius=R), E=E, nu=NU, control="force", target=P_TARGET,
                         n_steps=1, symmetric_half=True, traction="halfplane", **kw)


@pytest.fixture(scope="module")
def reference(mesh10):
    return _solve(mesh10, split_jacobian=False)


@pytest.mark.parametrize("kw", [dict(), dict(linear_solver="lu_reuse"), dict(linear_solver="gamg"),
                                dict(predictor="hertz_zone"),
                                dict(predictor="hertz_zone", linear_solver="lu_reuse"),
                                dict(linear_solver="auto")],
                         ids=["split", "lu_reuse", "gamg", "hertz_zone", "hertz_zone_lu_reuse", "auto"])
def test_same_answer(mesh10, reference, kw):
    res = _solve(mesh10, **kw)
    ref = reference
    for got, want in ((res.P, ref.P), (res.patches[0].p_max, ref.patches[0].p_max),
                      (res.patches[0].half_width, ref.patches[0].half_width)):
        assert abs(got - want) <= 1e-8 * abs(want), (kw, got, want)
    assert not res.warnings, res.warnings


def test_hertz_zone_needs_no_stiffness_solve(mesh10):
    """One load step from the Hertz zone: the prescribed-set iteration, then at most two Newton iterations (the
    discrete edge within a point of the Hertz one) and no force correction beyond the tangent."""
    res = _solve(mesh10, predictor="hertz_zone")
    assert res.newton_iterations[0] <= 3 and len(res.newton_iterations) <= 2, res.newton_iterations


@pytest.mark.parametrize("kw, words", [
    (dict(linear_solver="cholesky"), "linear_solver must be one of"),
    (dict(linear_solver="gamg", formulation="mixed"), "linear_solver='gamg' needs formulation='displacement'"),
    (dict(predictor="lcp"), "predictor must be one of"),
])
def test_bad_values_refused(mesh10, kw, words):
    with pytest.raises(ValueError, match=words):
        _solve(mesh10, **kw)


def test_hertz_zone_needs_force_control(mesh10):
    with pytest.raises(ValueError, match="predictor='hertz_zone' needs control='force'"):
        solve_contact(mesh10, CircleObstacle(center=(0.0, R), radius=R), E=E, nu=NU, control="displacement",
                      target=0.01, symmetric_half=True, predictor="hertz_zone")


def test_bench_config_refuses_bad_scale_solver():
    from workbench.studies.bench_config import BenchConfig

    for kw, field in ((dict(scale_linear_solver="cholesky"), "scale_linear_solver"),
                      (dict(scale_predictor="hertz"), "scale_predictor"),
                      (dict(krylov_threshold=-1), "krylov_threshold"),
                      (dict(krylov_threshold=1.5), "krylov_threshold"),
                      (dict(small_ndofs=-1), "small_ndofs"), (dict(small_ndofs=0.5), "small_ndofs")):
        with pytest.raises(ValueError, match=field):
            BenchConfig(**kw)


def test_scale_rows_switch_to_gamg_above_threshold():
    from workbench.studies.bench_config import BenchConfig
    from workbench.studies.bench_measure import scale_overrides

    cfg = BenchConfig(krylov_threshold=1000, scale_linear_solver="lu_reuse")
    assert scale_overrides(cfg, 1000)["linear_solver"] == "lu_reuse"
    assert scale_overrides(cfg, 1001) == {"predictor": "hertz_zone", "linear_solver": "gamg"}


def test_auto_chooses_by_size():
    """``auto``: lu_reuse with the AMF ordering up to AUTO_GAMG_NDOFS unknowns, gamg above; never gamg for a
    saddle point or without a size; the other kinds keep MUMPS's default ordering."""
    from fem.linear_solver import AUTO_GAMG_NDOFS, linear_options, resolve, snes_options

    assert resolve("auto", ndofs=AUTO_GAMG_NDOFS) == "lu_reuse"
    assert resolve("auto", ndofs=AUTO_GAMG_NDOFS + 1) == "gamg"
    assert resolve("auto", ndofs=AUTO_GAMG_NDOFS + 1, saddle=True) == "lu_reuse"
    assert resolve("auto") == "lu_reuse"
    # a hyperelastic or finite-strain bulk: its Jacobian changes everywhere, every Jacobian is factored
    assert resolve("auto", ndofs=1000, linear_bulk=False) == "lu"
    assert snes_options("auto", ndofs=1000, linear_bulk=False)["ksp_type"] == "preonly"
    assert resolve("lu", ndofs=10**9) == "lu"
    small = snes_options("auto", ndofs=1000)
    assert small["mat_mumps_icntl_7"] == 2 and small["snes_lag_preconditioner"] == -2
    assert snes_options("auto", ndofs=10**7)["pc_type"] == "gamg"
    assert "mat_mumps_icntl_7" not in snes_options("auto", ndofs=10**7)
    assert "mat_mumps_icntl_7" not in snes_options("lu") and "mat_mumps_icntl_7" not in linear_options("lu_reuse")
    assert linear_options("auto", ndofs=1000)["mat_mumps_icntl_7"] == 2
    with pytest.raises(ValueError, match="linear_solver must be one of"):
        resolve("cholesky")


def test_scale_rows_auto_is_one_configuration():
    from workbench.studies.bench_config import BenchConfig
    from workbench.studies.bench_measure import scale_overrides

    cfg = BenchConfig(krylov_threshold=1000, scale_linear_solver="auto")
    assert scale_overrides(cfg, 10**7) == {"predictor": "hertz_zone", "linear_solver": "auto"}
    with pytest.raises(ValueError, match="crossover_max_ndofs"):
        BenchConfig(crossover_max_ndofs=-1)


def test_mumps_analysis_once_per_problem(mesh10):
    """PETSc keeps MUMPS's symbolic analysis across the Newton iterations and force corrections of one solve
    (the split Jacobian keeps J's nonzero state): one MatLUFactorSymbolic for the SNES's KSP, one
    MatLUFactorNumeric per Newton iteration (``lu``), the force-controlled Newton's iterations on that KSP
    included (``hertz_zone``'s first level); the second level's Hertz predictor has a KSP of its own."""
    from petsc4py import PETSc

    PETSc.Log.begin()
    events = [PETSc.Log.Event(name) for name in ("MatLUFactorSym", "MatLUFactorNum")]
    before = [e.getPerfInfo()["count"] for e in events]
    # two load levels: the first solved by the force-controlled Newton (fem.force_newton) on the SNES's KSP, the
    # second by the SNES itself, on the same analysis
    res = solve_contact(mesh10, CircleObstacle(center=(0.0, R), radius=R), E=E, nu=NU, control="force",
                        target=P_TARGET, n_steps=2, symmetric_half=True, traction="halfplane",
                        predictor="hertz_zone",
                        force_rtol=1e-12, linear_solver="lu")
    sym, num = (e.getPerfInfo()["count"] - b for e, b in zip(events, before, strict=True))
    assert sum(res.newton_iterations) >= 2, res.newton_iterations
    # the second level's Hertz predictor solves once with a KSP of its own: one analysis and one factorisation more
    assert sym == 2 and num == sum(res.newton_iterations) + 1, (sym, num, res.newton_iterations)
