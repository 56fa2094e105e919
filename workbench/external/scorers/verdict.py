"""The verdict of a score: the main study against its theory, split into the discretisation band and a remainder,
the models of the workbench's hierarchy whose band holds the result (:func:`model_matches`), and every other study
with a theory, in or outside its band. Words only; the numbers come from the studies (:mod:`.base`).

Consistency with a model (:mod:`workbench.external.models`, the model solved on the case's own scene on its budget
levels): ``|external - model| <= U_external + U_model`` with U the absolute uncertainty of each extrapolated value
(the external: GCI band + load term; the model: its band). A round-off quantity (the patch test's uniformity,
``kind = "bound"``) is not extrapolated: the external value and the model's are consistent when both are within the
case's tolerance, or both above it and within a factor :data:`BOUND_FACTOR` of each other.
"""

from __future__ import annotations

import math

from workbench.external.scorers.base import fmt_order

__all__ = ["judge", "model_matches", "model_key", "BOUND_FACTOR", "NAMES"]

BOUND_FACTOR = 3.0
NAMES = {"p_max": "p_max/p0", "half_width": "a_edge/a", "half_width_moment": "a_moment/a",
         "b_over_b0": "b/b0 (edges)", "b_over_b0_moment": "b/b0 (moments)",
         "uniformity": "max |p / (P/W) - 1|"}
SHORT = {"p_max": "peak", "half_width": "edge half-width", "half_width_moment": "moment half-width",
         "b_over_b0": "ratio b/b0 (edges)", "b_over_b0_moment": "moment ratio b/b0", "uniformity": "non-uniformity"}
DEFAULT_UNIFORMITY = 1e-8


def _quantity(key: str, row: dict) -> str:
    return (row.get("group") or {}).get("quantity") or key


def _name(key: str, row: dict) -> str:
    q = _quantity(key, row)
    prefix = key[: -len(q)] if key.endswith(q) else ""
    return prefix + NAMES.get(q, q) if q in NAMES else key


def model_key(key: str, row: dict, score: dict) -> str:
    """The key of an external study in the model bands: a derived ratio without its run (``b_over_b0[convective]``
    -> ``b_over_b0``), a run's quantity without the run's label where the case has one scene (``small/p_max`` ->
    ``p_max``; the wedge's ``theta=pi/5/...`` keeps it: the models were solved per scene)."""
    group = row.get("group") or {}
    if "over" in group:
        return group["quantity"]
    single = {r["label"] for r in score["runs"] if r["label"] == r["kinematics"]}
    head, _, rest = key.partition("/")
    return rest if rest and head in single else key


def _bound_consistent(ext: float, model: float, tol: float) -> bool:
    if ext <= tol and model <= tol:
        return True
    if ext > tol and model > tol:
        return max(ext, model) <= BOUND_FACTOR * max(min(ext, model), 1e-300)
    return False


def model_matches(score: dict, bands: dict | None, *, tolerance: float) -> dict:
    """Study key -> {"models": rows (every model that has the quantity: its extrapolated value, band, distance,
    whether it holds the external value), "uncertainty"} for every external study with a finite extrapolation."""
    if not bands:
        return {}
    out = {}
    for key, row in score["studies"].items():
        ext = row.get("extrapolated")
        if ext is None or not math.isfinite(ext):
            continue
        mk = model_key(key, row, score)
        rows = []
        for m in bands.get("models", []):
            # the bands keep a run's label where the case has several scenes (the finite parabola's small, profile
            # and finite runs: "small/p_max"), which model_key strips for a run named as its kinematics
            st = (m.get("study") or {}).get(mk) or (m.get("study") or {}).get(key)
            if not st or st.get("extrapolated") is None or not math.isfinite(st["extrapolated"]):
                continue
            if row.get("kind") == "bound":
                contains = _bound_consistent(ext, st["extrapolated"], tolerance)
            else:
                contains = abs(ext - st["extrapolated"]) <= row["uncertainty"] + st["band"]
            rows.append({"model": m["name"], "description": m.get("description", m["name"]),
                         "traction": m.get("traction"), "kinematics": m.get("kinematics"),
                         "material_model": m.get("material_model"), "variant": m.get("variant"),
                         "extrapolated": st["extrapolated"], "band": st["band"], "status": st.get("status"),
                         "distance": ext - st["extrapolated"], "contains": bool(contains)})
        if rows:
            out[key] = {"measure": _name(key, row), "model_key": mk, "uncertainty": row["uncertainty"],
                        "source": bands.get("command"), "models": rows}
    return out


def _rel(value: float, ref: float | None) -> float:
    return value / ref - 1.0 if ref else math.nan


def _idealisation(match: dict) -> str:
    """The idealisation the consistent models share, in words (derived from their fields)."""
    inside = [r for r in match["models"] if r["contains"]]
    if not inside:
        near = min(match["models"], key=lambda r: abs(r["distance"]))
        return (f"No model of the workbench's hierarchy on this scene contains it; the nearest is "
                f"{near['description']}, {near['distance']:+.4g} away (uncertainty +-{match['uncertainty']:.3g}).")
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
            text += (f" (kinematics {' and '.join(sorted(kinematics))} agree to {spread:.4g} here: this result cannot "
                     "tell them apart)")
    else:
        text += "models of different traction directions: the result does not single out an idealisation"
    outside = [r for r in match["models"] if not r["contains"]]
    if outside:
        text += "; not " + ", ".join(f"{r['model']} ({r['distance']:+.3g})" for r in outside)
    return text + "."


def _main_sentence(key: str, s: dict) -> str:
    name = _name(key, s)
    if s.get("kind") == "bound":
        tol = s.get("tolerance")
        return (f"{name} = {s['max']:.3g} at worst over {len(s['ratios'])} level(s) (theory 0: {s['theory_name']}); "
                + ("no tolerance" if tol is None else
                   f"{'within' if s['max'] <= tol else 'beyond'} the case's tolerance {tol:.0e}") + ".")
    ext, band = s["extrapolated"], s["band"]
    band_rel = band / abs(s["fine"]) if s["fine"] else math.nan
    head = f"extrapolated {name} = {ext:.6f}" if abs(ext) < 100 else f"extrapolated {name} = {ext:.6g}"
    if s.get("theory") is not None:
        vs = f"{_rel(ext, s['theory']):+.3%} from {s['theory_name']}"
        if s.get("alt_theory"):
            vs += f", {_rel(ext, s['alt_value']):+.3%} from {s['alt_theory']}"
        head += f" ({vs})"
    text = (f"{head}; discretisation band (GCI) +-{band_rel:.3%}, observed order {fmt_order(s['observed_order'])} "
            f"({s['status']}).")
    if s.get("theory") is None:
        return text
    if not s["outside_band"]:
        return text + " The difference is within the discretisation band: consistent with the theory."
    return text + (f" The remainder {_rel(s['theory'] + s['remainder'], s['theory']):+.3%} is outside the band: not "
                   "discretisation but a modelling difference.")


def _headline(key: str, s: dict, match: dict | None) -> str:
    q = _quantity(key, s)
    short = SHORT.get(q, key)
    if s.get("kind") == "bound":
        text = f"The {short} is {s['max']:.2g} at worst" + (
            f" ({'within' if s['max'] <= s['tolerance'] else 'beyond'} the tolerance {s['tolerance']:.0e})"
            if s.get("tolerance") is not None else "")
    elif s.get("theory") is not None:
        text = f"The {short} extrapolates to {_rel(s['extrapolated'], s['theory']):+.2%} from {s['theory_name']}"
        if s.get("alt_theory"):
            text += f" ({_rel(s['extrapolated'], s['alt_value']):+.2%} from {s['alt_theory']})"
        band = s["band"] / abs(s["fine"]) if s["fine"] else math.nan
        text += (f"; the discretisation band is +-{band:.2%}, so the difference is "
                 f"{'not discretisation' if s['outside_band'] else 'within it'}")
    else:
        band = s["band"] / abs(s["fine"]) if s["fine"] else math.nan
        text = f"{key} extrapolates to {s['extrapolated']:.6g} (discretisation band +-{band:.2%})"
    if match is not None:
        inside = [r["model"] for r in match["models"] if r["contains"]]
        text += (f"; it lies within the band of the workbench's {', '.join(inside)}" if inside
                 else "; no model of the workbench's hierarchy holds it")
    return text + "."


def _others(score: dict, main: str) -> str:
    rows = [(k, s) for k, s in score["studies"].items() if k != main and s.get("theory") is not None
            and s.get("extrapolated") is not None and "outside_band" in s]
    if not rows:
        return ""
    inside = [k for k, s in rows if not s["outside_band"]]
    outside = [k for k, s in rows if s["outside_band"]]
    text = f" Other studies with a theory: {len(inside)} of {len(rows)} within their band"
    if outside:
        st = score["studies"]
        shown = "; ".join(f"{_name(k, st[k])} {_rel(st[k]['extrapolated'], st[k]['theory']):+.3%} from "
                          f"{st[k]['theory_name']}" for k in outside[:6])
        text += f"; outside: {shown}" + (f" and {len(outside) - 6} more" if len(outside) > 6 else "")
    return text + "."


def judge(case, score: dict, bands: dict | None) -> dict:
    """``score`` with the verdict: ``grid_study`` (the main group's studies by quantity), ``models`` (the main
    study's match), ``model_matches`` (every study's), ``theory``, ``headline`` and ``verdict``."""
    studies, main, reasons = score["studies"], score["main"], score["plausibility"]
    s = studies.get(main) if main else None
    tol = case.tolerances.get("patch_uniformity", DEFAULT_UNIFORMITY)
    matches = {} if reasons else model_matches(score, bands, tolerance=tol)
    group = (s or {}).get("group", {})
    same = [v for v in studies.values() if "over" not in v.get("group", {}) and "quantity" in v.get("group", {})
            and (v["group"].get("run"), v["group"].get("body")) == (group.get("run"), group.get("body"))]
    score["grid_study"] = ({v["group"]["quantity"]: v for v in same} | {group.get("quantity", main): s}) if s else None
    score["models"] = matches.get(main) if main else None
    score["model_matches"] = {k: [r["model"] for r in m["models"] if r["contains"]] for k, m in matches.items()}
    score["theory"] = (s or {}).get("theory_name", "").removeprefix("the ") or None
    score["bands_source"] = None if bands is None else bands.get("command")
    if s is None:
        score["headline"] = "Fewer than three mesh levels: no extrapolation, no verdict."
        score["verdict"] = ("fewer than three levels: no extrapolation (give three or more RESULT files, one per "
                            "mesh level)")
        return score
    if reasons:
        score["headline"] = f"No verdict: {reasons[0]}" + (f" (and {len(reasons) - 1} more reason(s))."
                                                            if len(reasons) > 1 else ".")
        score["verdict"] = "No verdict: " + "; ".join(reasons) + "."
        return score
    match = score["models"]
    score["headline"] = _headline(main, s, match)
    text = _main_sentence(main, s)
    if match is not None:
        text += " " + _idealisation(match)
    elif bands is None:
        text += (" The workbench's model bands of this case are not saved (or were solved on another version of the "
                 "case): no model is named.")
    score["verdict"] = text + _others(score, main)
    return score
