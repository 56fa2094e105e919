"""The case's data files and its report drawn from them (pure Python; no FEM run needed).

Requirement: a run saves its data (``pressure.csv``, ``series.json``, ``metrics.json``); the case report
(``pressure.png``, ``report.md``, ``report.html``) is drawn from those files alone, so it can be drawn again
later without the run, and the reports package depends on no layer above it.
"""

from __future__ import annotations

import ast
import csv
import json
import math
from pathlib import Path

import numpy as np

from workbench.atomic import write_json
from workbench.pipeline.case_files import pressure_csv, series_records, write_case_files
from workbench.reports.case_report import case_report_markdown, load_series, write_case_report
from workbench.reports.summary import write_summary
from workbench.scenes.base import Series

ROOT = Path(__file__).resolve().parents[1]


class _Outcome:
    """The only part of :class:`workbench.scenes.base.Outcome` the data files read."""

    def __init__(self, series):
        self.series = series


def _outcomes():
    x = np.linspace(-1.0, 1.0, 5)
    p = np.maximum(0.0, 1.0 - x**2) * 100.0
    hertz = np.sqrt(np.clip(1.0 - x**2, 0.0, None)) * 100.0
    wedge = np.array([np.nan, 10.0, 20.0, 10.0, np.inf])
    small = Series("small", x, p, p + 1e-3, {"Hertz (measured P)": hertz}, "x (mm)", (-1.5, 1.5))
    conv = Series("convective", x, p, p, {"Hertz (measured P)": hertz, "wedge, converged": wedge}, "x (mm)",
                  (-1.5, 1.5))
    return [_Outcome([small]), _Outcome([conv])]


def _metrics(name="demo_case", passed=True):
    run = {"label": "small", "method": "nitsche", "kinematics": "small", "traction": "halfplane", "degree": 2,
           "ndofs": 2568, "newton_iterations": [3, 1], "load_steps": [1.0, 2.0], "P": 4531.1, "P_pressure": 4531.0,
           "patches": [{"center": 0.0, "half_width": 0.5, "p_max": 100.0, "P": 4531.1}], "wall_time_s": 0.05,
           "errors": {"p_max": 6.2e-4, "rms": 2.7e-3}, "warnings": ["slow Newton"]}
    return {"case": name, "description": "A demo case: rigid cylinder on a block.", "pass": passed,
            "wall_time_s": 0.2, "mpi_processes": 1, "headline": "p_max off by 0.06 %", "runs": [run],
            "errors": {"p_max": 6.2e-4, "rms": 2.7e-3}, "tolerances": {"p_max": 0.01, "rms": 1e-3},
            "checks": {"p_max": True, "rms": False}, "P": 4531.1,
            "case_tables": {"Convective ratio b/b0": ["| source | b/b0 |", "|---|---|", "| FEM | 1.16351 |"]}}


def test_pressure_csv_columns_and_formatting():
    rows = list(csv.reader(pressure_csv(_outcomes()).splitlines()))
    assert rows[0] == ["run", "coordinate_mm", "p_fem_MPa", "sigma_nn_MPa", "p_hertz_measured_p_MPa",
                       "p_wedge_converged_MPa", "weight_mm", "q_MPa"]
    assert rows[1] == ["small", "-1", "0", "0.001", "0", "", "", ""]  # no wedge prediction, no weights here
    assert rows[7] == ["convective", "-0.5", "75", "75", "86.60254038", "10", "", ""]
    assert rows[6][-3] == "" and rows[10][-3] == ""  # NaN and inf leave the cell empty
    assert len(rows) == 1 + 2 * 5


def test_series_json_is_strict_json_with_null_for_non_finite(tmp_path):
    write_case_files(_outcomes(), tmp_path)
    text = (tmp_path / "series.json").read_text()
    assert "NaN" not in text and "Infinity" not in text
    data = json.loads(text)
    assert [s["label"] for s in data["series"]] == ["small", "convective"]
    conv = data["series"][1]
    assert set(conv) == {"label", "x", "p", "sigma_nn", "predictions", "xlabel", "xlim"}
    assert conv["predictions"]["wedge, converged"] == [None, 10.0, 20.0, 10.0, None]
    assert conv["xlim"] == [-1.5, 1.5] and conv["xlabel"] == "x (mm)"
    assert conv["x"] == _outcomes()[1].series[0].x.tolist()  # full double precision
    assert (tmp_path / "pressure.csv").read_bytes() == pressure_csv(_outcomes()).encode()
    back = load_series(tmp_path)
    assert math.isnan(back[1]["predictions"]["wedge, converged"][0])
    np.testing.assert_array_equal(back[0]["p"], _outcomes()[0].series[0].p)


def test_series_records_reject_mismatched_lengths():
    bad = Series("bad", [0.0, 1.0], [1.0], [1.0, 2.0], {}, "x (mm)", (0.0, 1.0))
    try:
        series_records([_Outcome([bad])])
    except ValueError as exc:
        assert "'bad'" in str(exc) and "p has 1 values for 2 points" in str(exc)
    else:
        raise AssertionError("a series with mismatched lengths must be rejected")


def test_case_report_markdown_from_metrics_only():
    md = case_report_markdown(_metrics())
    assert md.startswith("# demo_case\n\nA demo case: rigid cylinder on a block.\n")
    assert "Verdict: **PASS**" in md and "p_max off by 0.06 %" in md and "- small: slow Newton" in md
    header = next(line for line in md.splitlines() if line.startswith("| run | method"))
    cells = [c.strip() for c in header.strip("|").split("|")]
    assert cells[4] == "degree" and "P" not in cells and "P (N/mm)" in cells
    assert "| small | nitsche | small | halfplane | 2 | 2568 | 3 1 | 2 | 4531.1 | 4531 | 1 | 0.05 |" in md
    assert "| rms | 0.0027 | 0.001 | FAIL |" in md and "## Convective ratio b/b0" in md
    assert "[series.json](series.json)" in md


def test_write_case_report_reads_only_the_saved_files(tmp_path):
    write_case_files(_outcomes(), tmp_path)
    write_json(tmp_path / "metrics.json", _metrics())
    written = write_case_report(tmp_path)
    assert [f.name for f in written] == ["pressure.png", "report.md", "report.html"]
    assert (tmp_path / "pressure.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    html = (tmp_path / "report.html").read_text()
    assert "<title>demo_case</title>" in html and "<th>degree</th>" in html and "**" not in html
    assert '<img src="pressure.png" alt="pressure"' in html


def test_case_report_without_series_json_keeps_the_old_plot(tmp_path):
    write_json(tmp_path / "metrics.json", _metrics(passed=False))
    (tmp_path / "pressure.png").write_bytes(b"old")
    assert [f.name for f in write_case_report(tmp_path)] == ["report.md", "report.html"]
    assert (tmp_path / "pressure.png").read_bytes() == b"old"
    assert "Verdict: **FAIL**" in (tmp_path / "report.md").read_text()


def test_workbench_report_redraws_every_case_report(tmp_path):
    case = tmp_path / "hertz_cylinder"
    write_case_files(_outcomes(), case)
    write_json(case / "metrics.json", _metrics("hertz_cylinder"))
    write_summary(tmp_path)
    assert {"pressure.png", "report.md", "report.html"} <= {f.name for f in case.iterdir()}
    assert 'href="hertz_cylinder/report.html"' in (tmp_path / "report.html").read_text()


def _imports(path: Path) -> set[str]:
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0:
            out.add(node.module)
    return out


def test_reports_import_nothing_above_them():
    allowed_first_party = ("analytic", "cases", "workbench.atomic", "workbench.owned", "workbench.paths",
                           "workbench.reports")
    first_party = ("analytic", "measures", "cases", "meshes", "fem", "workbench")
    for path in sorted((ROOT / "workbench" / "reports").glob("*.py")):
        for mod in _imports(path):
            if mod.split(".")[0] in first_party:
                assert mod == "workbench" or mod.startswith(allowed_first_party), f"{path.name} imports {mod}"
