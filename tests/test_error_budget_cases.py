"""Issue 12: the error budget of the block cases in ``make run`` (three grids, three block sizes, theory).

Requirement: with the finite block extrapolated away and the grids extrapolated, the FEM converges onto the
half-plane theory of the indenter's own profile, the band (GCI + truncation) contains that theory and excludes
the other one; the subsurface stresses on the Hertz axis agree with McEwen's closed form within 1 % of p0,
the von Mises maximum at the same depth. Every new case field rejects a bad value with one line and exit 2.
"""

from __future__ import annotations

import csv
import json
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest
from test_cases_validation import GOOD

from workbench.cli import main

ROOT = Path(__file__).resolve().parents[1]

CONTRACT = ("fine", "extrapolated", "observed_order", "gci", "truncation", "theory", "theory_in_band")
# concave_symmetric's budget (about 130 s, the largest) runs with WORKBENCH_SLOW_TESTS=1 (`make slow-tests`); `make run`
# checks its bands (load symmetry) on every run; so does wedge's (the classical wedge). hertz_cylinder and
# wedge_convective run in `make test`.
SLOW = os.environ.get("WORKBENCH_SLOW_TESTS") == "1"
CASES = ("hertz_cylinder", "wedge_convective") + (("wedge", "concave_symmetric") if SLOW else ())
needs_slow_wedge = pytest.mark.skipif(not SLOW, reason="wedge's budget (about 40 s): make slow-tests runs it "
                                      "(WORKBENCH_SLOW_TESTS=1); make run checks its bands")
needs_concave = pytest.mark.skipif(not SLOW, reason="concave_symmetric's budget (about 130 s): make slow-tests runs "
                                   "it (WORKBENCH_SLOW_TESTS=1); make run checks its bands")


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    """The cases' ``make run`` budgets (:data:`CASES`), two processes at a time (2 cores; ``make -j2 run`` does the
    same into one results folder)."""
    out = tmp_path_factory.mktemp("budget")

    def run(name):
        return subprocess.run([sys.executable, "-m", "workbench", "run", name, "--out", str(out)], cwd=out,
                              capture_output=True, text=True, timeout=900)

    with ThreadPoolExecutor(max_workers=2) as pool:
        procs = list(pool.map(run, CASES))
    for proc in procs:
        assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return out


def _budget(results: Path, name: str) -> dict:
    b = json.loads((results / name / "metrics.json").read_text())["error_budget"]
    for q, row in b.items():
        assert set(CONTRACT) <= set(row), q
    return b


def test_hertz_moment_half_width_converges_onto_the_exact_circle(results):
    b = _budget(results, "hertz_cylinder")
    r = b["half_width_moment"]
    assert r["status"] == "asymptotic" and abs(r["observed_order"] - 4.0) < 0.5, r
    assert r["theory_in_band"] and r["gci"] + r["truncation"] < 1e-5, r
    assert abs(r["extrapolated"] - r["theory"]) / r["theory"] < 1e-6, r
    assert not r["alt_in_band"], r  # Hertz's parabola is outside the band
    p = b["p_max"]  # the largest sample: its differences grow below 1e-5 (named, not extrapolated)
    assert p["status"] == "diverging" and abs(p["extrapolated"] - p["theory"]) / p["theory"] < 1e-5, p
    assert not p["alt_in_band"], p


def test_hertz_subsurface_axis_within_one_percent_of_p0(results):
    m = json.loads((results / "hertz_cylinder" / "metrics.json").read_text())["subsurface"]
    assert max(m["max_abs_error_over_p0"].values()) < 0.01, m
    assert abs(m["z_vm_max_fem_over_a"] - m["z_vm_max_exact_over_a"]) <= 0.05 + 1e-12, m
    assert abs(m["vm_max_fem_over_p0"] - m["vm_max_exact_over_p0"]) < 0.01, m
    rows = list(csv.DictReader((results / "hertz_cylinder" / "subsurface.csv").open()))
    assert len(rows) >= 50 and float(rows[-1]["z_mm"]) >= 3 * m["a_mm"]
    assert {"z_mm", "sxx_fem", "syy_fem", "szz_fem", "vm_fem", "sxx_exact", "syy_exact", "szz_exact",
            "vm_exact"} <= set(rows[0])


def test_hertz_interior_stress_converges_onto_mcewen(results):
    """Interior field (issue 12 point 4): the L2 stress error over |x|, z <= 4 a falls with the grids (measured
    3.0e-3, 9.4e-4, 2.6e-4 p0, rate 1.78) and the largest von Mises stress has McEwen's value in its band."""
    b = _budget(results, "hertz_cylinder")
    r = b["interior_stress_l2"]
    assert r["observed_order"] > 1.5 and r["fine"] < 1e-3, r
    v = b["vm_max"]
    assert v["theory_in_band"] and abs(v["extrapolated"] - v["theory"]) / v["theory"] < 2e-3, v
    m = json.loads((results / "hertz_cylinder" / "metrics.json").read_text())["subsurface"]["interior"]
    assert abs(m["vm_max_fem_at_over_a"][1] - m["vm_max_exact_depth_over_a"]) < 0.05, m


def test_wedge_convective_moment_ratio_onto_converged_theory(results):
    r = _budget(results, "wedge_convective")["b_over_b0_moment"]
    assert abs(r["extrapolated"] - r["theory"]) / r["theory"] <= 1e-4, r
    assert r["theory_in_band"] and not r["alt_in_band"], r
    # the budget's blocks have the half-plane far field: truncation left 5.6e-7 (clamped: 4.7e-5, order 1 in a/W)
    assert r["truncation"] < 1e-5, r
    report = (results / "wedge_convective" / "report.md").read_text()
    assert "Error budget" in report and "b_over_b0_moment" in report


@needs_slow_wedge
def test_classical_wedge_moment_half_width_onto_closed_form(results):
    b = _budget(results, "wedge")
    for label in ("theta=pi/20", "theta=pi/5"):
        r = b[f"half_width_moment[{label}]"]
        assert r["status"] == "asymptotic" and abs(r["observed_order"] - 4.0) < 0.5, r
        assert r["theory_in_band"] and abs(r["extrapolated"] - r["theory"]) / r["theory"] < 1e-6, r


@needs_concave
def test_concave_steps_carry_a_gci(results):
    b = _budget(results, "concave_symmetric")
    for step in ("step1 (d = 0.6 mm)", "step2 (d = 0.8 mm)", "step3 (d = 1 mm)"):
        for q in ("P", "p_max", "width_fem[0]", "width_fem[1]"):
            r = b[f"{step} {q}"]
            assert r["gci"] is not None and r["gci"] < 0.01 and r["status"] != "diverging", (step, q, r)
    # Hertz superposition (eq. (4)) holds at the first step and fails at the last: the check can fail on physics
    assert b["step1 (d = 0.6 mm) width_fem[0]"]["theory_in_band"]
    assert not b["step3 (d = 1 mm) width_fem[0]"]["theory_in_band"]


def test_every_band_carries_its_iterative_and_round_off_terms(results):
    """Issue 22: each row's uncertainty is GCI + truncation + iterative (the finest level solved again at the
    solver tolerances / 100) + round-off; measured: the tight re-solve moves no value by more than 1e-12 (the
    small-strain contact problem is piecewise linear: semismooth Newton ends on the discrete solution)."""
    for name in CASES:
        for q, r in _budget(results, name).items():
            if r.get("gci") is None:
                continue
            assert r["iterative"] is not None and r["iterative"] <= 1e-8, (name, q, r)
            assert r["roundoff"] == 1e-9, (name, q)
            terms = r["gci"] + r["truncation"] + r["iterative"] + r["roundoff"] + (r.get("theory_uncertainty") or 0)
            if "symmetry_band" not in r:
                assert abs(r["uncertainty"] - terms) <= 1e-15 + 1e-12 * terms, (name, q, r)


@needs_concave
def test_concave_load_symmetry_band(results):
    sym = _budget(results, "concave_symmetric")
    for step in ("step1 (d = 0.6 mm)", "step2 (d = 0.8 mm)", "step3 (d = 1 mm)"):
        r = sym[f"{step} load_symmetry"]   # the fine ratio against 1, within the patch loads' uncertainties
        assert r["theory_in_band"] and r["extrapolated"] == r["fine"] and r["symmetry_band"] > 1e-6, r


BAD = {
    "two_levels": "budget_levels = [0.1, 0.05]\nbudget_widths = [640.0, 2560.0, 10000.0]",
    "level_above_one": "budget_levels = [2.0, 0.1, 0.05]\nbudget_widths = [640.0, 2560.0, 10000.0]",
    "equal_levels": "budget_levels = [0.1, 0.1, 0.05]\nbudget_widths = [640.0, 2560.0, 10000.0]",
    "width_too_small": "budget_levels = [0.2, 0.1, 0.05]\nbudget_widths = [5.0, 2560.0, 10000.0]",
    "width_too_large": "budget_levels = [0.2, 0.1, 0.05]\nbudget_widths = [640.0, 2560.0, 1e6]",
    "levels_without_widths": "budget_levels = [0.2, 0.1, 0.05]",
    "span_too_wide": "budget_levels = [0.8, 0.1, 0.05]\nbudget_widths = [640.0, 2560.0, 10000.0]",
    "widths_in_concave": None,
    "wrong_type": 'budget_levels = "fine"\nbudget_widths = [640.0, 2560.0, 10000.0]',
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_budget_field_exit_2_one_line(name, tmp_path, capsys):
    p = tmp_path / f"{name}.toml"
    if BAD[name] is None:  # a concave scene has no block to vary
        text = (ROOT / "cases" / "concave_symmetric.toml").read_text().replace(
            "budget_levels = [", "budget_widths = [640.0, 2560.0, 10000.0]\nbudget_levels = [", 1)
    else:
        text = GOOD + "[discretisation]\n" + BAD[name] + "\n"
    p.write_text(text)
    out = tmp_path / "results"
    code = main(["run", str(p), "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2, (name, err)
    assert len(err.splitlines()) == 1 and "discretisation.budget_" in err, err
    assert not out.exists() or not any(out.iterdir())
