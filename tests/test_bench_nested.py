"""The bench section ``nested`` (workbench/studies/bench_nested.py, issue 38): its refusals and its report.

Requirements:
1. Refused in one line before any solve: repeats not a whole number >= 1, a case without budget levels, a run
   label the case does not have (ValueError naming the field).
2. The report section states the total ratio and one row per level with both iteration counts and the value
   difference (a synthetic measurement: the section's measurement itself is a benchmark, `make bench`).
"""

import pytest

from workbench.studies.bench_config import BENCH_SECTIONS
from workbench.studies.bench_nested import NestedBench, run_nested_bench
from workbench.studies.bench_report import nested_markdown, to_markdown


def test_refusals_name_the_field():
    with pytest.raises(ValueError, match="repeats"):
        NestedBench(repeats=0)
    with pytest.raises(ValueError, match="budget_levels"):
        run_nested_bench(NestedBench(case="patch_test"))
    with pytest.raises(ValueError, match="run must be one of"):
        run_nested_bench(NestedBench(run="nope"))


def _row(h, ndofs, cold, nested):
    return {"h": h, "ndofs": ndofs, "ratio": nested[0] / cold[0], "moment_rel_diff": 5e-11,
            "cold": {"solve_s": cold[0], "newton_iterations": cold[1], "solves": 5},
            "nested": {"solve_s": nested[0], "newton_iterations": nested[1], "solves": 3}}


def test_report_section_states_the_ratio_and_every_level():
    data = {"config": {"case": "halfplanes_beta_pos", "run": "small", "repeats": 1}, "width": 2560.0,
            "rows": [_row(0.05, 14530, (1.2, 22), (1.1, 22)), _row(0.0125, 179668, (33.4, 30), (7.9, 7))],
            "total_cold_s": 34.6, "total_nested_s": 9.0, "ratio": 9.0 / 34.6, "load_avg": (1.0, 1.0, 1.0)}
    text = "\n".join(nested_markdown(data))
    assert "**0.26**" in text and "| 0.0125 | 179668 | 33.40 | 30 (5) | 7.90 | 7 (3) | 0.24 |" in text
    assert "nested" in BENCH_SECTIONS
    full = to_markdown({"nested": data, "load_avg_start": (1.0, 1.0, 1.0), "cpu_count": 2})
    assert "## Nested iteration" in full
