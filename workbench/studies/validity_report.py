"""``report.md`` of the validity study, from ``validity.json`` alone (no dolfinx); the HTML twin and the maps are
added by :mod:`workbench.studies.validity_plot` (:func:`workbench.reports.study_pages.publish_study`)."""

from __future__ import annotations

import json
import math
from pathlib import Path

from workbench.atomic import write_text
from workbench.studies.validity_config import HP_PAIRING
from workbench.studies.where_report import where_section

__all__ = ["MODEL_MEANING", "report_markdown", "write_report"]

MODEL_MEANING = {
    "halfplane/small": "vertical gap and traction at the undeformed surface: exactly the classical half-plane "
                       "hypotheses (on a finite block, with the exact indenter profile)",
    "halfplane/convective": "vertical traction, gap read at the particle's displaced tangential position: the "
                            "Ciavarella-Hills model",
    "obstacle/small": "gap and traction along the indenter's normal, evaluated at the undeformed surface",
    "obstacle/convective": "gap and traction along the indenter's normal at the displaced position (linear "
                           "elasticity): frictionless contact of the real geometry, small strain",
    "obstacle/finite": "finite-strain hyperelasticity (total Lagrangian), contact at the deformed position along the "
                       "current normal: the most complete model",
}
THEORY_NAMES = {"hertz": "Hertz", "exact_circle": "exact circle", "ch_circle": "C-H circle",
                "ch_parabola": "C-H parabola", "ch_first_order": "C-H 1st order", "wedge": "classical wedge",
                "ch_wedge": "C-H wedge", "ch_converged": "C-H converged"}


def _param(p: dict) -> str:
    if p["scene"] == "halfplanes":
        return f"b0/R = {p['param']:g}, beta = {p['beta']:+g}"
    if p["scene"] == "cylinder":
        return f"a/R = {p['param']:g}"
    k = math.pi / p["param"]
    return f"theta = pi/{k:.0f}" if abs(k - round(k)) < 1e-6 else f"theta = {p['param']:.4g}"


def _pct(v, digits=3) -> str:
    return "-" if v is None else f"{100 * v:+.{digits}g} %"


def _band_table(points: list[dict], scene: str) -> list[str]:
    pts = [p for p in points if p["scene"] == scene]
    if not pts:
        return []
    names = list(pts[0]["theories"])
    lines = ["| point | beta | most complete model | " + " | ".join(THEORY_NAMES.get(n, n) for n in names) + " |",
             "|---|---|---|" + "---|" * len(names)]
    for p in pts:
        cells = []
        for n in names:
            q = "half_width" if n == "ch_first_order" else "moment"
            b = p["bands"].get(n, {}).get(q)
            cells.append("-" if b is None else
                         f"{b['band']} ({100 * b['difference']:.3g} +- {100 * b['uncertainty']:.2g} %)")
        lines.append(f"| {_param(p)} | {p['beta']:.3g} | {p['complete_model'] or 'none'} | " + " | ".join(cells) + " |")
    return lines


def _part(r: dict) -> str:
    """One part of a gap split: its value +- U, marked when within 3 U of zero; "not run" without a value."""
    if r["value"] is None:
        return "not run"
    used = abs(r["value"]) > 3.0 * r["uncertainty"]
    return f"{_pct(r['value'])} +- {100 * r['uncertainty']:.1g} %" + ("" if used else " (below U)")


def _split_table(points: list[dict]) -> list[str]:
    lines = ["| point | beta | complete model | total gap | profile (FEM; theory) | convective term | "
             "traction direction | finite strain |", "|---|---|---|---|---|---|---|---|"]
    for p in points:
        if p["scene"] == "halfplanes":
            continue
        s = p.get("split")
        if not s:
            lines.append(f"| {_param(p)} | {p['beta']:.3g} | - | not split: a model is missing (see the dropped "
                         "list) | | | | |")
            continue

        def cell(k, s=s):
            return _part(s[k])

        prof = cell("profile") + f"; {_pct(s['profile']['theory'])}"
        lines.append(f"| {_param(p)} | {p['beta']:.3g} | {s['complete_model']} | {cell('total')} | {prof} | "
                     f"{cell('convective')} | {cell('traction')} | {cell('finite_strain')} |")
    return lines


def _hp_sections(points: list[dict], cfg: dict) -> list[str]:
    """The two-elastic-half-planes part (issue 25): its points, bands and gap split."""
    pts = [p for p in points if p["scene"] == "halfplanes"]
    if not pts:
        return []
    hr = cfg.get("halfplanes_h_ratios", [])
    md = ["", "## Two elastic half-planes: Ciavarella-Hills over beta of both signs", "",
          "Two graded elastic blocks (non-matching meshes, `halfplanes` scene), both nu = 0, E_lower / E_upper = "
          "(1 + 2 beta) / (1 - 2 beta) (body 1 = the upper body, which carries the parabolic gap b0/R; beta > 0: it "
          f"is the softer one), E* = {cfg.get('E', 0):g} MPa, b0 = 1 mm. Each point: `small` and `convective` "
          "(`convection = \"profile\"`: Ciavarella and Hills's eq. (8)) on levels b0/h_c = "
          f"{', '.join(f'{h:g}' for h in hr)} (W = {cfg['width_factor']:g} b0) and on the middle level with W = "
          f"{cfg['width_factor_far']:g} b0. Measured: the moment ratio R = 2 sqrt(M2/M0) of the convective run over "
          "the small one's (each over Hertz's b0 at its own load), per level, then Richardson + truncation as "
          "above (U relative). Theories: the moment ratio of the converged Ciavarella-Hills pressure and of its "
          "first-order pressure over the classical one (`analytic.convective.solve`); Hertz: 1. `inside`: "
          "|theory - R| <= U R.", "",
          "![map_halfplanes](map_halfplanes.png)", "",
          "| b0/R | beta | R (FEM) +- U | GCI status | C-H converged | C-H 1st order | Hertz band | C-H converged: "
          "band, inside | C-H 1st order: band, inside | R pairing +- U |", "|---|---|---|---|---|---|---|---|---|---|"]
    for p in pts:
        m = p["models"].get(p.get("complete_model") or "", {}).get("moment")
        th = p["theories"]
        if m is None or m.get("value") is None:
            reason = next(iter(v["moment"].get("reason") for v in p["models"].values()
                               if v["moment"].get("value") is None), "see the dropped list")
            md.append(f"| {p['param']:g} | {p['beta']:+g} | no value: {reason} | | "
                      f"{th['ch_converged']['moment']:.5f} | {th['ch_first_order']['moment']:.5f} | | | | "
                      f"{_pairing_cell(p)} |")
            continue

        def band(name, p=p):
            b = p["bands"].get(name, {}).get("moment")
            if b is None:
                return "-"
            return f"{b['band']} ({100 * b['difference']:.3g} %), {'inside' if b['inside'] else 'outside'}"

        md.append(f"| {p['param']:g} | {p['beta']:+g} | {m['value']:.5f} +- {m['uncertainty'] * m['value']:.1e} | "
                  f"{m['status']} | {th['ch_converged']['moment']:.5f} | {th['ch_first_order']['moment']:.5f} | "
                  f"{band('hertz')} | {band('ch_converged')} | {band('ch_first_order')} | {_pairing_cell(p)} |")
    if any(HP_PAIRING in p["models"] for p in pts):
        md += ["", "R pairing: the same ratio with `convection = \"pairing\"` (the particles that touch carry the "
               "displacements and forces; docs/models.md), beside the profile model's R (issue 39: which one the "
               "finite-strain runs follow, below)."]
    md += ["", "### The gap to Hertz of two half-planes, split", "",
           "Moment half-width of the convective run relative to Hertz at the same load: total = S R - 1 = profile "
           "S - 1 (the small run against Hertz: theory 0) + convective S (R - 1); the convective part = the converged "
           "theory's S (R_ch - 1) + the remainder S (R - R_ch) (what the theory does not explain). S: the small run "
           "over Hertz, extrapolated. A part within 3 U of zero is marked (below U).", "",
           "| b0/R | beta | total | profile | convective (FEM) | convective (C-H converged; 1st order) | remainder |",
           "|---|---|---|---|---|---|---|"]
    for p in pts:
        s = p.get("split")
        if not s:
            md.append(f"| {p['param']:g} | {p['beta']:+g} | not split: a value is missing (see the dropped list) "
                      "| | | | |")
            continue

        def cell(k, s=s):
            return _part(s[k])

        c = s["convective"]
        md.append(f"| {p['param']:g} | {p['beta']:+g} | {cell('total')} | {cell('profile')} | {cell('convective')} "
                  f"| {_pct(c['theory'])}; {_pct(c['theory_first_order'])} | {cell('remainder')} |")
    return md + _hp_finite_section(pts, cfg)


_MAP_SYMBOL = {"convective": "C", "material law": "M", "comparable": "="}


def _pairing_value(p: dict) -> str:
    v = p["models"].get(HP_PAIRING, {}).get("moment", {}).get("value")
    return "-" if v is None else f"{v:.5f}"


def _pairing_cell(p: dict) -> str:
    m = p["models"].get(HP_PAIRING, {}).get("moment")
    if m is None:
        return "-"
    if m.get("value") is None:
        return f"no value: {m['reason']}"
    return f"{m['value']:.5f} +- {m['uncertainty'] * m['value']:.1e}"


def _hp_follows(rows: list[dict], laws: list[str]) -> list[str]:
    """Which small-strain convective model the finite-strain ratios follow (issue 39): one sentence counting the
    (point, law) rows nearer each model, and a table per beta and law over b0/R."""
    fol = [(p, law, r["follows"]) for p in rows for law, r in p["finite"]["laws"].items()
           if r.get("follows", {}).get("model") and len(r["follows"]["distance"]) == 2]
    if not fol:
        return []
    resolved = [(p, law, f) for p, law, f in fol if f["resolved"]]
    near = {m: sum(f["model"] == m for _, _, f in resolved) for m in ("profile", "pairing")}
    alone = {m: sum(f["model"] == m and f["alone"] for _, _, f in resolved) for m in ("profile", "pairing")}
    neither = sum(not any(d["inside"] for d in f["distance"].values()) for _, _, f in fol)
    md = ["", f"**Which small-strain model: of {len(fol)} finite-strain rows, the profile and pairing models are "
          f"apart beyond their bands at {len(resolved)}; there F is nearer profile at {near['profile']} (within its "
          f"band and not pairing's at {alone['profile']}) and nearer pairing at {near['pairing']} (alone in its band "
          f"at {alone['pairing']}); at {neither} of {len(fol)} F lies in neither model's band.**", "",
          "Per beta and law, over b0/R: the nearer model, F minus it, and whether F is in its band (`in`), in the "
          "other's too (`both`), or in neither (`out`); `~` where the two models are within their bands of each "
          "other (not resolved).", ""]
    params = sorted({p["param"] for p, _, _ in fol})
    md += ["| beta | law | " + " | ".join(f"b0/R = {q:g}" for q in params) + " |",
           "|---|---|" + "---|" * len(params)]
    cells = {(p["beta"], law, p["param"]): f for p, law, f in fol}
    for beta in sorted({p["beta"] for p, _, _ in fol}):
        for law in laws:
            row = []
            for q in params:
                f = cells.get((beta, law, q))
                if f is None:
                    row.append("-")
                    continue
                d = f["distance"][f["model"]]
                where = ("both" if all(x["inside"] for x in f["distance"].values()) else "in" if d["inside"]
                         else "out")
                row.append(f"{'' if f['resolved'] else '~'}{f['model']} {_pct(d['difference'])} ({where})")
            md.append(f"| {beta:+g} | {law} | " + " | ".join(row) + " |")
    return md


def _hp_finite_section(pts: list[dict], cfg: dict) -> list[str]:
    """The finite-strain rows of the two-half-planes part (issue 39): the verdict sentence, the map over (b0/R,
    beta), the rows per point and law."""
    rows = [p for p in pts if p.get("finite", {}).get("laws")]
    if not rows:
        return []
    laws = list(cfg.get("halfplanes_finite_laws", []))
    verdicts = [p["finite"].get("spread", {}).get("verdict") for p in rows]
    n = {v: sum(x == v for x in verdicts) for v in _MAP_SYMBOL}
    missing = sum(v is None for v in verdicts)
    outside = sum(not r["inside"]["ch_converged"] for p in rows for r in p["finite"]["laws"].values()
                  if r["ratio"].get("value") is not None)
    total = sum(r["ratio"].get("value") is not None for p in rows for r in p["finite"]["laws"].values())
    head = (f"**Verdict: at {n['material law']} of {len(rows)} points the spread between the two material laws is "
            f"larger than the whole convective correction (beyond the bands), at {n['convective']} the convective "
            f"correction is the larger, at {n['comparable']} they are within the bands of each other"
            + (f" ({missing} without both laws)" if missing else "") + f"; {outside} of {total} finite-strain "
            "values lie outside the band of the converged Ciavarella-Hills theory.**")
    hr = cfg.get("halfplanes_finite_h_ratios", [])
    md = ["", "### At finite strain: both bodies hyperelastic (issue 39)", "", head, "",
          f"Each point and law ({', '.join(f'`{x}`' for x in laws)}): both bodies that law, P1 on levels b0/h_c = "
          f"{', '.join(f'{h:g}' for h in hr)} and the middle one on the wide block, the upper body meshed as the "
          "parabola capped at 3 b0, the traction along the deformed master normal (docs/models.md). F = its moment "
          "half-width over Hertz's (extrapolated) over the small run's, U the root sum of squares of both relative "
          "bands. Against F: the converged theory R_ch and its first order, and the small-strain convective model "
          "R (the table above), each `in` when within the combined band. F - R is finite strain and the traction "
          "direction together (finite strain with the vertical traction is refused). The spread is F of the first "
          "law minus F of the second; the verdict compares |R_ch - 1| with |spread| +- its band.", "",
          "Map (rows b0/R, columns beta): C the convective correction outweighs the law spread, M the law spread "
          "outweighs the convective correction, = neither beyond the bands, . no verdict "
          "(`map_halfplanes_finite.png`: the same, coloured, with |R_ch - 1| and |spread| in %).", "",
          "![map_halfplanes_finite](map_halfplanes_finite.png)", ""]
    follows = _hp_follows(rows, laws)
    params = sorted({p["param"] for p in rows})
    betas = sorted({p["beta"] for p in rows})
    grid = {(p["param"], p["beta"]): _MAP_SYMBOL.get(p["finite"].get("spread", {}).get("verdict"), ".")
            for p in rows}
    md += ["| b0/R \\ beta | " + " | ".join(f"{b:+g}" for b in betas) + " |",
           "|---|" + "---|" * len(betas)]
    md += [f"| {q:g} | " + " | ".join(grid.get((q, b), ".") for b in betas) + " |" for q in params]
    md += follows
    md += ["", "| b0/R | beta | law | F +- U | status | R_ch; in | 1st order; in | R (profile); in | R (pairing); in | "
           "F - R_ch | R - 1 (conv. model) | F - R (finite strain + traction) |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for p in rows:
        th, fin = p["theories"], p["finite"]
        R = p["models"].get(p.get("complete_model") or "", {}).get("moment", {})
        for law, r in fin["laws"].items():
            f = r["ratio"]
            if f.get("value") is None:
                md.append(f"| {p['param']:g} | {p['beta']:+g} | {law} | no value: {f['reason']} | | | | | | | | |")
                continue
            ins = r["inside"]

            def yn(k, ins=ins):
                return "-" if k not in ins else ("in" if ins[k] else "out")

            sp = r.get("split", {})
            md.append(f"| {p['param']:g} | {p['beta']:+g} | {law} | {f['value']:.5f} +- "
                      f"{f['uncertainty'] * f['value']:.1e} | {r['moment'].get('status', '-')} | "
                      f"{th['ch_converged']['moment']:.5f}; {yn('ch_converged')} | "
                      f"{th['ch_first_order']['moment']:.5f}; {yn('ch_first_order')} | "
                      + (f"{R['value']:.5f}; {yn('profile')}" if R.get("value") is not None else "-")
                      + f" | {_pairing_value(p)}; {yn('pairing')} | {_pct(r['minus_converged'])} | "
                      + (f"{_pct(sp['convective_model'])} | {_pct(sp['finite_strain_and_traction'])} +- "
                         f"{100 * sp['uncertainty']:.2g} %" if sp else "- | -") + " |")
        if "spread" in fin:
            sp = fin["spread"]
            md.append(f"| {p['param']:g} | {p['beta']:+g} | spread {' - '.join(sp['laws'])} | "
                      f"{sp['value']:+.5f} +- {sp['uncertainty']:.1e} | verdict: {sp['verdict']} | "
                      f"R_ch - 1 = {_pct(fin['convective_correction'])} | | | | | | |")
    return md


def _dropped_param(d: dict) -> str:
    if d.get("scene") == "halfplanes":
        return f"b0/R = {d['param']:.4g}, beta = {d['beta']:+g}"
    return f"{d['param']:.4g}"


def report_markdown(data: dict) -> str:
    """The report of the study JSON ``data``."""
    s, cfg, points = data["summary"], data["config"], data["points"]
    md = ["# Validity of the half-plane theories", "",
          f"{s['runs']} FEM runs ({s['failed']} failed), {s['points']} points, wall time {s['wall_time_s']:.0f} s "
          f"on {s['workers']} {s.get('executor', 'local')} worker(s) ({s.get('cpu_count')} cores seen here"
          + (f"; CPU time of the workers {s['cpu_s_workers']:.0f} s: on a shared machine the wall time includes "
             "waiting" if s.get("cpu_s_workers") is not None else "; the ranks' own times: see the end") + "). "
          "Every value is a ratio to the classical "
          "theory (Hertz or the classical wedge) at the run's measured load.", "",
          "## What each model means", ""]
    md += [f"- `{k}`: {v}" for k, v in MODEL_MEANING.items() if tuple(k.split("/")) in {tuple(m) for m in
                                                                                       cfg["models"]}]
    md += ["", "## How the numbers are made", "",
           f"Quantity: the moment half-width 2 sqrt(M2/M0) of the contact pressure (p_max for the circle too; the "
           f"zero-crossing half-width for the first-order closed forms, which give no pressure). Levels a/h_c = "
           f"{', '.join(f'{h:g}' for h in cfg['h_ratios'])} on a block W = {cfg['width_factor']:g} a give the "
           "Richardson value and its GCI; one run on the middle level with W = "
           f"{cfg['width_factor_far']:g} a corrects the truncation ((4/3) of the change, order 1 in a/W assumed) "
           "with a third of the change as its uncertainty. U = GCI + truncation. A theory's band is used only "
           f"where U is below the difference / {cfg['resolve_factor']:g}, or where difference + U is below "
           f"{100 * cfg['thresholds'][0]:g} % (then the verdict holds whatever the difference); otherwise it is "
           "`unresolved` and listed with its reason below. The most complete model is the last of "
           "obstacle/finite, obstacle/convective, ... that has a value at the point (finite strain has no mixed "
           "formulation: not run at nu >= 0.45).", ""]
    fs = data.get("finite_settings")
    if fs:
        md += [f"Finite-strain runs: {fs['load_steps']} load steps (each increment at most twice the last), a "
               f"backtracking line search, up to {fs['max_cutbacks']} step halvings, Nitsche theta = "
               f"{fs['nitsche_theta']:g} (the symmetric variant's active set cycled on the steep wedges); St "
               f"Venant-Kirchhoff wedges steeper than theta = {fs['svk_wedge_theta_max']:.4g} rad are skipped (it "
               "loses ellipticity below the stretch 1/sqrt(3); docs/models.md).", ""]
    md += ["## Maps", "", "![map_cylinder](map_cylinder.png)", "", "![map_wedge](map_wedge.png)", "",
           "## Bands, point by point (difference from the most complete model +- its uncertainty)", "",
           "### Cylinder (exact circle)", ""]
    md += _band_table(points, "cylinder")
    md += ["", "### Wedge", ""]
    md += _band_table(points, "wedge")
    md += _hp_sections(points, cfg)
    md += ["", "## Where the gap to classical theory comes from (rigid indenters)", "",
           "Moment half-width, relative to the classical value. total = complete model - 1 = profile + convective + "
           "traction (+ finite strain), exactly: profile = FEM(halfplane, small) - 1 (the exact circle against "
           "Hertz's parabola; its half-plane theory value beside it; 0 for the wedge), convective = "
           "FEM(halfplane, convective) - FEM(halfplane, small), traction = FEM(obstacle, convective) - "
           "FEM(halfplane, convective), finite strain = FEM(obstacle, finite) - FEM(obstacle, convective). A part "
           "within 3 U of zero is marked (below U).", ""]
    md += _split_table(points)
    md += _elastic_wedge_section(data.get("claim_elastic_wedge") or {})
    claim = data.get("claim") or {}
    md += ["", "## A rigid wedge: the traction along the face normal against the vertical one (not the paper's "
           "claim)", "",
           "The same quantity for another problem: a RIGID wedge on the block, two FEM models of the contact "
           "traction's direction. It tells how much that modelling choice moves the stresses; the paper's claim, "
           "an elastic wedge of the same material, is the section above.", "",
           f"Quantity: {claim.get('quantity', '-')}, probes x/b in {list(claim.get('probes_x_over_b', []))}, "
           f"z/b in {list(claim.get('probes_z_over_b', []))}.", ""]
    v = claim.get("verdict")
    md += [f"**Verdict: {v['text']}.**" if v else "**No verdict: the runs are missing (see the dropped list).**", ""]
    md += ["| theta | level | obstacle FEM vs theory | same, deepest row z = 2b | vertical-traction FEM vs theory "
           "(floor) | obstacle vs vertical FEM |", "|---|---|---|---|---|---|"]
    for r in claim.get("rows", []):
        for level in ("h2", "far"):
            c = r.get(level, {})
            if "obstacle_vs_theory" in c:
                md.append(f"| pi/{1 / r['theta_over_pi']:.0f} | {level} | {100 * c['obstacle_vs_theory']:.2f} % | "
                          f"{100 * c['obstacle_vs_theory_deepest_row']:.2f} % | "
                          f"{100 * c['halfplane_vs_theory']:.2f} % | "
                          f"{100 * c['obstacle_vs_halfplane_fem']:.2f} % |")
            else:
                md.append(f"| pi/{1 / r['theta_over_pi']:.0f} | {level} | {c.get('reason', '-')} | | | |")
    md += ["", "## Dropped or failed, and why", ""]
    dropped = data.get("dropped", [])
    if not dropped:
        md.append("Nothing was dropped.")
    else:
        md += ["| what | scene | parameter | nu | model / theory | quantity or level | reason |",
               "|---|---|---|---|---|---|---|"]
        for d in dropped:
            md.append(f"| {d['what']} | {d['scene']} | {_dropped_param(d)} | {d['nu']:g} | "
                      f"{d.get('model') or d.get('theory', '-')} | {d.get('quantity') or d.get('level', '-')} | "
                      f"{d['reason']} |")
    md += [""] + where_section(wall_time_s=s.get("wall_time_s"), records=data.get("runs", []), label=_run_label,
                               reference=s.get("reference"))
    return "\n".join(md) + "\n"


def _elastic_wedge_section(claim: dict) -> list[str]:
    """The paper's claim as it states it (:mod:`workbench.studies.validity_elastic_wedge`): verdict and table."""
    md = ["", "## The paper's claim: theta < pi/5, internal stresses within 0.5 % (elastic wedge, same material)", "",
          "An elastic wedge (faces y = m |x|, m = tan theta, meshed) pressed onto a block of the same material "
          f"(nu = {claim.get('nu', float('nan')):g}, beta = 0), against the half-plane solution at the measured "
          "load. `geometry` = shaped FEM minus the half-plane-idealised FEM (the upper block flat, the wedge an "
          "analytic gap) on the same sizes; `floor` = the idealised FEM against the half-plane solution. "
          f"Quantity: {claim.get('quantity', '-')}, probes x/b in +-{list(claim.get('probes_x_over_b', []))}, "
          f"depth z/b below each body's own surface in {list(claim.get('probes_z_over_b', []))}. U = GCI of three "
          "levels + the change to 4x wider bodies. Small strain, the contact traction vertical on both bodies "
          "(the flat block's normal). The verdict is the block's: inside the wedge the comparison depends on the "
          "frame (its faces are inclined) and on the traction's direction (docs/models.md).", ""]
    v = claim.get("verdict")
    md += [f"**Verdict: {v['text']}.**" if v else "**No verdict: the runs are missing (see the dropped list).**", ""]
    md += ["| theta | block: geometry (finest) | U (grid + width) | grid status | block: shaped FEM vs theory | "
           "floor | wedge: geometry +- U | moment half-width shaped / flat |", "|---|---|---|---|---|---|---|---|"]
    for r in claim.get("rows", []):
        t = f"{r['theta_over_pi']:.3g} pi"
        if "geometry" not in r:
            md.append(f"| {t} | no value: a run of the pair is missing or failed | | | | | | |")
            continue
        fine = r["levels"]["h2"]
        md.append(f"| {t} | {100 * r['geometry']:.2f} % | {100 * r['U']:.2f} % | {r['status']} | "
                  f"{100 * r['shaped_vs_theory']:.2f} % | {100 * r['floor']:.2f} % | "
                  f"{100 * r['geometry_wedge']:.2f} % +- {100 * r['U_wedge']:.2f} % | "
                  f"{fine['moment_shaped']:.4f} / {fine['moment_flat']:.4f} |")
    return md + _elastic_wedge_finite(claim)


def _elastic_wedge_finite(claim: dict) -> list[str]:
    """The shaped pair at finite strain (issue 39, item 4): per angle and law, F = its moment half-width over the
    small-strain shaped pair's, both extrapolated with their bands."""
    rows = [(r, law, f) for r in claim.get("rows", []) for law, f in (r.get("finite") or {}).items()]
    if not rows:
        return []
    done = [(r, law, f) for r, law, f in rows if f["ratio"].get("value") is not None]
    beyond = [(r, law) for r, law, f in done if f["beyond_bound"]]
    md = ["", "### The shaped wedge at finite strain (issue 39)", "",
          f"**Of {len(rows)} (angle, law) rows, {len(done)} have a value; at {len(beyond)} of them finite strain with "
          "the traction along the deformed interface changes the moment half-width by more than the claim's "
          "bound beyond its band.**", "",
          "Both bodies the hyperelastic law (from the same E and nu), P1, the traction along the wedge's current face "
          "normal, on the shaped pair's meshes. M: the moment half-width over the classical wedge's 2 b / sqrt(6) "
          "at the measured load (extrapolated as the two half-planes' values, band relative); S: the small-strain "
          "shaped pair's (P2); F = M / S, its band the root sum of squares. Under a wedge the contact strain is of "
          "the order of the slope m = tan theta whatever the load, so F - 1 is first order in m, its sign and size "
          "set by the material law.", "",
          "| theta | law | M +- U | status | S +- U | F +- U | beyond the bound | levels with a solver warning |",
          "|---|---|---|---|---|---|---|---|"]
    for r, law, f in rows:
        t = f"{r['theta_over_pi']:.3g} pi"
        if f["ratio"].get("value") is None:
            md.append(f"| {t} | {law} | no value: {f['ratio']['reason']} | | | | | |")
            continue
        M, S, F = f["moment"], f["small"], f["ratio"]
        md.append(f"| {t} | {law} | {M['value']:.4f} +- {M['uncertainty'] * M['value']:.1e} | {M['status']} | "
                  f"{S['value']:.4f} +- {S['uncertainty'] * S['value']:.1e} | {F['value']:.4f} +- "
                  f"{F['uncertainty'] * F['value']:.1e} | {'yes' if f['beyond_bound'] else 'no'} | "
                  f"{', '.join(M.get('warned_levels', [])) or 'none'} |")
    return md


def _run_label(r: dict) -> str:
    t = r["task"]
    if t["scene"] == "halfplanes":
        return f"halfplanes b0/R={t['param']:.4g} beta={t['beta']:+g} {r['model']} {t['level']}"
    return f"{t['scene']} {t['param']:.4g} nu={t['nu']:g} {r['model']} {t['level']}"


def write_report(folder: Path) -> Path:
    """Write ``folder/report.md`` from ``folder/validity.json``."""
    folder = Path(folder)
    data = json.loads((folder / "validity.json").read_text())
    path = folder / "report.md"
    write_text(path, report_markdown(data))
    return path
