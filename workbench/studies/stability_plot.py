"""Plots of the stability sweep from ``<results>/stability/stability.json`` (no computation here).

``python -m workbench.studies.stability_plot [--dir DIR]`` writes ``method.png`` (errors and the Jacobian's
condition estimate against kappa0 / gamma0, with the augmented-Lagrangian kappa0 sweep beside the penalty and
Nitsche ones) and ``incompressible.png`` (peak error against nu, P1/P2 displacement vs mixed).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from workbench.paths import default_paths  # noqa: E402
from workbench.reports.plots import save_figure  # noqa: E402
from workbench.reports.study_pages import publish_study  # noqa: E402

__all__ = ["plot_method", "plot_incompressible", "main"]


def _err(r, key):
    return r["errors"].get(key) if r.get("converged") else None


def plot_method(records: list[dict], path: Path, *, band: float = 0.02) -> Path:
    """Worst relative error and cond_1(J) against the method parameter (penalty kappa0, Nitsche gamma0 x theta,
    augmented Lagrangian kappa0: errors only, its runs carry no condition estimate)."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    groups = {"penalty": [r for r in records if r["study"] == "method" and r["params"]["method"] == "penalty"]}
    for theta in (1, 0, -1):
        groups[f"nitsche theta={theta}"] = [r for r in records if r["study"] == "method"
                                            and r["params"]["method"] == "nitsche" and r["params"]["theta"] == theta]
    al = [r for r in records if r["study"] == "augmented_lagrangian"]
    if al:
        groups["augmented Lagrangian"] = al
    for name, recs in groups.items():
        par = "gamma0" if name.startswith("nitsche") else "kappa0"
        ok = [r for r in recs if r["converged"]]
        x = [r["params"][par] for r in ok]
        ax1.loglog(x, [max(_err(r, k) for k in ("p_max", "half_width", "rms")) for r in ok], "o-", label=name)
        cond = [(xi, r["condition"]["cond_jacobian"]) for xi, r in zip(x, ok, strict=True) if r.get("condition")]
        if cond:
            ax2.loglog(*zip(*cond, strict=True), "o-", label=name)
        bad = [r["params"][par] for r in recs if not r["converged"]]
        if bad:
            ax1.loglog(bad, [1.0] * len(bad), "kx", label=f"{name}: diverged")
    ax1.axhline(band, color="grey", ls=":", label=f"{band:.0%} band")
    ax1.set(xlabel="kappa0 / gamma0", ylabel="worst of p_max, half-width, RMS/p0 errors")
    ax2.set(xlabel="kappa0 / gamma0", ylabel="cond_1(J) estimate (free dofs)")
    for ax in (ax1, ax2):
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("Method parameters, Hertz scene (P2, h = a/10)")
    return save_figure(fig, path, dpi=150)


def plot_incompressible(records: list[dict], path: Path, *, band: float = 0.02) -> Path:
    """Peak-pressure and RMS errors against nu for P1/P2 displacement and P2/P1 mixed (diverged runs at 1)."""
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    recs = [r for r in records if r["study"] == "incompressible"]
    for label in ("P1 displacement", "P2 displacement", "P2 mixed"):
        mine = [r for r in recs if r["label"].endswith(label)]
        x = [0.5 - r["params"]["nu"] for r in mine]
        y = [max(_err(r, "p_max"), _err(r, "rms")) if r["converged"] else 1.0 for r in mine]
        ax.loglog(x, y, "o-", label=label)
    ax.axhline(band, color="grey", ls=":", label=f"{band:.0%} band")
    ax.set(xlabel="0.5 - nu", ylabel="max(p_max error, RMS/p0)  (1 = diverged)",
           title="Near-incompressibility, Hertz scene")
    ax.invert_xaxis()
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    return save_figure(fig, path, dpi=150)


def main(argv: list[str] | None = None) -> int:
    """CLI: read ``<dir>/stability.json``, write the PNGs next to it."""
    ap = argparse.ArgumentParser(prog="python -m workbench.studies.stability_plot",
                                 description=__doc__.splitlines()[0])
    ap.add_argument("--dir", type=Path, default=None, help="study folder (default: <results>/stability)")
    args = ap.parse_args(argv)
    folder = args.dir if args.dir is not None else default_paths().study("stability")
    data = json.loads((folder / "stability.json").read_text())
    recs, band = data["records"], data["summary"]["band"]
    plots = []
    if any(r["study"] == "method" for r in recs):
        plots.append(plot_method(recs, folder / "method.png", band=band))
    if any(r["study"] == "incompressible" for r in recs):
        plots.append(plot_incompressible(recs, folder / "incompressible.png", band=band))
    publish_study(folder, plots)  # report.md shows the plots, report.html, summary rebuilt
    return 0


if __name__ == "__main__":
    sys.exit(main())
