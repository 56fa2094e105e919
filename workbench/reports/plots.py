"""Plots of the workbench (matplotlib, Agg backend, files only; no blocking ``show``).

Plotting is separate from computing: every function here takes arrays that a run already computed.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from workbench.atomic import atomic_path  # noqa: E402

__all__ = ["has_curve", "load_study_json", "plot_load_indentation", "plot_pressure_panels", "save_figure"]


def load_study_json(argv: list[str], default: Path, *, producer: str):
    """The ``(path, data)`` of a study JSON named on a plot CLI (``argv[0]``, else ``default``).

    Returns ``None`` after one error line on stderr when the file is missing (the caller exits 2).
    """
    import json
    import sys

    path = Path(argv[0]) if argv else Path(default)
    if not path.is_file():
        print(f"error: {path} not found; run `python -m {producer}` first", file=sys.stderr)
        return None
    return path, json.loads(path.read_text())


def save_figure(fig, path: Path, *, dpi: int = 150) -> Path:
    """Lay out ``fig``, write it to ``path`` atomically, close it, and return the path."""
    path = Path(path)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi)
    plt.close(fig)
    return path


SINGULAR_RATIO = 2.5
"""A pressure axis is logarithmic when the peak exceeds this times the mean over the contact (a singularity: the
wedge apex gives about 4, Hertz 4/pi = 1.27)."""


def _singular(p) -> bool:
    p = np.asarray(p, dtype=float)
    on = p[np.isfinite(p) & (p > 0)]
    return on.size > 3 and float(on.max()) > SINGULAR_RATIO * float(on.mean())


def has_curve(values) -> bool:
    """A curve exists when it has at least one finite value: a run without it (e.g. the two-body scene's samples,
    which have no stress-based pressure: all NaN) draws no line and lists nothing in the legend."""
    if values is None:
        return False
    a = np.asarray(values, dtype=float)
    return a.size > 0 and bool(np.isfinite(a).any())


def plot_pressure_panels(panels: list[dict], path: Path, *, title: str) -> None:
    """One column per run: FEM pressure against every analytic prediction, and below it the residual
    (FEM - theory) / p0 of the theory the run is judged by (``residual``; without it, the convective prediction
    where present, else the first; p0: that prediction's peak).

    Args:
        panels: dicts with ``label``, ``x`` (mm), ``p_fem`` (MPa), optional ``sigma_nn`` (MPa),
            ``predictions`` (name -> (x, p) arrays), ``xlabel``, ``xlim`` and optional ``marks``: a list of
            (label, x) drawn as vertical lines (e.g. the contact edge b = b0 (b/b0) of each theory), optional
            ``headline`` (lines under the panel's title: the measure the verdict reads) and ``residual`` (the
            name of the prediction the residual is taken against).
        path: PNG file to write (atomically, 150 dpi).
        title: Figure title.

    A pressure axis is logarithmic where a singularity dominates it (:data:`SINGULAR_RATIO`); legends sit to
    the right of the axes, never on the data. Only curves that exist are drawn and listed (:func:`has_curve`).
    """
    n = len(panels)
    ncol = min(n, 2)
    nrow = int(np.ceil(n / ncol))
    fig = plt.figure(figsize=(7.6 * ncol, 5.4 * nrow))
    grid = fig.add_gridspec(nrow * 2, ncol, height_ratios=[3, 1.3] * nrow)
    for k, panel in enumerate(panels):
        r, c = divmod(k, ncol)
        ax = fig.add_subplot(grid[2 * r, c])
        res = fig.add_subplot(grid[2 * r + 1, c], sharex=ax)
        x = np.asarray(panel["x"], dtype=float)
        p = np.asarray(panel["p_fem"], dtype=float)
        ax.plot(x, p, "k.", ms=2.5, label="FEM (contact law)")
        if has_curve(panel.get("sigma_nn")):
            ax.plot(x, panel["sigma_nn"], "-", color="0.6", lw=0.8, label=r"FEM $-\sigma_{nn}$")
        preds = [(name, xy) for name, xy in panel.get("predictions", {}).items() if has_curve(xy[1])]
        for (name, (xp, pp)), style in zip(preds, ("-", "--", "-.", ":"), strict=False):
            ax.plot(xp, pp, style, lw=1.4, label=name)
        for (name, xm), colour in zip(panel.get("marks", []), ("C3", "C4", "C5", "C6", "C8"), strict=False):
            ax.axvline(xm, color=colour, lw=1.0, ls=(0, (4, 2)), label=name)
        ax.set_ylabel("p (MPa)")
        ax.set_title("\n".join([panel["label"], *panel.get("headline", [])]), fontsize=10 if not panel.get("headline")
                     else 8)
        if panel.get("xlim"):
            ax.set_xlim(*panel["xlim"])
        if _singular(p):
            ax.set_yscale("log")
            ax.set_ylim(bottom=1e-2 * np.nanmax(p), top=2.0 * np.nanmax(p))
            ax.set_ylabel("p (MPa, log scale: singular peak)")
        else:
            ax.set_ylim(bottom=0)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
        plt.setp(ax.get_xticklabels(), visible=False)
        if preds:  # the residual against the theory the run is judged by (else the convective one, else the first)
            name, (xp, pp) = next((q for q in preds if q[0] == panel.get("residual")),
                                  next((q for q in preds if "convective" in q[0]), preds[0]))
            pp = np.asarray(pp, dtype=float)
            p0 = float(np.nanmax(pp)) if np.isfinite(pp).any() else float("nan")
            same = len(xp) == len(x) and np.allclose(np.asarray(xp, dtype=float), x)
            theory = pp if same else np.interp(x, np.asarray(xp, dtype=float), pp)
            res.plot(x, (p - theory) / p0, "k.", ms=2.0)
            res.axhline(0.0, color="0.5", lw=0.8)
            res.set_ylabel(f"(FEM - theory) / p0\n(theory: {name[:28]})", fontsize=7)
        else:
            res.text(0.5, 0.5, "no theory to compare", transform=res.transAxes, ha="center")
        res.set_xlabel(panel.get("xlabel", "x (mm)"))
        res.grid(alpha=0.3)
    fig.suptitle(title)
    save_figure(fig, path)


def plot_load_indentation(curves: dict, path: Path, *, title: str, reference: dict | None = None) -> None:
    """Load against indentation, one line per configuration, with optional reference points.

    Args:
        curves: label -> (delta (mm), P (N/mm)) arrays.
        path: PNG file to write (atomically).
        title: Figure title.
        reference: label -> (delta, P) points drawn as hollow markers (e.g. a paper's table).
    """
    fig, ax = plt.subplots(figsize=(5.5, 4.0))
    for (label, (delta, P)), marker in zip(curves.items(), ("o", "s", "^", "d"), strict=False):
        ax.plot(delta, P, marker=marker, label=label)
    for (label, (delta, P)), marker in zip((reference or {}).items(), ("o", "s", "^", "d"), strict=False):
        ax.plot(delta, P, marker=marker, ls=":", mfc="none", color="0.35", label=label)
    ax.set_xlabel(r"indentation $\delta$ (mm, LCP of the rigid curves)")
    ax.set_ylabel("P (N/mm, total load per unit thickness)")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    fig.set_size_inches(8.0, 4.2)
    save_figure(fig, path)
