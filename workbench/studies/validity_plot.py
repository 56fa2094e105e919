"""Validity maps from ``validity.json`` (plotting only): ``python -m workbench.studies.validity_plot --dir DIR``.

One PNG per scene (``map_cylinder.png``, ``map_wedge.png``, ``map_halfplanes.png``): a panel per theory, cells
over (a/R, theta or b0/R) x beta, coloured by the band of the theory's difference from the most complete FEM model
(within 0.1 %, 1 %, 5 %, beyond 5 %, or unresolved: the FEM uncertainty is not well below the difference), the
difference printed in each cell. Two elastic half-planes (beta of both signs): the model is the moment ratio
convective over small, and a cell whose theory lies outside the FEM's U is hatched. At finite strain
(``map_halfplanes_finite.png``): whether the convective correction outweighs the spread between the material laws.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

__all__ = ["BAND_COLOURS", "PANELS", "draw_maps", "main"]

BAND_COLOURS = {"<0.1%": "#1a7f37", "<1%": "#7ccf7f", "<5%": "#f2d45c", ">5%": "#d9534f", "unresolved": "#c8c8c8"}
# (theory, quantity, title) per scene
PANELS = {
    "cylinder": (("hertz", "moment", "Hertz (parabola, beta = 0)"),
                 ("exact_circle", "moment", "exact circle, beta = 0"),
                 ("ch_circle", "moment", "Ciavarella-Hills converged (circle)"),
                 ("ch_first_order", "half_width", "C-H first order (half-width)")),
    "wedge": (("wedge", "moment", "classical wedge"),
              ("ch_wedge", "moment", "Ciavarella-Hills converged"),
              ("ch_first_order", "half_width", "C-H first order (half-width)")),
    "halfplanes": (("hertz", "moment", "Hertz (no convective term)"),
                   ("ch_converged", "moment", "Ciavarella-Hills converged"),
                   ("ch_first_order", "moment", "C-H first order")),
}
XLABELS = {"cylinder": "a/R", "wedge": "theta", "halfplanes": "b0/R (two elastic half-planes)"}


def _label(scene: str, v: float) -> str:
    if scene in ("cylinder", "halfplanes"):
        return f"{v:g}"
    k = math.pi / v
    return f"pi/{k:.0f}" if abs(k - round(k)) < 1e-6 else f"{v:.3g}"


def draw_maps(data: dict, folder: Path) -> list[Path]:
    """Draw the maps of ``data`` (the study JSON) into ``folder``; returns the files written."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch

    written = []
    for scene, panels in PANELS.items():
        pts = [p for p in data["points"] if p["scene"] == scene]
        if not pts:
            continue
        xs = sorted({p["param"] for p in pts})
        betas = sorted({p["beta"] for p in pts})
        ncols = 2 if len(panels) == 4 else len(panels)
        nrows = math.ceil(len(panels) / ncols)
        fig, axes = plt.subplots(nrows, ncols, figsize=(4.6 * ncols, 3.2 * nrows + 0.8), squeeze=False)
        for ax, (theory, q, title) in zip(axes.ravel(), panels, strict=True):
            for p in pts:
                i, j = xs.index(p["param"]), betas.index(p["beta"])
                band = p.get("bands", {}).get(theory, {}).get(q)
                colour = BAND_COLOURS[band["band"]] if band else "white"
                ax.add_patch(plt.Rectangle((i, j), 1, 1, facecolor=colour, edgecolor="white", linewidth=2))
                if band is not None and band.get("inside") is False:  # the theory lies outside the FEM's U
                    ax.add_patch(plt.Rectangle((i + 0.04, j + 0.04), 0.92, 0.92, fill=False, hatch="//",
                                               edgecolor="0.35", linewidth=0))
                text = "no run" if band is None else f"{100 * band['difference']:.2g}%"
                dark = band is not None and band["band"] in ("<0.1%", ">5%")
                hatched = band is not None and band.get("inside") is False
                ax.text(i + 0.5, j + 0.5, text, ha="center", va="center", fontsize=8,
                        color="white" if dark and not hatched else "black",
                        bbox={"facecolor": "white", "edgecolor": "none", "pad": 1.5} if hatched else None)
            ax.set_xlim(0, len(xs))
            ax.set_ylim(0, len(betas))
            ax.set_xticks([i + 0.5 for i in range(len(xs))], [_label(scene, v) for v in xs], fontsize=8)
            ax.set_yticks([j + 0.5 for j in range(len(betas))], [f"{b:.2g}" for b in betas], fontsize=8)
            ax.set_xlabel(XLABELS[scene])
            ax.set_ylabel("beta")
            ax.set_title(title, fontsize=9)
        handles = [Patch(facecolor=c, label=("within " + b[1:]) if b.startswith("<") else
                         ("beyond " + b[1:]) if b.startswith(">") else b) for b, c in BAND_COLOURS.items()]
        if any(p.get("bands", {}).get(t, {}).get(q, {}).get("inside") is False for p in pts for t, q, _ in panels):
            handles.append(Patch(facecolor="white", edgecolor="0.35", hatch="//", label="theory outside the FEM's U"))
        fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=8, frameon=False)
        fig.suptitle(f"{scene}: theory against the most complete FEM model (difference, cell colour = band)",
                     fontsize=10)
        fig.tight_layout(rect=(0, 0.06, 1, 0.95))
        path = Path(folder) / f"map_{scene}.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        written.append(path)
    finite = _finite_map(data, folder, plt, Patch)
    return written + ([finite] if finite else [])


VERDICT_COLOURS = {"convective": "#1a7f37", "comparable": "#f2d45c", "material law": "#d9534f"}


def _finite_map(data: dict, folder: Path, plt, Patch) -> Path | None:
    """``map_halfplanes_finite.png`` (issue 39): over (b0/R, beta), whether the convective correction |R_ch - 1|
    outweighs the spread between the finite-strain laws (green), the reverse (red) or neither beyond the bands
    (yellow); each cell prints the correction and the spread (%)."""
    pts = [p for p in data["points"] if p["scene"] == "halfplanes" and p.get("finite", {}).get("laws")]
    if not pts:
        return None
    xs, betas = sorted({p["param"] for p in pts}), sorted({p["beta"] for p in pts})
    fig, ax = plt.subplots(figsize=(max(7.0, 1.2 * len(xs) + 3.0), 0.55 * len(betas) + 2.0))
    for p in pts:
        i, j = xs.index(p["param"]), betas.index(p["beta"])
        sp = p["finite"].get("spread")
        colour = VERDICT_COLOURS.get(sp["verdict"]) if sp else "white"
        ax.add_patch(plt.Rectangle((i, j), 1, 1, facecolor=colour, edgecolor="white", linewidth=2))
        c = 100 * abs(p["finite"]["convective_correction"])
        text = f"{c:.2g} | {100 * abs(sp['value']):.2g}" if sp else "no spread"
        ax.text(i + 0.5, j + 0.5, text, ha="center", va="center", fontsize=8)
    ax.set_xlim(0, len(xs))
    ax.set_ylim(0, len(betas))
    ax.set_xticks([i + 0.5 for i in range(len(xs))], [f"{v:g}" for v in xs], fontsize=8)
    ax.set_yticks([j + 0.5 for j in range(len(betas))], [f"{b:.2g}" for b in betas], fontsize=8)
    ax.set_xlabel("b0/R (two elastic half-planes, finite strain)")
    ax.set_ylabel("beta")
    ax.set_title("convective correction | law spread (%, moment half-width)", fontsize=9)
    handles = [Patch(facecolor=VERDICT_COLOURS["convective"], label="convective > spread + band"),
               Patch(facecolor=VERDICT_COLOURS["comparable"], label="within the bands"),
               Patch(facecolor=VERDICT_COLOURS["material law"], label="spread > convective + band")]
    fig.legend(handles=handles, loc="lower center", ncol=3, fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    path = Path(folder) / "map_halfplanes_finite.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="validity_plot", description=__doc__.splitlines()[0])
    ap.add_argument("--dir", type=Path, required=True, help="folder holding validity.json")
    args = ap.parse_args(argv)
    data = json.loads((args.dir / "validity.json").read_text())
    plots = draw_maps(data, args.dir)
    from workbench.reports.study_pages import publish_study

    publish_study(args.dir, plots)
    return 0


if __name__ == "__main__":
    sys.exit(main())
