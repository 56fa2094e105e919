"""Plots of the performance benchmark (reads ``<results>/bench/bench.json``; files only, Agg backend).

Run: ``python -m workbench.studies.bench_plot [JSON]`` -> ``time_to_accuracy.png`` (RMS/p0 against warm time,
baseline and the four configurations of ours) and ``cost_growth.png`` (solver, fast-variant and linear-solve
time and peak memory against ndofs, log-log, with the fitted power laws) next to the JSON. ``workbench bench``
calls :func:`plot_bench` itself.
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.ticker import NullFormatter  # noqa: E402

from workbench.paths import default_paths  # noqa: E402
from workbench.reports.plots import load_study_json, save_figure  # noqa: E402
from workbench.reports.study_pages import publish_study  # noqa: E402

__all__ = ["main", "plot_bench"]

STYLE = {
    "baseline": ("k", "x", ":"),
    "penalty P1": ("tab:orange", "s", "--"),
    "penalty P2": ("tab:red", "s", "-"),
    "nitsche P1": ("tab:cyan", "o", "--"),
    "nitsche P2": ("tab:blue", "o", "-"),
}


def _accuracy(ax, acc: dict) -> None:
    series = {"baseline": acc["baseline"], **acc["ours"]}
    for name, rows in series.items():
        color, marker, ls = STYLE.get(name, ("gray", ".", "-"))
        pts = [(r["total_s"], r["rms"]) for r in rows if r["rms"] > 0]
        if pts:
            xs, ys = zip(*pts, strict=True)
            ax.loglog(xs, ys, ls=ls, marker=marker, color=color, ms=4, lw=1.2, label=name)
    ax.axhline(acc["target_rms"], color="gray", lw=0.8, ls="--", label=f"target {acc['target_rms']:.1%}")
    ax.set_xlabel("warm wall time to the result (s): mesh + solve + comparison")
    ax.set_ylabel("RMS(p - p_Hertz) / p0")
    ax.grid(which="both", alpha=0.3)
    ax.legend(fontsize=7)


def _growth(ax, scale: dict) -> None:
    keys = (("solve_s", "contact solve (row options)", "-"), ("linear_s", "one linear solve", ":"))
    colors = {"graded": "tab:blue", "uniform": "tab:red"}
    for family, fam in scale.items():
        n = np.array([r["ndofs"] for r in fam["rows"]], dtype=float)
        for key, label, ls in keys:
            t = np.array([r[key] for r in fam["rows"]])
            k = fam["fits"][key]["all"]["exponent"]
            ax.loglog(
                n, t, ls=ls, marker="o", ms=3, color=colors.get(family, "k"), label=f"{family}: {label} (k = {k:.2f})"
            )
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("ndofs")
    ax.set_ylabel("wall time (s)")
    ax.grid(which="both", alpha=0.3)
    ax.legend(fontsize=6)


def _memory(ax, scale: dict) -> None:
    colors = {"graded": "tab:blue", "uniform": "tab:red"}
    for family, fam in scale.items():
        n = [r["ndofs"] for r in fam["rows"]]
        for key, ls, what in (("peak_rss_first_solve_mb", "-", "after the first solve"), ("peak_rss_mb", ":", "end")):
            m = [r.get(key, float("nan")) for r in fam["rows"]]
            ax.loglog(n, m, marker="o", ms=3, ls=ls, color=colors.get(family, "k"), label=f"{family}, {what}")
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.yaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("ndofs")
    ax.set_ylabel("peak RSS (VmHWM) of the process (MB)")
    ax.grid(which="both", alpha=0.3)
    ax.legend(fontsize=7)


def plot_bench(data: dict, out_dir: Path) -> list[Path]:
    """Write ``time_to_accuracy.png`` and ``cost_growth.png`` (when the sections exist); returns the paths.

    Args:
        data: The JSON written by :mod:`workbench.studies.bench`.
        out_dir: Output folder.
    """
    paths = []
    if data.get("accuracy"):
        fig, ax = plt.subplots(figsize=(6.4, 4.4))
        _accuracy(ax, data["accuracy"])
        ax.set_title("hertz_cylinder: error against warm time", fontsize=9)
        paths.append(_save(fig, Path(out_dir) / "time_to_accuracy.png"))
    if data.get("scale"):
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(11.0, 4.4))
        _growth(a1, data["scale"])
        _memory(a2, data["scale"])
        a1.set_title("cost growth (P2, Nitsche)", fontsize=9)
        paths.append(_save(fig, Path(out_dir) / "cost_growth.png"))
    publish_study(Path(out_dir), paths)  # report.md shows the plots, report.html, summary rebuilt
    return paths


def _save(fig, path: Path) -> Path:
    return save_figure(fig, path, dpi=150)


def main(argv: list[str] | None = None) -> int:
    """``python -m workbench.studies.bench_plot [JSON]``."""
    loaded = load_study_json(sys.argv[1:] if argv is None else argv, default_paths().study("bench") / "bench.json",
                             producer="workbench.studies.bench")
    if loaded is None:
        return 2
    path, data = loaded
    for p in plot_bench(data, path.parent):
        print(p)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
