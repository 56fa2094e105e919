"""The validity study's points from its records: the theories at each point, every model's extrapolated value with
its uncertainty, the theories' bands, the split of the gap into its idealisations, and the paper's claim on the rigid
wedge (:mod:`workbench.studies.validity` runs the records; its module docstring defines the measures and the
uncertainty). Pure numpy and the half-plane theories: no dolfinx.
"""

from __future__ import annotations

import math

import numpy as np

from analytic import convective, halfplane, materials
from vocabulary import FINITE, OBSTACLE
from workbench.error_budget import grid_study
from workbench.studies.validity_config import HP_COMPLETE, HP_PAIRING, ValidityConfig
from workbench.studies.validity_halfplanes import halfplanes_theories

__all__ = ["CLAIM_X", "CLAIM_Z", "HP_COMPLETE", "HP_PAIRING", "assemble", "assemble_halfplanes", "beta_of",
           "claim_points", "classify", "extrapolated_value", "point_theories"]

CLAIM_X = (0.0, 0.25, 0.5, 0.75, 1.0, 1.5)  # stress probes of the paper's claim, x / b (half model, x >= 0)
CLAIM_Z = (0.25, 0.5, 0.75, 1.0, 1.5, 2.0)  # and depths z / b


def beta_of(nu: float) -> float:
    """Dundurs beta of a rigid indenter on a body of Poisson ratio nu (plane strain)."""
    return materials.beta_rigid_indenter(nu)


# --- theories ---------------------------------------------------------------------------------------


def point_theories(scene: str, param: float, nu: float, *, E: float) -> dict:
    """The theories' ratios at a point (over the classical value at the same load; a = 1 mm, P its classical
    load): ``{name: {"moment": .., "p_max": .., "half_width": ..}}`` (a missing key: the theory does not give it)."""
    E_star = materials.plane_strain_modulus(E, nu)
    beta = beta_of(nu)
    out = {}
    if scene == "cylinder":
        R = 1.0 / param
        P = math.pi * E_star / (4.0 * R)  # Hertz load of a = 1
        p0 = 2.0 * P / math.pi
        out["hertz"] = {"moment": 1.0, "p_max": 1.0, "half_width": 1.0}
        for name, kind, bb in (("exact_circle", "circle", 0.0), ("ch_circle", "circle", beta),
                               ("ch_parabola", "parabola", beta)):
            s = halfplane.solve_halfplane(halfplane.profile(kind, R=R), P=P, E_star=E_star, beta=bb, n_nodes=4096)
            out[name] = {"moment": s.moment_half_width, "p_max": s.p_max / p0, "half_width": s.half_width}
        out["ch_first_order"] = {"half_width": convective.parabola_first_order_from_b0(param, beta)}
    else:
        m = math.tan(param)
        P = E_star * m  # classical load of b = 1
        out["wedge"] = {"moment": 1.0, "half_width": 1.0}
        s = halfplane.solve_halfplane(halfplane.profile("wedge", m=m), P=P, E_star=E_star, beta=beta, n_nodes=16384)
        out["ch_wedge"] = {"moment": s.moment_half_width / (2.0 / math.sqrt(6.0)), "half_width": s.half_width}
        out["ch_first_order"] = {"half_width": convective.wedge_first_order(m, beta)}
    return out


# --- assembling ---------------------------------------------------------------------------------------


def extrapolated_value(levels: dict, quantity: str, h_ratios) -> dict:
    """Extrapolated value and relative uncertainty of ``quantity`` from the three levels and the far block."""
    f = [levels.get(f"h{i}", {}).get(quantity) for i in range(3)]
    far = levels.get("far", {}).get(quantity)
    if any(v is None or not math.isfinite(v) for v in f):
        missing = [f"h{i}" for i, v in enumerate(f) if v is None or not math.isfinite(v)]
        return {"value": None, "reason": f"no value on level(s) {', '.join(missing)} (see their runs)"}
    gs = grid_study(tuple(1.0 / h for h in h_ratios), tuple(f), expected_order=None)
    if far is None or not math.isfinite(far):
        return {"value": None, "reason": "the wide-block (truncation) run has no value (see its run)"}
    dW = far - f[1]
    value = gs.extrapolated + 4.0 / 3.0 * dW
    u_trunc = abs(dW) / 3.0 / abs(value)
    return {"value": value, "uncertainty": gs.gci + u_trunc, "gci": gs.gci, "truncation": u_trunc,
            "truncation_correction": 4.0 / 3.0 * dW / abs(value), "status": gs.status,
            "observed_order": gs.observed_order if math.isfinite(gs.observed_order) else None,
            "levels": f, "far": far}


def _complete(cfg: ValidityConfig, models: dict) -> str | None:
    """The most complete model with a moment value (the last of ``cfg.models`` that has one)."""
    for traction, kin in reversed(cfg.models):
        key = f"{traction}/{kin}"
        if models.get(key, {}).get("moment", {}).get("value") is not None:
            return key
    return None


def classify(d: float, u: float, thresholds, resolve_factor: float) -> tuple[str, str | None]:
    """The band of a theory's relative difference ``d`` from a model value of relative uncertainty ``u``.

    Returns ``(band, reason)``: band ``"<0.1%"``-style for the smallest threshold with d + u below it, ``">5%"``
    when d - u exceeds the largest, else ``"unresolved"``; a band is used only when u <= d / resolve_factor
    (the uncertainty well below the difference) or d + u is below the smallest threshold (the verdict holds
    whatever the difference); otherwise the reason says why it is dropped."""
    small = d + u <= thresholds[0]
    if not small and u * resolve_factor > d:
        return "unresolved", f"uncertainty {u:.2e} not well below the difference {d:.2e} (factor {resolve_factor:g})"
    for t in thresholds:
        if d + u <= t:
            return f"<{100 * t:g}%", None
    if d - u > thresholds[-1]:
        return f">{100 * thresholds[-1]:g}%", None
    for t in thresholds:
        if d - u <= t < d + u:
            return "unresolved", f"the band [{d - u:.2e}, {d + u:.2e}] straddles {100 * t:g}%"
    return "unresolved", "no band decided"


def _split(models: dict, complete: str | None, theories: dict, scene: str) -> dict | None:
    """Split the gap (most complete model - classical) of the moment ratio into its idealisations."""
    def val(key):
        m = models.get(key, {}).get("moment", {})
        return (m["value"], m["uncertainty"] * abs(m["value"])) if m.get("value") is not None else (None, None)

    hs, u_hs = val("halfplane/small")
    hc, u_hc = val("halfplane/convective")
    oc, u_oc = val("obstacle/convective")
    of, u_of = val("obstacle/finite")
    if complete is None or hs is None or hc is None or oc is None:
        return None
    tot, u_tot = val(complete)
    rows = {"total": (tot - 1.0, u_tot),
            "profile": (hs - 1.0, u_hs),
            "convective": (hc - hs, math.hypot(u_hc, u_hs)),
            "traction": (oc - hc, math.hypot(u_oc, u_hc)),
            "finite_strain": ((of - oc, math.hypot(u_of, u_oc)) if of is not None and complete == "obstacle/finite"
                              else (None, None))}
    out = {k: {"value": v, "uncertainty": u} for k, (v, u) in rows.items()}
    out["profile"]["theory"] = theories.get("exact_circle", {}).get("moment", 1.0) - 1.0 if scene == "cylinder" \
        else 0.0
    out["complete_model"] = complete
    return out


def assemble(cfg: ValidityConfig, records: list[dict], skipped: list[dict]) -> tuple[list[dict], list[dict]]:
    """Points (scene, param, nu): every model's values with uncertainty, the theories, their bands; and the
    list of dropped or failed entries with their reasons. The two-half-planes records go to
    :func:`assemble_halfplanes` (their points come after the rigid ones)."""
    hp_records = [r for r in records if r["task"]["scene"] == "halfplanes"]
    records = [r for r in records if r["task"]["scene"] not in ("halfplanes", "elastic_wedge")]
    by_point: dict = {}
    for r in records:
        t = r["task"]
        key = (t["scene"], t["param"], t["nu"])
        lev = by_point.setdefault(key, {}).setdefault(r["model"], {})
        lev[t["level"]] = ({q: r.get(q) for q in ("moment", "p_max", "half_width")} if r["converged"] else {})
    dropped = [dict(s, what="model skipped") for s in skipped]
    for r in records:
        if not r["converged"]:
            t = r["task"]
            dropped.append({"scene": t["scene"], "param": t["param"], "nu": t["nu"], "model": r["model"],
                            "level": t["level"], "what": "run failed", "reason": r["error"]})
    points = []
    for (scene, param, nu), models_levels in sorted(by_point.items()):
        theories = point_theories(scene, param, nu, E=cfg.E)
        models = {}
        for model, levels in models_levels.items():
            models[model] = {q: extrapolated_value(levels, q, cfg.h_ratios) for q in ("moment", "p_max", "half_width")
                             if scene == "cylinder" or q != "p_max"}
            for q, v in models[model].items():
                if v.get("value") is None:
                    dropped.append({"scene": scene, "param": param, "nu": nu, "model": model, "quantity": q,
                                    "what": "value dropped", "reason": v["reason"]})
        complete = _complete(cfg, models)
        bands = {}
        if complete is not None:
            for name, th in theories.items():
                for q, tv in th.items():
                    mv = models[complete].get(q, {})
                    if mv.get("value") is None:
                        continue
                    d = abs(tv / mv["value"] - 1.0)
                    band, reason = classify(d, mv["uncertainty"], cfg.thresholds, cfg.resolve_factor)
                    bands.setdefault(name, {})[q] = {"difference": d, "uncertainty": mv["uncertainty"], "band": band,
                                                     "reason": reason}
                    if reason:
                        dropped.append({"scene": scene, "param": param, "nu": nu, "theory": name, "quantity": q,
                                        "what": "map point unresolved", "reason": reason})
        else:
            dropped.append({"scene": scene, "param": param, "nu": nu, "what": "point unused",
                            "reason": "no model has a moment value at this point"})
        points.append({"scene": scene, "param": param, "nu": nu, "beta": beta_of(nu), "models": models,
                       "theories": theories, "complete_model": complete, "bands": bands,
                       "split": _split(models, complete, theories, scene)})
    hp_points, hp_dropped = assemble_halfplanes(cfg, hp_records)
    return points + hp_points, dropped + hp_dropped




def _hp_split(models: dict, theories: dict) -> dict | None:
    """Split the gap to Hertz of the moment half-width of two half-planes (relative, at the same load), exactly:
    total = S R - 1 = profile + convective, with S the small run over Hertz and R the ratio convective over small
    (each extrapolated, :func:`_value`): profile = S - 1 (the FEM's own distance from Hertz: theory 0 for a
    parabola), convective = S (R - 1). The convective part = its theory S (R_ch - 1) (converged Ciavarella-Hills;
    the first order beside it) + ``remainder`` S (R - R_ch): how much of the FEM-vs-classical gap the convective
    theory explains and how much remains. Uncertainties: S U_S; the convective part and the remainder S R U_R (the
    two runs' errors are correlated: the ratio's own GCI is used); the total their root sum of squares."""
    def val(key):
        m = models.get(key, {}).get("moment", {})
        return (m["value"], m["uncertainty"] * abs(m["value"])) if m.get("value") is not None else (None, None)

    S, u_S = val("halfplane/small")
    R, u_R = val(HP_COMPLETE)
    if S is None or R is None:
        return None
    r_ch, r_first = theories["ch_converged"]["moment"], theories["ch_first_order"]["moment"]
    u_conv = abs(S) * u_R
    return {"total": {"value": S * R - 1.0, "uncertainty": math.hypot(u_S, u_conv)},
            "profile": {"value": S - 1.0, "uncertainty": u_S, "theory": 0.0},
            "convective": {"value": S * (R - 1.0), "uncertainty": u_conv, "theory": S * (r_ch - 1.0),
                           "theory_first_order": S * (r_first - 1.0)},
            "remainder": {"value": S * (R - r_ch), "uncertainty": u_conv},
            "traction": {"value": None, "uncertainty": None}, "finite_strain": {"value": None, "uncertainty": None},
            "complete_model": HP_COMPLETE}


def assemble_halfplanes(cfg: ValidityConfig, records: list[dict]) -> tuple[list[dict], list[dict]]:
    """Points (b0/R, beta) of the two-half-planes part: each run's moment half-width over Hertz and their ratio
    convective over small per level, each extrapolated with its uncertainty (:func:`_value`: three levels and the
    far block); the theories' moment ratios (:func:`workbench.studies.validity_halfplanes.halfplanes_theories`)
    against the ratio, banded (:func:`classify`) and marked ``inside`` when |theory - FEM| <= U; the gap split
    (:func:`_hp_split`); and the dropped entries with their reasons."""
    by_point: dict = {}
    dropped = []
    for r in records:
        t = r["task"]
        lev = by_point.setdefault((t["param"], t["beta"]), {}).setdefault(r["model"], {})
        lev[t["level"]] = {"moment": r.get("moment")} if r["converged"] else {}
        if not r["converged"]:
            dropped.append({"scene": "halfplanes", "param": t["param"], "nu": t["nu"], "beta": t["beta"],
                            "model": r["model"], "level": t["level"], "what": "run failed", "reason": r["error"]})
    points = []
    for (param, beta), ml in sorted(by_point.items()):
        small, conv = ml.get("halfplane/small", {}), ml.get("halfplane/convective", {})

        def ratio_levels(conv, small=small):
            out = {}
            for level in ("h0", "h1", "h2", "far"):
                s_, c_ = small.get(level, {}).get("moment"), conv.get(level, {}).get("moment")
                out[level] = {"moment": c_ / s_} if s_ and c_ is not None else {}
            return out

        runs = [("halfplane/small", small), ("halfplane/convective", conv), (HP_COMPLETE, ratio_levels(conv))]
        if cfg.halfplanes_pairing:
            pairing = ml.get("halfplane/convective/pairing", {})
            runs += [("halfplane/convective/pairing", pairing), (HP_PAIRING, ratio_levels(pairing))]
        models = {k: {"moment": extrapolated_value(levels, "moment", cfg.halfplanes_h_ratios)} for k, levels in runs}
        here = {"scene": "halfplanes", "param": param, "nu": 0.0, "beta": beta}
        for model, v in models.items():
            if v["moment"].get("value") is None:
                dropped.append(here | {"model": model, "quantity": "moment", "what": "value dropped",
                                       "reason": v["moment"]["reason"]})
        theories = halfplanes_theories(param, beta)
        mv = models[HP_COMPLETE]["moment"]
        bands = {}
        if mv.get("value") is not None:
            for name, th in theories.items():
                tv, value, u = th["moment"], mv["value"], mv["uncertainty"]
                d = abs(tv / value - 1.0)
                band, reason = classify(d, u, cfg.thresholds, cfg.resolve_factor)
                bands[name] = {"moment": {"difference": d, "uncertainty": u, "band": band, "reason": reason,
                                          "inside": abs(tv - value) <= u * abs(value)}}
                if reason:
                    dropped.append(here | {"theory": name, "quantity": "moment", "what": "map point unresolved",
                                           "reason": reason})
        else:
            dropped.append(here | {"what": "point unused", "reason": "no moment ratio (convective over small) at "
                                                                     "this point: " + mv["reason"]})
        finite = _hp_finite(cfg, ml, models, theories)
        for law, f in finite.get("laws", {}).items():
            if f["ratio"].get("value") is None:
                dropped.append(here | {"model": f"{OBSTACLE}/{FINITE}/{law}", "quantity": "moment",
                                       "what": "value dropped", "reason": f["ratio"]["reason"]})
        points.append(here | {"models": models, "theories": theories,
                              "complete_model": HP_COMPLETE if mv.get("value") is not None else None,
                              "bands": bands, "split": _hp_split(models, theories), "finite": finite})
    return points, dropped


def _hp_finite(cfg: ValidityConfig, ml: dict, models: dict, theories: dict) -> dict:
    """A point's finite-strain rows (issue 39), each law's moment ratio F = M / S: its moment half-width over Hertz
    (P1, extrapolated over ``cfg.halfplanes_finite_h_ratios`` and the far block, :func:`_value`) over the small
    run's S (P2), relative uncertainty the root sum of squares of both. Against it: the converged theory, the first
    order and the small-strain convective (profile) model R, each ``inside`` when within the combined band; the
    split of F - 1 into the convective model's R - 1 and the rest F - R (finite strain and the traction along the
    deformed normal together: finite strain with the vertical traction is refused, so they are not separated).
    ``follows``: which small-strain convective model (profile, and pairing when run) F is nearer, and whether the
    two are told apart (:func:`_follows`); ``inside["pairing"]`` as for profile.
    With two laws: their spread F_1 - F_2 and the verdict ``convective`` (|R_ch - 1| > |spread| + its band: the
    convective correction outweighs the material law), ``material law`` (the reverse) or ``comparable``."""
    laws = cfg.halfplanes_finite_laws
    if not laws:
        return {}
    S = models["halfplane/small"]["moment"]
    R = models[HP_COMPLETE]["moment"]
    r_ch, r_first = theories["ch_converged"]["moment"], theories["ch_first_order"]["moment"]
    out: dict = {"laws": {}, "convective_correction": r_ch - 1.0}
    for law in laws:
        M = extrapolated_value(ml.get(f"{OBSTACLE}/{FINITE}/{law}", {}), "moment", cfg.halfplanes_finite_h_ratios)
        if M.get("value") is None or S.get("value") is None:
            why = M.get("reason") if M.get("value") is None else "the small run has no value: " + S["reason"]
            out["laws"][law] = {"moment": M, "ratio": {"value": None, "reason": why}}
            continue
        F, u = M["value"] / S["value"], math.hypot(M["uncertainty"], S["uncertainty"])
        row = {"moment": M, "ratio": {"value": F, "uncertainty": u},
               "inside": {"ch_converged": abs(F - r_ch) <= u * abs(F),
                          "ch_first_order": abs(F - r_first) <= u * abs(F)},
               "minus_converged": F - r_ch}
        row["follows"] = _follows(F, u, {"profile": R, "pairing": models.get(HP_PAIRING, {}).get("moment", {})})
        dist = row["follows"]["distance"]
        row["inside"] |= {name: d["inside"] for name, d in dist.items()}
        if "profile" in dist:
            row["split"] = {"convective_model": R["value"] - 1.0, "finite_strain_and_traction": F - R["value"],
                            "uncertainty": dist["profile"]["uncertainty"]}
        out["laws"][law] = row
    done = [(law, r["ratio"]) for law, r in out["laws"].items() if r["ratio"].get("value") is not None]
    if len(done) >= 2:
        (l1, a), (l2, b) = done[0], done[1]
        spread = a["value"] - b["value"]
        u_s = math.hypot(a["uncertainty"] * abs(a["value"]), b["uncertainty"] * abs(b["value"]))
        c = abs(r_ch - 1.0)
        verdict = ("convective" if c > abs(spread) + u_s else "material law" if abs(spread) > c + u_s
                   else "comparable")
        out["spread"] = {"laws": [l1, l2], "value": spread, "uncertainty": u_s, "verdict": verdict}
    return out


def _follows(F: float, u: float, small_models: dict) -> dict:
    """Which small-strain convective model a finite-strain ratio F (relative band u) follows: per model with a
    value, the difference F - R and the combined absolute band (root sum of squares), ``inside`` when within it;
    ``model`` the nearer one, ``resolved`` when the two models' own difference exceeds their combined band (else the
    measurement cannot tell them apart), ``alone`` when F lies in the band of that model and not of the other."""
    dist = {}
    for name, R in small_models.items():
        if R.get("value") is None:
            continue
        band = math.hypot(u * abs(F), R["uncertainty"] * abs(R["value"]))
        dist[name] = {"difference": F - R["value"], "uncertainty": band, "inside": abs(F - R["value"]) <= band}
    if not dist:
        return {"distance": dist, "model": None}
    model = min(dist, key=lambda k: abs(dist[k]["difference"]))
    out = {"distance": dist, "model": model}
    if len(dist) == 2:
        other = next(k for k in dist if k != model)
        a, b = small_models[model], small_models[other]
        apart = math.hypot(a["uncertainty"] * abs(a["value"]), b["uncertainty"] * abs(b["value"]))
        out["resolved"] = abs(a["value"] - b["value"]) > apart
        out["alone"] = dist[model]["inside"] and not dist[other]["inside"]
    return out


def claim_points(cfg: ValidityConfig, records: list[dict]) -> dict:
    """The paper's claim: FEM wedge stresses (obstacle traction, small strain, nu = claim_nu) against the
    half-plane wedge solution at the same load, over the probe grid |x| <= 1.5 b, b/4 <= z <= 2 b, relative to
    the mean pressure P/(2b) (the wedge's peak is log-singular). Also the halfplane-traction run against the
    same theory (the numerical floor) and the two FEM runs against each other (the traction effect alone)."""
    from analytic.halfplane_stress import stress_under_pressure
    from analytic.wedge import wedge_pressure

    runs = {}
    for r in records:
        t = r["task"]
        if r.get("stresses") is not None and t["scene"] == "wedge":  # the rigid wedge's (not the elastic wedge's)
            runs[(t["param"], t["traction"], t["level"])] = r
    rows = []
    for theta in cfg.wedge_theta:
        row = {"theta": theta, "theta_over_pi": theta / math.pi, "nu": cfg.claim_nu}
        for level in ("h2", "far"):
            hp, ob = runs.get((theta, "halfplane", level)), runs.get((theta, "obstacle", level))
            if hp is None or ob is None:
                row[level] = {"reason": "a run of the pair is missing or failed"}
                continue
            E_star = materials.plane_strain_modulus(cfg.E, cfg.claim_nu)
            m = math.tan(theta)
            res = {}
            for name, r in (("halfplane", hp), ("obstacle", ob)):
                b = r["P"] / (E_star * m)
                st = r["stresses"]
                ex = stress_under_pressure(np.array(st["x"]), np.array(st["z"]),
                                           pressure=lambda x, b=b, m=m, E_star=E_star: float(
                                               wedge_pressure(np.array([x]), b=b, m=m, E_star=E_star)[0]),
                                           b=b, nu=cfg.claim_nu)
                p_mean = r["P"] / (2.0 * b)
                dev = np.max([np.abs(np.array(st[k]) - getattr(ex, k)) for k in ("sxx", "szz", "sxz")], axis=0)
                deep = np.isclose(np.array(st["z"]) / b, max(CLAIM_Z), rtol=1e-6)
                res[name] = {"max_diff_over_p_mean": float(np.nanmax(dev)) / p_mean,
                             "deepest_row_max_diff_over_p_mean": float(np.nanmax(dev[deep])) / p_mean,
                             "p_mean": p_mean}
            p_mean = res["obstacle"]["p_mean"]
            direct = max(float(np.nanmax(np.abs(np.array(ob["stresses"][k]) - np.array(hp["stresses"][k]))))
                         for k in ("sxx", "szz", "sxz")) / p_mean
            row[level] = {"obstacle_vs_theory": res["obstacle"]["max_diff_over_p_mean"],
                          "obstacle_vs_theory_deepest_row": res["obstacle"]["deepest_row_max_diff_over_p_mean"],
                          "halfplane_vs_theory": res["halfplane"]["max_diff_over_p_mean"],
                          "obstacle_vs_halfplane_fem": direct}
        rows.append(row)
    verdict = None
    best = None
    for level in ("h2", "far"):  # the level whose numerical floor is the smaller
        tested = [r for r in rows if r["theta"] < cfg.claim_theta_max * (1.0 + 1e-9) and
                  "obstacle_vs_theory" in r.get(level, {})]
        if not tested:
            continue
        floor = max(r[level]["halfplane_vs_theory"] for r in tested)
        if best is None or floor < best[1]:
            best = (level, floor, tested)
    if best is not None:
        level, floor, tested = best
        worst = max(r[level]["obstacle_vs_theory"] for r in tested)
        direct = max(r[level]["obstacle_vs_halfplane_fem"] for r in tested)
        if direct + floor <= cfg.claim_bound:
            state = "holds"
        elif direct - floor > cfg.claim_bound:
            state = "does not hold"
        else:
            state = "undecided"
        verdict = {"level": level, "worst_obstacle_vs_theory": worst, "worst_floor": floor,
                   "worst_traction_effect": direct, "bound": cfg.claim_bound, "state": state,
                   "angles_tested": [r["theta"] for r in tested],
                   "text": (f"{state}: for theta <= pi/5 the FEM wedge with the traction along the face normal "
                            f"(nu = {cfg.claim_nu:g}, beta = {beta_of(cfg.claim_nu):.1e}) differs from the same FEM "
                            f"with the half-plane's vertical traction by up to {100 * direct:.2f} % of the mean "
                            f"pressure P/(2b) in |x| <= 1.5 b, b/4 <= z <= 2 b; numerical floor (vertical-traction "
                            f"FEM against the half-plane wedge stresses) {100 * floor:.2f} %; obstacle FEM against "
                            f"the half-plane stresses {100 * worst:.2f} %; the paper's bound "
                            f"{100 * cfg.claim_bound:g} %")}
    return {"quantity": "max over the probes of max(|d s_xx|, |d s_zz|, |d s_xz|) / (P / 2b)",
            "probes_x_over_b": CLAIM_X, "probes_z_over_b": CLAIM_Z, "rows": rows, "verdict": verdict}
