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

__all__ = ["load_study_json", "plot_load_indentation", "plot_pressure_panels", "save_figure"]


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


def save_figure(fig, path: Path, *, dpi: int = 110) -> Path:
    """Lay out ``fig``, write it to ``path`` atomically, close it, and return the path."""
    path = Path(path)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi)
    plt.close(fig)
    return path


def plot_pressure_panels(panels: list[dict], path: Path, *, title: str) -> None:
    """One panel per run: FEM pressure against every analytic prediction.

    Args:
        panels: dicts with ``label``, ``x`` (mm), ``p_fem`` (MPa), optional ``sigma_nn`` (MPa),
            ``predictions`` (name -> (x, p) arrays), ``xlabel`` and ``xlim``.
        path: PNG file to write (atomically).
        title: Figure title.
    """
    n = len(panels)
    ncol = min(n, 3)
    nrow = int(np.ceil(n / ncol))
    fig, axes = plt.subplots(nrow, ncol, figsize=(5.2 * ncol, 3.8 * nrow), squeeze=False)
    for ax, panel in zip(axes.flat, panels, strict=False):
        x = np.asarray(panel["x"])
        ax.plot(x, panel["p_fem"], "k.", ms=2.5, label="FEM (contact law)")
        if panel.get("sigma_nn") is not None:
            ax.plot(x, panel["sigma_nn"], "-", color="0.6", lw=0.8, label=r"FEM $-\sigma_{nn}$")
        for (name, (xp, pp)), style in zip(panel.get("predictions", {}).items(), ("-", "--", "-.", ":"),
                                           strict=False):
            ax.plot(xp, pp, style, lw=1.4, label=name)
        ax.set_xlabel(panel.get("xlabel", "x (mm)"))
        ax.set_ylabel("p (MPa)")
        ax.set_title(panel["label"], fontsize=10)
        if panel.get("xlim"):
            ax.set_xlim(*panel["xlim"])
        ax.set_ylim(bottom=0)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
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
    ax.legend(fontsize=8)
    save_figure(fig, path)
