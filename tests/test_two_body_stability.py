"""Two elastic bodies over E ratios 1e-3 to 1e3 and Poisson's ratios up to 0.499 on either side (issue 24): every
solve converges, the contact load balances the support reaction, and a near-incompressible body is named.

The points are the stability sweep's own (``workbench stability --study two_body``,
:func:`workbench.studies.stability.run_two_body_spec`: the elastic_cylinder case through the scene registry, a/R =
0.05, h_contact = a/10, W = 40 a, penalty, mortar). Measured: E_upper / E_lower 1e-3 ... 1e3 converge in <= 4 Newton
iterations per step with p_max within 0.3 % of the exact circle at the combined modulus; nu = 0.499 on either side
converges (p_max +2.6 % block, +0.4 % cylinder: volumetric locking of the displacement formulation, named by the
warning); the worst pair, a stiff cylinder (1e3) on a nu = 0.499 block, takes 10 Newton iterations and its peak is
19 % off (locking), named.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401

import pytest
from mpi4py import MPI

from workbench.studies.stability import (
    StabilityConfig,
    TwoBodySpec,
    classify_two_body,
    report_markdown,
    run_two_body_spec,
    two_body_specs,
)


@pytest.fixture(scope="module")
def cfg(tmp_path_factory):
    return StabilityConfig(studies=("two_body",), mesh_cache=tmp_path_factory.mktemp("mesh"))


def test_the_sweep_covers_the_issue():
    pairs = StabilityConfig().two_body_pairs
    assert {r for r, *_ in pairs} >= {1e-3, 1e3} and min(r for r, *_ in pairs) == 1e-3
    assert {(nl, nu) for r, nl, nu in pairs if r == 1.0} >= {(0.499, 0.3), (0.3, 0.499)}
    assert len(two_body_specs()) == len(pairs)


@pytest.mark.parametrize(("ratio", "nu_lower", "nu_upper", "p_tol", "max_its"),
                         [(1e-3, 0.3, 0.3, 3e-3, 4), (1e3, 0.3, 0.3, 3e-3, 4), (1.0, 0.499, 0.3, 5e-2, 4),
                          (1.0, 0.3, 0.499, 1e-2, 4)])
def test_extreme_pairs_converge(cfg, ratio, nu_lower, nu_upper, p_tol, max_its):
    spec = TwoBodySpec("t", ratio, nu_lower, nu_upper, h_ratio=10.0, band=cfg.band, newton=4)
    rec = run_two_body_spec(spec, cfg, comm=MPI.COMM_SELF)
    assert rec["converged"], rec["error"]
    assert rec["errors"]["load_balance"] <= 1e-9
    assert rec["max_iterations"] <= max_its
    assert rec["errors"]["p_max"] < p_tol
    incompressible = max(nu_lower, nu_upper) >= 0.45
    assert any(w.startswith("near-incompressible") for w in rec["warnings"]) == incompressible
    status = classify_two_body(rec)
    assert status == "ok" if not incompressible else status.startswith("named (warning): "), status
    rec["status"] = status
    text = report_markdown({"runs": 1, "ok": 1, "named": 0, "silent": 0, "band": cfg.band, "wall_time_s": 1.0},
                           [rec])
    assert "## two_body" in text
    assert f"{rec['errors']['p_max']:.2e}" in text and status in text


def test_silent_and_slow_points_are_classified():
    rec = {"params": {"band": 0.02, "newton": 4}, "converged": True, "warnings": [], "max_iterations": 6,
           "errors": {"p_max": 1e-3, "half_width_moment": 1e-3}}
    assert classify_two_body(rec) == "SILENT [out of band, 6 Newton its in a step]"
    rec |= {"max_iterations": 3, "errors": {"p_max": 0.05, "half_width_moment": 1e-3}}
    assert classify_two_body(rec) == "SILENT [out of band]"
    rec |= {"converged": False, "error": "diverged: SNES reason -5\nmore"}
    assert classify_two_body(rec) == "named (failure): diverged: SNES reason -5"
