"""Off-screen pyvista renders of a case's VTK output, for the case report (reads ``vtk/<run>/`` files only).

* :func:`render_contact`: the body near the contact, deformed (true scale), coloured by von Mises, with the
  contact surface drawn as a thick line coloured by the contact pressure; one image per run, last step.
* :func:`render_steps`: a strip of the recorded steps (concave scenes): the same picture at every
  ``recorded`` step, so the patches can be seen forming and merging (one window and one von Mises range for
  all tiles; the surface colour of each tile spans 0 to that step's own peak pressure, printed in the tile).

The camera frames the contact box of ``frames.json`` (a few half-widths). Von Mises uses a log colour scale when
a singularity sets its range near the contact (its 99th percentile above :data:`LOG_RATIO` times its median,
e.g. the wedge apex), else a linear one from 0 to the 99th percentile. Rendering is off-screen
(``pyvista.OFF_SCREEN``): VTK uses EGL without a display (measured here: ``vtkEGLRenderWindow``, Mesa's
libEGL), or the X server of ``xvfb-run`` when there is one.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

__all__ = ["LOG_RATIO", "colour_range", "render_case", "render_contact", "render_steps", "view_window"]

LOG_RATIO = 4.0
"""Von Mises gets a log colour scale when its 99th percentile near the contact exceeds this times its median
(measured: wedge 5.2, Hertz 2.2, close-to-conformal 1.8)."""


def _pyvista():
    import pyvista as pv
    from vtkmodules.vtkCommonCore import vtkLogger

    pv.OFF_SCREEN = True
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_ERROR)  # no "bad X server connection" notice on stderr
    return pv


def colour_range(stats: dict) -> tuple[tuple[float, float], bool]:
    """Von Mises colour range (MPa) and whether it is logarithmic, from ``von_Mises_near_contact_MPa``."""
    if stats["p99"] > LOG_RATIO * stats["p50"] and stats["max"] > 0:
        lo = max(stats["p01"], 1e-3 * stats["max"])
        return (lo, stats["max"]), True
    return (0.0, max(stats["p99"], 1e-12)), False


# width / height of the render views (ParaView's 0.62 x 1600 by 700 window; pyvista's renders are wider)
VIEW_ASPECT = 1.4


def view_window(step: dict, *, bounds) -> tuple[float, float, float]:
    """(centre x, centre y, half-height) in mm of a window a few contact half-widths wide around the contact
    box of ``step`` (the whole body when there is no contact)."""
    box = step.get("contact_box_deformed_mm") or step.get("contact_box_mm")
    if box is None:
        return (0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), 0.5 * (bounds[3] - bounds[2]))
    a = max(0.5 * (box[1] - box[0]), 0.5 * (box[3] - box[2]), 1e-6)
    half_height = 1.6 * a
    cx = 0.5 * (box[0] + box[1])
    body = step.get("bounds_mm")  # (undeformed) body bounds: a contact as wide as the body is framed on the body
    if body is not None:
        half_width = 0.5 * (body[1] - body[0])
        half_height = min(half_height, half_width / VIEW_ASPECT)
        cx = min(max(cx, body[0] + VIEW_ASPECT * half_height), body[1] - VIEW_ASPECT * half_height)
    return cx, box[3] - 0.75 * half_height, half_height


def _load(folder: Path):
    index = json.loads((folder / "frames.json").read_text())
    return index, index["steps"]


def _plot_step(pv, plotter, folder: Path, step: dict, *, clim, log: bool, title: str, bars: bool = True,
               p_bar: bool = True) -> None:
    body = pv.read(folder / step["body"])
    surf = pv.read(folder / step["surface"])
    warped = body.warp_by_vector("displacement_mm", factor=1.0)
    line = surf.warp_by_vector("displacement_mm", factor=1.0)
    cx, cy, hh = view_window(step, bounds=body.bounds)
    bar = dict(title="von Mises (MPa)", vertical=True, position_x=0.86, position_y=0.1, height=0.8, width=0.06,
               title_font_size=12, label_font_size=10, fmt="%.3g") if bars else None
    plotter.add_mesh(warped, scalars="von_Mises_MPa", cmap="viridis", clim=clim, log_scale=log,
                     show_edges=True, edge_color=(0.35, 0.35, 0.35), line_width=0.3, show_scalar_bar=bars,
                     scalar_bar_args=bar)
    pbar = dict(title="p (MPa)", vertical=False, position_x=0.15, position_y=0.03, height=0.06, width=0.6,
                title_font_size=12, label_font_size=10, fmt="%.3g") if p_bar else None
    if line.n_points > 1:
        p_max = float(np.max(line["p_MPa"]))
        plotter.add_mesh(line, scalars="p_MPa", cmap="inferno", clim=(0.0, max(p_max, 1e-12)), line_width=6,
                         render_lines_as_tubes=True, show_scalar_bar=p_bar, scalar_bar_args=pbar)
    plotter.add_text(title, font_size=9, position="upper_left")
    plotter.view_xy()
    plotter.enable_parallel_projection()
    cam = plotter.camera
    cam.focal_point = (cx, cy, 0.0)
    cam.position = (cx, cy, 10.0 * hh + 1.0)
    cam.up = (0.0, 1.0, 0.0)
    cam.parallel_scale = hh
    plotter.set_background("white")


def render_contact(folder: Path, out: Path, *, label: str, size=(900, 560)) -> Path:
    """The last step of the run in ``folder`` (a ``vtk/<run>/`` directory) as a PNG."""
    pv = _pyvista()
    _, steps = _load(folder)
    last = steps[-1]
    clim, log = colour_range(last["von_Mises_near_contact_MPa"])
    plotter = pv.Plotter(off_screen=True, window_size=list(size))
    title = (f"{label}: step {last['step']}, d = {last['d_mm']:.4g} mm, P = {last['P_N_per_mm']:.4g} N/mm\n"
             f"deformed (true scale), von Mises{' (log scale)' if log else ''}; surface: contact pressure")
    _plot_step(pv, plotter, folder, last, clim=clim, log=log, title=title)
    plotter.screenshot(str(out))
    plotter.close()
    return out


def render_steps(folder: Path, out: Path, *, label: str, tile=(330, 300), max_steps: int = 6) -> Path | None:
    """A strip of the ``recorded`` steps of the run in ``folder`` (one tile each, the same colour range and
    the same window: that of the last step), or None when fewer than two steps are recorded."""
    pv = _pyvista()
    _, steps = _load(folder)
    rec = [s for s in steps if s.get("recorded")][-max_steps:]
    if len(rec) < 2:
        return None
    last = steps[-1]
    clim, log = colour_range(last["von_Mises_near_contact_MPa"])
    plotter = pv.Plotter(off_screen=True, shape=(1, len(rec)), window_size=[tile[0] * len(rec), tile[1]],
                         border=False)
    for k, st in enumerate(rec):
        plotter.subplot(0, k)
        window = {"contact_box_mm": last["contact_box_mm"], "contact_box_deformed_mm": last["contact_box_mm"]}
        _plot_step(pv, plotter, folder, st | window, clim=clim, log=log, bars=(k == len(rec) - 1), p_bar=False,
                   title=f"d = {st['d_mm']:.3g} mm, P = {st['P_N_per_mm']:.4g} N/mm\n"
                         f"p_max = {st['p_max_MPa']:.4g} MPa (surface colour 0..p_max)")
    plotter.screenshot(str(out))
    plotter.close()
    return out


def render_case(case_dir: Path) -> list[tuple[str, Path]]:
    """Every render of a case folder: ``render_<run>.png`` per run and ``steps_<run>.png`` where steps were
    recorded. Returns ``(caption, path)`` pairs, in the order of the runs."""
    case_dir = Path(case_dir)
    out = []
    for folder in sorted(p.parent for p in (case_dir / "vtk").glob("*/frames.json")):
        run = folder.name
        png = render_contact(folder, case_dir / f"render_{run}.png", label=run)
        out.append((f"{run}: von Mises on the deformed body near the contact, contact pressure along the surface",
                    png))
        strip = render_steps(folder, case_dir / f"steps_{run}.png", label=run)
        if strip is not None:
            out.append((f"{run}: the recorded displacement steps (same colour range and window)", strip))
    return out
