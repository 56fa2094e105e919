"""The "paper claims" table: every numerical claim of both papers that the workbench can test.

Each claim has the paper's printed value, our value and its source (closed form, converged numerics or
FEM), and a verdict: ``confirmed``, ``not confirmed`` or ``not testable`` (e.g. the geometry is not
published). Analytic values are computed here from :mod:`analytic`; FEM values are read from the case
results, so a claim whose case has not run says so.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import NamedTuple

from analytic import hertz, materials

__all__ = ["Claim", "collect_claims", "claims_markdown"]

CH = "Ciavarella & Hills (convective)"
CC = "close-to-conformal"


class Claim(NamedTuple):
    """One tested claim."""

    paper: str
    claim: str
    printed: str
    ours: str
    source: str
    verdict: str


def _load(results: Path, name: str) -> dict | None:
    f = results / name / "metrics.json"
    return json.loads(f.read_text()) if f.is_file() else None


def _rel(a: float, b: float) -> float:
    return abs(a - b) / abs(b)


def _analytic_claims(results: Path) -> list[Claim]:
    out: list[Claim] = []
    conv = results / "analytic" / "convective.json"
    if conv.is_file():
        for chk in json.loads(conv.read_text()).get("paper_checks", []):
            comp = chk.get("computed", {})
            ours = ", ".join(f"{k} = {v:.4f}" if isinstance(v, float) else f"{k} = {v}" for k, v in comp.items())
            verdict = chk["verdict"]
            out.append(Claim(CH, chk["claim"], "-" if chk.get("printed") is None else str(chk["printed"]), ours,
                             "closed form + converged numerics (analytic/convective.py)",
                             verdict.rstrip(": ")))
    else:
        out.append(Claim(CH, "convective b/b0 figures", "-", "not computed yet", "-",
                         "run `python -m workbench.studies.convective_table`"))
    E_star = materials.plane_strain_modulus(214000.0, 0.3)
    out.append(Claim(CC, "E* = 235 GPa for E = 214 GPa, nu = 0.3, rigid particle", "235 GPa",
                     f"{E_star / 1000:.2f} GPa", "closed form",
                     "confirmed" if _rel(E_star, 235000.0) < 0.005 else "not confirmed"))
    for row in hertz.table1_patch_sizes():
        if row.row.d not in (0.60, 0.46):
            continue
        cfg = row.row.config
        if row.row.d == 0.60:
            out.append(Claim(CC, f"{cfg} d = 0.60: eq. (4) patch size from P = 5106, p0 = 8361", "0.78 mm",
                             f"{row.width_eq4:.3f} mm (full width 2a)", "closed form",
                             "confirmed (a full width)" if abs(row.width_eq4 - 0.78) < 0.005 else "not confirmed"))
        else:
            out.append(Claim(CC, f"{cfg} d = 0.46: eq. (4) patch size from P = 208, p0 = 578", "0.46 mm",
                             f"{row.width_eq4:.3f} mm (full width 2a)", "closed form",
                             "confirmed (a full width)" if abs(row.width_eq4 - 0.46) < 0.005 else "not confirmed"))
        for e, radii in zip(row.eq5, (r for r in hertz.PAPER_RADII if r.d == row.row.d), strict=True):
            lo, hi = _rounding_range(radii.R_convex, radii.R_concave)
            inside = lo <= e.R_printed <= hi
            out.append(Claim(
                CC, f"{cfg} d = {row.row.d:.2f}: relative radius of the {e.pair} radii "
                f"{radii.R_convex:g} and -{radii.R_concave:g} mm",
                f"{e.R_printed:g} mm", f"{e.R_computed:.2f} mm from the printed radii", "closed form",
                "confirmed" if _rel(e.R_computed, e.R_printed) < 0.01 else
                f"not confirmed from the printed radii ({100 * _rel(e.R_computed, e.R_printed):.1f} % off); "
                + (f"consistent with radii rounded to 1 mm (range {lo:.1f}-{hi:.1f} mm)" if inside else
                   f"outside the 1 mm rounding range {lo:.1f}-{hi:.1f} mm")))
            out.append(Claim(
                CC, f"{cfg} d = {row.row.d:.2f}: eq. (5) patch size with the {e.pair} R", f"{e.width_printed:g} mm",
                f"{e.width_eq5_R_printed:.3f} mm (printed R), {e.width_eq5_R_computed:.3f} mm (R from radii)",
                "closed form",
                "confirmed (a full width)" if abs(e.width_eq5_R_printed - e.width_printed) < 0.006
                else "not confirmed"))
    out.append(_table1_stiffness_claim())
    return out


def _table1_stiffness_claim() -> Claim:
    """Fig. 3's "close-to-conformal is stiffer", checked against the paper's own Table 1.

    Eq. (4) gives the printed 0.78 mm from P = 5106 N/mm as ONE patch's load, so Table 1's symmetric P is a
    per-patch load; the symmetric configuration carries twice that in total.
    """
    import numpy as np

    sym = [r for r in hertz.TABLE1 if r.config == "symmetrical"]
    ctc = [r for r in hertz.TABLE1 if r.config == "close_to_conformal"]
    d = 0.27
    P_sym = next(r.P for r in sym if r.delta == d)
    P_ctc = float(np.interp(d, [r.delta for r in ctc], [r.P for r in ctc]))
    per_patch = P_ctc > P_sym
    total = P_ctc > 2 * P_sym
    verdict = ("confirmed" if per_patch and total else
               "ambiguous: holds per patch, NOT for the total load" if per_patch else "not confirmed")
    return Claim(CC, "Fig. 3: the close-to-conformal contact is stiffer, checked on the paper's own Table 1 "
                 "(its symmetric P is a per-patch load: eq. (4) gives 0.78 mm from P = 5106 as one patch)",
                 "stiffer", f"at delta = {d} mm: close-to-conformal {P_ctc:.0f} N/mm (interpolated) vs symmetric "
                 f"{P_sym:.0f} per patch, {2 * P_sym:.0f} total", "the paper's Table 1", verdict)


def _rounding_range(R_convex: float, R_concave: float) -> tuple[float, float]:
    """Range of the relative radius when both printed radii are rounded to the nearest mm."""
    vals = [hertz.relative_radius(r1, -r2) for r1 in (R_convex - 0.5, R_convex + 0.5)
            for r2 in (R_concave - 0.5, R_concave + 0.5)]
    return min(vals), max(vals)


def _fem_claims(results: Path) -> list[Claim]:
    out: list[Claim] = []
    wc = _load(results, "wedge_convective")
    if wc and "b_over_b0_fem" in wc.get("analytic", {}):
        a = wc["analytic"]
        out.append(Claim(CH, "wedge theta = pi/5, beta = -1/2: b/b0 ~ 1.097 (FEM check, face slope theta)", "1.097",
                         f"FEM {a['b_over_b0_fem']:.4f}; converged theory {a['b_over_b0_converged']:.4f}",
                         f"FEM (h_c = {wc['h_contact']} b0, {wc['method']})",
                         "not confirmed: the FEM agrees with the converged theory, not with the printed figure"
                         if _rel(a["b_over_b0_fem"], 1.097) > 0.02 and _rel(a["b_over_b0_fem"],
                                                                            a["b_over_b0_converged"]) < 0.02
                         else "see wedge_convective report"))
    else:
        out.append(Claim(CH, "wedge b/b0 by FEM", "1.097", "not run yet", "FEM", "run `make wedge_convective`"))
    pc = _load(results, "parabola_convective")
    if pc and "b_over_b0_fem" in pc.get("analytic", {}):
        a = pc["analytic"]
        out.append(Claim(CH, "parabola b0/R = 1/4, beta = -1/2: b/b0 (FEM check)", "1.09 (first order at b/R = 1/4)",
                         f"FEM {a['b_over_b0_fem']:.4f}; converged theory {a['b_over_b0_converged']:.4f}; "
                         f"first order {a['b_over_b0_first_order']:.4f}", f"FEM (h_c = {pc['h_contact']} b0)",
                         "FEM confirms the converged theory (the printed 1.09 is a first-order value)"
                         if _rel(a["b_over_b0_fem"], a["b_over_b0_converged"]) < 0.01 else
                         "see parabola_convective report"))
    else:
        out.append(Claim(CH, "parabola b/b0 by FEM", "1.09", "not run yet", "FEM", "run `make parabola_convective`"))
    for name, d, printed in (("concave_symmetric", 0.60, 7.49e-3), ("close_to_conformal", 0.46, 5.00e-3)):
        m = _load(results, name)
        step = None
        if m:
            step = next((s for s in m.get("steps", []) if math.isclose(s["d"], d)), None)
        if step and step.get("fit"):
            out.append(Claim(CC, f"{name} d = {d:.2f}: elliptical-fit RMS/p0", f"{printed:.3g}",
                             f"{step['fit']['rms_over_p0']:.3g} on our design geometry", "FEM",
                             "not testable exactly (the paper's splines are not published); same order"
                             if step["fit"]["rms_over_p0"] < 3 * printed else
                             "not testable exactly (geometry not published); ours differs"))
        else:
            out.append(Claim(CC, f"{name} d = {d:.2f}: elliptical-fit RMS/p0", f"{printed:.3g}",
                             "not run yet" if not m else "no patch at this step", "FEM",
                             "not testable (geometry not published)" if m else f"run `make {name}`"))
    sym, ctc = _load(results, "concave_symmetric"), _load(results, "close_to_conformal")
    if sym and ctc and sym.get("steps") and ctc.get("steps"):
        # compare the loads at the same indentation (largest symmetric indentation, interpolated on the
        # close-to-conformal P-delta curve), and the tangent stiffness at the last steps
        ds = [st["delta_lcp"] for st in ctc["steps"]]
        Ps = [st["P"] for st in ctc["steps"]]
        d_sym, P_sym = sym["steps"][-1]["delta_lcp"], sym["steps"][-1]["P"]
        if ds[0] <= d_sym <= ds[-1]:
            import numpy as np

            P_ctc = float(np.interp(d_sym, ds, Ps))
            out.append(Claim(
                CC, "the close-to-conformal contact is stiffer (load against indentation, Fig. 3)", "stiffer",
                f"at delta = {d_sym:.3f} mm: P = {P_ctc:.4g} N/mm (close-to-conformal) vs {P_sym:.4g} N/mm "
                f"(symmetric, both patches; {P_sym / 2:.4g} per patch); last-step dP/ddelta "
                f"{ctc.get('stiffness') or math.nan:.4g} vs {sym.get('stiffness') or math.nan:.4g} N/mm^2",
                "FEM (our design geometry)",
                "confirmed on our designs, per patch and in total" if P_ctc > P_sym else
                "confirmed per patch only" if P_ctc > P_sym / 2 else "not confirmed on our designs"))
    else:
        out.append(Claim(CC, "the close-to-conformal contact is stiffer", "stiffer", "not run yet", "FEM",
                         "run both concave cases"))
    rows = [r for r in hertz.TABLE1 if r.config == "close_to_conformal"]
    secant = [r.P / r.delta for r in rows[:3]]
    ours = ""
    if ctc and ctc.get("steps") and len(ctc["steps"]) >= 3:
        st = ctc["steps"][:3]
        ours = "; our FEM: " + ", ".join(f"{x['P'] / x['delta_lcp']:.3g}" for x in st if x["delta_lcp"] > 0)
    out.append(Claim(
        CC, "Table 1, close-to-conformal rows d = 0.46, 0.47, 0.48: P and delta (secant stiffness P/delta)",
        ", ".join(f"({r.delta:g} mm, {r.P:g} N/mm)" for r in rows[:3]),
        "P/delta = " + ", ".join(f"{v:.3g}" for v in secant) + " N/mm^2 (paper)" + ours,
        "the paper's Table 1; FEM on our design",
        "not consistent: the first row's P/delta is "
        f"{secant[0] / secant[1]:.1f}x the next rows', while a contact that stiffens with load has a rising P/delta "
        "(as our FEM does); the three rows cannot lie on one such curve, and the paper does not say why"
        if secant[0] > 2 * secant[1] else "consistent"))
    if ctc and ctc.get("superposition_rms_over_p0") is not None:
        v = ctc["superposition_rms_over_p0"]
        out.append(Claim(CC, "Hertz superposition fails once the close-to-conformal patches merge",
                         "qualitative", f"best two-patch Hertz superposition RMS/p0 = {v:.3g} at d = 1.00",
                         "FEM + least-squares superposition", "confirmed" if v > 0.05 else "not confirmed"))
    out.append(_elastic_wedge_claim(results))
    out.append(_stress_claim(results))
    return out


_VERDICTS = {"holds": "confirmed", "does not hold": "not confirmed"}  # a study verdict's state -> the table's


def _validity_verdict(results: Path, key: str) -> dict | None:
    """The verdict under ``key`` of ``<results>/validity/validity.json``, or None (not run, or no verdict)."""
    f = Path(results) / "validity" / "validity.json"
    return (json.loads(f.read_text()).get(key) or {}).get("verdict") if f.is_file() else None


def _elastic_wedge_claim(results: Path) -> Claim:
    """The C&H claim 'for theta < pi/5 the internal stress state of the elastically similar problem differs by
    at most 0.5 % from the exact solution', as the paper states it: an elastic wedge on a block of the same material
    (the validity study's elastic-wedge part, ``validity/validity.json`` key ``claim_elastic_wedge``)."""
    claim = ("ABAQUS: for theta < pi/5 the internal stress state of the elastically similar problem (elastic wedge, "
             "same material) differs < 0.5 % from the exact (half-plane) solution")
    v = _validity_verdict(results, "claim_elastic_wedge")
    if not v:
        return Claim(CH, claim, "0.5 %", "not run yet", "FEM (validity study)", "run `make validity`")
    ours = (f"{100 * v['geometry']:.2f} % +- {100 * v['U']:.2f} % (grid and body size) of P/(2b) at theta = "
            f"{v['worst_theta'] / math.pi:.3g} pi: largest |stress difference| in the block over |x| <= 1.5 b, depth "
            "b/4 ... 2 b, between the meshed elastic wedge and the half-plane-idealised FEM; shaped FEM against the "
            f"half-plane stresses {100 * v['shaped_vs_theory']:.2f} %, floor {100 * v['floor']:.2f} %; inside the "
            f"wedge {100 * v['geometry_wedge']:.2f} %")
    verdict = _VERDICTS.get(v["state"], "undecided")
    note = {"confirmed": "within 0.5 % beyond the grid and size uncertainty",
            "not confirmed": "a wedge of the same material is not a half-plane at these angles: the block's "
                             "stresses differ from the half-plane solution's by more than 0.5 % beyond the "
                             "uncertainty (small strain, the half-plane's own vertical traction)",
            "undecided": "the uncertainty straddles the bound"}[verdict]
    return Claim(CH, claim, "0.5 %", ours, f"FEM (validity study, elastic wedge nu = {v['nu']:g}, P2 mortar)",
                 f"{verdict}: {note}")


def _stress_claim(results: Path) -> Claim:
    """The C&H claim 'for theta < pi/5 the internal stress state of the elastically similar problem differs by
    at most 0.5 % from the exact solution', measured by the validity study (``validity/validity.json``)."""
    claim = ("Not the paper's problem: a RIGID wedge, the traction along its face normal against the vertical one "
             "(the traction's direction as a modelling choice), theta <= pi/5, beta ~ 0")
    v = _validity_verdict(results, "claim")
    if not v:
        return Claim(CH, claim, "0.5 %", "not run yet", "FEM (validity study)", "run `make validity`")
    ours = (f"up to {100 * v['worst_traction_effect']:.2f} % of P/(2b): largest |stress difference| over "
            "|x| <= 1.5 b, b/4 <= z <= 2 b between the FEM wedge with the traction along the face normal and the "
            f"same FEM with vertical traction (nu = 0.499); numerical floor {100 * v['worst_floor']:.2f} %; "
            f"FEM against the half-plane stresses {100 * v['worst_obstacle_vs_theory']:.2f} %")
    verdict = _VERDICTS.get(v["state"], "undecided")
    note = {"confirmed": "the direction moves the stresses by less than 0.5 % beyond the numerical floor",
            "not confirmed": "the face-normal traction's horizontal part (~ p sin theta) changes the stresses "
                             "under the contact far more than 0.5 %",
            "undecided": "the numerical floor is not small enough to decide"}[verdict]
    return Claim(CH, claim, "0.5 %", ours, "FEM (validity study, mixed P2, theta = pi/40 ... pi/5)",
                 f"{verdict}: {note}")


def collect_claims(results: Path) -> list[Claim]:
    """All claims, analytic first, then FEM-based."""
    return _analytic_claims(Path(results)) + _fem_claims(Path(results))


def claims_markdown(results: Path) -> str:
    """The paper-claims table as Markdown."""
    lines = ["## Paper claims", "",
             "Every numerical claim the workbench can test, with our value, its source and a verdict.", "",
             "| paper | claim | printed | ours | source | verdict |", "|---|---|---|---|---|---|"]
    for c in collect_claims(results):
        cells = [x.replace("|", "\u2223") for x in c]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)
