"""The forest plot of the summary page (``forest.png``): every judged quantity against its theory (issue 37).

Plotting only: the rows are :class:`workbench.reports.forest.ForestRow` records (value over theory, band,
verdict), computed from the cases' ``metrics.json`` by :func:`workbench.reports.forest.forest_rows`.

One row per judged quantity, the case's name on it; the horizontal axis is ``value / theory`` with the theory at
1, on a symmetric-log scale of the deviation (linear within the smallest deviation or band drawn, logarithmic
beyond), so a 1e-5 band and a 3 % deviation are both seen. A budget row (``make run``) is its extrapolated
value (circle) with its band as an interval (hollow, with the reason, where the band is undefined); a CI-level
row is its fine value (square) with no band, and the check's tolerance shaded around 1. Colour is the verdict:
green passes, red fails, grey is not judged. An alternative theory (the one an exclusion must tell apart) is a
black x. A row whose ratio is undefined says so in place of its marker.
"""

from __future__ import annotations

import math
from pathlib import Path

from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from matplotlib.ticker import FuncFormatter, NullLocator

from workbench.atomic import atomic_path
from workbench.reports.forest import ForestRow
from workbench.reports.plots import plt

__all__ = ["plot_forest"]

_COLOUR = {True: "tab:green", False: "tab:red", None: "0.5"}
_KIND_NOTE = {"exclude_theory": " (excludes the theory)"}


def _linthresh(rows: list[ForestRow]) -> float:
    """The linear range of the symmetric-log axis: the decade of the smallest band or tolerance (a deviation
    smaller than every band sits in the linear range, near the theory), else of the smallest deviation."""
    scales = [r.band for r in rows if r.band] + [r.tolerance for r in rows if r.tolerance]
    if not scales:
        scales = [abs(r.ratio - 1.0) for r in rows if r.ratio is not None]
    positive = [s for s in scales if s > 0.0 and math.isfinite(s)]
    smallest = min(positive, default=1e-3)
    return min(max(10.0 ** math.floor(math.log10(smallest)), 1e-9), 1e-3)


def _ticks(thresh: float, lim: float) -> list[float]:
    """At most four decades each side of the theory, from the linear range's edge to the axis limit."""
    lo, hi = math.ceil(math.log10(thresh)), math.floor(math.log10(lim))
    step = max(1, math.ceil((hi - lo + 1) / 4))
    decades = [10.0 ** k for k in range(hi, lo - 1, -step)]
    return sorted([-d for d in decades] + [0.0] + decades)


def _tick(v: float, _pos=None) -> str:
    """Tick labels as the ratio: ``1``, ``1+1e-03``, ``1-1e-02``."""
    if v == 0.0:
        return "1"
    return f"1{'+' if v > 0 else '-'}{abs(v):.0e}"


def plot_forest(rows: list[ForestRow], path: Path, *, title: str) -> Path | None:
    """Write ``path`` (PNG) with one line per row (module docstring); None (nothing written) when ``rows`` is
    empty."""
    if not rows:
        return None
    n = len(rows)
    fig, ax = plt.subplots(figsize=(11.0, 1.6 + 0.26 * n))
    thresh = _linthresh(rows)
    ax.set_xscale("symlog", linthresh=thresh, linscale=1.0)
    ys = list(range(n))[::-1]  # the first row on top
    span = [thresh]
    for y, r, prev in zip(ys, rows, [None, *rows[:-1]], strict=True):
        if prev is not None and prev.case != r.case:
            ax.axhline(y + 0.5, color="0.8", lw=0.6)
        colour = _COLOUR[r.passed]
        if r.tolerance:
            ax.fill_betweenx([y - 0.35, y + 0.35], -r.tolerance, r.tolerance, color="0.85", lw=0)
            span.append(r.tolerance)
        if r.ratio is None:
            ax.text(0.0, y, f"undefined: {r.note}", ha="center", va="center", fontsize=6, color=colour)
            continue
        dev = r.ratio - 1.0
        span.append(abs(dev))
        if r.band is not None:
            ax.errorbar([dev], [y], xerr=[[r.band], [r.band]], fmt="o", color=colour, ms=4, capsize=2, lw=1.2)
            span.append(abs(dev) + r.band)
        elif "tolerance" in r.kinds:
            ax.plot([dev], [y], "s", ms=4, color=colour, mfc=colour if r.signed else "none")
        else:  # a budget row whose band is undefined: its value, hollow, and why
            ax.plot([dev], [y], "o", ms=4, color=colour, mfc="none")
        if r.note:  # at the right edge, clear of the bars
            ax.text(0.995, y, r.note[:70], transform=ax.get_yaxis_transform(), ha="right", va="bottom", fontsize=5,
                    color=colour)
        if r.alt_ratio is not None:
            ax.plot([r.alt_ratio - 1.0], [y], "x", color="k", ms=4)
            span.append(abs(r.alt_ratio - 1.0))
    lim = 2.0 * max(span)
    ax.set_xlim(-lim, lim)
    ax.axvline(0.0, color="k", lw=1.0)
    ax.set_yticks(ys, [f"{r.case}: {r.quantity}{_KIND_NOTE.get(r.kinds[0], '') if r.kinds else ''}" for r in rows],
                  fontsize=6)
    ax.set_ylim(-0.7, n - 0.3)
    ax.set_xticks(_ticks(thresh, lim))
    ax.xaxis.set_minor_locator(NullLocator())
    ax.xaxis.set_major_formatter(FuncFormatter(_tick))
    ax.tick_params(axis="x", labelsize=6)
    ax.set_xlabel("value / theory (theory = 1; symmetric log of the deviation, linear within "
                  f"+-{thresh:.0e})", fontsize=7)
    ax.grid(axis="x", alpha=0.3)
    ci = [r for r in rows if "tolerance" in r.kinds]
    handles = [(len(ci) < n, Line2D([], [], marker="o", color="0.3", ls="-", ms=4,
                                    label="extrapolated, band (budget)")),
               (bool(ci), Line2D([], [], marker="s", color="0.3", ls="", ms=4, label="fine value, no band (CI level)")),
               (any(not r.signed for r in rows), Line2D([], [], marker="s", color="0.3", mfc="none", ls="", ms=4,
                                                        label="|value/theory - 1| only")),
               (bool(ci), Patch(color="0.85", label="tolerance (CI level)")),
               (any(r.alt_ratio is not None for r in rows),
                Line2D([], [], marker="x", color="k", ls="", ms=4, label="alternative theory")),
               *[(any(r.passed is v for r in rows), Patch(color=_COLOUR[v], label=text))
                 for v, text in ((True, "passes"), (False, "fails"), (None, "not judged"))]]
    ax.legend(handles=[h for shown, h in handles if shown], fontsize=6, loc="upper left", bbox_to_anchor=(1.01, 1.0),
              borderaxespad=0.0)
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=120)
    plt.close(fig)
    return path
