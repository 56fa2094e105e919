"""``workbench score CASE RESULT... [--format csv] [--h H...] [--out DIR]``: an external code's contact
pressure, one RESULT per mesh level, against the case's theory, with the workbench's own definitions.

Per level (:func:`level_measures`; every measure from :mod:`measures.contact`, the code the FEM pipeline uses):

* ``P``: the file's load column if it has one (the external load), else ``P_integral``;
* ``P_integral``: the integral of the pressure over the samples (N/mm): the file's ``weight_mm`` quadrature
  weights, else the trapezoid rule; the edges use the file's ``q_MPa`` pressure argument, else q = p;
* ``p_max``: the largest sampled pressure of the main patch (MPa);
* ``half_width``: the edge fit (square-root edge model through the two outermost active samples, else the
  linear zero crossing; :func:`measures.contact.contact_edges`) of the main patch, half its width (mm);
* ``half_width_moment``: ``2 sqrt(M2/M0)`` of the pressure (trapezoid weights; = a for a Hertz pressure), mm;
* ``errors``: signed relative errors of ``p_max``, ``half_width``, ``half_width_moment`` against the case's
  classical theory at the level's load ``P`` (the block scenes' :func:`workbench.scenes.block_theory.block_theory`),
  and ``rms`` = RMS(p - p_theory)/p0 over the patch (:func:`measures.contact.rms_error`, as the FEM's rms);
* vtu/vtp/pvd results (:mod:`workbench.external.vtk_xml`): the point field ``--field`` on the block top;
* frd results (:mod:`workbench.external.frd`): the nodes on the block top, CPRESS turned into force per
  reference length (``--configuration reference``, default) or kept at the current positions (``current``);
* ``h``: the level's element size on the contact surface: ``--h`` or the file's ``h_mm`` column, else
  ESTIMATED as the median sample spacing inside the patch times the samples per element (``--samples-per-element``,
  default 1: nodal values); ``h_source`` says which.

With three or more levels the three finest go through :func:`workbench.error_budget.grid_study` for the ratios
``p_max/p0``, ``half_width_moment/a`` (formal order 2) and ``half_width/a`` (1.5): observed order, GCI band,
extrapolated value. The verdict splits the extrapolated difference from the theory into the discretisation band
and a remainder, after the plausibility checks (:func:`plausibility`): the levels carry one load (to twice the
case's p_max tolerance), their sizes h rank them as their sample spacings do, each level's contact half-width is
within a factor 2 of the theory's at its load (positions in mm, pressures in MPa), the sequence does not diverge,
and the band is finite and narrower than the quantity. A failed check gives "no verdict" with its reason, never
"consistent". Output (only inside the output folder, :func:`workbench.paths.checked_paths`):
``<out>/score_<case>/`` with ``score.json``, ``report.md``, ``report.html``, ``pressure.png``. Bad input (an option,
a case score cannot judge: checked before any file is read, a malformed file, a load the theory cannot
evaluate): one line naming it, exit 2, nothing written. This module imports no dolfinx (the score needs no solve).
Units: mm, N/mm, MPa.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

from measures.contact import SurfaceSamples, find_patches, moment_half_width, rms_error, trapezoid_weights
from workbench.external.results import ExternalResult, ResultError, read_csv_result

__all__ = ["level_measures", "score_levels", "write_score", "main", "ScoreError", "scoreable", "plausibility"]

FORMAL = {"p_max": 2.0, "half_width_moment": 2.0, "half_width": 1.5}
INDENTERS = ("circle", "parabola")  # the block indenters with a Hertz peak, the quantity the verdict reads
MAX_SAMPLES_PER_ELEMENT = 1000
HALF_WIDTH_FACTOR = 2.0  # a level's contact half-width within this factor of the theory's at its load
SPACING_TIE = 0.1  # sample spacings closer than this (relative) do not rank two levels


class ScoreError(ValueError):
    """Bad input to the scorer (one line)."""


def _samples(x: np.ndarray, p: np.ndarray, w: np.ndarray, q: np.ndarray) -> SurfaceSamples:
    z = np.zeros_like(x)
    return SurfaceSamples(s=x, X=np.column_stack([x, z]), x=np.column_stack([x, z]), p=p, q=q, sigma_nn=p,
                          gap=z, weight=w)


def _theory(geometry, material, P: float, *, where: str):
    """The case's classical theory at the level's load ``P``; ResultError (one line) where it cannot be evaluated
    (a load of 0, or beyond what a half-plane under the indenter carries: a file in other units?)."""
    from workbench.scenes.block_theory import block_theory

    if not (math.isfinite(P) and P > 0):
        raise ResultError(f"{where}: its load P = {P:.6g} N/mm; allowed: a finite load > 0 (a pressure that "
                          "integrates to 0: all weights 0?)")
    try:
        th = block_theory(geometry, material, P=P)
        if geometry.indenter == "circle":
            from analytic.circle import circle_contact

            circle_contact(P, th.R, th.E_star)
    except (ValueError, ArithmeticError) as exc:
        raise ResultError(f"{where}: its load P = {P:.6g} N/mm is outside what the case's theory evaluates "
                          f"({' '.join(str(exc).split())[:160]}); positions in mm and pressures in MPa?") from None
    if not all(math.isfinite(v) and v > 0 for v in (th.half_width, th.p_ref)):
        raise ResultError(f"{where}: its load P = {P:.6g} N/mm gives a theory half-width {th.half_width:.3g} mm and "
                          f"peak {th.p_ref:.3g} MPa; allowed: a load whose theory is finite and > 0")
    return th


def level_measures(res: ExternalResult, *, geometry, material, h: float | None = None,
                   samples_per_element: int = 1) -> dict:
    """The measures of one level against the case's theory at the level's load (see the module docstring)."""
    x, p = res.x, res.p
    w = trapezoid_weights(x) if res.weight is None else res.weight
    q = p if res.q is None else res.q
    patches = find_patches(_samples(x, p, w, q))
    if not patches:
        raise ResultError(f"{res.path}: no contact patch (no positive pressure between two samples)")
    main = max(patches, key=lambda pt: pt.P)
    with np.errstate(over="ignore", under="ignore"):
        P_int = float(np.sum(w * p))
    P = res.load if res.load is not None else P_int
    if not (math.isfinite(P_int) and P_int > 0):
        raise ResultError(f"{res.path}: the pressure integrates to P = {P_int:.6g} N/mm; allowed: a finite load > 0 "
                          "(all weights 0? pressures in MPa?)")
    th = _theory(geometry, material, P, where=res.path)
    inside = np.abs(x - main.center) <= main.half_width
    dx = np.diff(x[inside])
    spacing = float(np.median(dx)) if dx.size else math.nan
    if h is not None:
        h_val, h_source = h, "option --h"
    elif res.h is not None:
        h_val, h_source = res.h, "column h_mm"
    else:
        h_val = spacing * samples_per_element
        h_source = f"estimated: median sample spacing in the patch x {samples_per_element} sample(s) per element"
    hw_m = 2.0 * moment_half_width(x, p, w)
    errors = {
        "p_max": (main.p_max - th.p_ref) / th.p_ref if th.kind == "hertz" else math.nan,
        "half_width": (main.half_width - th.half_width) / th.half_width,
        "half_width_moment": (hw_m - th.half_width) / th.half_width if th.kind == "hertz" else math.nan,
        "rms": rms_error(x, p, th.pressure(x), center=0.0, half_width=max(main.half_width, th.half_width),
                         p_ref=th.p_ref),
        "load_balance": (P_int - P) / P,
    }
    if geometry.indenter == "circle":  # the case's own theory: the exact circle (Hertz is its parabolic form)
        from analytic.circle import circle_contact, circle_pressure

        ex = circle_contact(P, th.R, th.E_star)
        errors["p_max_vs_exact_circle"] = (main.p_max - ex.p0) / ex.p0
        errors["half_width_vs_exact_circle"] = (main.half_width - ex.half_width) / ex.half_width
        errors["rms_vs_exact_circle"] = rms_error(
            x, p, circle_pressure(x, b=ex.half_width, R=th.R, E_star=th.E_star), center=0.0,
            half_width=max(main.half_width, ex.half_width), p_ref=ex.p0)
        exact = {"p0": ex.p0, "half_width": ex.half_width}
    else:
        exact = None
    return {"file": res.path, "half_model": res.half, "configuration": res.configuration,
            "samples": int(x.size), "merged_samples": int(res.merged), "spacing": spacing,
            "h": h_val, "h_source": h_source,
            "P": P, "P_source": "file" if res.load is not None else "integral", "P_integral": P_int,
            "p_max": main.p_max, "half_width": main.half_width, "half_width_moment": hw_m, "center": main.center,
            "patches": len(patches),
            "theory": {"kind": th.kind, "P": th.P, "p0": th.p_ref, "half_width": th.half_width,
                       "E_star": th.E_star, "R": th.R, "exact_circle": exact},
            "errors": errors}


def _check_surface(results: list[ExternalResult], run) -> None:
    """ResultError when a result's positions leave the case's contact surface (the block top, |x| <= W/2)."""
    from workbench.scenes.block_theory import block_theory

    ld = run.loading
    target = (block_theory(run.geometry, run.material, P=ld.P) if ld.P is not None
              else block_theory(run.geometry, run.material, half_width=ld.half_width))
    half_w = 0.5 * run.geometry.width_factor * target.half_width
    for r in results:
        far = float(np.max(np.abs(r.x)))
        if far > half_w * (1.0 + 1e-6):
            raise ResultError(f"{r.path}: positions reach |x| = {far:.6g} mm, beyond the case's block top "
                              f"(|x| <= W/2 = {half_w:.6g} mm): the surface does not match the case")


def _study(levels: list[dict]) -> dict:
    """Observed order, GCI and extrapolation of the three finest levels (ratios to the theory at each load)."""
    from workbench.error_budget import grid_study

    fine = sorted(levels, key=lambda lv: lv["h"])[:3]
    hs = tuple(lv["h"] for lv in fine)
    if len(set(hs)) < 3 or not all(math.isfinite(v) and v > 0 for v in hs):
        raise ScoreError(f"the three finest levels need three different sizes h > 0, got {hs}; give --h")
    out = {"h": list(hs)}
    for key, ref in (("p_max", "p0"), ("half_width_moment", "half_width"), ("half_width", "half_width")):
        f = tuple(lv[key] / lv["theory"][ref] for lv in fine)
        if not all(math.isfinite(v) for v in f):
            continue
        gs = grid_study(hs, f, expected_order=FORMAL[key], reference=1.0, formal_order=FORMAL[key])
        deviation = gs.extrapolated - 1.0
        band = gs.gci * abs(gs.fine)
        # the load the pressure integrates to differs from the level's load P by load_balance; the theory's
        # p0 and a go as sqrt(P), so the ratio is uncertain by half of it (finest level)
        load_term = 0.5 * abs(fine[0]["errors"]["load_balance"])
        out[key] = gs._asdict() | {"ratios": list(f), "deviation": deviation, "band": band,
                                    "load_term": load_term, "uncertainty": band + load_term,
                                    "remainder": (math.copysign(abs(deviation) - band, deviation)
                                                  if abs(deviation) > band else 0.0),
                                    "outside_band": bool(abs(deviation) > band)}
    return out


def plausibility(levels: list[dict], study: dict | None, *, p_max_tolerance: float | None) -> list[str]:
    """Why no verdict may be given (empty: a verdict may be given): see the module docstring. ``levels``: the
    :func:`level_measures` records; ``study``: :func:`_study`'s; ``p_max_tolerance``: the case's (relative)."""
    reasons = []
    for lv in levels:
        ratio = lv["half_width"] / lv["theory"]["half_width"]
        if not (math.isfinite(ratio) and 1.0 / HALF_WIDTH_FACTOR <= ratio <= HALF_WIDTH_FACTOR):
            reasons.append(f"{Path(lv['file']).name}: its contact half-width {lv['half_width']:.4g} mm is "
                           f"{ratio:.3g} times the theory's at its load {lv['P']:.6g} N/mm (allowed: within a factor "
                           f"{HALF_WIDTH_FACTOR:g}; positions in mm and pressures in MPa?)")
    loads = [lv["P"] for lv in levels]
    allowed = 2.0 * (p_max_tolerance if p_max_tolerance else 0.005)
    if len(loads) > 1 and max(loads) / min(loads) - 1.0 > allowed:
        reasons.append(f"the levels' loads differ by {max(loads) / min(loads) - 1.0:.3%} ({min(loads):.6g} to "
                       f"{max(loads):.6g} N/mm); the case allows {allowed:.2%} (twice its p_max tolerance: p0 goes "
                       "as sqrt(P)), so they are not one problem at several resolutions")
    given = [lv for lv in levels if not lv["h_source"].startswith("estimated")]
    inverted = next(((a, b) for a in given for b in given if a["h"] < b["h"]
                     and math.isfinite(a["spacing"]) and math.isfinite(b["spacing"])
                     and a["spacing"] > (1.0 + SPACING_TIE) * b["spacing"]), None)
    if inverted is not None:
        a, b = inverted
        reasons.append(f"the sizes h rank {Path(a['file']).name} (h = {a['h']:.4g} mm) finer than "
                       f"{Path(b['file']).name} (h = {b['h']:.4g} mm), but its samples are "
                       f"{a['spacing'] / b['spacing']:.3g} times wider apart: h does not decrease with the levels "
                       "(--h in reverse order?)")
    s = (study or {}).get("p_max")
    if s is not None:
        if s["status"] == "diverging":
            reasons.append("the three finest levels diverge (their differences grow on refinement): no order, no "
                           "extrapolation")
        if not (math.isfinite(s["band"]) and s["band"] < abs(s["fine"])):
            reasons.append(f"the discretisation band +-{s['band']:.4g} is not finite or not narrower than the "
                           f"quantity ({s['fine']:.4g})")
        if not math.isfinite(s["extrapolated"]):
            reasons.append("the extrapolated value is not finite")
    return reasons


def model_match(study: dict | None, bands: dict | None) -> dict | None:
    """Which of the workbench's models (:mod:`workbench.external.models`, solved on the case's own scene) the
    extrapolated peak is consistent with: every model with its distance and whether its band contains the
    result (|external - model| <= U_external + U_model, U_external = GCI band + load term)."""
    if study is None or "p_max" not in study or bands is None:
        return None
    from workbench.external.models import consistent_models, describe

    s = study["p_max"]
    inside = consistent_models(bands, measure="p_max", value=s["extrapolated"], uncertainty=s["uncertainty"])
    rows = []
    for m in bands["models"]:
        st = m["study"]["p_max"]
        rows.append({"model": f"{m['traction']}/{m['kinematics']}", "description": describe(m),
                     "traction": m["traction"], "kinematics": m["kinematics"], "material_model": m["material_model"],
                     "extrapolated": st["extrapolated"], "band": st["band"],
                     "distance": s["extrapolated"] - st["extrapolated"],
                     "contains": any(i["traction"] == m["traction"] and i["kinematics"] == m["kinematics"]
                                     for i in inside)})
    return {"measure": "p_max / p0 (Hertz at the measured load)", "uncertainty": s["uncertainty"],
            "source": bands.get("command"), "models": rows}


def _idealisation(match: dict) -> str:
    """The idealisation the consistent models share, in words (derived from their fields)."""
    inside = [r for r in match["models"] if r["contains"]]
    if not inside:
        near = min(match["models"], key=lambda r: abs(r["distance"]))
        return (f"No model of the workbench's hierarchy on this scene contains it; the nearest is "
                f"{near['description']}, {near['distance']:+.3%} away (uncertainty +-{match['uncertainty']:.3%}).")
    names = ", ".join(r["model"] for r in inside)
    tractions = {r["traction"] for r in inside}
    kinematics = {r["kinematics"] for r in inside}
    text = f"Consistent with the workbench's model(s) {names}: "
    if len(tractions) == 1:
        t = tractions.pop()
        text += ("the traction along the obstacle's normal" if t == "obstacle"
                 else "the vertical (half-plane) traction")
        if len(kinematics) == 1:
            text += f" with {kinematics.pop()} kinematics"
        else:
            spread = max(r["extrapolated"] for r in inside) - min(r["extrapolated"] for r in inside)
            text += (f" (kinematics {' and '.join(sorted(kinematics))} agree to {spread:.4%} here: the deformed "
                     "normal cannot be told from the undeformed one at this load)")
    else:
        text += "models of different traction directions: the result does not single out an idealisation"
    outside = [r for r in match["models"] if not r["contains"]]
    if outside:
        text += "; not " + ", ".join(f"{r['model']} ({r['distance']:+.3%})" for r in outside)
    return text + "."


def verdict(study: dict | None, kind: str, match: dict | None = None, exact: float | None = None,
            reasons: list[str] | None = None) -> str:
    """One paragraph: the extrapolated peak against the theory, split into the discretisation band and the rest,
    and the models of the workbench's hierarchy whose band contains it (``match``, :func:`model_match`).
    ``exact``: the exact circle's p0 over Hertz's at the finest level's load (circle indenters). ``reasons``
    (:func:`plausibility`): no verdict, and why."""
    if study is None or "p_max" not in study:
        return "fewer than three levels: no extrapolation (give three or more RESULT files, one per mesh level)"
    if reasons:
        return "No verdict: " + "; ".join(reasons) + "."
    s = study["p_max"]
    dev, band = s["deviation"], s["band"]
    vs = f"{dev:+.3%} from {kind}"
    if exact is not None:
        vs = f"{s['extrapolated'] / exact - 1.0:+.3%} from the exact circle, {dev:+.3%} from Hertz"
    text = (f"extrapolated p_max/p0 = {s['extrapolated']:.6f} ({vs}); discretisation band (GCI) "
            f"+-{band:.3%}, observed order {fmt_order(s['observed_order'])} ({s['status']}). ")
    if not s["outside_band"]:
        text += "The difference is within the discretisation band: consistent with the theory."
    else:
        text += (f"The remainder {s['remainder']:+.3%} is outside the band: not discretisation but a modelling "
                 "difference.")
    if match is not None:
        text += " " + _idealisation(match)
    return text


def headline(study: dict | None, match: dict | None, reasons: list[str] | None = None) -> str:
    """One sentence to read first: how far the peak is, how much is discretisation, which models hold it (or why
    there is no verdict: ``reasons``)."""
    if study is None or "p_max" not in study:
        return "Fewer than three mesh levels: no extrapolation, no verdict."
    if reasons:
        return f"No verdict: {reasons[0]}" + (f" (and {len(reasons) - 1} more reason(s))." if len(reasons) > 1
                                              else ".")
    s = study["p_max"]
    part = "not discretisation" if s["outside_band"] else "within it"
    text = (f"The peak extrapolates to {s['deviation']:+.2%} from Hertz; the discretisation band is "
            f"+-{s['band']:.2%}, so the difference is {part}")
    if match is not None:
        inside = [r["model"] for r in match["models"] if r["contains"]]
        text += (f"; it lies within the band of the workbench's {', '.join(inside)}" if inside
                 else "; no model of the workbench's hierarchy holds it")
    return text + "."


def fmt_order(v) -> str:
    return "-" if v is None or not math.isfinite(v) else f"{v:.3g}"


def scoreable(case) -> None:
    """ScoreError unless ``score`` can judge ``case``: a block scene under an indenter with a Hertz peak
    (:data:`INDENTERS`; the verdict reads p_max/p0). Checked before any file is read."""
    g = case.runs()[0].geometry
    if g.scene != "block" or getattr(g, "indenter", None) not in INDENTERS:
        raise ScoreError(f"case {case.name}: scene {g.scene!r} indenter {getattr(g, 'indenter', None)!r} cannot be "
                         f"scored (the verdict reads the Hertz peak p_max/p0); allowed: block scenes with a "
                         f"{' or '.join(INDENTERS)} indenter")


def score_levels(case_name: str, results: list[ExternalResult], *, h: list[float] | None = None,
                 samples_per_element: int = 1) -> dict:
    """The score of a case's external results (``score.json``'s content)."""
    import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
    from cases import load_case

    case = load_case(case_name)
    scoreable(case)
    run = case.runs()[0]
    _check_surface(results, run)
    if h is not None and len(h) != len(results):
        raise ScoreError(f"--h: {len(h)} sizes for {len(results)} RESULT files; allowed: one per file")
    with np.errstate(all="ignore"):  # extreme values are named by the checks below, not as numpy warnings
        levels = [level_measures(r, geometry=run.geometry, material=run.material,
                                 h=None if h is None else h[i], samples_per_element=samples_per_element)
                  for i, r in enumerate(results)]
        study = _study(levels) if len(levels) >= 3 else None
    reasons = plausibility(levels, study, p_max_tolerance=case.tolerances.get("p_max"))
    kind = levels[0]["theory"]["kind"]
    from workbench.external.models import load_model_bands

    match = None if reasons else model_match(study, load_model_bands(case.name, run=run))
    fine = min(levels, key=lambda lv: lv["h"])
    ex = fine["theory"]["exact_circle"]
    exact = ex["p0"] / fine["theory"]["p0"] if ex else None
    theory = "exact circle" if ex else kind
    return {"case": case.name, "theory": theory, "ratios_to": kind,
            "units": {"length": "mm", "load": "N/mm", "pressure": "MPa"},
            "levels": levels, "grid_study": study, "plausibility": reasons, "models": match,
            "headline": headline(study, match, reasons), "verdict": verdict(study, kind, match, exact, reasons)}


def _report_md(score: dict) -> str:
    from workbench.reports.markdown import fmt

    lines = [f"# External result scored against `{score['case']}`", "", f"**{score.get('headline', '')}**", "",
             f"**Verdict.** {score['verdict']}", "",
             "| file | h (mm) | P (N/mm) | p_max (MPa) | a edge (mm) | a moment (mm) | p_max err (Hertz) | a err | "
             "a_mom err | RMS/p0 |", "|---|---|---|---|---|---|---|---|---|---|"]
    for lv in score["levels"]:
        e = lv["errors"]
        lines.append(f"| {Path(lv['file']).name} | {fmt(lv['h'])} | {fmt(lv['P'], 8)} | {fmt(lv['p_max'], 8)} | "
                     f"{fmt(lv['half_width'], 8)} | {fmt(lv['half_width_moment'], 8)} | {e['p_max']:+.3%} | "
                     f"{e['half_width']:+.3%} | {e['half_width_moment']:+.3%} | {e['rms']:.3%} |")
    lines += ["", f"Level size h: {score['levels'][0]['h_source']}. "
              f"Positions: {score['levels'][0]['configuration']} configuration. "
              f"Theory ({score['theory']}) at each level's load "
              f"P ({score['levels'][0]['P_source']}).", ""]
    merged = [f"{Path(lv['file']).name}: {lv['merged_samples']}" for lv in score["levels"] if lv.get("merged_samples")]
    if merged:
        lines += [f"Samples at a repeated position were merged, the largest pressure kept (as for coincident nodes of "
                  f"a .frd or .vtu): {', '.join(merged)}.", ""]
    if score.get("plausibility"):
        lines += ["## Why there is no verdict", ""] + [f"- {r}" for r in score["plausibility"]] + [""]
    st = score.get("grid_study")
    if st:
        lines += ["## Grid study (three finest levels)", "",
                  "| measure / theory | fine | extrapolated | observed order | GCI band | status |",
                  "|---|---|---|---|---|---|"]
        for key in ("p_max", "half_width_moment", "half_width"):
            if key in st:
                s = st[key]
                lines.append(f"| {key} | {s['fine']:.6f} | {s['extrapolated']:.6f} | {fmt(s['observed_order'], 3)} | "
                             f"{s['band']:.3%} | {s['status']} |")
    m = score.get("models")
    if m:
        lines += ["", "## The workbench's models on the same scene", "",
                  f"Extrapolated p_max/p0 (Hertz) of each model of the hierarchy (`{m['source']}`); the external "
                  f"value's uncertainty +-{m['uncertainty']:.3%} is its GCI band plus half its finest level's "
                  "load balance.", "", "| model | what it assumes | p_max/p0 | band | external - model | "
                  "band contains the external value |", "|---|---|---|---|---|---|"]
        for r in m["models"]:
            lines.append(f"| {r['model']} | {r['description'].split(' (', 1)[1].rstrip(')')} | "
                         f"{r['extrapolated']:.6f} | {r['band']:.4%} | {r['distance']:+.3%} | "
                         f"{'yes' if r['contains'] else 'no'} |")
    cal = [lv for lv in score["levels"] if "load_calibration" in lv]
    if cal:
        lines += ["", "## Load calibration (displacement-driven deck)", "",
                  "| h (mm) | target P (N/mm) | runs: d (mm) -> P (N/mm) | final P / target |", "|---|---|---|---|"]
        for lv in cal:
            c = lv["load_calibration"]
            runs = "; ".join(f"{r['d']:.6g} -> {r['P']:.6g}" for r in c["runs"])
            ratio = c["runs"][-1]["P"] / c["target_P"]
            lines.append(f"| {fmt(lv['h'])} | {c['target_P']:.6g} | {runs} | {ratio:.4f} |")
    lines += ["", "![pressure](pressure.png)", ""]
    return "\n".join(lines)


def _plot(score: dict, results: list[ExternalResult], path: Path, fem: ExternalResult | None = None) -> None:
    """Left: the external pressure of every level and the theory at the finest level's load (MPa, mm). Right:
    every curve over its own theory at its own load (p/p0 against x/a), the workbench's FEM too."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from workbench.scenes.block_theory import BlockTheory

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11.0, 4.2))
    curves = [(r, lv, f"{Path(lv['file']).name} (h = {lv['h']:.3g} mm)", ".-") for lv, r in
              zip(score["levels"], results, strict=True)]
    for r, _lv, label, style in curves:
        ax.plot(r.x, r.p, style, ms=3, lw=0.8, label=label)
    fine = min(score["levels"], key=lambda lv: lv["h"])
    t = fine["theory"]
    th = BlockTheory(t["kind"], t["P"], t["E_star"], t["half_width"], t["p0"], R=t["R"])
    xx = np.linspace(-1.3 * th.half_width, 1.3 * th.half_width, 801)
    for name, p_th, p_ref, style in theory_curves(t, xx):
        ax.plot(xx, p_th, style, lw=1.2, label=f"{name} at P = {t['P']:.6g} N/mm")
        bx.plot(xx / th.half_width, p_th / p_ref, style, lw=1.2, label=name)
    ax.set_xlim(-1.5 * th.half_width, 1.5 * th.half_width)
    ax.set(xlabel="x (mm, reference)", ylabel="contact pressure (MPa)", title="external result")
    ax.legend(fontsize=7)
    if fem is not None and "fem_level" in score:
        curves.append((fem, score["fem_level"], f"workbench FEM ({Path(fem.path).name})", "m:"))
    for r, lv, label, style in curves:
        bx.plot(r.x / lv["theory"]["half_width"], r.p / lv["theory"]["p0"], style, ms=3, lw=0.9, label=label)
    bx.set_xlim(-1.5, 1.5)
    bx.set(xlabel="x / a (theory at each curve's own load)", ylabel="p / p0 (Hertz)", title="each at its own load")
    bx.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def theory_curves(theory: dict, x: np.ndarray) -> list[tuple[str, np.ndarray, float, str]]:
    """The theory curves of a level's ``theory`` record at ``x`` (mm): (label, pressure MPa, Hertz p0 MPa, style).
    A circle indenter's theory is the exact circle (:mod:`analytic.circle`; the case's own), with Hertz, its
    parabolic approximation, drawn thinner beside it; other indenters their classical theory."""
    from workbench.scenes.block_theory import BlockTheory

    th = BlockTheory(theory["kind"], theory["P"], theory["E_star"], theory["half_width"], theory["p0"], R=theory["R"])
    ex = theory.get("exact_circle")
    if not ex:
        return [(theory["kind"], th.pressure(x), theory["p0"], "k--")]
    from analytic.circle import circle_pressure

    return [("exact circle", circle_pressure(x, b=ex["half_width"], R=theory["R"], E_star=theory["E_star"]),
             theory["p0"], "k--"), ("Hertz (parabola)", th.pressure(x), theory["p0"], "0.6")]


def write_score(score: dict, results: list[ExternalResult], folder: Path, *, fem: ExternalResult | None = None) -> None:
    """``score.json``, ``report.md``, ``report.html`` and ``pressure.png`` into ``folder`` (staged: a failure
    leaves the previous folder intact)."""
    from workbench.atomic import atomic_dir, write_json, write_text
    from workbench.reports.markdown import markdown_to_html

    with atomic_dir(folder, kind="score") as stage:
        write_json(stage / "score.json", score)
        md = _report_md(score)
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
    p.add_argument("--samples-per-element", type=int, default=1)
    p.add_argument("--configuration", choices=("reference", "current"), default="reference",
                   help="frd: positions X with CPRESS per reference length (default), or X + u with CPRESS as written")
    p.add_argument("--fem", default=None, metavar="CSV",
                   help="the workbench's own pressure.csv of the case, drawn beside the external pressure")
    p.add_argument("--out", default=None, help="output folder (default: $WORKBENCH_RESULTS, else results/ of this "
                   "checkout)")
    return p


def read_results(paths: list[str], *, fmt: str, configuration: str = "reference",
                 field: str = "p_MPa") -> list[ExternalResult]:
    """The RESULT files of one ``--format`` (each refused in one line if malformed:
    :mod:`workbench.external.result_files`)."""
    from workbench.external.result_files import parsing

    out = []
    for p in paths:
        with parsing(str(p)):
            if fmt == "vtu":
                from workbench.external.vtk_xml import read_vtk_result

                out.append(read_vtk_result(p, field=field))
            elif fmt == "frd":
                from workbench.external.frd import read_frd_result

                out.append(read_frd_result(p, configuration=configuration))
            else:
                out.append(read_csv_result(p))
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
        score = score_levels(args.case, results, h=args.h, samples_per_element=args.samples_per_element)
        fem = read_results([args.fem], fmt="csv")[0] if args.fem else None
        if fem is not None:
            run = case.runs()[0]
            score["fem_level"] = level_measures(fem, geometry=run.geometry, material=run.material)
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
