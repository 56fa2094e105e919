"""``<case>/view.py``: a ParaView script that shows a case's VTK output the way a reader should first see it.

``pvpython view.py [RUN]`` (headless: ``xvfb-run -a pvpython view.py``) and ``paraview --script=view.py`` both
run it. It opens ``vtk/<run>/body.pvd`` and ``contact_surface.pvd`` (the first run unless RUN names another),
goes to the last step, warps the body by ``displacement_mm`` (true scale) and colours it by von Mises (log scale
where a singularity sets the range near the contact, see :func:`workbench.reports.renders.colour_range`), draws
the contact surface as a thick line coloured by ``p_MPa`` on the deformed body, frames the contact zone (a few
half-widths, from ``frames.json``), plots p and sigma_nn against s in a chart beside it, and saves a screenshot
``view.png`` (``view_<run>.png`` for another run) next to the script. Every step stays in the time series.

The script is written from ``vtk/<run>/frames.json`` only (reports read files); its settings sit in one
dictionary at the top so a user can edit them.
"""

from __future__ import annotations

import json
import pprint
from pathlib import Path

from cases.schema import label_folder
from workbench.atomic import write_text
from workbench.reports.renders import colour_range, view_window

__all__ = ["view_script", "write_view_script"]

_TEMPLATE = '''"""ParaView view of the case {case!r}: `pvpython view.py [RUN]` or `paraview --script=view.py`.

Written by the workbench from vtk/<run>/frames.json. Runs: {runs}. Saves view.png (view_<RUN>.png for another
run) beside this file. Edit SETTINGS to change the window or the colour range.
"""

import os
import sys

from paraview.simple import (AssignViewToLayout, ColorBy, CreateLayout, CreateView, GetAnimationScene,
                             GetColorTransferFunction, GetScalarBar, PVDReader, Render, SaveScreenshot, Show,
                             Text, WarpByVector)

SETTINGS = {settings}

HERE = os.path.dirname(os.path.abspath(__file__))
args = [a for a in sys.argv[1:] if a in SETTINGS]
RUN = args[0] if args else next(iter(SETTINGS))
S = SETTINGS[RUN]
folder = os.path.join(HERE, "vtk", RUN)

body = PVDReader(registrationName="body " + RUN, FileName=os.path.join(folder, "body.pvd"))
surface = PVDReader(registrationName="contact surface " + RUN, FileName=os.path.join(folder, "contact_surface.pvd"))
scene = GetAnimationScene()
scene.UpdateAnimationUsingDataTimeSteps()
scene.AnimationTime = S["time"]

layout = CreateLayout("contact " + RUN)
view = CreateView("RenderView")
AssignViewToLayout(view=view, layout=layout, hint=0)
view.ViewSize = [1000, 700]
view.OrientationAxesVisibility = 0
view.Background = [1.0, 1.0, 1.0]
try:  # ParaView >= 5.10: the background is set per view only when the palette is not used
    view.UseColorPaletteForBackground = 0
except AttributeError:
    pass

warped = WarpByVector(registrationName="deformed body", Input=body)
warped.Vectors = ["POINTS", "displacement_mm"]
warped.ScaleFactor = 1.0
shown = Show(warped, view)
shown.SetRepresentationType("Surface With Edges")
shown.EdgeColor = [0.35, 0.35, 0.35]
ColorBy(shown, ("POINTS", "von_Mises_MPa"))
vm = GetColorTransferFunction("von_Mises_MPa")
vm.ApplyPreset("Viridis (matplotlib)", True)
vm.AutomaticRescaleRangeMode = "Never"
vm.RescaleTransferFunction(*S["vm_range"])
if S["log"]:
    vm.MapControlPointsToLogSpace()
    vm.UseLogScale = 1
bar = GetScalarBar(vm, view)
bar.Title = "von Mises (MPa)" + (" log scale" if S["log"] else "")
bar.ComponentTitle = ""
bar.TitleColor = bar.LabelColor = [0.1, 0.1, 0.1]
shown.SetScalarBarVisibility(view, True)

line = WarpByVector(registrationName="deformed contact surface", Input=surface)
line.Vectors = ["POINTS", "displacement_mm"]
line.ScaleFactor = 1.0
ls = Show(line, view)
ColorBy(ls, ("POINTS", "p_MPa"))
pf = GetColorTransferFunction("p_MPa")
pf.ApplyPreset("Inferno (matplotlib)", True)
pf.AutomaticRescaleRangeMode = "Never"
pf.RescaleTransferFunction(0.0, max(S["p_max"], 1e-12))
ls.LineWidth = 5.0
ls.RenderLinesAsTubes = 1
pbar = GetScalarBar(pf, view)
pbar.Title = "contact pressure p (MPa)"
pbar.ComponentTitle = ""
pbar.TitleColor = pbar.LabelColor = [0.1, 0.1, 0.1]
pbar.WindowLocation = "Lower Center"
pbar.Orientation = "Horizontal"
ls.SetScalarBarVisibility(view, True)

title = Text(registrationName="title")
title.Text = S["title"]
ts = Show(title, view)
ts.Color = [0.1, 0.1, 0.1]
ts.FontSize = 14
ts.WindowLocation = "Upper Left Corner"

Render(view)  # the first render resets the camera: set it afterwards
cx, cy, hh = S["window"]
view.InteractionMode = "2D"
view.CameraParallelProjection = 1
view.CameraFocalPoint = [cx, cy, 0.0]
view.CameraPosition = [cx, cy, 10.0 * hh + 1.0]
view.CameraViewUp = [0.0, 1.0, 0.0]
view.CameraParallelScale = hh

layout.SplitHorizontal(0, 0.62)
chart = CreateView("XYChartView")
AssignViewToLayout(view=chart, layout=layout, hint=2)
cs = Show(surface, chart)
cs.UseIndexForXAxis = 0
cs.XArrayName = "s_mm"
cs.SeriesVisibility = S["series"]
chart.ChartTitle = "contact pressure along the surface"
chart.BottomAxisTitle = "s (mm, surface coordinate)"
chart.LeftAxisTitle = "MPa"
chart.BottomAxisUseCustomRange = 1
chart.BottomAxisRangeMinimum, chart.BottomAxisRangeMaximum = S["s_range"]
layout.SetSize(1600, 700)
view.CameraFocalPoint = [cx, cy, 0.0]
view.CameraPosition = [cx, cy, 10.0 * hh + 1.0]
view.CameraParallelScale = hh
Render(view)
Render(chart)
shot = os.path.join(HERE, "view.png" if RUN == next(iter(SETTINGS)) else "view_%s.png" % RUN)
SaveScreenshot(shot, layout, ImageResolution=[1600, 700])
print("wrote " + shot)
'''


def _settings(folder: Path, metrics: dict | None) -> dict:
    index = json.loads((folder / "frames.json").read_text())
    last = index["steps"][-1]
    (lo, hi), log = colour_range(last["von_Mises_near_contact_MPa"])
    box = last.get("contact_box_mm")
    if box is not None:
        a = max(0.5 * (box[1] - box[0]), 1e-6)
        s_range = [box[0] - 1.5 * a, box[1] + 1.5 * a]
    else:
        s_range = [-1.0, 1.0]
    cx, cy, hh = view_window(last, bounds=(-1.0, 1.0, -1.0, 1.0))
    case = (metrics or {}).get("case", folder.parent.parent.name)
    title = (f"{case} [{folder.name}]: step {last['step']} of {len(index['steps'])}, d = {last['d_mm']:.4g} mm, "
             f"P = {last['P_N_per_mm']:.4g} N/mm (deformed, true scale)")
    if index.get("bodies"):  # several bodies on one grid: name them (Threshold on "body" shows one)
        title += "\nbodies " + ", ".join(f"{b['index']} = {b['name']} (E {b['E_MPa']:.4g} MPa, nu {b['nu']:.3g})"
                                         for b in index["bodies"])
    return {"time": last["time"], "vm_range": [lo, hi], "log": log, "p_max": last["p_max_MPa"],
            "window": [cx, cy, hh], "s_range": s_range, "title": title, "series": _series(folder)}


def _series(folder: Path) -> list[str]:
    """The surface arrays the chart draws: p, and sigma_nn where the run has a stress-based pressure (two bodies
    have none: their samples carry NaN, which a chart would list without a line)."""
    import csv

    path = folder / "contact_surface.csv"
    series = ["p_MPa"]
    if path.is_file():
        with path.open() as f:
            rows = list(csv.reader(line for line in f if not line.startswith("#")))
        head = [h.strip() for h in rows[0]] if rows else []
        if "sigma_nn_MPa" in head:
            k = head.index("sigma_nn_MPa")
            if any(r[k].strip().lower() not in ("nan", "") for r in rows[1:] if len(r) > k):
                series.append("sigma_nn_MPa")
    return series


def view_script(case_dir: Path) -> str | None:
    """The text of ``view.py`` for the case folder (None when it has no ``vtk/*/frames.json``)."""
    case_dir = Path(case_dir)
    runs = sorted(p.parent for p in (case_dir / "vtk").glob("*/frames.json"))
    if not runs:
        return None
    mfile = case_dir / "metrics.json"
    metrics = json.loads(mfile.read_text()) if mfile.is_file() else None
    labels = [r.get("label") for r in (metrics or {}).get("runs", [])]
    order = {name: k for k, name in enumerate(label_folder(lb) for lb in labels if lb is not None)}
    runs.sort(key=lambda p: order.get(p.name, len(order)))
    settings = {r.name: _settings(r, metrics) for r in runs}
    return _TEMPLATE.format(case=(metrics or {}).get("case", case_dir.name), runs=", ".join(settings),
                            settings=pprint.pformat(settings, width=110, sort_dicts=False))


def write_view_script(case_dir: Path) -> Path | None:
    """Write ``view.py`` into the case folder; returns its path (None without VTK output)."""
    text = view_script(case_dir)
    if text is None:
        return None
    path = Path(case_dir) / "view.py"
    write_text(path, text)
    return path
