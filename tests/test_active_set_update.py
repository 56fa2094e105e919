"""The solver option ``active_set_update`` (issue 16): prescribed-active-set iterations with the contact edges
extrapolated from the pressure (:mod:`fem.active_set_update`) give the same answer as the default path, and bad
values are refused with one line (solver: ValueError; bench: exit 2, nothing written).

Scene: the Hertz scene of :mod:`tests.test_fem_active_set` (exact circle R = 10 mm, a = 0.5 mm, half model, P2,
h_contact = a/10, E = 200 GPa, nu = 0.3), force control to the Hertz load of a, ``predictor="extrapolate"``,
``active_set="geometry"``.
"""

import dolfinx_solver  # noqa: F401

import numpy as np
import pytest
from dolfinx.io import gmsh as dgmsh
from mpi4py import MPI

from analytic.hertz import hertz_load_from_half_width
from fem.active_set_update import (
    _secant_edge,
    accelerated_runs,
    extrapolated_runs,
    merged_runs,
    safeguarded_runs,
    same_active_points,
    sign_runs,
)
from fem.elasticity import plane_strain_modulus
from fem.obstacles import CircleObstacle
from fem.solver import solve_contact
from meshes.block import build_block_mesh
from workbench.studies.bench_config import BenchConfig

R, E, NU = 10.0, 200e3, 0.3
A = 0.05 * R
P_TARGET = hertz_load_from_half_width(A, R, plane_strain_modulus(E=E, nu=NU))


def _hertz_samples(b: float, h: float):
    """Two Gauss points per facet of size h on [-2b, 2b]; q = sqrt(1 - x^2/b^2) inside, -(|x| - b) outside."""
    g = 0.5 / np.sqrt(3.0)
    left = np.arange(-2 * b, 2 * b, h)
    s = np.sort(np.concatenate([left + (0.5 - g) * h, left + (0.5 + g) * h]))
    q = np.where(np.abs(s) < b, np.sqrt(np.clip(1.0 - (s / b) ** 2, 0.0, None)), -(np.abs(s) - b))
    return s, q


def test_extrapolated_edges_of_a_hertz_pressure():
    b, h = 1.0, 0.05
    s, q = _hertz_samples(b, h)
    (lo, hi), = extrapolated_runs(s, q)
    assert abs(hi - b) < 0.25 * h and abs(lo + b) < 0.25 * h, (lo, hi)


def test_the_fit_leaves_out_the_penetration_beyond_a_prescribed_set():
    """Outside the prescribed set no law acts: a positive q there is a penetration, not a pressure. Fitted
    through it, the edge lands at the end of the penetration; with ``zone`` it is the set's own pressure's root."""
    b, h = 1.0, 0.05
    s, q = _hertz_samples(b, h)
    zone = ((-0.8, 0.8),)
    # a too-small set: the pressure of the set inside, a penetration growing outwards to 1.6 b outside it
    pen = np.where(np.abs(s) >= 0.8, 0.6 * np.clip(1.6 - np.abs(s), 0.0, None) ** 1.5, 0.0)
    q_it = np.where(np.abs(s) < 0.8, q, pen - (np.abs(s) >= 1.6) * (np.abs(s) - 1.6))
    (_, hi_all), = extrapolated_runs(s, q_it)
    (_, hi_zone), = extrapolated_runs(s, q_it, zone=zone)
    assert hi_all > 1.2 * b  # the overshoot: the penetration's own zero
    assert abs(hi_zone - b) < 0.1 * b, hi_zone  # the pressure's root, near the true edge


def test_safeguard_takes_the_sign_change_when_the_fit_moves_against_it():
    zone, sign = ((-1.0, 1.0),), ((-1.1, 1.2),)  # the set was too small: both edges move out
    assert safeguarded_runs(zone, sign, ((-1.3, 0.9),)) == ((-1.3, 1.2),)
    assert safeguarded_runs(zone, sign, ((-np.inf, 1.3),)) == ((-np.inf, 1.3),)
    assert safeguarded_runs(zone, ((-1.1, 1.2), (3.0, 4.0)), ((-1.3, 0.9), (3.0, 4.0))) == ((-1.3, 0.9), (3.0, 4.0))


def test_same_active_points_and_sign_runs():
    s = np.linspace(-1.0, 1.0, 21)
    assert same_active_points(s, ((-0.51, 0.51),), ((-0.55, 0.55),))
    assert not same_active_points(s, ((-0.51, 0.51),), ((-0.51, 0.61),))
    q = 0.5 - np.abs(s)
    (lo, hi), = sign_runs(s, q)
    assert lo == pytest.approx(-0.5, abs=0.1) and hi == pytest.approx(0.5, abs=0.1)


def test_secant_edge_finds_the_root_of_a_linear_edge_map():
    m = lambda e: 0.3 + 0.4 * e  # noqa: E731  fixed point e = 0.5
    assert _secant_edge(0.1, m(0.1), 0.2, m(0.2)) == pytest.approx(0.5, abs=1e-12)


def test_fragments_merge_and_a_linearly_converging_edge_takes_the_secant_step():
    assert merged_runs(((-np.inf, 0.15), (0.1501, 0.152), (0.16, 0.6)), 0.001) == ((-np.inf, 0.152), (0.16, 0.6))
    # a too-large set halving its excess each update (true edge 0.15, spacing 1e-3): the secant lands on it
    prev, prev_sign, cur, cur_sign = ((-np.inf, 0.19),), ((-np.inf, 0.17),), ((-np.inf, 0.17),), ((-np.inf, 0.16),)
    (lo, hi), = accelerated_runs(prev, prev_sign, cur, cur_sign, ((-np.inf, 0.159),), 1e-3)
    assert np.isinf(lo) and hi == pytest.approx(0.15, abs=1e-12)
    # within a few spacings the fit is kept (quadrature grain)
    assert accelerated_runs(((0.0, 0.152),), ((0.0, 0.151),), ((0.0, 0.151),), ((0.0, 0.1505),), ((0.0, 0.1504),),
                            1e-3) == ((0.0, 0.1504),)


@pytest.fixture(scope="module")
def mesh10(tmp_path_factory):
    mf = build_block_mesh(width=40 * A, height=40 * A, contact_half_width=A, h_contact=A / 10, half_model=True,
                          out_dir=tmp_path_factory.mktemp("active_set_update"), name="hertz_active_set_update")
    return dgmsh.read_from_msh(str(mf.msh), MPI.COMM_WORLD, 0, gdim=2)


def _solve(mesh, update, predictor="extrapolate"):
    return solve_contact(mesh, CircleObstacle(center=(0.0, R), radius=R), E=E, nu=NU, control="force", target=P_TARGET,
                         n_steps=2, symmetric_half=True, traction="halfplane", predictor=predictor,
                         active_set="geometry", active_set_update=update)


def test_edge_fit_same_answer(mesh10):
    ref, fit = _solve(mesh10, "newton"), _solve(mesh10, "edge_fit")
    assert abs(fit.P - ref.P) <= 1e-10 * ref.P
    (pr,), (pf,) = ref.patches, fit.patches
    assert abs(pf.half_width - pr.half_width) <= 1e-8 * pr.half_width
    assert abs(pf.p_max - pr.p_max) <= 1e-8 * pr.p_max
    # the iteration counts are a measurement (bench section 6), not asserted: on this coarse mesh (8 facets
    # across the half zone) edge_fit took [2, 3, 3, 1, 1, 1] against [2, 3, 2, 1, 1, 1]
    assert len(fit.newton_iterations) == len(ref.newton_iterations)


def test_edge_fit_from_the_hertz_zone_start_same_answer(mesh10):
    """predictor="hertz_zone": the updates start from the solved Hertz-zone state (no extra iteration on it)."""
    ref, fit = _solve(mesh10, "newton", "hertz_zone"), _solve(mesh10, "edge_fit", "hertz_zone")
    assert abs(fit.P - ref.P) <= 1e-10 * ref.P
    assert abs(fit.patches[0].half_width - ref.patches[0].half_width) <= 1e-8 * ref.patches[0].half_width
    assert fit.newton_iterations[0] <= ref.newton_iterations[0], (fit.newton_iterations, ref.newton_iterations)


def test_bad_active_set_update_refused(mesh10):
    with pytest.raises(ValueError, match="active_set_update must be one of"):
        _solve(mesh10, "pdas")


def test_bench_refuses_bad_active_set_update(tmp_path, capsys):
    with pytest.raises(ValueError, match="predictor_free_active_set_update"):
        BenchConfig(predictor_free_active_set_update="pdas")
    from workbench.studies.bench import main

    assert main(["--active-set-update", "pdas", "--sections", "predictor_free", "--out", str(tmp_path / "b")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "predictor_free_active_set_update" in err[0], err
    assert not (tmp_path / "b").exists()
