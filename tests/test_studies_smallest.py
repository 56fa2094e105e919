"""Issue 28: every study's smallest configuration end to end through the real command line (``workbench <study>``):
its options, its runs through the case pipeline, its JSON and its report, in seconds. Not the study's numbers
(those need the full configuration): that each layer runs and writes what the README says.

convective-table runs end to end in tests/test_studies_layout.py (test_convective_table_from_another_directory).
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _study(tmp_path, *args):
    env = dict(os.environ, OMP_NUM_THREADS="1")
    env.setdefault("PYTHONPATH", str(ROOT))
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "workbench", *args, "--out", str(out), "--mesh-cache",
                           str(tmp_path / "mesh")], capture_output=True, text=True, env=env, cwd=tmp_path,
                          timeout=900)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return out


def test_convergence_smallest(tmp_path):
    out = _study(tmp_path, "convergence", "--cases", "hertz_cylinder", "--levels", "0.4", "0.2", "0.1",
                 "--ideal-levels", "0.4", "0.2", "0.1", "--repeats", "1", "--no-diagnostics", "--no-plot")
    d = json.loads((out / "convergence.json").read_text())
    # 2 methods x 2 degrees x 2 series x 3 levels
    assert len(d["rows"]) == 24 and {r["case"] for r in d["rows"]} == {"hertz_cylinder"}
    assert all(r["time_s"] > 0 for r in d["rows"])
    assert (out / "convergence.csv").is_file() and "hertz_cylinder" in (out / "report.md").read_text()


def test_stability_smallest(tmp_path):
    out = _study(tmp_path, "stability", "--study", "faults")
    d = json.loads((out / "stability.json").read_text())
    assert {r["study"] for r in d["records"]} == {"faults"} and len(d["records"]) == 2
    assert (out / "report.md").stat().st_size > 0 and (out / "report.html").stat().st_size > 0


@pytest.mark.skipif(os.environ.get("WORKBENCH_SLOW_TESTS") != "1",
                    reason="the validity study's smallest run (about 30 s cold): make slow-tests runs it "
                           "(WORKBENCH_SLOW_TESTS=1); tests/test_validity_study.py checks its parts in make test")
def test_validity_smallest(tmp_path):
    out = _study(tmp_path, "validity", "--tiny", "--workers", "1")
    d = json.loads((out / "validity.json").read_text())
    assert d["summary"]["runs"] > 0 and d["summary"]["runs"] == len(d["runs"])
    assert d["config"]["h_ratios"] == [2.0, 3.0, 4.0]
    assert (out / "report.md").stat().st_size > 0
    hp = [p for p in d["points"] if p["scene"] == "halfplanes"]  # two elastic half-planes, beta of both signs
    assert sorted(p["beta"] for p in hp) == [-0.3, 0.3]
    assert all(p["theories"]["ch_converged"]["moment"] for p in hp)
    md = (out / "report.md").read_text()
    assert "| 0.1 | -0.3 |" in md and "| 0.1 | +0.3 |" in md and (out / "map_halfplanes.png").is_file()
    assert all(x["reason"] for x in d["dropped"])  # every dropped entry says why
    ew = d["claim_elastic_wedge"]  # the paper's theta < pi/5 claim as stated: an elastic wedge, same material
    assert [r["theta"] for r in ew["rows"]] == [math.pi / 5] and ew["verdict"]["state"] in (
        "holds", "does not hold", "undecided")
    assert ew["rows"][0]["geometry"] > 0.02  # the wedge is no half-plane at pi/5, even on these coarse grids
    assert "elastic wedge, same material" in md


@pytest.mark.parametrize("section", ["linear"])
def test_bench_smallest(tmp_path, section):
    out = _study(tmp_path, "bench", "--quick", "--repeats", "1", "--sections", section)
    d = json.loads((out / "bench.json").read_text())
    assert section in d and d["repeats"] == 1
    assert (out / "report.md").stat().st_size > 0
