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
