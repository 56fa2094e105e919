"""Markdown report of the convergence study (reads its JSON only; formatting, no study code imported).

Run: ``python -m workbench.studies.convergence_report [JSON]`` -> ``report.md`` next to the JSON
(``workbench convergence`` writes it through :func:`workbench.studies.convergence.write_outputs`; default JSON
``<results>/convergence/convergence.json``). Every number in the report is read from the JSON; the only
constants typed here are the derivations of the expected rates (:data:`RATE_NOTES`). The run-time slope uses
the shared fit of :mod:`workbench.studies.rates`.
"""

from __future__ import annotations

import math
import statistics
import sys
from pathlib import Path

from workbench.atomic import write_text
from workbench.paths import default_paths
from workbench.studies.rates import fit_rate
from workbench.studies.where_report import where_section

__all__ = ["RATE_NOTES", "discussion", "main", "to_markdown"]
HZ, WD = "hertz_cylinder", "wedge_convective"

RATE_NOTES = """\
**Hertz: the square-root edge caps the L2 pressure error at h^1, for P1 and P2.** Near the edge,
p = p0 sqrt(1 - x^2/a^2) ~ p0 sqrt(2 r / a) with r = a - |x|. The mesh size at the edge is proportional to h
(the edge refinement h_c/2 included), so on the element holding the edge any polynomial misses sqrt(r) by
O(p0 sqrt(h/a)) over a length h: that element alone contributes O(h) to the L2 norm over the patch. On the
element k h away from the edge the interpolation error of the (discontinuous) stress of degree P - 1 is
h^P |p^(P)| ~ h^P (k h)^(1/2 - P), whose squares times h sum over k to O(h^2) for P2 and to O(h^2 log(1/h))
for P1. Hence rms and l2 ~ h^1 for both degrees (expected rate 1.0). This agrees with the a priori
estimate of Nitsche contact (Chouly, Hild & Renard 2015): for u in H^(1+nu), nu <= P,
||u - u_h||_1 + ||(h/gamma0)^(1/2) (sigma_n(u) - sigma_n(u_h))||_L2(contact) <= C h^nu. With p ~ r^(1/2)
the displacement behaves like r^(3/2), u in H^(5/2 - eps): P2 gives nu = 3/2 - eps, an H1 displacement
rate of ~1.5 but an L2 pressure rate of nu - 1/2 = 1 - eps; h^1.5 is therefore not reachable for the
pressure on this mesh family. P1 has the bound nu - 1/2 = 1/2 only, but its best approximation is O(h);
the expected rate stated is the approximation rate 1.0. The interior band |x| <= 0.8 a (column l2_inner)
has no singularity, so it is expected to converge faster than the whole patch if the edge limits the rate.
Peak pressure and half-width have no stated rate: the peak is a maximum over Gauss points and the FEM
half-width is the position of the last loaded point, which jumps with the mesh.

**Wedge: the log apex singularity caps it at h^(1/2).** p = (E* m / pi) arccosh(b/|x|) ~ (E* m / pi)
ln(2 b/|x|) at the apex. On the apex element [0, h'] (h' = h_c/4, still proportional to h) the best
constant leaves int_0^h' (ln(x/h') - c)^2 dx = C h' (the ln h' part is absorbed by the constant), an
O(h^(1/2)) contribution that dominates the O(h) of the square-root edges at |x| = b (the elements k h'
away add h' sum 1/k^4 for P2, h' sum 1/k^2 for P1: also O(h^(1/2))). Expected rate 0.5 for rms and l2 in
both wedge series: the block size barely changes the wedge rms (Model floors table), so the case series is
judged as well.

**Penalty (kappa = kappa0 E / h).** Its consistency error is the penetration p/kappa = p h/(kappa0 E): an
elastic layer whose compliance, relative to the block's ~a/E, is ~h_c/kappa0 (< 4e-4 here), falling with
h. So the same rates are expected as for Nitsche; the Gauss-point zig-zag of kappa [-g]_+ is what breaks
them in practice (penalty paragraph below)."""


def _e(v) -> str:
    return "-" if v is None or (isinstance(v, float) and not math.isfinite(v)) else f"{v:.2e}"


def _t(v) -> str:
    return "-" if v is None or (isinstance(v, float) and not math.isfinite(v)) else f"{v:.3f}"


def _s(v) -> str:
    return "-" if v is None else f"{v:+.2f}"


def _status(r: dict) -> str:
    if not r["failed"]:
        return "ok"
    return "diverged (SNES max iterations)" if "DIVERGED_MAX_IT" in r["failed"] else r["failed"][:80]


def _group(rows: list[dict], *keys: str) -> dict[tuple, list[dict]]:
    out: dict[tuple, list[dict]] = {}
    for r in rows:
        out.setdefault(tuple(r[k] for k in keys), []).append(r)
    return out


def _find(rows: list[dict], **match) -> dict | None:
    """The row matching every ``key=value`` (finest h_c when ``h_contact`` is not given), or None."""
    sel = [r for r in rows if all(r.get(k) == v for k, v in match.items()) and not r.get("failed")]
    return min(sel, key=lambda r: r["h_contact"]) if sel else None


def _rate(data: dict, case: str, series: str, method: str, degree: int, metric: str) -> dict:
    for x in data["rates"]:
        if (x["case"], x["series"], x["method"], x["degree"], x["metric"]) == (case, series, method, degree,
                                                                              metric):
            return x
    return {"slope_h": None, "slope_ndofs": None, "verdict": "", "expected": None}


def _slope(data: dict, *key) -> float | None:
    return _rate(data, *key)["slope_h"]


def _header(data: dict) -> list[str]:
    lv, sec = data["levels"], data.get("section_wall_time_s", {})
    ideal = ", ".join(f"{v:g} (growth {1 + data['growth_per_h'] * v:.3g})" for v in lv["ideal"])
    parts = "; ".join(f"{k} {v:.0f} s" for k, v in sec.items())
    return ["# Convergence study: error against run time", "",
            f"Series `case`: the case files as they are (mesh growth 1.3), h_c/a = "
            f"{', '.join(f'{v:g}' for v in lv['case'])}. Series `ideal`: model floors removed (block "
            f"640 a, Hertz parabola) and the grading refined with h_c, growth = 1 + {data['growth_per_h']:g} "
            f"h_c, so the whole size field h(d) = h_c a + (growth - 1) d scales with h_c: h_c/a = {ideal}.",
            "",
            f"Times are WARM solver times: each run was solved once to warm the JIT/form caches (cold = that "
            f"first solve), then {data['repeats']} more identical times; the median is reported. Whole "
            f"study: {data['study_wall_time_s']:.0f} s, {_how(data)} ({parts}). Slopes: least "
            f"squares of log(error) against log(h_c) / log(ndofs) over the finest {data['n_finest']} levels.",
            ""]


def _how(data: dict) -> str:
    """How the study ran (an older JSON: serial, one process)."""
    if data.get("executor", "local") == "local" and data.get("workers", 1) == 1:
        return "serial, one process"
    return f"{data.get('workers')} {data.get('executor')} workers (warm times on shared cores: see the worker table)"


def _rates_section(data: dict) -> list[str]:
    band = data["rate_band"]
    lines = ["## Expected rates", "", RATE_NOTES, "",
             f"Observed against expected (slope vs h_c over the finest {data['n_finest']} levels, band "
             f"+-{band:g}):", "", "| case | series | method | P | metric | expected | observed | verdict |",
             "|---" * 8 + "|"]
    for x in data["rates"]:
        if x.get("expected") is not None:
            lines.append(f"| {x['case']} | {x['series']} | {x['method']} | {x['degree']} | {x['metric']} | "
                         f"{x['expected']:.2f} | {_s(x['slope_h'])} | {x['verdict']} |")
    return lines + [""]


def _series_tables(data: dict) -> list[str]:
    lines = []
    for (case, series), sel in _group(data["rows"], "case", "series").items():
        mets = data["metrics"][case]
        tcol, ccol = ("time_pair_s", "cold_pair_s") if case.startswith("wedge") else ("time_s", "cold_s")
        overrides = data["series"][case][series] or "none"
        lines += [f"## {case}, series `{series}` (geometry overrides {overrides})", "",
                  "| method | P | h_c/a | growth | ndofs | warm s | cold s | " + " | ".join(mets)
                  + " | Newton its | solver warnings |", "|---" * (9 + len(mets)) + "|"]
        for r in sel:
            lines.append(f"| {r['method']} | {r['degree']} | {r['h_contact']:g} | {r['growth']:.3g} | "
                         f"{r['ndofs']} | {_t(r[tcol])} | {_t(r[ccol])} | "
                         + " | ".join(_e(r[m]) for m in mets)
                         + f" | {r['newton_iterations']} | {r['warnings'] or '-'} |"
                         + (f" {_status(r)}" if r["failed"] else ""))
        if case.startswith("wedge"):
            lines += ["", "Wedge times: the small + convective pair (b/b0 needs both); half_width, rms and "
                      "l2: the small run against the classical wedge (p_ref = P/(2b))."]
        lines += ["", f"Fitted slopes, finest {data['n_finest']} levels (vs h_c / vs ndofs):", "",
                  "| method | P | " + " | ".join(mets) + " |", "|---" * (2 + len(mets)) + "|"]
        for method, degree in sorted({(r["method"], r["degree"]) for r in sel}):
            cells = [f"{_s(f['slope_h'])} / {_s(f['slope_ndofs'])}"
                     for f in (_rate(data, case, series, method, degree, m) for m in mets)]
            lines.append(f"| {method} | {degree} | " + " | ".join(cells) + " |")
        best = data["cheapest_rms"].get(f"{case}/{series}")
        found = (f"{best['method']} P{best['degree']} h_c/a = {best['h_contact']:g} ({best['ndofs']} dofs, "
                 f"warm {best['time_s']:.3f} s, rms {best['rms']:.2e})" if best else "none reached it")
        lines += ["", f"Cheapest configuration with rms <= {data['rms_target']:.1%}: {found}", ""]
    return lines


def _diagnostic_tables(data: dict) -> list[str]:
    lines = []
    if data.get("floors"):
        lines += [f"## Model floors (Nitsche P2, h_c/a = {data['levels']['case'][-1]:g}, growth 1.3)", "",
                  "| case | variant | ndofs | p_max | half_width | rms | l2 | b_over_b0 | rms_convective |",
                  "|---" * 9 + "|"]
        for f in data["floors"]:
            lines.append(f"| {f['case']} | {f['series']} | {f['ndofs']} | " + " | ".join(
                _e(f[k]) for k in ("p_max", "half_width", "rms", "l2", "b_over_b0", "rms_convective")) + " |")
        lines.append("")
    if data.get("kappa0_sweep"):
        lines += [f"## Penalty factor sweep (case geometry, h_c/a = {data['kappa0_level']:g})", "",
                  "| case | P | kappa0 | p_max | half_width | rms | b_over_b0 | Newton its | status |",
                  "|---" * 9 + "|"]
        for f in data["kappa0_sweep"]:
            lines.append(f"| {f['case']} | {f['degree']} | {f['kappa0']:g} | " + " | ".join(
                _e(f[k]) for k in ("p_max", "half_width", "rms", "b_over_b0"))
                + f" | {f['newton_iterations']} | {_status(f)} |")
        lines.append("")
    if data.get("grading_probe"):
        base = {(r["degree"], r["h_contact"]): r for r in data["rows"]
                if (r["case"], r["series"], r["method"]) == (HZ, "ideal", "nitsche")}
        lines += ["## Grading probe (hertz_cylinder, ideal geometry, Nitsche)", "",
                  "Fixed growth 1.3 (the case default) against the ideal series' growth 1 + "
                  f"{data['growth_per_h']:g} h_c at the same h_c.", "",
                  "| P | h_c/a | ndofs 1.3 | ndofs ideal | rms 1.3 | rms ideal | l2_inner 1.3 | "
                  "l2_inner ideal |",
                  "|---" * 8 + "|"]
        for r in data["grading_probe"]:
            b = base.get((r["degree"], r["h_contact"]), {})
            lines.append(f"| {r['degree']} | {r['h_contact']:g} | {r['ndofs']} | {b.get('ndofs', '-')} | "
                         + " | ".join(f"{_e(r[k])} | {_e(b.get(k))}" for k in ("rms", "l2_inner")) + " |")
        lines += ["", "Slopes vs h_c of the fixed-growth probe: " + "; ".join(
            f"P{x['degree']} {x['metric']} {_s(x['slope_h'])}" for x in data.get("grading_rates", [])
            if x["metric"] in ("rms", "l2_inner")), ""]
    if data.get("extension"):
        ext = data["extension_setting"]
        lines += [f"## Extension level ({ext['case']}, series `{ext['series']}`, h_c/a = {ext['level']:g}, "
                  f"growth {1 + data['growth_per_h'] * ext['level']:g})", "",
                  "Growth below the case schema's 1.05: a diagnostic, solved once (time = cold solve). "
                  "Slopes refitted over the finest three levels including this one.", "",
                  "| method | P | ndofs | cold s | p_max | half_width | rms | l2 | l2_inner | rms slope | "
                  "l2 slope | l2_inner slope | verdict (rms, l2) |", "|---" * 13 + "|"]
        er = {(x["method"], x["degree"], x["metric"]): x for x in data.get("extension_rates", [])}
        errs, fits = ("p_max", "half_width", "rms", "l2", "l2_inner"), ("rms", "l2", "l2_inner")
        for r in data["extension"]:
            k = (r["method"], r["degree"])
            lines.append(f"| {r['method']} | {r['degree']} | {r['ndofs']} | {_t(r['cold_s'])} | "
                         + " | ".join(_e(r[m]) for m in errs) + " | "
                         + " | ".join(_s(er.get((*k, m), {}).get("slope_h")) for m in fits)
                         + f" | {er.get((*k, 'rms'), {}).get('verdict', '-')}, "
                         f"{er.get((*k, 'l2'), {}).get('verdict', '-')} |")
        lines.append("")
    ec = _edge_constant(data)
    if ec:
        lines += ["## Edge position (hertz_cylinder, ideal geometry, Nitsche P2, growth 1 + "
                  f"{data['growth_per_h']:g} h_c)", "",
                  "The study levels, the extension level and h_c perturbed by +-10 % (solved once). If the "
                  "error is C h_c with C set by where the contact edge falls in its element, rms/h_c "
                  "scatters around a constant instead of drifting.", "",
                  "| h_c/a | growth | ndofs | rms | rms / h_c | half_width |", "|---" * 6 + "|"]
        for r in ec:
            lines.append(f"| {r['h_contact']:g} | {r['growth']:.4g} | {r['ndofs']} | {_e(r['rms'])} | "
                         f"{r['rms'] / r['h_contact']:.4f} | {_e(r['half_width'])} |")
        lines.append("")
    return lines


def _edge_constant(data: dict) -> list[dict]:
    """Nitsche P2 rows of the Hertz ideal geometry with refined grading at h_c <= 0.1, coarse to fine."""
    rows = [r for r in data["rows"] if (r["case"], r["series"], r["method"], r["degree"])
            == (HZ, "ideal", "nitsche", 2) and r["h_contact"] <= 0.1]
    extra = [r for r in data.get("extension", []) + data.get("perturbed", [])
             if (r["method"], r["degree"]) == ("nitsche", 2)]
    if not data.get("perturbed"):
        return []
    return sorted((r for r in rows + extra if not r["failed"] and r["rms"]), key=lambda r: -r["h_contact"])


def _p_run_time(data: dict) -> list[str]:
    out = []
    for series in ("case", "ideal"):
        n2 = sorted((r for r in data["rows"] if (r["case"], r["series"], r["method"], r["degree"])
                     == (HZ, series, "nitsche", 2) and not r["failed"]), key=lambda r: -r["h_contact"])
        if len(n2) >= data["n_finest"]:
            tfit = fit_rate([r["ndofs"] for r in n2], [r["time_s"] for r in n2])
            out.append(f"Hertz Nitsche P2 `{series}`: warm time ~ ndofs^{tfit.slope:.2f} over the finest "
                       f"levels ({n2[-1]['ndofs']} dofs: {n2[-1]['time_s']:.3f} s)")
    ok = [r for r in data["rows"] if not r["failed"] and r["time_s"]]
    sp = max((r["repeat_spread"] for r in ok), default=0.0)
    ratio = statistics.median(r["cold_s"] / r["time_s"] for r in ok) if ok else math.nan
    return ["**Run time.** " + "; ".join(out) + ". The wedge pair costs more: its force-controlled runs "
            "need several times more Newton iterations (column Newton its). Cold (first solve in the "
            f"process) over warm time, median over all rows: {ratio:.2f}: fem.solver starts the clock of "
            "wall_time_s after building its NonlinearProblem, so the form JIT stays outside the timed "
            "load stepping and the warm-up solve mainly guards against first-call effects. Repeated solves "
            f"are deterministic (largest relative change of the FEM half-width over repeats: {sp:.1e}).", ""]


def _p_hertz(data: dict) -> list[str]:
    rows, out = data["rows"], []
    fl = {f["series"]: f for f in data.get("floors", []) if f["case"] == HZ}
    c, b_, p_ = (fl.get(k) for k in ("case (W = H = 40 a, circle)", "W = H = 640 a, circle",
                                       "W = H = 640 a, parabola"))
    if c and b_ and p_:
        out += ["**Hertz, case series: model floors, not a method limit.** At the finest level Nitsche P2 "
                f"has p_max {c['p_max']:.1e}, rms {c['rms']:.1e}. A block 16 times larger (W = H = 640 a) "
                "gives "
                f"{b_['p_max']:.1e} / {b_['rms']:.1e} (finite clamped block), and the parabola instead of "
                f"the exact circle (a/R = 0.05) {p_['p_max']:.1e} / {p_['rms']:.1e}; the fixed grading 1.3 "
                "adds its own floor (grading probe). The case-series slopes (Nitsche P2 rms "
                f"{_s(_slope(data, HZ, 'case', 'nitsche', 2, 'rms'))}) measure the distance between the "
                "modelled scene and half-plane Hertz theory; no rate is expected there.", ""]
    txt = []
    for method in ("nitsche", "penalty"):
        for degree in (1, 2):
            r, ri = (_rate(data, HZ, "ideal", method, degree, m) for m in ("rms", "l2_inner"))
            f = _find(rows, case=HZ, series="ideal", method=method, degree=degree)
            e = next((x for x in data.get("extension_rates", [])
                      if (x["case"], x["method"], x["degree"], x["metric"]) == (HZ, method, degree, "rms")),
                     None)
            if f:
                txt.append(f"{method} P{degree} rms {_s(r['slope_h'])} ({r['verdict'] or '-'}), l2_inner "
                           f"{_s(ri['slope_h'])}, finest rms {f['rms']:.1e}"
                           + (f", rms refitted with the extension level {_s(e['slope_h'])} ({e['verdict']})"
                              if e else ""))
    gp = {(r["degree"], r["h_contact"]): r for r in data.get("grading_probe", [])}
    g2 = min((k for k in gp if k[0] == 2), default=None, key=lambda k: k[1])
    b2 = _find(rows, case=HZ, series="ideal", method="nitsche", degree=2, h_contact=g2[1]) if g2 else None
    probe = ""
    if g2 and b2:
        gr = {(x["degree"], x["metric"]): x["slope_h"] for x in data.get("grading_rates", [])}
        probe = (f" With the fixed growth 1.3 instead, at h_c/a = {g2[1]:g} Nitsche P2 has rms "
                 f"{gp[g2]['rms']:.1e} against {b2['rms']:.1e} (slopes P1 {_s(gr.get((1, 'rms')))}, P2 "
                 f"{_s(gr.get((2, 'rms')))}): the far-field elements, whose size a fixed growth never "
                 "reduces, set the floor of a fixed-growth study.")
    ec = _edge_constant(data)
    edge = ""
    if ec:
        c = [r["rms"] / r["h_contact"] for r in ec]
        lo, hi = min(c), max(c)
        edge = (f" Nitsche P2 rms/h_c stays within {lo:.4f} .. {hi:.4f} for h_c/a = "
                f"{ec[-1]['h_contact']:g} .. {ec[0]['h_contact']:g} (edge-position table): the error "
                "behaves as C h_c with a C that depends on the mesh near the edge, so a slope over one "
                f"halving can move by up to log2({hi:.4f}/{lo:.4f}) = {math.log2(hi / lo):.2f} around 1.")
    if txt:
        out += ["**Hertz, ideal series (growth refined with h_c).** Slopes vs h_c over the finest levels: "
                + "; ".join(txt) + "." + probe + edge, ""]
    return out


def _p_penalty(data: dict) -> list[str]:
    rows = data["rows"]
    lvl = data["kappa0_level"]
    sw = [r for r in data.get("kappa0_sweep", []) if r["case"] == HZ and r["degree"] == 2]
    if not sw:
        return []
    txt = ", ".join(f"kappa0 = {r['kappa0']:g}: "
                    + ("diverged" if r["failed"] else f"p_max {r['p_max']:.1e}, rms {r['rms']:.1e}")
                    for r in sw)
    nit = _find(rows, case=HZ, series="case", method="nitsche", degree=2, h_contact=lvl)
    ref = f"; Nitsche at the same level: p_max {nit['p_max']:.1e}, rms {nit['rms']:.1e}" if nit else ""
    pen_rows = [r for r in rows if r["method"] == "penalty"]
    n_osc = sum(1 for r in pen_rows if "oscillation" in r.get("warnings", ""))
    failed = sorted({r["kappa0"] for r in data["kappa0_sweep"] if r["failed"]})
    fails = (f" Penalty runs with kappa0 in {{{', '.join(f'{k:g}' for k in failed)}}} did not converge "
             "within the solver's cut-backs (table above)." if failed else "")
    return ["**Penalty.** The pressure read from kappa [-g]_+ at the Gauss points zig-zags between "
            "neighbouring points with an amplitude that GROWS with kappa0 (Hertz P2, case geometry, h_c/a = "
            f"{lvl:g}: {txt}{ref}).{fails} The solver flags the zig-zag (\"pressure oscillation\") in "
            f"{n_osc} of the {len(pen_rows)} penalty rows; this noise, not the O(h_c/kappa0) consistency "
            "error, sets the penalty's rms and its irregular slopes.", ""]


def _p_wedge(data: dict) -> list[str]:
    rows, out = data["rows"], []
    for series in ("case", "ideal"):
        sl = [f"{m} P{d} {_s(_slope(data, WD, series, m, d, 'rms'))}" for m in ("nitsche", "penalty")
              for d in (1, 2)]
        out.append(f"`{series}` " + ", ".join(sl))
    text = ["**Wedge.** rms slopes vs h_c: " + "; ".join(out) + " (expected 0.5, log apex singularity)."]
    w = [r for r in rows if r["case"] == WD and r["series"] == "case" and not r["failed"]
         and r.get("b_over_b0_fem") is not None]
    if w:
        h_min = min(x["h_contact"] for x in w)
        fine = [r for r in w if r["h_contact"] == h_min]
        vals, theory = [r["b_over_b0_fem"] for r in fine], fine[0]["b_over_b0_theory"]
        gap = abs(1.0 - statistics.mean(vals) / theory)
        n2 = next((r for r in fine if (r["method"], r["degree"]) == ("nitsche", 2)), None)
        text.append(f" b/b0, case series (block 160 b0, growth 1.3) at the finest level h_c/b0 = {h_min:g}: "
                    f"FEM {min(vals):.4f} to {max(vals):.4f} over the four method x degree pairs against "
                    f"the converged theory {theory:.4f}, a mean gap of {gap:.2%}"
                    + (f"; Nitsche P2 {n2['b_over_b0']:.2%} (case acceptance 1 %)." if n2 else "."))
    fw = [f"{f['b_over_b0']:.1e} ({f['series']})" for f in data.get("floors", []) if f["case"] == WD]
    if fw:
        text.append(" Block size at that level (Nitsche P2), b/b0 error: " + ", ".join(fw) + ".")
    i2 = _find(rows, case=WD, series="ideal", method="nitsche", degree=2)
    if i2:
        text.append(f" Ideal series, Nitsche P2 at h_c/b0 = {i2['h_contact']:g} (growth {i2['growth']:.3g}, "
                    f"640 b0): b/b0 error {i2['b_over_b0']:.1e}, rms_convective {i2['rms_convective']:.1e}.")
    return ["".join(text), ""]


def _last_pair(data: dict, x: dict) -> float | None:
    """Slope vs h_c between the two finest levels of the rate record ``x`` (local rate)."""
    sel = sorted((r for r in data["rows"] if (r["case"], r["series"], r["method"], r["degree"])
                  == (x["case"], x["series"], x["method"], x["degree"]) and not r["failed"]),
                 key=lambda r: r["h_contact"])
    if len(sel) < 2 or not all(r.get(x["metric"]) for r in sel[:2]):
        return None
    f, c = sel[0], sel[1]
    return math.log(c[x["metric"]] / f[x["metric"]]) / math.log(c["h_contact"] / f["h_contact"])


def _p_verdicts(data: dict) -> list[str]:
    """Why each rate outside the band is outside, from the data: local rate, warnings, other series."""
    judged = [x for x in data["rates"] if x.get("expected") is not None]
    bad = [x for x in judged if x["verdict"] != "within"]
    if not judged:
        return []
    ext = {(x["case"], x["method"], x["degree"], x["metric"]): x for x in data.get("extension_rates", [])}
    ext_rows = {(r["case"], r["method"], r["degree"]): r for r in data.get("extension", [])
                if not r["failed"]}
    out = []
    for x in bad:
        n_fit = data["n_finest"]
        fitted = sorted((r for r in data["rows"] if (r["case"], r["series"], r["method"], r["degree"])
                         == (x["case"], x["series"], x["method"], x["degree"])), key=lambda r: r["h_contact"])
        osc = sum(1 for r in fitted[:n_fit] if "oscillation" in r.get("warnings", ""))
        why = [f"last-pair rate {_s(_last_pair(data, x))}"]
        if x["slope_h"] is not None and x["slope_h"] > x["expected"]:
            why.append("faster than the singular bound: the singular term does not dominate yet")
        if osc:
            why.append(f"penalty zig-zag flagged on {osc} of the {n_fit} fitted levels")
        if x["series"] == "case":
            other = _rate(data, x["case"], "ideal", x["method"], x["degree"], x["metric"])
            why.append(f"the fixed grading 1.3 of the case series (ideal series: {_s(other['slope_h'])}, "
                       f"{other['verdict'] or '-'})")
        key = (x["case"], x["method"], x["degree"])
        e = ext.get((*key, x["metric"])) if x["series"] == "ideal" else None
        if e and key in ext_rows:
            r_e, r_f, m = ext_rows[key], fitted[0], x["metric"]
            local = math.log(r_f[m] / r_e[m]) / math.log(r_f["h_contact"] / r_e["h_contact"])
            why.append(f"with the extension level h_c/a = {r_e['h_contact']:g}: fit {_s(e['slope_h'])} "
                       f"({e['verdict']}), last pair {_s(local)}")
        out.append(f"{x['case']}/{x['series']} {x['method']} P{x['degree']} {x['metric']} "
                   f"{_s(x['slope_h'])} ({'; '.join(why)})")
    head = (f"**Rates against expectations.** {len(judged) - len(bad)} of {len(judged)} judged slopes lie "
            f"within +-{data['rate_band']:g} of the expected rate.")
    return [head + (" Outside: " + "; ".join(out) + "." if out else ""), ""]


def _p_cheapest(data: dict) -> list[str]:
    found = []
    for key, r in data["cheapest_rms"].items():
        case, series = key.split("/")
        if r:
            found.append(f"{key}: {r['method']} P{r['degree']} at h_c/a = {r['h_contact']:g}, growth "
                         f"{r['growth']:.3g} ({r['ndofs']} dofs, {r['time_s']:.3f} s warm, "
                         f"rms {r['rms']:.1e})")
            continue
        cand = _find(data["rows"], case=case, series=series, method="nitsche", degree=2)
        sl = _slope(data, case, series, "nitsche", 2, "rms")
        if cand and sl and sl > 0:
            h_need = cand["h_contact"] * (data["rms_target"] / cand["rms"]) ** (1.0 / sl)
            found.append(f"{key}: none within the levels; Nitsche P2 reaches rms {cand['rms']:.1e} at "
                         f"h_c/a = {cand['h_contact']:g} and its slope {sl:+.2f} extrapolates to "
                         f"h_c/a ~ {h_need:.1e}")
        else:
            found.append(f"{key}: none within the levels")
    return [f"**Cheapest configuration with rms <= {data['rms_target']:.1%}.** " + "; ".join(found) + ".", ""]


def discussion(data: dict) -> str:
    """The discussion of ``report.md``: every number in it is read from ``data`` (nothing typed in)."""
    out = ["## Discussion", ""]
    for part in (_p_run_time, _p_verdicts, _p_hertz, _p_penalty, _p_wedge, _p_cheapest):
        out += part(data)
    return "\n".join(out)


def to_markdown(data: dict) -> str:
    """``report.md``: expected rates, error tables, fitted slopes, cheapest configuration, diagnostics,
    discussion."""
    lines = (_header(data) + _rates_section(data) + _series_tables(data) + _diagnostic_tables(data)
             + [discussion(data), ""])
    rows = [r for key in ("rows", "floors", "kappa0_sweep", "grading_probe", "extension", "perturbed")
            for r in data.get(key, [])]
    lines += where_section(wall_time_s=data.get("study_wall_time_s"), records=rows,
                           label=lambda r: f"{r['case']} [{r['series']}] {r['method']} P{r['degree']} "
                                           f"h_c={r['h_contact']:g}", reference=data.get("reference"))
    return "\n".join(lines).rstrip() + "\n"


def main(argv: list[str] | None = None) -> int:
    """CLI: rewrite report.md from the study JSON (default ``<results>/convergence/convergence.json``); exit 2 if
    it is missing."""
    import json

    argv = sys.argv[1:] if argv is None else argv
    path = Path(argv[0]) if argv else default_paths().study("convergence") / "convergence.json"
    if not path.is_file():
        print(f"error: {path} does not exist; run `workbench convergence` first", file=sys.stderr)
        return 2
    out = path.parent / "report.md"
    write_text(out, to_markdown(json.loads(path.read_text())))
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
