"""A re-solve from converged states (``warm_start``, fem/warm_start.py): the error budget's iterative term.

Requirements:
1. Force control (Hertz cylinder of tests/test_fem_hertz.py at h = a/20, augmented Lagrangian: Newton inside an
   Uzawa loop): the warm re-solve at tolerances / 100 reaches the target load in one solve plus at most two
   force corrections, at most 3 Newton iterations each (the cold solve took its load path), and its P, d and
   peak pressure agree with the cold solve to 1e-9 relative (they differ by the iterative error of the cold one:
   the tolerances are 1e-10).
2. Recorded displacements (displacement control with ``record_at``): one warm solve and one snapshot per
   recorded level, each within 1e-9 of the cold solve's snapshot.
3. A state of another size (another mesh) is refused with a ValueError naming ``warm_start``.
"""

import dolfinx_solver  # noqa: F401

import numpy as np
import pytest
from dolfinx.io import gmsh as dgmsh
from mpi4py import MPI
from test_fem_hertz import NU, P_TARGET, A, E, R

from fem.obstacles import CircleObstacle
from fem.solver import solve_contact
from fem.warm_start import WarmLevel, WarmStart
from meshes.block import build_block_mesh

TIGHT = dict(snes_rtol=1e-12, force_rtol=1e-12, uzawa_rtol=1e-12)


@pytest.fixture(scope="module")
def mesh20(tmp_path_factory):
    mf = build_block_mesh(width=40 * A, height=40 * A, contact_half_width=A, h_contact=A / 20, half_model=True,
                          out_dir=tmp_path_factory.mktemp("warm"), name="hertz20")
    return dgmsh.read_from_msh(str(mf.msh), MPI.COMM_WORLD, 0, gdim=2)


def _solve(mesh, **kw):
    return solve_contact(mesh, CircleObstacle(center=(0.0, R), radius=R), E=E, nu=NU, degree=2,
                         method="augmented_lagrangian", kinematics="small", traction="halfplane",
                         symmetric_half=True, **kw)


@pytest.fixture(scope="module")
def cold(mesh20):
    return _solve(mesh20, control="force", target=P_TARGET, n_steps=3)


def test_force_control_warm_resolve_continues_the_iteration(mesh20, cold):
    warm = _solve(mesh20, control="force", target=P_TARGET, n_steps=3, warm_start=cold.warm_start, **TIGHT)
    kinds = [r["kind"] for r in warm.load_steps]
    assert kinds[0] == "warm" and set(kinds[1:]) <= {"force-correction"} and len(kinds) <= 3, kinds
    assert max(warm.newton_iterations) <= 3, warm.newton_iterations
    assert sum(warm.newton_iterations) < sum(cold.newton_iterations)
    assert abs(warm.P - P_TARGET) <= 1e-12 * P_TARGET
    assert warm.d == pytest.approx(cold.d, rel=1e-9)
    assert np.max(warm.samples.p) == pytest.approx(np.max(cold.samples.p), rel=1e-9)


def test_recorded_levels_each_from_its_state(mesh20, cold):
    d_levels = (0.7 * cold.d, cold.d)
    kw = dict(control="displacement", target=d_levels[-1], n_steps=2, record_at=d_levels)
    cold = _solve(mesh20, **kw)
    assert [lv.d for lv in cold.warm_start.levels] == list(d_levels)
    warm = _solve(mesh20, **kw, warm_start=cold.warm_start, **TIGHT)
    assert [r["kind"] for r in warm.load_steps] == ["warm", "warm"]
    assert [s.d for s in warm.snapshots] == list(d_levels)
    for a, b in zip(warm.snapshots, cold.snapshots, strict=True):
        assert a.P == pytest.approx(b.P, rel=1e-9)


def test_a_state_of_another_mesh_is_refused(mesh20):
    bad = WarmStart((WarmLevel(0.01, np.zeros(7)),))
    with pytest.raises(ValueError, match="warm_start"):
        _solve(mesh20, control="displacement", target=0.01, n_steps=1, warm_start=bad)
