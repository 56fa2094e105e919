"""The concave map's report, table and picture, from ``concave_map.json`` alone (issue 40, item 3).

``concave_map.md`` opens on where Hertz superposition can be trusted, as a rule in the design numbers (the
separation of the pairs over the Hertz contact width, s/(2a), at the main patch's load), and where the
interacting-patch model must be used instead, with the measured errors and how many points they come from.
``concave_map.csv`` holds every point; ``concave_map.png`` is the map: relative radius R against s/(2a), the best
model's error class by colour, the model by marker, the paper's two designs ringed.
"""

from __future__ import annotations

import csv
import io
import json
import math
from pathlib import Path

from workbench.studies.concave_map_band import attach_bands
from workbench.studies.concave_map_models import CLASS_NAMES
from workbench.studies.concave_map_rule import HERTZ_RULE, past_limit, rule_lines, rule_numbers

__all__ = ["MODELS", "hertz_rule", "write_report", "csv_text", "plot_map"]

MODELS = {"hertz_lcp": "Hertz superposition at the LCP pairs (eq. 5)",
          "hertz_intersections": "Hertz superposition at the intersection-based pairs",
          "interacting": "interacting-patch model"}
_COLOURS = {"1%": "#1a9850", "5%": "#91cf60", "10%": "#fee08b", "beyond": "#d73027", "n/a": "#bbbbbb"}


def _worst(pt: dict, model: str) -> float:
    """The model's error at a point as the map judges it: its worst relative error, or 0 where it lies within the
    FEM's own band (:func:`workbench.studies.concave_map_band.effective_error`)."""
    from workbench.studies.concave_map_band import effective_error

    return effective_error(pt, model)


def _raw(pt: dict, model: str) -> float:
    v = pt["models"][model]["worst"]
    return math.nan if v is None else float(v)


def hertz_rule(points: list[dict], *, model: str = "hertz_lcp", edge: float = 0.05) -> dict:
    """The smallest s/(2a) from which on every point keeps ``model`` within ``edge``: ``{"threshold", "n_above",
    "worst_above", "n_below", "n"}`` (threshold None: no such region among the points; inf: none is within)."""
    pts = sorted((p for p in points if p["separation_over_contact"] is not None
                  and math.isfinite(p["separation_over_contact"]) and math.isfinite(_worst(p, model))),
                 key=lambda p: p["separation_over_contact"])
    if not pts:
        return {"threshold": None, "n_above": 0, "worst_above": None, "n_below": 0, "n": 0}
    k = len(pts)  # the first index from which on every point is within the edge
    while k > 0 and _worst(pts[k - 1], model) <= edge:
        k -= 1
    above = pts[k:]
    return {"threshold": above[0]["separation_over_contact"] if above else math.inf, "n_above": len(above),
            "worst_above": max((_worst(p, model) for p in above), default=None), "n_below": k, "n": len(pts)}


def _fmt(v, spec: str = ".3g") -> str:
    return "-" if v is None or (isinstance(v, float) and not math.isfinite(v)) else format(v, spec)


def _headline(data: dict) -> list[str]:
    pts, s = data["points"], data["summary"]
    lines = ["# Concave map: where Hertz superposition can be trusted (issue 40, item 3)", ""]
    if s.get("tiny"):
        lines += ["**This is the TINY run (2 designs x 2 loads on coarse meshes): it checks the machinery; its "
                  "numbers are no map and support no rule.**", ""]
    src = (f"measured at {len(pts)} points, {s['designs'] - s['failed_designs']} of {s['designs']} designs solved, "
           f"{s['failed_designs']} failed; {s.get('banded_points', 0)} points with the FEM's band")
    lines += rule_lines(pts, source=src)
    lines.append("- R = the primary pair's relative radius, R_convex = the particle's radius there, s = the distance "
                 "of the two pairs on the concave surface at first touch, 2a = the Hertz width of eq. (5) at the main "
                 "FEM patch's load, b = the largest FEM patch half-width. Errors are relative to the FEM; a point "
                 "within the FEM's own band counts as within. Hertz is compared at the measured load (2D has no Hertz "
                 "P(delta)); the interacting-patch model also by P at the FEM's d (Flamant's depth convention).")
    return lines


def _cls(e: float) -> str:
    from workbench.studies.concave_map_models import classify

    return classify(e)


def csv_text(points: list[dict]) -> str:
    """Every point as one csv row (numbers in mm, N/mm, MPa; errors relative)."""
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    head = ["design", "kind", "paper", "radius_convex", "radius_concave", "relative_radius", "pair_separation",
            "central_gap", "depth", "d_mm", "approach_mm", "P_fem", "p_max_fem", "n_patches_fem",
            "separation_over_contact"]
    for m in MODELS:
        head += [f"{m}_{q}" for q in ("P", "width", "p0", "worst", "class")]
        head.append(f"{m}_within_fem_band")
    head += ["fem_band_P", "fem_band_p0", "fem_band_width"]
    w.writerow([*head, "best_model", "best_class", "note_interacting"])
    for p in points:
        n = p["numbers"]
        row = [p["design"], p["kind"], p["paper"], n["radius_convex"], n["radius_concave"], p["relative_radius"],
               n["pair_separation"], n["central_gap"], n["depth"], p["d_mm"], p["approach_mm"], p["P_fem"],
               p["p_max_fem"], len(p["fem_patches"]), p["separation_over_contact"]]
        for m in MODELS:
            e = p["models"][m]
            row += [e["P"], e["width"], e["p0"], e["worst"], e["class"], e.get("within_fem_band")]
        b = p.get("fem_band") or {}
        row += [b.get("P"), b.get("p0"), b.get("width")]
        w.writerow(["" if v is None else v for v in [*row, p["best_model"], p["best_class"],
                                                      p["models"]["interacting"]["note"]]])
    return out.getvalue()


def _table(points: list[dict]) -> list[str]:
    rows = ["| design | R (mm) | d (mm) | P FEM (N/mm) | patches | s/(2a) | FEM band P / p0 / width | Hertz LCP | "
            "Hertz intersections | interacting | best |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for p in points:
        cells = [f"{_fmt(p['models'][m]['worst'])} ({p['models'][m]['class']}"
                 f"{', in band' if p['models'][m].get('within_fem_band') else ''})" for m in MODELS]
        b = p.get("fem_band")
        band = " / ".join(_fmt(b[q], ".2g") for q in ("P", "p0", "width")) if b else "-"
        rows.append(f"| {p['design']}{' (paper)' if p['paper'] else ''} | {p['relative_radius']:.4g} | "
                    f"{p['d_mm']:.5g} | {p['P_fem']:.4g} | {len(p['fem_patches'])} | "
                    f"{_fmt(p['separation_over_contact'])} | {band} | {' | '.join(cells)} | {p['best_model'] or '-'} |")
    return rows


_PANELS = (("hertz_lcp", "Hertz superposition at the LCP pairs (eq. 5)"),
           ("interacting", "interacting-patch model (workbench forcelaw)"))
_KIND_MARKERS = {"close_to_conformal": "o", "symmetric": "s"}


def _judged_class(pt: dict, model: str) -> str:
    """The class the map gives a model at a point: its error's class, "band" where it is beyond 5 % but within the
    FEM's band, "n/a" where it gives nothing."""
    e = pt["models"][model]
    if e["class"] in ("10%", "beyond") and e.get("within_fem_band"):
        return "band"
    return e["class"]


def plot_map(points: list[dict], path: Path, *, tiny: bool) -> None:
    """The map picture: one panel per model (Hertz superposition at the LCP pairs; the interacting-patch model),
    x the conformity R/R_convex, y the pair separation over the Hertz contact width s/(2a) at each load, colour the
    model's error class against the FEM, marker the design's kind, the paper's two designs ringed and named, the
    rule's region (:data:`workbench.studies.concave_map_rule.HERTZ_RULE`) shaded, points it excludes by their patch
    size crossed, the interacting-patch model's points past its analytic slope limit edged in black."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    colours = {**_COLOURS, "band": "#4575b4"}
    names = {"1%": "within 1 %", "5%": "within 5 %", "10%": "within 10 %", "beyond": "beyond 10 %",
             "band": "beyond 5 %, within the FEM's band", "n/a": "model refused or unsolved"}
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.8), sharex=True, sharey=True)
    shown = [p for p in points if p["separation_over_contact"] is not None
             and math.isfinite(p["separation_over_contact"])]
    for ax, (model, title) in zip(axes, _PANELS, strict=True):
        for p in sorted(shown, key=lambda q: q["paper"]):
            c, y, b = rule_numbers(p)
            past = model == "interacting" and past_limit(p)
            ax.scatter(c, y, c=colours[_judged_class(p, model)], marker=_KIND_MARKERS.get(p["kind"], "o"), s=42,
                       edgecolors="black" if past else "none", linewidths=0.9 if past else 0.0, zorder=3)
            if b > HERTZ_RULE["patch_max"]:
                ax.scatter(c, y, marker="x", c="black", s=30, linewidths=1.0, zorder=4)
        for label, text in (("paper_close_to_conformal", "paper: close to conformal"),
                            ("paper_symmetric", "paper: symmetric")):
            mine = [p for p in shown if p["design"] == label]
            if not mine:
                continue
            xs = [rule_numbers(p)[0] for p in mine]
            ys = [p["separation_over_contact"] for p in mine]
            ax.scatter(xs, ys, s=150, facecolors="none", edgecolors="black", linewidths=1.6, zorder=4)
            ax.annotate(text, (xs[0], max(ys)), xytext=(12, 14), textcoords="offset points", fontsize=9,
                        fontweight="bold", arrowprops={"arrowstyle": "-", "lw": 0.8}, zorder=5)
        x_max, y_min = HERTZ_RULE["conformity_max"], HERTZ_RULE["separation_min"]
        ax.fill_between([0.5, x_max], y_min, 100.0, color="#1a9850", alpha=0.12, zorder=1, lw=0)
        ax.plot([0.5, x_max, x_max], [y_min, y_min, 100.0], color="#1a9850", lw=1.5, ls="--", zorder=2)
        if model == "hertz_lcp":
            ax.text(0.63, 6.0, "Hertz\ntrusted\n(the rule)", fontsize=9, color="#1a6b34", fontweight="bold",
                    zorder=6)
        else:
            ax.text(2.5, 0.07, "use the interacting-patch model\n(where it applies)", fontsize=9, color="#223f7a",
                    fontweight="bold", zorder=6)
        ax.set_xscale("log")
        ax.set_yscale("log")
        for axis in (ax.xaxis, ax.yaxis):
            axis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
            axis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v:g}"))
            axis.set_minor_formatter(NullFormatter())
        ax.set_title(title, fontsize=11)
        ax.set_xlim(0.6, 300.0)
        ax.set_ylim(0.05, 30.0)
        ax.set_xlabel("conformity R/R_convex of the primary pair (1: flat concave flank)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("pair separation / Hertz contact width, s/(2a)")
    handles = [Line2D([], [], marker="o", ls="", color=colours[k], markersize=8, label=names[k])
               for k in ("1%", "5%", "10%", "beyond", "band", "n/a")]
    handles += [Line2D([], [], marker=mk, ls="", color="grey", label=f"{kind.replace('_', ' ')} design")
                for kind, mk in _KIND_MARKERS.items()]
    handles.append(Line2D([], [], marker="o", ls="", mfc="white", mec="black", mew=1.6, markersize=10,
                          label="the paper's two designs"))
    handles.append(Line2D([], [], marker="x", ls="", color="black", label="patch b/R_convex > 0.32"))
    handles.append(Line2D([], [], marker="o", ls="", mfc="grey", mec="black", mew=0.9, markersize=8,
                          label="interacting: past its slope limit"))
    fig.legend(handles=handles, loc="lower center", ncol=5, fontsize=9, frameon=False)
    fig.suptitle(("TINY RUN (machinery check, not a map): " if tiny else "")
                 + "error against the FEM (widths, p0; interacting also P(d)), each design at 5 loads", fontsize=12)
    fig.tight_layout(rect=(0, 0.1, 1, 0.95))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _band_section(pts: list[dict], middle: list[dict], coarse: list[dict]) -> list[str]:
    """The FEM band's method and its values over the points (median, 90th percentile, largest, per quantity), and
    the assumed order checked on three grids where the middle pass exists."""
    from workbench.studies.concave_map_band import ASSUMED_ORDER, FS_TWO_GRID, REFINEMENT, order_check

    banded = [p for p in pts if p.get("fem_band")]
    lines = ["## The FEM's own band", "",
             f"Two-grid GCI per point: the map's grid and one {REFINEMENT:g} times coarser in every element "
             f"(`workbench concave-map --coarse`), band = {FS_TWO_GRID:g} |q_coarse - q_fine| / |q_fine| / "
             f"({REFINEMENT:g}^p - 1) with the ASSUMED order p = {ASSUMED_ORDER:g} (two grids observe no order). "
             "A model within the band at a point counts as within, whatever its class.", ""]
    if not banded:
        return [*lines, "No coarse pass in this folder: no point has a band.", ""]
    lines += [f"{len(banded)} of {len(pts)} points have a band.", "",
              "| quantity | points | median | 90 % | largest |", "|---|---|---|---|---|"]
    for q, text in (("P", "load P"), ("p0", "peak p0"), ("width", "patch width (largest over patches)")):
        v = sorted(p["fem_band"][q] for p in banded if p["fem_band"][q] is not None)
        if v:
            lines.append(f"| {text} | {len(v)} | {v[len(v) // 2]:.2g} | {v[int(0.9 * (len(v) - 1))]:.2g} | "
                         f"{v[-1]:.2g} |")
    differ = sum(1 for p in banded if p["fem_band"]["width"] is None)
    lines += ["", f"{differ} points where the two grids find a different number of patches (widths unbanded there; "
              "no model rescued by width).", ""]
    if middle:
        chk = order_check(pts, middle, coarse)
        designs = len({p["design"] for p in middle})
        lines += [f"The assumed order checked on a third grid (every element x sqrt(2), `--middle`) at {designs} "
                  "designs: Roache's three-grid study (`workbench.error_budget.grid_study`) per quantity.", "",
                  "| quantity | studied | observed order (median, range) | status | two-grid band >= three-grid GCI |",
                  "|---|---|---|---|---|"]
        for q, r in chk.items():
            o = sorted(r["orders"])
            order = f"{o[len(o) // 2]:.2g} ({o[0]:.2g} to {o[-1]:.2g})" if o else "-"
            status = ", ".join(f"{k} {v}" for k, v in sorted(r["status"].items()))
            lines.append(f"| {q} | {r['n']} | {order} | {status} | {r['covered']} of {r['n']} |")
        lines.append("")
    return lines


def write_report(out: Path) -> None:
    """``concave_map.md``, ``concave_map.csv`` and ``concave_map.png`` from ``<out>/concave_map.json``."""
    from workbench.atomic import write_text

    out = Path(out)
    data = json.loads((out / "concave_map.json").read_text(encoding="utf-8"))
    pts = data["points"]
    coarse_file = out / "concave_map_coarse.json"
    coarse = json.loads(coarse_file.read_text(encoding="utf-8")) if coarse_file.is_file() else None
    data["summary"]["banded_points"] = attach_bands(pts, coarse["points"] if coarse else [])
    middle_file = out / "concave_map_middle.json"
    middle = json.loads(middle_file.read_text(encoding="utf-8"))["points"] if middle_file.is_file() else []
    counts = ["| model | " + " | ".join(CLASS_NAMES) + " | n/a | beyond 5 % but within the FEM's band |",
              "|---|" + "---|" * (len(CLASS_NAMES) + 2)]
    for m, text in MODELS.items():
        c = [sum(1 for p in pts if p["models"][m]["class"] == k) for k in (*CLASS_NAMES, "n/a")]
        rescued = sum(1 for p in pts if p["models"][m].get("within_fem_band") and _raw(p, m) > 0.05)
        counts.append(f"| {text} | " + " | ".join(str(v) for v in c) + f" | {rescued} |")
    fails = [f"- {f['design']}: {f['error']}" for f in data.get("failures", [])] or ["- none"]
    md = [*_headline(data), "", "![map](concave_map.png)", "", "## Error classes per model (points)", "", *counts,
          "", *_band_section(pts, middle, coarse["points"] if coarse else []),
          "## Every point (worst relative error over P, widths and p0; class)", "", *_table(pts), "",
          "## Designs that failed", "", *fails, ""]
    write_text(out / "concave_map.md", "\n".join(md))
    write_text(out / "concave_map.csv", csv_text(pts))
    plot_map(pts, out / "concave_map.png", tiny=bool(data["summary"].get("tiny")))
