"""The summary page says the verdict first (issue 22): "N of M cases PASS", then every failing check with its
one-line reason, before any table; the long error-budget table comes after the case table."""

from __future__ import annotations

import json

from cases import case_names
from workbench.reports.summary import summary_markdown


def _metrics(name: str, *, passed: bool, band_fail: bool = False) -> dict:
    m = {"case": name, "method": "nitsche", "kinematics": "small", "ndofs": 1764, "wall_time_s": 3.0, "P": 10.0,
         "errors": {"p_max": 0.02 if not passed and not band_fail else 1e-4, "load_balance": 1e-13},
         "tolerances": {"p_max": 0.01, "load_balance": 1e-3},
         "checks": {"p_max": passed or band_fail, "load_balance": True}, "pass": passed, "runs": [{}]}
    if band_fail:
        m["band_checks"] = {"contain_theory:load_symmetry": {"passed": False, "rows": ["a"],
                                                             "reason": "theory 1 outside [1.0000001, 1.0000005]"}}
        m["error_budget"] = {"p_max": {"theory": 1.0, "gci": 1e-3, "extrapolated": 1.0, "status": "asymptotic",
                                       "theory_in_band": True}}
    return m


def test_failing_cases_are_named_first_with_their_reasons(tmp_path):
    names = case_names()
    for i, n in enumerate(names):
        (tmp_path / n).mkdir()
        m = _metrics(n, passed=i > 1, band_fail=i == 1)
        (tmp_path / n / "metrics.json").write_text(json.dumps(m))
    md = summary_markdown(tmp_path)
    first_table = md.index("\n|")
    head = md[:first_table]
    assert f"**{len(names) - 2} of {len(names)} cases PASS** (FAIL)" in head
    assert f"FAIL **{names[0]}**" in head and "`p_max` 0.02 > tolerance 0.01" in head
    assert f"FAIL **{names[1]}**" in head and "`contain_theory:load_symmetry`: theory 1 outside" in head
    assert f"FAIL **{names[2]}**" not in head
    # the case table (verdict in its second column) comes before the long error-budget table
    assert md.index("| case | verdict |") < md.index("## Error budget")
    assert f"| [{names[0]}]({names[0]}/report.md) | FAIL |" in md


def test_all_pass_says_so(tmp_path):
    for n in case_names():
        (tmp_path / n).mkdir()
        (tmp_path / n / "metrics.json").write_text(json.dumps(_metrics(n, passed=True)))
    head = summary_markdown(tmp_path).split("\n|")[0]
    assert f"**{len(case_names())} of {len(case_names())} cases PASS** (PASS)" in head and "FAIL" not in head


def test_ci_report_opens_with_the_count_and_the_failing_case(tmp_path, monkeypatch, capsys):
    import subprocess

    from workbench.owned import make_dirs
    from workbench.paths import OutputPaths
    from workbench.pipeline import ci

    names = case_names()
    make_dirs(tmp_path / "ci", kind="ci")  # the workbench's own folders (an unmarked one is refused: issue 23)
    for i, n in enumerate(names):
        make_dirs(tmp_path / "ci" / n, kind="case")
        m = _metrics(n, passed=i != 0)
        (tmp_path / "ci" / n / "metrics.json").write_text(json.dumps(m))
    monkeypatch.setattr(ci.subprocess, "run", lambda cmd, **kw: subprocess.CompletedProcess(
        cmd, 1 if cmd[4] == names[0] else 0, "", ""))
    assert ci.run_ci(OutputPaths(tmp_path)) == 1
    md = (tmp_path / "ci_report.md").read_text()
    head = md[:md.index("\n|")]
    assert f"**{len(names) - 1} of {len(names)} cases PASS** (FAIL)" in head and f"FAIL **{names[0]}**: p_max" in head
