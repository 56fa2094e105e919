"""The summary's opening figure (issue 37): every judged quantity over its theory, with its band.

The records (:mod:`workbench.reports.forest`) are checked on a small synthetic set of metrics (a budget case with
band checks, a CI-level case without a budget); the summary page references the figure before its verdict text
and tables; the figure is written and opens."""

from __future__ import annotations

import json

import pytest

from cases import case_names
from workbench.reports.forest import case_forest_rows, forest_caption, forest_rows
from workbench.reports.summary import FOREST_PNG, summary_markdown


def _budget_case() -> dict:
    """A full-level case: two b/b0 rows, one whose band holds the theory (passes) and one that misses it."""
    budget = {
        # band 2e-3 * 0.98 = 1.96e-3 around 0.9805: holds 0.981; the alternative 0.9817 outside
        "b_over_b0": {"fine": 0.98, "extrapolated": 0.9805, "gci": 1.5e-3, "uncertainty": 2e-3, "theory": 0.981,
                      "theory_in_band": True, "alt_value": 0.9830, "alt_in_band": False, "status": "asymptotic"},
        # no "uncertainty" (an older row): gci + truncation = 1e-4 * 0.97 around 0.9760: misses 0.9770
        "b_over_b0_moment": {"fine": 0.97, "extrapolated": 0.9760, "gci": 6e-5, "truncation": 4e-5,
                             "theory": 0.9770, "theory_in_band": False, "alt_value": 0.9772, "alt_in_band": False,
                             "status": "asymptotic"},
        "vm_max": {"fine": 0.55, "extrapolated": 0.556, "gci": 1e-3, "theory": 0.5575, "theory_in_band": True,
                   "status": "asymptotic"},
    }
    checks = {"contain_theory:b_over_b0": {"kind": "contain_theory", "passed": True, "rows": {"b_over_b0": True},
                                           "reason": ""},
              "contain_theory:b_over_b0_moment": {"kind": "contain_theory", "passed": False,
                                                  "rows": {"b_over_b0_moment": False}, "reason": "theory outside"},
              "exclude_alt:b_over_b0": {"kind": "exclude_alt", "passed": True, "rows": {"b_over_b0": True},
                                        "reason": ""}}
    return {"case": "budgeted", "pass": False, "error_budget": budget, "band_checks": checks,
            "errors": {}, "tolerances": {}, "checks": {}}


def _ci_case() -> dict:
    """A CI-level case (no budget): p_max with a signed deviation, half_width with only the checked error, an RMS
    check (no value against a theory: no row)."""
    run = {"label": "only", "p_max": 101.0, "patch_half_width": 0.99,
           "analytic": {"p_ref": 100.0, "half_width": 1.0},
           "errors": {"p_max": 0.01, "half_width_vs_other": 0.02, "rms": 0.003}}
    return {"case": "ci_only", "pass": False, "errors": {"p_max": 0.01, "half_width_vs_other": 0.02, "rms": 0.003},
            "tolerances": {"p_max": 0.005, "half_width": 0.05, "rms": 0.01},
            "checks": {"p_max": False, "half_width": True, "rms": True},
            "checked_errors": {"p_max": "p_max", "half_width": "half_width_vs_other", "rms": "rms"},
            "runs": [run]}


def test_budget_rows_are_value_over_theory_with_the_band_and_the_band_checks_verdict():
    rows = {r.quantity: r for r in case_forest_rows("budgeted", _budget_case())}
    assert list(rows) == ["b_over_b0", "b_over_b0_moment"]  # judged rows only; vm_max is no band check's row
    b = rows["b_over_b0"]
    assert b.ratio == pytest.approx(0.9805 / 0.981, rel=1e-14)
    assert b.band == pytest.approx(2e-3 * 0.98 / 0.981, rel=1e-14)
    lo, hi = b.interval
    assert lo < 1.0 < hi and b.passed is True  # the band holds the theory: it passes
    assert b.kinds == ("contain_theory", "exclude_alt")
    assert b.alt_ratio == pytest.approx(0.9830 / 0.981, rel=1e-14) and not lo <= b.alt_ratio <= hi
    m = rows["b_over_b0_moment"]
    assert m.band == pytest.approx((6e-5 + 4e-5) * 0.97 / 0.977, rel=1e-12)  # older rows: gci + truncation
    assert m.interval[1] < 1.0 and m.passed is False  # the band misses the theory: it fails


def test_a_budget_without_band_checks_gives_its_rows_with_a_theory_not_judged():
    m = _budget_case() | {"band_checks": {}}
    m["error_budget"]["interior"] = {"fine": 0.01, "extrapolated": None, "gci": None, "theory": 0.0}
    rows = case_forest_rows("budgeted", m)
    assert [r.quantity for r in rows] == ["b_over_b0", "b_over_b0_moment", "vm_max"]  # theory 0: no ratio
    assert all(r.passed is None for r in rows)


def test_an_unresolved_exclusion_passes_and_says_so():
    m = _budget_case()
    m["error_budget"]["b_over_b0"] |= {"alt_value": 0.9810, "alt_in_band": True}
    m["band_checks"]["exclude_alt:b_over_b0"]["unresolved"] = {"b_over_b0": "unresolved: ..."}
    row = case_forest_rows("budgeted", m)[0]
    assert row.passed is True and row.note.startswith("unresolved")


def test_an_undefined_band_keeps_its_row_and_says_why():
    m = _budget_case()
    m["error_budget"]["b_over_b0"] |= {"gci": None, "status": "oscillating"}
    m["error_budget"]["b_over_b0_moment"] |= {"extrapolated": float("nan")}
    rows = {r.quantity: r for r in case_forest_rows("budgeted", m)}
    assert rows["b_over_b0"].band is None and "oscillating" in rows["b_over_b0"].note
    assert rows["b_over_b0_moment"].ratio is None and "undefined" in rows["b_over_b0_moment"].note


def test_ci_rows_are_the_fine_value_over_theory_with_no_band():
    rows = {r.quantity: r for r in case_forest_rows("ci_only", _ci_case())}
    assert list(rows) == ["p_max", "half_width"]  # the RMS check is no value against a theory
    p = rows["p_max"]
    assert p.ratio == pytest.approx(1.01, rel=1e-14) and p.band is None and p.interval is None
    assert p.signed and p.passed is False and p.tolerance == 0.005  # 1 % > 0.5 %: fails, as the case's check
    hw = rows["half_width"]  # 0.99 / 1.0 - 1 = -1 % does not reproduce the checked 2 % (another theory)
    assert not hw.signed and hw.ratio == pytest.approx(1.02) and hw.passed is True


def test_ci_b_over_b0_is_the_fem_ratio_over_the_converged_theory():
    m = _ci_case() | {"analytic": {"b_over_b0_moment_fem": 0.97640, "b_over_b0_moment_converged": 0.97631}}
    m["checks"] |= {"b_over_b0_moment": True}
    m["tolerances"] |= {"b_over_b0_moment": 0.002}
    row = next(r for r in case_forest_rows("ci_only", m) if r.quantity == "b_over_b0_moment")
    assert row.ratio == pytest.approx(0.97640 / 0.97631, rel=1e-14) and row.passed and row.band is None


def test_the_caption_says_which_cases_have_no_band():
    rows = forest_rows({"budgeted": _budget_case(), "ci_only": _ci_case()})
    text = forest_caption(rows)
    assert "no band" in text and "ci_only" in text and "budgeted" not in text.split("no band")[1]


def _write_cases(tmp_path, make) -> list[str]:
    names = case_names()
    for i, n in enumerate(names):
        (tmp_path / n).mkdir()
        m = make(i) | {"case": n, "method": "nitsche", "kinematics": "small", "ndofs": 10, "wall_time_s": 1.0,
                       "P": 1.0}
        (tmp_path / n / "metrics.json").write_text(json.dumps(m))
    return names


def test_the_summary_opens_with_the_figure_before_the_verdict_text_and_tables(tmp_path):
    _write_cases(tmp_path, lambda i: _budget_case() if i == 0 else _ci_case())
    md = summary_markdown(tmp_path)
    fig = md.index(f"]({FOREST_PNG})")
    assert md.index("cases PASS**") < fig < md.index("- FAIL **")  # after the count, before the failing checks
    assert fig < md.index("\n|") and fig < md.index("## Cases") and fig < md.index("## Error budget")
    assert "no band" in md[fig:md.index("- FAIL **")]  # its caption says which rows have no band


def test_no_judged_quantity_no_figure(tmp_path):
    _write_cases(tmp_path, lambda i: {"pass": True, "errors": {"rms": 0.001}, "tolerances": {"rms": 0.01},
                                      "checks": {"rms": True}, "runs": [{}]})
    assert FOREST_PNG not in summary_markdown(tmp_path)


def test_write_summary_draws_the_figure(tmp_path):
    from matplotlib.image import imread

    from workbench.reports.summary import write_summary

    _write_cases(tmp_path, lambda i: _budget_case() if i % 2 else _ci_case())
    write_summary(tmp_path, case_reports=False)
    png = tmp_path / FOREST_PNG
    assert png.is_file() and png.stat().st_size > 10_000
    assert imread(png).shape[0] > 400  # one line per row: a tall figure
    assert f'src="{FOREST_PNG}"' in (tmp_path / "report.html").read_text()


def test_a_users_forest_png_is_refused_before_anything_is_written(tmp_path):
    from workbench.paths import OutputError
    from workbench.reports.summary import check_summary_writes

    (tmp_path / FOREST_PNG).write_bytes(b"mine")
    with pytest.raises(OutputError, match=FOREST_PNG):
        check_summary_writes(tmp_path, case_reports=False)
    assert (tmp_path / FOREST_PNG).read_bytes() == b"mine"


def test_the_figure_draws_undefined_and_exact_rows(tmp_path):
    from workbench.reports.forest import ForestRow
    from workbench.reports.forest_plot import plot_forest

    rows = [ForestRow("a", "q", None, None, False, ("contain_theory",), note="no theory"),
            ForestRow("a", "exact", 1.0, 0.0, True, ("contain_theory",)),
            ForestRow("b", "far", 5.0, None, None, ())]
    assert plot_forest(rows, tmp_path / "f.png", title="t").stat().st_size > 5_000
    assert plot_forest([], tmp_path / "g.png", title="t") is None and not (tmp_path / "g.png").exists()
