"""Per-case outputs: ``pressure.csv``, ``pressure.png`` and ``report.md`` / ``report.html``.

Everything here formats what the runs computed; nothing is recomputed.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np

from workbench.atomic import write_text
from workbench.reports.markdown import fmt, markdown_to_html
from workbench.reports.plots import plot_pressure_panels

__all__ = ["write_case_outputs", "case_report_markdown"]


def _slug(name: str) -> str:
    return "_".join("".join(c if c.isalnum() else " " for c in name.lower()).split())


def _csv_text(outcomes) -> str:
    series = [sr for o in outcomes for sr in o.series]
    names = list(dict.fromkeys(k for sr in series for k in sr.predictions))
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(["run", "coordinate_mm", "p_fem_MPa", "sigma_nn_MPa", *[f"p_{_slug(n)}_MPa" for n in names]])
    for sr in series:
        for i in range(len(sr.x)):
            row = [sr.label, f"{sr.x[i]:.10g}", f"{sr.p[i]:.10g}", f"{sr.sigma_nn[i]:.10g}"]
            for n in names:
                v = sr.predictions.get(n)
                row.append("" if v is None or not np.isfinite(v[i]) else f"{v[i]:.10g}")
            w.writerow(row)
    return buf.getvalue()


def _fmt(v) -> str:
    return fmt(v, 5)


def case_report_markdown(case, outcomes, metrics) -> str:
    """The case report as Markdown: description, plot, metrics table per run, checks."""
    lines = [f"# {case.name}", "", case.description, "",
             f"Verdict: **{'PASS' if metrics['pass'] else 'FAIL'}** against the case tolerances. "
             f"Wall time {metrics['wall_time_s']:.1f} s on {metrics.get('mpi_processes', 1)} process(es) "
             "(includes meshing, and form compilation when the JIT cache is cold).", ""]
    if metrics.get("headline"):
        lines += [metrics["headline"], ""]
    warns = [(r["label"], w) for r in metrics["runs"] for w in r.get("warnings", [])]
    if warns:
        lines += ["## Warnings", "", *[f"- {label}: {w}" for label, w in warns], ""]
    lines += ["![pressure](pressure.png)", "",
              "Data: [pressure.csv](pressure.csv) · metrics: [metrics.json](metrics.json) · ParaView: `vtk/` "
              "(open the `.pvd` files) · log: [run.log](run.log)", "", "## Runs", "",
              "| run | method | kinematics | traction | P | ndofs | Newton its (per solve) | load steps | P (N/mm) | "
              "P_pressure (N/mm) | patches | time (s) |",
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
    lines += ["", "## Errors against theory (relative, at the measured load)", "",
              "| run | " + " | ".join(sorted({k for r in metrics["runs"] for k in r.get("errors", {})})) + " |"]
    keys = sorted({k for r in metrics["runs"] for k in r.get("errors", {})})
    lines.append("|---|" + "---|" * len(keys))
    for r in metrics["runs"]:
        lines.append(f"| {r['label']} | " + " | ".join(_fmt(r.get("errors", {}).get(k)) for k in keys) + " |")
    lines += ["", "## Checks", "", "| quantity | value | tolerance | verdict |", "|---|---|---|---|"]
    for k, t in metrics["tolerances"].items():
        v = metrics["errors"].get(k)
        lines.append(f"| {k} | {_fmt(v)} | {_fmt(t)} | {'PASS' if metrics['checks'][k] else 'FAIL'} |")
    if metrics.get("case_tables"):
        for title, table in metrics["case_tables"].items():
            lines += ["", f"## {title}", "", *table]
    return "\n".join(lines) + "\n"


def write_case_outputs(case, outcomes, metrics, stage: Path) -> None:
    """Write the CSV, the plot and the report of a case into its staging folder."""
    write_text(stage / "pressure.csv", _csv_text(outcomes))
    panels = [{"label": sr.label, "x": sr.x, "p_fem": sr.p, "sigma_nn": sr.sigma_nn, "xlabel": sr.xlabel,
               "predictions": {k: (sr.x, v) for k, v in sr.predictions.items()}, "xlim": sr.xlim}
              for o in outcomes for sr in o.series]
    plot_pressure_panels(panels, stage / "pressure.png", title=case.name)
    md = case_report_markdown(case, outcomes, metrics)
    write_text(stage / "report.md", md)
    write_text(stage / "report.html", markdown_to_html(md, title=case.name))
