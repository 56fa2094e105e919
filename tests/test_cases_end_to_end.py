"""Every case runs end to end at its coarsest (CI) level, fills the results contract and meets its tolerances.

Requirement: no case can rot. Each case is run through the real CLI (``workbench run CASE --ci``)
in a subprocess, from a foreign working directory, into a temporary results folder. Its key numbers must
match those saved (``tests/data/key_numbers_ci.json``) at the tolerance of each number's class
(``workbench.pipeline.number_classes``): verdicts exactly, round-off against its ceiling, iterations within a
margin, physics within what the solver and another machine's mesh can move it. This holds on any machine;
the 1e-10 refactor check is ``make check-numbers`` against a baseline saved on the same machine.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from pages import raw_markdown

from cases import case_names
from cases.schema import label_folder
from workbench.pipeline.key_numbers import key_numbers, load_saved
from workbench.pipeline.number_classes import compare_portable

ROOT = Path(__file__).resolve().parents[1]

CONTRACT = ("case", "method", "kinematics", "ndofs", "wall_time_s", "newton_iterations", "load_steps", "P",
            "P_pressure", "patches", "analytic", "errors", "tolerances", "pass")


@pytest.mark.parametrize("name", case_names())
def test_case_runs_at_ci_level(name, tmp_path):
    proc = subprocess.run([sys.executable, "-m", "workbench", "run", name, "--ci", "--out", str(tmp_path)],
                          cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    out = tmp_path / name
    m = json.loads((out / "metrics.json").read_text())
    for key in CONTRACT:
        assert key in m, key
    for pt in m["patches"]:
        assert set(pt) >= {"center", "half_width", "p_max", "P"}
    assert m["pass"] is True, m["checks"]
    # load by virtual work and by the integral of the pressure agree (both are measured, not imposed)
    assert abs(m["P"] - m["P_pressure"]) <= 2e-3 * abs(m["P"])
    for f in ("pressure.csv", "pressure.png", "report.md", "report.html", "run.log"):
        assert (out / f).is_file(), f
    header = (out / "pressure.csv").read_text().splitlines()[0].split(",")
    assert header[:4] == ["run", "coordinate_mm", "p_fem_MPa", "sigma_nn_MPa"] and len(header) >= 5
    assert list((out / "vtk").rglob("*.pvd")), "VTK output for ParaView"
    assert not list(tmp_path.glob(f".{name}.staging.*")), "no staging folder left behind"
    # nothing written outside the output folder: the mesh cache lives in it too
    assert (tmp_path / "mesh_cache").is_dir()
    # what users look at (issue 14): a VTK time step per converged solve, view.py, pyvista renders in the report,
    # an HTML page without raw Markdown
    for run in m["runs"]:
        label = label_folder(run["label"])  # the folder the workbench writes (cases.schema)
        frames = json.loads((out / "vtk" / label / "frames.json").read_text())
        assert len(frames["steps"]) == len(run["load_steps"]), label
        assert (out / "vtk" / label / "body.pvd").is_file() and (out / "vtk" / label / "contact_surface.pvd").is_file()
    assert (out / "view.py").is_file()
    md = (out / "report.md").read_text()
    renders = sorted(out.glob("render_*.png"))
    assert len(renders) == len(m["runs"]) and all(f"]({p.name})" in md for p in renders), md[:2000]
    assert all(p.stat().st_size > 10_000 for p in renders)  # an image, not an empty window
    assert "Render failed" not in md
    if m["runs"][0].get("steps"):  # concave scenes: the strip of steps
        assert (out / "steps_base.png").is_file() and "](steps_base.png)" in md
    assert not raw_markdown((out / "report.html").read_text())
    saved = load_saved(ROOT / "tests" / "data" / "key_numbers_ci.json")
    saved = {k: v for k, v in saved.items() if k.startswith(f"{name}/")}
    assert saved, f"no saved key numbers for {name}"
    # numbers added since (new measures) are allowed; none of the saved ones may vanish or leave its class
    moves = compare_portable(key_numbers(tmp_path), saved, allow_new=True)
    bad = [f"{mv.key} [{mv.cls}] {mv.old!r} -> {mv.new!r} (moved {mv.moved:.3g} > {mv.tolerance:.3g} {mv.note})"
           for mv in moves if not mv.ok]
    assert not bad, "\n".join(bad[:20])
