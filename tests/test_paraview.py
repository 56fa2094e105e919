"""The VTK output as the real ParaView client reads it, and every case's ``view.py`` run by ``pvpython``.

Requirements (issue 14): ParaView reads the stress as a symmetric tensor with named components XX YY ZZ XY YZ
XZ, units are in the array names, displacement and stress share one mesh, every converged load or
displacement step is a time step (with d and P as field data), the contact surface is a polyline; for Hertz
the YY stress has its minimum within 3 % of -p0; ``close_to_conformal`` has one time step per displacement
step; ``pvpython view.py`` exits 0 for every case and writes a screenshot whose render view is filled by the
body near the contact.

Needs Debian's ``paraview`` (``pvpython``) and ``xvfb-run``: without them the tests are skipped with that reason
(``make viz-check`` installs both and runs this file on ``results/``). Without ``WORKBENCH_VIZ_RESULTS`` the
cases are run at their CI level into a temporary folder first.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from cases import case_names
from cases.schema import label_folder

HERE = Path(__file__).resolve().parent
INSPECT = HERE / "paraview" / "inspect_vtk.py"
NEED = [tool for tool in ("pvpython", "xvfb-run") if shutil.which(tool) is None]
pytestmark = pytest.mark.skipif(bool(NEED), reason=f"{' and '.join(NEED)} not found: install Debian's paraview and "
                                "xvfb (`make viz-check` does, then runs these tests on results/)")


@pytest.fixture(scope="module")
def results(tmp_path_factory) -> Path:
    env = os.environ.get("WORKBENCH_VIZ_RESULTS")
    if env:
        return Path(env)
    out = tmp_path_factory.mktemp("viz")
    proc = subprocess.run([sys.executable, "-m", "workbench", "run", *case_names(), "--ci", "--out", str(out)],
                          capture_output=True, text=True, timeout=1200)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return out


def _pv(args: list, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(["xvfb-run", "-a", "pvpython", *map(str, args)], cwd=cwd, capture_output=True,
                          text=True, timeout=600)


@pytest.fixture(scope="module")
def seen(results) -> dict:
    """What pvpython reads from every run folder of every case."""
    folders = [f for name in case_names() for f in sorted((results / name / "vtk").glob("*/"))]
    assert folders, f"no VTK output under {results}"
    proc = _pv([INSPECT, *folders], results)
    line = next((ln for ln in proc.stdout.splitlines() if ln.startswith("JSON")), None)
    assert proc.returncode == 0 and line, proc.stdout[-2000:] + proc.stderr[-2000:]
    return json.loads(line[4:])


@pytest.mark.parametrize("name", case_names())
def test_vtk_as_paraview_reads_it(name, results, seen):
    metrics = json.loads((results / name / "metrics.json").read_text())
    for run in metrics["runs"]:
        label = label_folder(run["label"])  # the folder the workbench writes (cases.schema)
        entry = seen[str(results / name / "vtk" / label)]
        body, surf = entry["body"], entry["contact_surface"]
        steps = run["load_steps"]
        assert body["times"] == [float(k) for k in range(1, len(steps) + 1)], (name, label, body["times"])
        assert surf["times"] == body["times"]
        arrays = body["last"]["arrays"]
        assert arrays["stress_MPa"]["names"] == ["XX", "YY", "ZZ", "XY", "YZ", "XZ"]
        assert arrays["displacement_mm"]["names"] == ["X", "Y", "Z"]
        assert "von_Mises_MPa" in arrays and body["last"]["cell_types"] == [5]  # triangles
        field = body["last"]["field"]
        assert field["TimeValue"] == len(steps) and field["d_mm"] == pytest.approx(steps[-1]["d"], rel=1e-12)
        assert field["P_N_per_mm"] == pytest.approx(steps[-1]["P"], rel=1e-12)
        assert body["first"]["field"]["d_mm"] == pytest.approx(steps[0]["d"], rel=1e-12)
        # the contact surface is one polyline (VTK_POLY_LINE = 4) with the contact quantities
        assert surf["last"]["cell_types"] == [4] and surf["last"]["cells"] == 1
        assert {"p_MPa", "sigma_nn_MPa", "gap_mm", "s_mm", "displacement_mm"} <= set(surf["last"]["arrays"])
        p_max = max(pt["p_max"] for pt in run["patches"])
        assert surf["last"]["arrays"]["p_MPa"]["range"][0][1] == pytest.approx(p_max, rel=1e-9)
        xmin, xmax = body["last"]["bounds"][:2]
        if run.get("indenter") == "stacked":  # the patch test's blocks sit on [0, W], x = 0 their roller edge
            assert xmin == pytest.approx(0.0, abs=1e-12) and xmax > 0
        else:  # a half model is written as the full body: symmetric about x = 0
            assert xmin == pytest.approx(-xmax, rel=1e-9)
        an = run.get("analytic") or {}
        if an.get("kind") == "hertz" and run["kinematics"] == "small":  # Hertz: sigma_yy = -p0 under the centre
            p0 = (an.get("exact_circle") or {}).get("p0", an["p_ref"])
            yy_min = arrays["stress_MPa"]["range"][1][0]
            assert abs(yy_min / -p0 - 1.0) <= 0.03, f"{name}/{label}: YY min {yy_min:.6g} MPa vs -p0 = {-p0:.6g}"
    if name == "close_to_conformal":  # one time step per displacement step, the recorded ones among them
        run = metrics["runs"][0]
        assert len(seen[str(results / name / "vtk" / "base")]["body"]["times"]) == len(run["load_steps"])
        frames = json.loads((results / name / "vtk" / "base" / "frames.json").read_text())
        assert [s["d_mm"] for s in frames["steps"] if s["recorded"]] == [st["d"] for st in metrics["steps"]]


@pytest.mark.parametrize("name", case_names())
def test_view_script_runs_and_frames_the_contact(name, results):
    from matplotlib.image import imread

    folder = results / name
    shot = folder / "view.png"
    shot.unlink(missing_ok=True)
    proc = _pv([folder / "view.py"], folder)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    assert shot.is_file(), proc.stdout[-2000:]
    img = imread(shot)[..., :3]
    render = img[:, : int(0.6 * img.shape[1])]  # the render view (the chart is on the right)
    body = np.any(render < 0.97, axis=2).mean()
    # the body near the contact fills the view: at most the strip above the surface is background
    assert body >= 0.6, f"{name}: only {body:.0%} of the render view shows the body"
