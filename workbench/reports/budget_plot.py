"""The error budget against h: one panel per budget quantity (``budget.png`` of a case, and of the summary).

Plotting only: the panels are read from ``metrics.json["error_budget"]`` (each row's ``by_h`` values on the
three grids, the extrapolated value, the relative GCI and truncation, the theory and the alternative theory).
Every panel shows the relative deviation from the extrapolated value ``x``,

    y = f / x - 1,

against h_c (log axis), the band ``+-uncertainty |fine| / |x|`` (older rows: gci + truncation) shaded, the
theory as a solid line and the alternative theory as a dashed line (or, beyond the axis range, as an arrow
with its value). A row whose band is undefined (oscillating with no GCI, a level that failed) is drawn as a
panel that says so: nothing is left out silently.
"""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

from matplotlib.ticker import NullFormatter

from workbench.atomic import atomic_path
from workbench.reports.plots import plt

__all__ = ["budget_panels", "plot_budget"]

_NCOLS = 4


def budget_panels(budget: dict) -> list[dict]:
    """The panels of :func:`plot_budget` from an ``error_budget`` dict (pure data; NaN/None kept as None)."""
    panels = []
    for name, r in budget.items():
        by_h = r.get("by_h") or {}
        h = [float(k) for k in by_h]
        x = r.get("extrapolated")
        ok = x not in (None, 0.0) and r.get("gci") is not None and all(v is not None for v in by_h.values())
        panel = {"name": name, "status": r.get("status", ""), "ok": bool(ok), "h": h}
        if ok:
            panel |= {
                "y": [float(v) / x - 1.0 for v in by_h.values()],
                "band": r.get("uncertainty", r["gci"] + (r.get("truncation") or 0.0)) * abs(r["fine"]) / abs(x),
                "theory": None if r.get("theory") is None else r["theory"] / x - 1.0,
                "alt": None if r.get("alt_value") is None else r["alt_value"] / x - 1.0,
                "alt_name": r.get("alt_theory"),
                "theory_in_band": r.get("theory_in_band"),
            }
        panels.append(panel)
    return panels


def _mark(ax, y, span, *, style, label):
    lo, hi = span
    if lo <= y <= hi:
        ax.axhline(y, color="k", ls=style, lw=1.0, label=label)
    else:
        ax.annotate(f"{label}: {y:+.2e}", xy=(0.02, 0.95 if y > hi else 0.05), xycoords="axes fraction",
                    fontsize=6, va="top" if y > hi else "bottom")


def plot_budget(budget: dict, path: Path, *, title: str) -> Path | None:
    """Write ``path`` (PNG) with one panel per budget row; None (nothing written) for an empty budget."""
    panels = budget_panels(budget)
    if not panels:
        return None
    ncols = min(len(panels), _NCOLS)  # no empty columns when there are few panels
    nrows = math.ceil(len(panels) / ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(3.6 * ncols, 2.8 * nrows), squeeze=False)
    for ax in axes.flat[len(panels):]:
        ax.axis("off")
    for ax, pn in zip(axes.flat, panels, strict=False):
        ax.set_title(pn["name"], fontsize=7)
        ax.set_xscale("log")
        ax.tick_params(labelsize=6)
        if not pn["ok"]:
            ax.set_xticks([])
            ax.set_yticks([])
            status = "\n".join(textwrap.wrap(str(pn["status"]), 38)[:8])
            ax.text(0.5, 0.5, f"band undefined\n{status}", ha="center", va="center", fontsize=6,
                    transform=ax.transAxes)
            continue
        band = pn["band"]
        ys = [abs(v) for v in pn["y"]] + [band]
        lim = 1.3 * max(max(ys), 1e-15)
        h_lo, h_hi = min(pn["h"]) / 1.5, max(pn["h"]) * 1.5
        ax.fill_between([h_lo, h_hi], -band, band, color="tab:blue", alpha=0.2, label="band")
        ax.plot(pn["h"], pn["y"], "o-", color="tab:blue", ms=3, label="FEM")
        ax.axhline(0.0, color="tab:blue", lw=0.6)
        if pn["theory"] is not None:
            _mark(ax, pn["theory"], (-lim, lim), style="-", label="theory")
        if pn["alt"] is not None:
            _mark(ax, pn["alt"], (-lim, lim), style="--", label=pn["alt_name"] or "alternative")
        ax.set_xlim(h_lo, h_hi)
        ax.set_xticks(pn["h"], [f"{v:g}" for v in pn["h"]])
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.set_ylim(-lim, lim)
        ax.set_xlabel("h_c (fraction of the half-width)", fontsize=6)
        ax.set_ylabel("f / extrapolated - 1", fontsize=6)
        ax.text(0.98, 0.05, textwrap.shorten(str(pn["status"]), 40), transform=ax.transAxes, ha="right",
                fontsize=6)
    axes.flat[0].legend(fontsize=6, loc="upper right")
    fig.suptitle(f"{title}: error budget (band = GCI + truncation + iterative + round-off)", fontsize=9)
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.35 / (2.8 * nrows)))  # room for the title
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110)
    plt.close(fig)
    return path
