"""Issue 27, point 4: the summary prints every study's wall time, how it ran, its JIT retries, its ratio to the
reference solve of the same run, and the total (workbench/reports/study_times.py), from the studies' JSON alone."""

from __future__ import annotations

import json

from workbench.reports.study_times import study_times, study_times_markdown


def _write(path, data):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(data))


def test_study_times_table_from_the_json_files(tmp_path):
    ref = {"case": "hertz_cylinder", "h_contact": 0.05, "ndofs": 2568, "solve_s": 0.5}
    _write(tmp_path / "validity" / "validity.json",
           {"summary": {"wall_time_s": 100.0, "executor": "mpi", "workers": 8, "jit_retries": 0, "reference": ref}})
    _write(tmp_path / "stability" / "stability.json",
           {"summary": {"wall_time_s": 30.0, "executor": "local", "workers": 1, "jit_retries": 0}})
    _write(tmp_path / "convergence" / "convergence.json",
           {"study_wall_time_s": 20.0, "executor": "local", "workers": 1, "where": {"jit_retries": 0},
            "reference": ref})
    _write(tmp_path / "hertz_cylinder" / "metrics.json", {"wall_time_s": 5.0})
    t = study_times(tmp_path)
    assert t["bench"] is None and t["validity"]["wall_s"] == 100.0 and t["convergence"]["jit_retries"] == 0
    md = "\n".join(study_times_markdown(tmp_path))
    assert "| validity | 100 | mpi, 8 worker(s) | 0 | 200 |" in md  # 100 s / 0.5 s reference
    assert "| convergence | 20 | local, 1 worker(s) | 0 | 40 |" in md
    assert "| bench | not run yet |" in md
    assert "| **total** | **155** |" in md  # 100 + 30 + 20 + the case's 5


def test_summary_has_the_study_times(tmp_path):
    from workbench.reports.summary import summary_markdown

    _write(tmp_path / "stability" / "stability.json", {"summary": {"wall_time_s": 12.0}})
    md = summary_markdown(tmp_path)
    assert "## Study times" in md and "| stability | 12 |" in md


def _case(tmp_path, name, wall_s, written_at):
    import os

    f = tmp_path / name / "metrics.json"
    _write(f, {"wall_time_s": wall_s})
    os.utime(f, (written_at, written_at))


def test_issue_total_of_make_run_and_the_three_studies(tmp_path):
    from workbench.reports.study_times import make_run_time

    # two cases run together (make -j2): 100 s and 60 s, the second started 10 s after the first
    _case(tmp_path, "hertz_cylinder", 100.0, 1_000_100.0)
    _case(tmp_path, "wedge", 60.0, 1_000_070.0)
    assert make_run_time(tmp_path)[0] == 100.0  # first start 1_000_000 to last file 1_000_100, not the sum 160
    _write(tmp_path / "stability" / "stability.json", {"summary": {"wall_time_s": 30.0}})
    _write(tmp_path / "validity" / "validity.json", {"summary": {"wall_time_s": 900.0}})  # not in the issue's total
    md = "\n".join(study_times_markdown(tmp_path))
    assert "incomplete**, not run yet: convergence, bench" in md and "measured so far: 130 s" in md
    _write(tmp_path / "convergence" / "convergence.json", {"study_wall_time_s": 200.0})
    _write(tmp_path / "bench" / "bench.json", {"bench_wall_time_s": 300.0})
    md = "\n".join(study_times_markdown(tmp_path))
    assert "+ bench: 630 s (10.5 min)**" in md and "NOT met" in md  # 100 + 30 + 200 + 300 > 600


def test_make_run_time_of_cases_run_apart_is_their_sum(tmp_path):
    from workbench.reports.study_times import make_run_time

    _case(tmp_path, "hertz_cylinder", 10.0, 1_000_010.0)
    _case(tmp_path, "wedge", 20.0, 2_000_020.0)  # a day later: the span would be meaningless
    t, how = make_run_time(tmp_path)
    assert t == 30.0 and "different times" in how
    assert make_run_time(tmp_path / "nothing") is None
