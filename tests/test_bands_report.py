"""The budget in the results contract, the key numbers and the case report (issue 12, point 6).

Requirement: every ``error_budget`` row's contract fields and every band verdict become NEW key numbers
(``workbench.pipeline.key_numbers``); the case report shows the band checks and ``budget.png``, one panel
per quantity, drawn from ``metrics.json`` alone; a row whose band is undefined gets a panel that says so.
"""

from __future__ import annotations

import json

from workbench.pipeline.key_numbers import key_numbers
from workbench.reports.budget_plot import budget_panels, plot_budget
from workbench.reports.case_report import case_report_markdown

ROW = {"fine": 1.2724, "extrapolated": 1.27239, "observed_order": None, "gci": 5.7e-5, "truncation": 4.7e-5,
       "theory": 1.2724024, "theory_in_band": True, "alt_theory": "first order", "alt_value": 1.28868,
       "alt_in_band": False, "status": "oscillating", "by_h": {"0.05": 1.2724, "0.1": 1.27245, "0.2": 1.2723}}
UNDEFINED = {"fine": 3.0, "extrapolated": None, "observed_order": None, "gci": None, "truncation": 0.0,
             "theory": None, "theory_in_band": None, "status": "patch count differs between levels: [1, 2]"}


def _metrics():
    return {"case": "probe", "description": "", "pass": True, "wall_time_s": 1.0, "runs": [], "errors": {},
            "tolerances": {}, "checks": {"contain_theory:b_over_b0_moment": True},
            "error_budget": {"b_over_b0_moment": ROW, "step2 (d = 0.47 mm) patches": UNDEFINED},
            "band_checks": {"contain_theory:b_over_b0_moment": {
                "kind": "contain_theory", "quantity": "b_over_b0_moment", "passed": True,
                "rows": {"b_over_b0_moment": True}, "reason": ""}}}


def test_budget_rows_and_band_verdicts_are_key_numbers(tmp_path):
    (tmp_path / "probe").mkdir()
    (tmp_path / "probe" / "metrics.json").write_text(json.dumps(_metrics()))
    k = key_numbers(tmp_path)
    assert k["probe/error_budget/b_over_b0_moment/extrapolated"] == ROW["extrapolated"]
    assert k["probe/error_budget/b_over_b0_moment/alt_in_band"] is False
    assert k["probe/error_budget/b_over_b0_moment/observed_order"] is None
    assert k["probe/error_budget/step2 (d = 0.47 mm) patches/gci"] is None
    assert k["probe/band_checks/contain_theory:b_over_b0_moment"] is True


def test_budget_panels_and_plot_keep_undefined_rows(tmp_path):
    panels = budget_panels(_metrics()["error_budget"])
    assert [p["ok"] for p in panels] == [True, False]
    ok = panels[0]
    assert abs(ok["band"] - (5.7e-5 + 4.7e-5) * 1.2724 / 1.27239) < 1e-15
    assert ok["alt"] > ok["band"] and abs(ok["theory"]) < ok["band"]
    path = plot_budget(_metrics()["error_budget"], tmp_path / "budget.png", title="probe")
    assert path.is_file() and path.stat().st_size > 1000
    assert plot_budget({}, tmp_path / "none.png", title="probe") is None


def test_case_report_shows_band_checks_and_the_budget_plot():
    md = case_report_markdown(_metrics())
    assert "## Band checks" in md and "| contain_theory:b_over_b0_moment | b_over_b0_moment |" in md
    assert "first order" in md and "![error budget](budget.png)" in md
