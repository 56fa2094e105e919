"""The report of ``workbench external compare`` (reads its ``compare.json`` content only): the verdict first (per
case: how close each code comes to the theory on its finest level and extrapolated, and how long it takes to reach
1 % and 0.1 %), the table of every code, geometry and level, and one figure per case of the main quantity's error
against the process wall time. Units: s; errors relative (see :mod:`workbench.external.compare`)."""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

__all__ = ["verdict_lines", "report_markdown", "plot_case", "write_compare_report"]

NAMES = {"workbench": "workbench", "ccx": "CalculiX", "kratos": "Kratos"}


def _name(code: str) -> str:
    return NAMES.get(code, code)


def _pct(x: float | None, digits: int = 2) -> str:
    if x is None or not math.isfinite(x):
        return "-"
    return f"{100.0 * x:.{digits}g} %"


def _t(reach: dict) -> str:
    if reach["seconds"] is None:
        return "not reached"
    return f"{reach['seconds']:.3g} s" + (" (interp.)" if reach["how"] == "interpolated" else "")


def _rel_dev(r: dict) -> float | None:
    if r.get("extrapolated") is None or r.get("theory") is None:
        return None
    ref = r["theory"]
    return (r["extrapolated"] - ref) / abs(ref) if ref else r["extrapolated"]


def _where(r: dict) -> str:
    return r["case"] if r["geometry"] == r["case"] else f"{r['case']} [{r['geometry']}]"


def verdict_lines(rows: list[dict]) -> list[str]:
    """One line per case and geometry: each code's error at its finest level, its extrapolated difference to the
    theory and its time to 1 % and 0.1 %; the codes that could not be scored, and why."""
    out = []
    by: dict[tuple, list[dict]] = {}
    for r in rows:
        by.setdefault((r["case"], r["geometry"]), []).append(r)
    for _key, rs in by.items():
        scored = [r for r in rs if r["status"] == "scored"]
        parts = []
        for r in scored:
            reach = {x["target"]: x for x in r["reach"]}
            parts.append(f"{_name(r['code'])} {_pct(r['errors'][-1])} at its finest level (extrapolated "
                         f"{_pct(_rel_dev(r), 3) if r['theory'] is not None else 'n/a'} from the theory), "
                         f"1 %: {_t(reach[0.01]) if 0.01 in reach else '-'}, "
                         f"0.1 %: {_t(reach[0.001]) if 0.001 in reach else '-'}")
        first = rs[0]
        q = scored[0]["label"] if scored else ""
        line = f"{_where(first)}" + (f" ({q}; against {scored[0]['reference']})" if scored else "") + ": "
        line += "; ".join(parts) if parts else "no code scored"
        others = [f"{_name(r['code'])} {r['status']}" for r in rs if r["status"] != "scored"]
        if others:
            line += ". " + "; ".join(o[:200] for o in others)
        if len(scored) > 1:
            best = min(scored, key=lambda r: r["errors"][-1])
            fast = [r for r in scored if any(x["target"] == 0.01 and x["seconds"] is not None for x in r["reach"])]
            line += f". Most accurate on the finest level: {_name(best['code'])}"
            if fast:
                f = min(fast, key=lambda r: next(x["seconds"] for x in r["reach"] if x["target"] == 0.01))
                line += f"; fastest to 1 %: {_name(f['code'])}"
        out.append(line + ".")
    return out


def report_markdown(data: dict, figures: dict[str, str]) -> str:
    rows = data["rows"]
    lines = ["# Three codes side by side", "", "## Verdict", ""]
    lines += [f"- {ln}" for ln in verdict_lines(rows)]
    lines += ["", "## Every code, geometry and level", "",
              "The error of a level is the main quantity's distance to the reference, relative; the wall time is "
              "the process's (one core). `workbench external compare --help` says what both include.", "",
              "| case | code | quantity | values (coarse to fine) | extrapolated +- band | vs theory | "
              "models holding it | wall per level (s) | to 1 % | to 0.1 % |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if r["status"] != "scored":
            lines.append(f"| {_where(r)} | {_name(r['code'])} | {r['status'][:300]} | | | | | | | |")
            continue
        reach = {x["target"]: x for x in r["reach"]}
        vals = ", ".join(f"{v:.6g}" for v in r["values"])
        band = f"{r['extrapolated']:.7g} +- {r['band']:.2g}" if r["band"] is not None else f"{r['extrapolated']:.7g}"
        models = ", ".join(r["models"]) if r["models"] else r["models_why"]
        walls = ", ".join(f"{t:.3g}" for t in r["wall_s"])
        lines.append(f"| {_where(r)} | {_name(r['code'])} | {r['label']} (against {r['reference']}) | {vals} | "
                     f"{band} ({r['status_study']}) | {_pct(_rel_dev(r), 3)} | {models} | {walls} | "
                     f"{_t(reach[0.01]) if 0.01 in reach else '-'} | {_t(reach[0.001]) if 0.001 in reach else '-'} |")
    if figures:
        lines += ["", "## Error against run time", ""]
        lines += [f"![{case}]({name})" for case, name in figures.items()]
    lines += ["", f"Levels per code: {data['levels']}. Codes: "
              + "; ".join(f"{k}: {v}" for k, v in data["codes"].items()) + "."]
    return "\n".join(lines) + "\n"


def plot_case(rows: list[dict], path: Path) -> None:
    """The main quantity's error against the process wall time (log-log), one line per code and geometry, the 1 %
    and 0.1 % lines."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    markers = {"workbench": "o", "ccx": "s", "kratos": "^"}
    for r in rows:
        if r["status"] != "scored" or not r["wall_s"]:
            continue
        e = [max(x, 1e-16) for x in r["errors"]]  # log axis: an exact zero only; round-off (1e-11) shown as is
        label = _name(r["code"]) + ("" if r["geometry"] == r["case"] else f" [{r['geometry']}]")
        ax.loglog(r["wall_s"], e, marker=markers.get(r["code"], "x"), label=label)
    for target in (1e-2, 1e-3):
        ax.axhline(target, color="0.6", lw=0.8, ls="--")
    scored = [r for r in rows if r["status"] == "scored"]
    from matplotlib.ticker import NullFormatter

    ax.xaxis.set_minor_formatter(NullFormatter())  # decades only: minor labels overlap on a short time span
    ax.set_xlabel("process wall time per level (s)")
    ax.set_ylabel("error of the main quantity (relative)")
    # wrapped, not cut: a quantity's label with its theory runs past 80 characters ("... at each level's load")
    ax.set_title(textwrap.fill(f"{rows[0]['case']}: {scored[0]['label'] if scored else ''}", 90), fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    if scored:
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def write_compare_report(data: dict, folder: Path) -> None:
    """``error_time_<case>.png`` per case, ``report.md`` and ``report.html`` into ``folder``."""
    from workbench.atomic import write_text
    from workbench.reports.markdown import markdown_to_html

    figures = {}
    by_case: dict[str, list[dict]] = {}
    for r in data["rows"]:
        by_case.setdefault(r["case"], []).append(r)
    for case, rows in by_case.items():
        if any(r["status"] == "scored" for r in rows):
            name = f"error_time_{case}.png"
            plot_case(rows, folder / name)
            figures[case] = name
    md = report_markdown(data, figures)
    write_text(folder / "report.md", md)
    write_text(folder / "report.html", markdown_to_html(md, title="external compare"))
