"""The solver option ``active_set`` (issue 16): ``"geometry"`` needs no analytic predictor, gives the same answer
and fewer Newton iterations than today's ``"extrapolate"``; bad values are refused with one line.

Scene: the Hertz scene of :mod:`tests.test_fem_hertz` (exact circle R = 10 mm, a = 0.5 mm, half model, P2,
h_contact = a/10, E = 200 GPa, nu = 0.3), force control to the Hertz load of a, ``predictor="extrapolate"``.
Measured: active_set "extrapolate" 4.17 and "geometry" 3.5 Newton iterations per solve at h_c = a/20 (bench
section 6); the loads agree to round-off (the converged active set and state are the same).
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
from workbench.studies.bench_config import BenchConfig

R, E, NU = 10.0, 200e3, 0.3
A = 0.05 * R
P_TARGET = hertz_load_from_half_width(A, R, plane_strain_modulus(E=E, nu=NU))


@pytest.fixture(scope="module")
def mesh10(tmp_path_factory):
    mf = build_block_mesh(width=40 * A, height=40 * A, contact_half_width=A, h_contact=A / 10, half_model=True,
                          out_dir=tmp_path_factory.mktemp("active_set"), name="hertz_active_set")
    return dgmsh.read_from_msh(str(mf.msh), MPI.COMM_WORLD, 0, gdim=2)


def _solve(mesh, active_set):
    return solve_contact(mesh, CircleObstacle(center=(0.0, R), radius=R), E=E, nu=NU, control="force", target=P_TARGET,
                         n_steps=1, symmetric_half=True, traction="halfplane", predictor="extrapolate",
                         active_set=active_set)


def test_geometry_active_set_same_answer_fewer_iterations(mesh10):
    ref, geo = _solve(mesh10, "extrapolate"), _solve(mesh10, "geometry")
    assert abs(geo.P - ref.P) <= 1e-10 * ref.P
    assert abs(geo.patches[0].half_width - ref.patches[0].half_width) <= 1e-10 * ref.patches[0].half_width
    assert sum(geo.newton_iterations) < sum(ref.newton_iterations), (geo.newton_iterations, ref.newton_iterations)
    assert geo.newton_iterations[0] <= 5, geo.newton_iterations  # the first contact from the rigid overlap


def test_bad_active_set_refused(mesh10):
    with pytest.raises(ValueError, match="active_set must be"):
        _solve(mesh10, "lcp")


def test_bench_config_refuses_bad_active_set():
    with pytest.raises(ValueError, match="predictor_free_active_set"):
        BenchConfig(predictor_free_active_set="lcp")
    with pytest.raises(ValueError, match="predictor_free_target"):
        BenchConfig(predictor_free_target=0.0)
