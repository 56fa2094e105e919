"""Plots of the convergence study (reads ``<results>/convergence/convergence.json``; files only, Agg backend).

Run: ``python -m workbench.studies.convergence_plot [JSON]`` -> ``error_vs_time.png`` and ``error_vs_ndofs.png``
next to the JSON. One row of panels per case x series, one panel per error metric, one line per method x degree,
log-log axes; each line joins the h_c levels in refinement order.
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import NullFormatter  # noqa: E402

from workbench.paths import default_paths  # noqa: E402
from workbench.reports.plots import load_study_json, save_figure  # noqa: E402
from workbench.reports.study_pages import publish_study  # noqa: E402

__all__ = ["main", "plot_study"]

STYLE = {("penalty", 1): ("tab:orange", "s", "--"), ("penalty", 2): ("tab:red", "s", "-"),
         ("nitsche", 1): ("tab:cyan", "o", "--"), ("nitsche", 2): ("tab:blue", "o", "-")}
LABELS = {"p_max": "peak pressure error", "half_width": "half-width error", "rms": "RMS(p - p_th) / p_ref",
          "l2": "Gauss L2(p - p_th) / p_ref", "l2_inner": "Gauss L2 on |x| <= 0.8 a / p_ref",
          "b_over_b0": "b/b0 error (vs converged theory)",
          "rms_convective": "RMS(p - p_conv) / p_ref, convective run"}


def _panel(ax, rows: list[dict], *, metric: str, xkey: str) -> None:
    for (method, degree), (color, marker, ls) in STYLE.items():
        sel = [r for r in rows if r["method"] == method and r["degree"] == degree]
        sel = sorted(sel, key=lambda r: -r["h_contact"])  # refinement order: the line follows h_c
        pts = [(r[xkey], r[metric]) for r in sel if r[metric] is not None and r[metric] > 0
               and r[xkey] is not None and r[xkey] > 0]
        if pts:
            xs, ys = zip(*pts, strict=True)
            ax.loglog(xs, ys, ls=ls, marker=marker, color=color, ms=4, lw=1.2, label=f"{method} P{degree}")
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.grid(which="both", alpha=0.3)
    ax.set_ylabel(LABELS.get(metric, metric), fontsize=8)


def _guide(ax, rows: list[dict], *, metric: str, rate: float) -> None:
    """Dotted reference slope ndofs^(-rate/2) (= h^rate for the ideal series, whose size field scales with
    h_c, so ndofs ~ h^-2), anchored at the finest Nitsche P2 point."""
    sel = [r for r in rows if (r["method"], r["degree"]) == ("nitsche", 2) and r[metric] is not None
           and r[metric] > 0 and not r["failed"]]
    if len(sel) < 2:
        return
    ref = min(sel, key=lambda r: r["h_contact"])
    n = [min(r["ndofs"] for r in sel), ref["ndofs"]]
    ax.loglog(n, [ref[metric] * (x / ref["ndofs"]) ** (-rate / 2.0) for x in n], ls=":", color="grey",
              lw=1.5, label=f"expected h^{rate:g}")


def plot_study(data: dict, *, out_dir: Path) -> list[Path]:
    """Write ``error_vs_time.png`` (warm solver time) and ``error_vs_ndofs.png``; returns the paths.

    One row of panels per case x series, one panel per error metric, one line per method x degree.

    Args:
        data: The JSON written by :mod:`workbench.studies.convergence` (``rows``, ``metrics``, ``time_of``).
        out_dir: Output folder.
    """
    groups: dict[tuple, list[dict]] = {}
    for r in data["rows"]:
        groups.setdefault((r["case"], r["series"]), []).append(r)
    ncol = max(len(data["metrics"][case]) for case, _ in groups)
    paths = []
    for stem, xlabel in (("error_vs_time", "warm solver wall time (s)"), ("error_vs_ndofs", "ndofs")):
        fig, axes = plt.subplots(len(groups), ncol, figsize=(3.9 * ncol, 3.3 * len(groups)), squeeze=False)
        for i, ((case, series), rows) in enumerate(groups.items()):
            metrics = data["metrics"][case]
            for j, metric in enumerate(metrics):
                ax = axes[i, j]
                xkey = data.get("time_of", {}).get(metric, "time_s") if stem == "error_vs_time" else "ndofs"
                _panel(ax, rows, metric=metric, xkey=xkey)
                rate = data.get("expected_rates", {}).get(f"{case}/{series}", {}).get(metric)
                if stem == "error_vs_ndofs" and series == "ideal" and rate is not None:
                    _guide(ax, rows, metric=metric, rate=rate)
                    ax.legend(fontsize=6)
                    ax.xaxis.set_minor_formatter(NullFormatter())
                ax.set_title(f"{case} [{series}]: {metric}", fontsize=9)
                pair = " (small + convective pair)" if xkey == "time_pair_s" else ""
                ax.set_xlabel(xlabel + pair, fontsize=8)
                if j == 0:
                    ax.legend(fontsize=7)
            for ax in axes[i, len(metrics):]:
                ax.set_visible(False)
        fig.suptitle(f"Error against {'warm run time' if stem == 'error_vs_time' else 'ndofs'} "
                     "(one line per method x degree over the h_c levels)", fontsize=10)
        paths.append(save_figure(fig, Path(out_dir) / f"{stem}.png"))
    publish_study(Path(out_dir), paths)  # report.md shows the plots, report.html, summary rebuilt
    return paths


def main(argv: list[str] | None = None) -> int:
    """CLI: plot the study JSON (default ``<results>/convergence/convergence.json``); exit 2 if it is missing."""
    loaded = load_study_json(sys.argv[1:] if argv is None else argv,
                             default_paths().study("convergence") / "convergence.json",
                             producer="workbench.studies.convergence")
    if loaded is None:
        return 2
    path, data = loaded
    for p in plot_study(data, out_dir=path.parent):
        print(f"wrote {p}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
