"""The case report: ``pressure.png``, ``report.md`` and ``report.html`` of ``<out>/<case>/``.

It reads only the files the run saved in the case folder, ``metrics.json`` and ``series.json`` (written by
:mod:`workbench.pipeline.case_files`), so any case report can be drawn again later from its folder
(:func:`write_case_reports`, called by ``workbench report``). Nothing is recomputed.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import NamedTuple

import numpy as np

from workbench.atomic import write_text
from workbench.reports.markdown import fmt, markdown_to_html

__all__ = ["B_MEASURES", "BMeasure", "b_headline", "case_report_markdown", "judged_b_measure", "judged_prediction",
           "load_series", "pressure_panels", "write_case_report", "write_case_reports"]


def _fmt(v) -> str:
    return fmt(v, 5)


def load_series(folder: Path) -> list[dict] | None:
    """The pressure series of ``folder/series.json`` (``null`` values as NaN), or None if the file is absent."""
    f = Path(folder) / "series.json"
    if not f.is_file():
        return None

    def arr(values):
        return None if values is None else np.array(values, dtype=float)  # None -> NaN

    return [sr | {"x": arr(sr["x"]), "p": arr(sr["p"]), "sigma_nn": arr(sr["sigma_nn"]),
                  "predictions": {k: arr(v) for k, v in sr["predictions"].items()}}
            for sr in json.loads(f.read_text())["series"]]


class BMeasure(NamedTuple):
    """One measure of the convective contact-size ratio b/b0 and where ``metrics.json["analytic"]`` keeps it.

    Attributes:
        check: The case's tolerance check (and error) of the measure.
        name: What it measures, for the headline.
        fem, converged, first_order, paper: The ``analytic`` keys of the FEM value and of the theories (converged
            theory, its first order, the paper's printed value; None where no such key exists).
    """

    check: str
    name: str
    fem: str
    converged: str
    first_order: str
    paper: str | None = None


B_MEASURES = (
    BMeasure("b_over_b0_moment", "moment ratio", "b_over_b0_moment_fem", "b_over_b0_moment_converged",
             "b_over_b0_moment_first_order"),
    BMeasure("b_over_b0", "edge ratio", "b_over_b0_fem", "b_over_b0_converged", "b_over_b0_first_order",
             "b_over_b0_paper"),
)
"""The b/b0 measures a convective case records: the moment ratio (2 sqrt(M2/M0) of the pressure, convective over
small; smooth, resolved on coarse grids) and the edge ratio (the zero crossings, unresolved between nodes)."""


def judged_b_measure(metrics: dict | None) -> BMeasure | None:
    """The b/b0 measure the case's verdict reads: of the measures whose FEM value ``metrics["analytic"]`` records,
    the one the case checks with the tightest tolerance (the halfplanes cases: the moment ratio at 0.2 %, the edges
    at 5 %); a measure recorded but not checked only when none is checked; None for a case with no b/b0."""
    an, tol = (metrics or {}).get("analytic") or {}, (metrics or {}).get("tolerances") or {}
    recorded = [b for b in B_MEASURES if an.get(b.fem) is not None]
    checked = [b for b in recorded if tol.get(b.check) is not None]
    if checked:
        return min(checked, key=lambda b: tol[b.check])
    return recorded[0] if recorded else None


def _run_of(metrics: dict | None, label: str) -> dict:
    return next((r for r in (metrics or {}).get("runs", []) if r.get("label") == label), {})


def _is_convective(metrics: dict | None, label: str) -> bool:
    return _run_of(metrics, label).get("kinematics", label) == "convective"


def _fem_key(metrics: dict, b: BMeasure, label: str | None) -> str:
    """The key of run ``label``'s own FEM value of measure ``b``: ``<fem>_<convection>`` where the case records one
    per convective run (several convective runs), else the case's ``b.fem``."""
    tag = _run_of(metrics, label).get("convection") if label is not None else None
    own = f"{b.fem}_{tag}"
    return own if tag and metrics["analytic"].get(own) is not None else b.fem


def b_headline(metrics: dict | None, label: str | None = None) -> list[str]:
    """The convective panel's headline (issue 37): first the measure the verdict reads (:func:`judged_b_measure`),
    FEM against the converged theory with its error and tolerance, then each other b/b0 measure the case records,
    named as such. Empty for a case with no b/b0. With ``label``, the FEM values are that run's own
    (:func:`_fem_key`); the error and tolerance only where its value is the one the check reads."""
    judged = judged_b_measure(metrics)
    if judged is None:
        return []
    an, tol = metrics["analytic"], metrics.get("tolerances") or {}
    errors, checks = metrics.get("errors") or {}, metrics.get("checks") or {}

    def line(b: BMeasure, lead: str) -> str:
        fem = an[_fem_key(metrics, b, label)]
        text = f"{lead}{b.name} b/b0: FEM {fem:.5f}"
        if an.get(b.converged) is not None:
            text += f" against converged theory {an[b.converged]:.5f}"
        if errors.get(b.check) is not None and b.check in tol and fem == an[b.fem]:
            verdict = {True: "PASS", False: "FAIL"}.get(checks.get(b.check), "")
            text += f" (error {errors[b.check]:.1e}, tolerance {tol[b.check]:.0e}{' ' + verdict if verdict else ''})"
        return text

    others = [b for b in B_MEASURES if b is not judged and an.get(b.fem) is not None]
    read = judged.check in tol and an[_fem_key(metrics, judged, label)] == an[judged.fem]
    return [line(judged, "judged by the " if read else ""),
            *[line(b, "also: ") for b in others]]


def _b_marks(metrics: dict | None, label: str) -> list[tuple[str, float]]:
    """Contact edges x = b0 (b/b0) of the judged b/b0 measure (:func:`judged_b_measure`: FEM, converged theory,
    first order, the paper's printed value) on the convective run's panel; b0 is the classical half-width of the
    small-kinematics run."""
    b = judged_b_measure(metrics)
    if b is None or not _is_convective(metrics, label):
        return []
    an = metrics["analytic"]
    b0 = ((an.get("runs") or {}).get("small") or {}).get("half_width")
    if not b0:
        return []
    names = ((_fem_key(metrics, b, label), "FEM"), (b.converged, "converged theory"), (b.first_order, "first order"),
             (b.paper, "paper (printed)"))
    return [(f"{b.name} b/b0 {text} = {an[key]:.5g}", b0 * an[key]) for key, text in names
            if key is not None and an.get(key) is not None]


def judged_prediction(label: str, names: list[str], metrics: dict | None) -> str | None:
    """The prediction (of ``names``, a series' predictions) the case judges run ``label`` against, for the
    residual panel: the converged convective theory for a convective run of a case that checks
    ``rms_convective``; the theory named by the checked RMS error (``rms_vs_exact_circle``: the exact circle);
    else the first (the scene's classical theory at the measured load). None when there is no prediction."""
    if not names:
        return None
    tol = (metrics or {}).get("tolerances") or {}
    if "rms_convective" in tol and _is_convective(metrics, label):
        found = [n for n in names if "converged" in n.lower()]
        if found:
            return found[0]
    rms = ((metrics or {}).get("checked_errors") or {}).get("rms", "")
    if rms.startswith("rms_vs_"):
        words = rms.removeprefix("rms_vs_").replace("_", " ")
        found = [n for n in names if words in n.lower()]
        if found:
            return found[0]
    return names[0]


def pressure_panels(series: list[dict], metrics: dict | None = None) -> list[dict]:
    """The panels of :func:`workbench.reports.plots.plot_pressure_panels`, one per series: the convective run's
    panel headlines the b/b0 measure the verdict reads (:func:`b_headline`) and marks its contact edges
    (:func:`_b_marks`); every residual is against the theory the case judges that run by
    (:func:`judged_prediction`)."""
    panels = []
    for sr in series:
        preds = {k: (sr["x"], v) for k, v in sr["predictions"].items() if v is not None}
        headline = b_headline(metrics, sr["label"]) if _is_convective(metrics, sr["label"]) else []
        panels.append({"label": sr["label"], "x": sr["x"], "p_fem": sr["p"], "sigma_nn": sr["sigma_nn"],
                       "xlabel": sr["xlabel"], "xlim": sr["xlim"], "marks": _b_marks(metrics, sr["label"]),
                       "headline": headline, "residual": judged_prediction(sr["label"], list(preds), metrics),
                       "predictions": preds})
    return panels


# What each model means physically: docs/models.md (linked from every case report, one line per run; the
# report sits in results/<case>/, two levels below the repository root).
_TRACTION = {"halfplane": "vertical gap and traction (half-plane theory)",
             "obstacle": "gap and traction along the obstacle's normal"}
_KINEMATICS = {"small": "gap at the undeformed position, small strain",
               "convective": "obstacle evaluated at the deformed position X + u, small strain",
               "finite": "finite-strain hyperelasticity, contact at the deformed position"}


def model_line(run: dict) -> str:
    """One Markdown line naming a run's model (traction, kinematics, material model) with a link to
    ``docs/models.md``; a run saved before material models existed is linear elastic."""
    trac, kin = run.get("traction", "?"), run.get("kinematics", "?")
    mat = run.get("material_model", "linear")
    return (f"- {run['label']}: traction = {trac} ({_TRACTION.get(trac, '?')}), kinematics = {kin} "
            f"({_KINEMATICS.get(kin, '?')}), material model = {mat} "
            "([what the models mean](../../docs/models.md))")


NO_PICTURES = ("Pictures not drawn (`workbench run --no-pictures`): `workbench report` draws them from the saved "
               "files of this folder.")
"""The line a case report carries in place of its pictures when the run skipped them."""


def case_report_markdown(metrics: dict, *, renders: list[tuple[str, str]] | None = None,
                         render_error: str | None = None, view_script: bool = False, pictures: bool = True) -> str:
    """The case report as Markdown from ``metrics.json``: description, plot, renders, runs, patches, errors,
    checks. ``renders``: (caption, file name) of the pyvista renders; ``render_error``: why they are missing;
    ``pictures=False``: no image links (none were drawn), the :data:`NO_PICTURES` line instead."""
    lines = [f"# {metrics['case']}", "", metrics.get("description", ""), "",
             f"Verdict: **{'PASS' if metrics['pass'] else 'FAIL'}** against the case tolerances"
             f"{' and bands (error budget)' if metrics.get('band_checks') else ''}. "
             f"Wall time {metrics['wall_time_s']:.1f} s on {metrics.get('mpi_processes', 1)} process(es) "
             "(includes meshing, and form compilation when the JIT cache is cold).", ""]
    if metrics.get("headline"):
        lines += [metrics["headline"], ""]
    warns = [(r["label"], w) for r in metrics["runs"] for w in r.get("warnings", [])]
    if warns:
        lines += ["## Warnings", "", *[f"- {label}: {w}" for label, w in warns], ""]
    lines += ["![pressure](pressure.png)" if pictures else NO_PICTURES, "",
              "Data: [pressure.csv](pressure.csv), [series.json](series.json) · "
              "metrics: [metrics.json](metrics.json) · ParaView: `vtk/<run>/body.pvd` and `contact_surface.pvd` "
              "(one time step per converged load step)"
              + (", or run `pvpython view.py` ([view.py](view.py))" if view_script else "")
              + " · log: [run.log](run.log)", ""]
    if renders or render_error:
        lines += ["## The deformed body (pyvista renders of `vtk/`)", ""]
        for caption, name in renders or []:
            lines += [f"![{caption}]({name})", "", f"*{caption}.*", ""]
        if render_error:
            lines += [f"Render failed: `{render_error}`", ""]
    lines += ["## Models", "", *[model_line(r) for r in metrics["runs"]], ""]
    lines += ["## Runs", "",
              "| run | method | kinematics | traction | degree | ndofs | Newton its (per solve) | load steps | "
              "P (N/mm) | P_pressure (N/mm) | patches | time (s) |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in metrics["runs"]:
        lines.append(
            f"| {r['label']} | {r['method']} | {r['kinematics']} | {r['traction']} | {r['degree']} | {r['ndofs']} | "
            f"{' '.join(str(i) for i in r['newton_iterations'])} | {len(r['load_steps'])} | {_fmt(r['P'])} | "
            f"{_fmt(r['P_pressure'])} | {len(r['patches'])} | {_fmt(r['wall_time_s'])} |"
        )
    lines += ["", "## Patches", "", "| run | center (mm) | half-width (mm) | p_max (MPa) | P (N/mm) |",
              "|---|---|---|---|---|"]
    for r in metrics["runs"]:
        for pt in r["patches"]:
            lines.append(f"| {r['label']} | {_fmt(pt['center'])} | {_fmt(pt['half_width'])} | "
                         f"{_fmt(pt['p_max'])} | {_fmt(pt['P'])} |")
    keys = sorted({k for r in metrics["runs"] for k in r.get("errors", {})})
    lines += ["", "## Errors against theory (relative, at the measured load)", "",
              "| run | " + " | ".join(keys) + " |", "|---|" + "---|" * len(keys)]
    for r in metrics["runs"]:
        lines.append(f"| {r['label']} | " + " | ".join(_fmt(r.get("errors", {}).get(k)) for k in keys) + " |")
    lines += ["", "## Checks", "", "| quantity | error checked | value | tolerance | verdict |",
              "|---|---|---|---|---|"]
    checked = metrics.get("checked_errors") or {}
    for k, t in metrics["tolerances"].items():
        key = checked.get(k, k)
        v = metrics["errors"].get(key)
        lines.append(f"| {k} | {key} | {_fmt(v)} | {_fmt(t)} | {'PASS' if metrics['checks'][k] else 'FAIL'} |")
    lines += _band_lines(metrics)
    for title, table in (metrics.get("case_tables") or {}).items():
        lines += ["", f"## {title}", "", *table]
    if metrics.get("error_budget") and pictures:
        lines += ["", "![error budget](budget.png)", "",
                  "*Every budget quantity against h_c: deviation from the extrapolated value, the band (GCI + "
                  "truncation + iterative + round-off) shaded, the theory (solid) and the alternative theory "
                  "(dashed).*"]
    return "\n".join(lines) + "\n"


def _verdict_text(ok: bool, unresolved: str | None) -> str:
    """PASS / FAIL, or PASS with what an unresolved exclusion would need (issue 22)."""
    if not ok:
        return "FAIL"
    return f"PASS ({unresolved})" if unresolved else "PASS"


def _band_lines(metrics: dict) -> list[str]:
    """The band checks (``metrics.json["band_checks"]``): per selected budget row, the extrapolated value, the
    band, the theory and the alternative theory with both verdicts."""
    checks = metrics.get("band_checks") or {}
    if not checks:
        return []
    budget = metrics.get("error_budget") or {}
    lines = ["", "## Band checks (tolerance = the error budget's band)", "",
             "| check | quantity | extrapolated | band (abs.) | theory | theory in band | alternative | alt. in band "
             "| verdict |", "|---|---|---|---|---|---|---|---|---|"]
    for key, c in checks.items():
        if not c["rows"]:
            lines.append(f"| {key} | - | - | - | - | - | - | - | FAIL ({c['reason']}) |")
        for name, ok in c["rows"].items():
            r = budget.get(name, {})
            band = (None if r.get("gci") is None else
                    r.get("uncertainty", r["gci"] + (r.get("truncation") or 0.0)) * abs(r["fine"]))
            alt = "-" if r.get("alt_value") is None else f"{r.get('alt_theory')} {_fmt(r['alt_value'])}"
            yn = {True: "yes", False: "no", None: "n/a"}
            lines.append(f"| {key} | {name} | {_fmt(r.get('extrapolated'))} | {_fmt(band)} | {_fmt(r.get('theory'))} | "
                         f"{yn[r.get('theory_in_band')]} | {alt} | {yn[r.get('alt_in_band')]} | "
                         f"{_verdict_text(ok, (c.get('unresolved') or {}).get(name))} |")
    return lines


def write_case_report(folder: Path, *, pictures: bool = True) -> list[Path]:
    """Write ``pressure.png``, ``report.md`` and ``report.html`` of the case in ``folder``, and, when it has
    ``vtk/*/frames.json``, ``view.py`` (ParaView) and the pyvista renders ``render_<run>.png`` /
    ``steps_<run>.png``.

    Reads ``folder/metrics.json`` and ``folder/series.json``. Without ``series.json`` (a folder written before
    it existed) the plot is not drawn and an existing ``pressure.png`` is left as it is.

    ``pictures=False`` (``workbench run --no-pictures``, the fast path): no PNG at all (``pressure.png``,
    ``budget.png``, the renders), and neither matplotlib nor pyvista is imported; ``report.md`` says so in their
    place. ``view.py`` and the text are written as usual.

    Returns:
        The files written.
    """
    folder = Path(folder)
    metrics = json.loads((folder / "metrics.json").read_text())
    name = metrics["case"]
    written = []
    series = load_series(folder) if pictures else None
    if series:
        from workbench.reports.plots import plot_pressure_panels  # matplotlib only when a plot is drawn

        plot_pressure_panels(pressure_panels(series, metrics), folder / "pressure.png", title=name)
        written.append(folder / "pressure.png")
    if metrics.get("error_budget") and pictures:
        from workbench.reports.budget_plot import plot_budget

        written.append(plot_budget(metrics["error_budget"], folder / "budget.png", title=name))
    renders, render_error, view = [], None, None
    if list((folder / "vtk").glob("*/frames.json")):
        from workbench.reports.paraview_view import write_view_script

        view = write_view_script(folder)
    if view is not None and pictures:
        from workbench.reports.renders import render_case  # pyvista only when a picture is rendered

        try:
            renders = [(caption, png.name) for caption, png in render_case(folder)]
            written += [folder / name for _, name in renders]
        except Exception as exc:  # a missing OpenGL stack must not lose the report; the report says why
            render_error = f"{type(exc).__name__}: {exc}".splitlines()[0]
            print(f"warning: {name}: pyvista render failed: {render_error}", file=sys.stderr)
    md = case_report_markdown(metrics, renders=renders, render_error=render_error, view_script=view is not None,
                              pictures=pictures)
    write_text(folder / "report.md", md)
    write_text(folder / "report.html", markdown_to_html(md, title=name))
    return [*written, folder / "report.md", folder / "report.html"]


def write_case_reports(results: Path, names: list[str]) -> list[Path]:
    """Draw again the report of every case of ``names`` that has ``results/<name>/metrics.json``.

    Returns:
        The case folders whose reports were written.
    """
    done = []
    for name in names:
        folder = Path(results) / name
        if (folder / "metrics.json").is_file():
            write_case_report(folder)
            done.append(folder)
    return done
