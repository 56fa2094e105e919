"""Stiff penalties converge (issue 15): the penalty method on ``hertz_cylinder`` for kappa0 = 1e0 ... 1e10.

Requirements:
1. Every kappa0 from 1e0 to 1e10 converges on the case's own scene (P2, h = a/20, half model, force control to
   the Hertz load; ``cases/hertz_cylinder.toml`` with method = "penalty"). Before, kappa0 >= 1e6 ended in SNES
   DIVERGED_MAX_IT; above STIFF_KAPPA0 = 1e5 the penalty law is now collocated at the contact nodes and reached
   by relaxed Uzawa updates (fem.methods.penalty).
2. From kappa0 = 1e3 upwards p_max and the half-width stay within the case tolerances (0.5 % each). Measured:
   Gauss-point law 1e3 / 1e5: p_max 0.07 % / 0.16 %, half-width 0.39 % / 0.41 %; nodal law 1e6 ... 1e10: p_max
   0.062 %, half-width 0.003 %, RMS/p0 0.14 %, no warning.
3. The answer of the nodal law stops moving with kappa0 (its penetration p / kappa vanishes): 1e8 and 1e10 give
   the same p_max and load-approach d within 1e-6 relative.
4. Where the Gauss-point law oscillates (kappa0 = 1e3: 'pressure oscillation'), the run also compares the stress-
   based pressure -sigma_nn (measured RMS/p0 0.26 % against 1.3 % for the contact-law pressure) and says so in a
   named warning line.
5. The default penalty (kappa0 = 1e3) is the Gauss-point law, unchanged (no Uzawa loop, no nodal samples).
"""

import dolfinx_solver  # noqa: F401

import dataclasses

import pytest
from mpi4py import MPI

from cases import load_case
from fem.methods.penalty import STIFF_KAPPA0
from workbench.pipeline.run_case import run_one

CASE = load_case("hertz_cylinder")
KAPPA0 = tuple(10.0**k for k in range(11))
_CACHE: dict = {}


@pytest.fixture(scope="module")
def mesh_cache(tmp_path_factory):
    return tmp_path_factory.mktemp("stiff_penalty_meshes")


def _penalty(kappa0: float, mesh_cache):
    if kappa0 not in _CACHE:
        run = CASE.runs()[0]
        run = dataclasses.replace(run, solver=dataclasses.replace(run.solver, method="penalty", kappa0=kappa0))
        _CACHE[kappa0] = run_one(run, name="stiff_penalty", mesh_cache=mesh_cache, comm=MPI.COMM_WORLD,
                                 progress=lambda _: None)
    return _CACHE[kappa0]


@pytest.mark.parametrize("kappa0", KAPPA0, ids=[f"1e{k}" for k in range(11)])
def test_penalty_converges_for_every_kappa0(kappa0, mesh_cache):
    out = _penalty(kappa0, mesh_cache)  # a ContactSolveError here is the failure this test guards against
    m = out.metrics
    assert m["P"] > 0 and abs(m["errors"]["load_balance"]) <= 1e-9, m["errors"]
    if kappa0 >= 1e3:
        for key in ("p_max", "half_width"):
            assert m["errors"][key] <= CASE.tolerances[key], (kappa0, key, m["errors"][key])
    if kappa0 > STIFF_KAPPA0:
        assert out.result.options["penalty_law"] == "nodal (Uzawa)"
        assert m["warnings"] == [], m["warnings"]
        assert m["errors"]["rms"] <= CASE.tolerances["rms"], m["errors"]


def test_stiff_answer_is_kappa_independent(mesh_cache):
    a, b = _penalty(1e8, mesh_cache).metrics, _penalty(1e10, mesh_cache).metrics
    for key in ("p_max", "d"):
        assert abs(a[key] / b[key] - 1.0) <= 1e-6, (key, a[key], b[key])


def test_oscillating_law_is_named_and_the_stress_based_pressure_compared(mesh_cache):
    m = _penalty(1e3, mesh_cache).metrics
    names = [w.split(":")[0] for w in m["warnings"]]
    assert "pressure oscillation" in names and "stress-based pressure" in names, m["warnings"]
    sb = m["stress_based"]
    assert set(sb) == {"rms", "p_max"}
    assert sb["rms"] < m["errors"]["rms"], (sb, m["errors"])  # the smoother estimate is the better one here


def test_default_penalty_is_the_gauss_point_law(mesh_cache):
    res = _penalty(1e3, mesh_cache).result
    assert "penalty_law" not in res.options and all("uzawa" not in r for r in res.load_steps)
