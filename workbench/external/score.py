"""``workbench score CASE RESULT... [--format csv|frd|vtu] [--h H...] [--run R...] [--step N...] [--body B...]
[--out DIR]``: an external code's contact pressure, one RESULT per mesh level, against the case's theory, with the
workbench's own measures (any of the 14 cases: one scorer per scene, :mod:`workbench.external.scorers`).

A RESULT is one mesh level of the runs it holds: a csv in the schema of :mod:`workbench.external.results` (columns
``x_mm, p_MPa``, optionally ``y_mm``, ``P_N_per_mm``, ``h_mm``, ``weight_mm``, ``q_MPa``, ``run``, ``step``, ``body``;
several runs, steps and bodies in one file), or a CalculiX ``.frd`` (``--format frd``: its last CONTACT block, the
block top y = 0: one step of one run on the slave body) or a VTK ``.vtu/.vtp/.pvd`` (``--format vtu``: the point field
``--field`` on the surface y = 0 of its last dataset: likewise one step). What a file does not say is given by
``--run``, ``--step`` and ``--body`` (one value for all RESULTs, or one per RESULT; a case with one run, one reported
step and one scored body needs none). Per scene (the module docstrings of :mod:`workbench.external.scorers`):

* block: p_max, edge and moment half-widths, RMS against Hertz, the exact circle or the classical wedge at each
  level's load; b/b0 of a convective (or finite) run over the small one against Ciavarella-Hills;
* concave: per step and patch P, p0, patch widths against eq. (4)/(5), the Hertz superposition, load symmetry;
* two bodies: the exact circle at the combined modulus; the patch test's uniformity;
* two half-planes: the classical solution at E* (small run), b/b0 against Ciavarella-Hills at the bodies' beta.

``h``: the level's element size on the contact surface: ``--h`` or the file's ``h_mm`` column, else ESTIMATED as the
median sample spacing inside the main patch times ``--samples-per-element`` (default 1: nodal values); ``h_source``
says which. With three or more levels the three finest give the observed order, the GCI band and the extrapolated
value of each quantity (:func:`workbench.error_budget.grid_study`). Before any verdict the plausibility rules
(:func:`workbench.external.scorers.base.plausibility`): each level's contact half-width within a factor 2 of the
theory's at its load, the levels at one load, sizes h that rank the levels as their sample spacings do, a main
sequence that does not diverge and a finite band narrower than the quantity. A failed check gives "no verdict" with
its reason, never "consistent". Then the verdict names the models of the workbench's hierarchy (solved on the case's
own scene: :mod:`workbench.external.models`) whose band holds the extrapolated value, or none.

Output (only inside the output folder, :func:`workbench.paths.checked_paths`): ``<out>/score_<case>/`` with
``score.json``, ``report.md``, ``report.html``, ``pressure.png``. Bad input (an option, a case score cannot judge:
checked before any file is read; a malformed file, a run, step or body that is not the case's, a load the theory
cannot evaluate): one line naming it, exit 2, nothing written. This module imports no dolfinx. Units: mm, N/mm, MPa.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import NamedTuple

import numpy as np

from workbench.external.results import ExternalResult, ResultError, read_csv_groups
from workbench.external.scorers.base import ScoreError, fmt_order, plausibility

__all__ = ["level_measures", "score_levels", "write_score", "main", "ScoreError", "scoreable", "plausibility",
           "read_results", "theory_curves", "fmt_order"]

MAX_SAMPLES_PER_ELEMENT = 1000


def scoreable(case) -> None:
    """ScoreError unless ``score`` can judge ``case`` (a scene with a scorer whose check passes). Checked before any
    file is read."""
    from workbench.external.scorers import scoreable as _scoreable

    _scoreable(case)


class _Scene(NamedTuple):
    """What the block scorer reads of a case run."""

    geometry: object
    material: object


def level_measures(res: ExternalResult, *, geometry, material, h: float | None = None,
                   samples_per_element: int = 1) -> dict:
    """The block scorer's level record of one result (a block case's run with this geometry and material)."""
    from workbench.external.results import mirror_half
    from workbench.external.scorers.block import BlockScorer
    from workbench.external.scorers.runs import Group, ScoredBody, ScoredRun

    group = Group(ScoredRun("small", "small", _Scene(geometry, material), None), 0, ScoredBody("body", "slave"),
                  mirror_half(res))
    return BlockScorer().measure(None, group, h=h, samples_per_element=samples_per_element)


def score_levels(case_name: str, results: list, *, h: list[float] | None = None, samples_per_element: int = 1,
                 run=None, step=None, body=None) -> dict:
    """The score of a case's external results (``score.json``'s content); ``results``: one entry per RESULT, each a
    list of its groups (or one :class:`ExternalResult`)."""
    import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
    from cases import load_case
    from workbench.external.models import load_model_bands
    from workbench.external.scorers import score_case

    case = load_case(case_name)
    files = [r if isinstance(r, list) else [r] for r in results]
    return score_case(case, files, h=h, samples_per_element=samples_per_element, run=run, step=step, body=body,
                      bands=load_model_bands(case.name, case=case))


def _json_ready(score: dict) -> dict:
    """``score`` without the private keys (``_...``) the plot reads."""
    out = dict(score)
    out["levels"] = [{k: v for k, v in lv.items() if not k.startswith("_")} for lv in score["levels"]]
    return out


def _fmt(v, digits: int = 8) -> str:
    from workbench.reports.markdown import fmt

    return fmt(v, digits) if v is None or isinstance(v, float) else str(v)


def _level_tables(score: dict) -> list[str]:
    """One table per (run, step, body): a row per level with its load, peak, half-width and quantities."""
    lines = []
    groups: dict[tuple, list[dict]] = {}
    for lv in score["levels"]:
        groups.setdefault((lv["run"], lv["step"], lv["body"]), []).append(lv)
    for (run, step, body), levels in groups.items():
        levels = sorted(levels, key=lambda lv: lv["h"])
        qs = list(dict.fromkeys(q for lv in levels for q in lv.get("quantities", {})))
        errs = [e for e in ("p_max", "half_width", "half_width_moment", "rms", "patch_uniformity", "load_balance")
                if any(isinstance(lv.get("errors", {}).get(e), float) and math.isfinite(lv["errors"][e])
                       for lv in levels)]
        d = f", d = {levels[0]['d']:g} mm" if "d" in levels[0] else ""
        lines += [f"### run {run}, step {step}{d}, body {body} ({levels[0].get('role', '')})", "",
                  "| file | h (mm) | P (N/mm) | " + " | ".join(qs) + " | "
                  + " | ".join(f"{e} err" for e in errs) + " |",
                  "|---" * (3 + len(qs) + len(errs)) + "|"]
        for lv in levels:
            cells = [Path(lv["file"]).name, _fmt(lv["h"], 5), _fmt(lv["P"], 8)]
            cells += [_fmt(lv["quantities"].get(q), 8) for q in qs]
            cells += [f"{lv['errors'][e]:+.3%}" if isinstance(lv["errors"].get(e), float) else "-" for e in errs]
            lines.append("| " + " | ".join(cells) + " |")
        lines.append("")
    return lines


def _study_table(score: dict) -> list[str]:
    st = score.get("studies") or {}
    if not st:
        return []
    lines = ["## Grid studies (three finest levels)", "",
             "| study | fine | extrapolated | observed order | band | status | theory | from theory | in band |",
             "|---|---|---|---|---|---|---|---|---|"]
    for key, s in st.items():
        fine, ext = s.get("fine"), s.get("extrapolated")
        band = (s["band"] / abs(fine) if fine and math.isfinite(s.get("band", math.nan)) else math.nan)
        th = s.get("theory")
        dev = f"{ext / th - 1.0:+.4%}" if th and ext is not None else ("-" if th is None else f"{ext:.3g}")
        inside = "-" if "outside_band" not in s else ("no" if s["outside_band"] else "yes")
        if s.get("kind") == "bound":
            inside = "-" if s.get("within_tolerance") is None else ("yes" if s["within_tolerance"] else "no")
        name = f"{s.get('theory_name', '')} {th:.6g}" if th is not None else "-"
        lines.append(f"| {key} | {_fmt(fine)} | {_fmt(ext)} | {fmt_order(s.get('observed_order'))} | "
                     f"{band:.3%} | {s.get('status', '')} | {name} | {dev} | {inside} |")
    return lines + [""]


def _report_md(score: dict) -> str:
    lines = [f"# External result scored against `{score['case']}`", "", f"**{score.get('headline', '')}**", "",
             f"**Verdict.** {score['verdict']}", "", "## Levels", ""]
    lines += _level_tables(score)
    lv0 = score["levels"][0]
    lines += [f"Level size h: {lv0['h_source']}. Positions: {lv0['configuration']} configuration. Theory at each "
              f"level's load P ({lv0['P_source']}). Runs: " + "; ".join(
                  f"{r['label']} ({r['kinematics']}" + (", added" if r["added"] else "") + ")" for r in score["runs"])
              + ".", ""]
    merged = [f"{Path(lv['file']).name}: {lv['merged_samples']}" for lv in score["levels"] if lv.get("merged_samples")]
    if merged:
        lines += [f"Samples at a repeated position were merged, the largest pressure kept (as for coincident nodes of "
                  f"a .frd or .vtu): {', '.join(merged)}.", ""]
    if score.get("plausibility"):
        lines += ["## Why there is no verdict", ""] + [f"- {r}" for r in score["plausibility"]] + [""]
    lines += _study_table(score)
    m = score.get("models")
    if m:
        lines += ["## The workbench's models on the same scene", "",
                  f"`{m['measure']}` of each model of the hierarchy (`{m['source']}`); the external value's "
                  f"uncertainty +-{m['uncertainty']:.4g} is its GCI band plus its load term.", "",
                  "| model | what it assumes | extrapolated | band | external - model | band contains the external "
                  "value |", "|---|---|---|---|---|---|"]
        for r in m["models"]:
            what = r["description"].split(" (", 1)[1].rstrip(")") if " (" in r["description"] else r["description"]
            lines.append(f"| {r['model']} | {what} | {r['extrapolated']:.6g} | {r['band']:.3g} | "
                         f"{r['distance']:+.4g} | {'yes' if r['contains'] else 'no'} |")
        lines.append("")
    if score.get("model_matches"):
        lines += ["Models whose band holds each study: " + "; ".join(
            f"{k}: {', '.join(v) or 'none'}" for k, v in score["model_matches"].items()) + ".", ""]
    cal = [lv for lv in score["levels"] if "load_calibration" in lv]
    if cal:
        lines += ["## Load calibration (displacement-driven deck)", "",
                  "| h (mm) | target P (N/mm) | runs: d (mm) -> P (N/mm) | final P / target |", "|---|---|---|---|"]
        for lv in cal:
            c = lv["load_calibration"]
            runs = "; ".join(f"{r['d']:.6g} -> {r['P']:.6g}" for r in c["runs"])
            ratio = c["runs"][-1]["P"] / c["target_P"]
            lines.append(f"| {_fmt(lv['h'], 5)} | {c['target_P']:.6g} | {runs} | {ratio:.4f} |")
    lines += ["", "![pressure](pressure.png)", ""]
    return "\n".join(lines)


def theory_curves(theory: dict, x: np.ndarray) -> list[tuple[str, np.ndarray, float, str]]:
    """The theory curves of a level's ``theory`` record at ``x`` (mm): (label, pressure MPa, reference pressure MPa,
    style). A circle indenter's theory is the exact circle (:mod:`analytic.circle`; the case's own), with Hertz, its
    parabolic approximation, drawn thinner beside it; the elastic cylinder's the exact circle at the combined modulus;
    other profiles their classical theory; the patch test's the uniform pressure."""
    from analytic.circle import circle_pressure

    kind = theory.get("kind")
    if kind == "uniform":
        return [("uniform P / W", np.full_like(x, theory["p"]), theory["p"], "k--")]
    if kind == "exact_circle":
        return [("exact circle (E*)", circle_pressure(x, b=theory["half_width"], R=theory["R"],
                                                      E_star=theory["E_star"]), theory["p0"], "k--")]
    from workbench.scenes.block_theory import BlockTheory

    th = BlockTheory(kind, theory["P"], theory["E_star"], theory["half_width"], theory["p0"], R=theory.get("R"),
                     m=theory.get("m"))
    ex = theory.get("exact_circle")
    if not ex:
        return [(kind, th.pressure(x), theory["p0"], "k--")]
    return [("exact circle", circle_pressure(x, b=ex["half_width"], R=theory["R"], E_star=theory["E_star"]),
             theory["p0"], "k--"), ("Hertz (parabola)", th.pressure(x), theory["p0"], "0.6")]


def _plot(score: dict, results: list, path: Path, fem: ExternalResult | None = None) -> None:
    """One panel per (run, step) of the slave body (at most eight): every level's pressure (MPa) against the surface
    coordinate (mm; the concave scenes: arc length), and the theory at the finest level's load where the scene has a
    closed form."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    curves: dict[tuple, list] = {}
    for lv in score["levels"]:
        if lv.get("role", "slave") == "slave" and "_curve" in lv:
            curves.setdefault((lv["run"], lv["step"]), []).append(lv)
    keys = list(curves)[:8]
    n = max(1, len(keys))
    cols = min(n, 2)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(6.0 * cols, 4.0 * rows), squeeze=False)
    for ax, key in zip(axes.flat, keys, strict=False):
        levels = sorted(curves[key], key=lambda lv: lv["h"])
        for lv in levels:
            s, p = lv["_curve"]
            ax.plot(s, p, ".-", ms=3, lw=0.8, label=f"{Path(lv['file']).name} (h = {lv['h']:.3g} mm)")
        fine = levels[0]
        t = fine.get("theory")
        s0, _ = fine["_curve"]
        if t and t.get("kind") in ("hertz", "wedge", "exact_circle", "uniform"):
            half = t.get("half_width") or 0.5 * float(np.ptp(s0))
            xx = (np.linspace(float(s0.min()), float(s0.max()), 801) if t["kind"] == "uniform"
                  else np.linspace(-1.3 * half, 1.3 * half, 801))
            for name, p_th, _ref, style in theory_curves(t, xx):
                ax.plot(xx, p_th, style, lw=1.2, label=f"{name} at P = {t['P']:.6g} N/mm")
            if t["kind"] != "uniform":
                ax.set_xlim(-1.5 * half, 1.5 * half)
        elif "half_width" in fine and math.isfinite(fine.get("half_width", math.nan)):
            lo = min(float(lv["_curve"][0][lv["_curve"][1] > 0].min()) for lv in levels)
            hi = max(float(lv["_curve"][0][lv["_curve"][1] > 0].max()) for lv in levels)
            pad = max(0.3 * (hi - lo), 0.2)
            ax.set_xlim(lo - pad, hi + pad)
        if fem is not None and key == keys[0]:
            ax.plot(fem.x, fem.p, "m:", lw=1.0, label=f"workbench FEM ({Path(fem.path).name})")
        d = f", d = {fine['d']:g} mm" if "d" in fine else ""
        ax.set(xlabel="s (mm, arc length of the undeformed surface)" if score["scene"] == "concave"
               else "x (mm, reference)", ylabel="contact pressure (MPa)", title=f"run {key[0]}, step {key[1]}{d}")
        ax.legend(fontsize=6)
    for ax in list(axes.flat)[len(keys):]:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def write_score(score: dict, results: list, folder: Path, *, fem: ExternalResult | None = None) -> None:
    """``score.json``, ``report.md``, ``report.html`` and ``pressure.png`` into ``folder`` (staged: a failure
    leaves the previous folder intact)."""
    from workbench.atomic import atomic_dir, write_json, write_text
    from workbench.reports.markdown import markdown_to_html

    clean = _json_ready(score)
    with atomic_dir(folder, kind="score") as stage:
        write_json(stage / "score.json", clean)
        md = _report_md(clean)
        write_text(stage / "report.md", md)
        write_text(stage / "report.html", markdown_to_html(md, title=f"score {score['case']}"))
        _plot(score, results, stage / "pressure.png", fem)


def _parser() -> argparse.ArgumentParser:
    from workbench.cli import _Parser

    p = _Parser(prog="workbench score", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("case", metavar="CASE")
    p.add_argument("results", nargs="+", metavar="RESULT", help="one file per mesh level")
    p.add_argument("--format", choices=("csv", "frd", "vtu"), default="csv")
    p.add_argument("--field", default="p_MPa", help="vtu/vtp/pvd: the point field holding the contact pressure")
    p.add_argument("--h", type=float, nargs="+", default=None, help="element size on the contact surface per RESULT")
    p.add_argument("--run", nargs="+", default=None, metavar="LABEL",
                   help="the run of RESULTs without a run column (one for all, or one per RESULT)")
    p.add_argument("--step", type=int, nargs="+", default=None, metavar="N",
                   help="the step (index in the case's schedule) of RESULTs without a step column")
    p.add_argument("--body", nargs="+", default=None, metavar="NAME",
                   help="the body of RESULTs without a body column (default: the slave surface's)")
    p.add_argument("--samples-per-element", type=int, default=1)
    p.add_argument("--configuration", choices=("reference", "current"), default="reference",
                   help="frd: positions X with CPRESS per reference length (default), or X + u with CPRESS as written")
    p.add_argument("--fem", default=None, metavar="CSV",
                   help="the workbench's own pressure.csv of the case (one run), drawn beside the external pressure")
    p.add_argument("--out", default=None, help="output folder (default: $WORKBENCH_RESULTS, else results/ of this "
                   "checkout)")
    return p


def read_results(paths: list[str], *, fmt: str, configuration: str = "reference",
                 field: str = "p_MPa") -> list[list[ExternalResult]]:
    """The groups of every RESULT file of one ``--format`` (each file refused in one line if malformed:
    :mod:`workbench.external.result_files`)."""
    from workbench.external.result_files import parsing

    out = []
    for p in paths:
        with parsing(str(p)):
            if fmt == "vtu":
                from workbench.external.vtk_xml import read_vtk_result

                out.append([read_vtk_result(p, field=field)])
            elif fmt == "frd":
                from workbench.external.frd import read_frd_result

                out.append([read_frd_result(p, configuration=configuration)])
            else:
                out.append(read_csv_groups(p))
    return out


def _check_options(args) -> None:
    if not 1 <= args.samples_per_element <= MAX_SAMPLES_PER_ELEMENT:
        text = str(args.samples_per_element)
        text = text if len(text) <= 20 else f"a number of {len(text)} digits"
        raise ScoreError(f"--samples-per-element = {text}; allowed: 1 to {MAX_SAMPLES_PER_ELEMENT}")
    if args.h is not None:
        for v in args.h:
            if not (math.isfinite(v) and v > 0):
                raise ScoreError(f"--h {v!r}; allowed: finite sizes > 0 (mm)")
    for name in ("h", "run", "step", "body"):
        value = getattr(args, name)
        if value is not None and len(value) not in ((len(args.results),) if name == "h" else (1, len(args.results))):
            allowed = "one per RESULT" if name == "h" else "one, or one per RESULT"
            raise ScoreError(f"--{name}: {len(value)} values for {len(args.results)} RESULT files; allowed: {allowed}")
    if args.step is not None and any(not 0 <= s <= 999_999 for s in args.step):
        raise ScoreError(f"--step {min(args.step)}; allowed: a step index >= 0 of the case's schedule")


def main(argv: list[str] | None = None) -> int:
    """``workbench score`` (exit 0 written, 2 bad input, 1 the results could not be written)."""
    from cases import CaseError
    from workbench import interrupt
    from workbench.owned import check_dir
    from workbench.paths import OutputError, checked_paths

    args = _parser().parse_args(argv)
    try:
        _check_options(args)
        paths = checked_paths(args.out)  # the output folder's guard, whichever way it was given
        import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
        from cases import load_case

        case = load_case(args.case)
        scoreable(case)  # before any file is read
        folder = paths.command("score_", case.name)
        check_dir(folder, kinds=("score",))
        interrupt.stage(f"reading the results scored against {case.name}")
        results = read_results(args.results, fmt=args.format, configuration=args.configuration, field=args.field)
        score = score_levels(args.case, results, h=args.h, samples_per_element=args.samples_per_element,
                             run=args.run, step=args.step, body=args.body)
        fem = None
        if args.fem:
            from workbench.external.results import read_csv_result

            with _parsing(args.fem):
                fem = read_csv_result(args.fem)
    except (ResultError, ScoreError, CaseError, OutputError) as exc:
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    interrupt.stage(f"writing {folder.name}")
    try:
        write_score(score, results, folder, fem=fem)
    except OutputError as exc:  # the folder changed meanwhile (atomic_dir checks it again)
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    except OSError as exc:  # e.g. ENOSPC: the staging folder is removed, the previous score stays
        print(f"error: score {case.name}: cannot write the results: {' '.join(str(exc.strerror or exc).split())}; "
              "previous results left intact", file=sys.stderr)
        return 1
    n_merged = sum(lv["merged_samples"] for lv in score["levels"])
    print(f"score {score['case']}: {len(results)} level(s) -> {folder}"
          + (f" ({n_merged} sample(s) at a repeated position merged, the largest pressure kept)" if n_merged else ""))
    print(score.get("headline", ""))
    print(score["verdict"])
    return 0


def _parsing(where: str):
    from workbench.external.result_files import parsing

    return parsing(where)
