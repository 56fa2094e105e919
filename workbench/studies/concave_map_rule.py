"""The concave map's rule: where Hertz superposition can be trusted, in the design numbers, and what the map measured
inside and outside it (issue 40, item 3). Pure Python on the points of ``concave_map.json``.

The rule (:data:`HERTZ_RULE`) is read off the full map (docs/concave_map.md: 55 designs x 5 loads) and then
CHECKED against the points every time the report is written: the report says how many points lie inside, how
many of them keep Hertz within :data:`EDGE` (a point within the FEM's own band counts as within), and names the
rule as contradicted if one does not. Its three numbers, per point:

* conformity ``R / R_convex``: the primary pair's relative radius over the particle's radius at it (1 for a flat
  concave flank, large when the concavity nearly conforms to the particle);
* separation ``s / (2a)``: the pair separation at first touch over the eq. (5) contact width at the main FEM
  patch's load;
* patch size ``b / R_convex``: the largest FEM patch half-width over the particle's radius.
"""

from __future__ import annotations

import math

__all__ = ["EDGE", "HERTZ_RULE", "PAST_LIMIT_NOTE", "in_hertz_region", "past_limit", "rule_lines", "rule_numbers",
           "rule_summary"]

EDGE = 0.05
PAST_LIMIT_NOTE = "past the analytic slope limit"
"""The head of the interacting-patch model's note at a design it was evaluated at past its analytic slope limit
(:mod:`workbench.studies.concave_map_interacting`, ``ConcaveMapConfig.past_limit_slope``)."""
HERTZ_RULE = {"conformity_max": 1.8, "separation_min": 4.6, "patch_max": 0.32}
"""Read off the map (docs/concave_map.md): Hertz within 5 % at every point with conformity <= 1.77 (the map has no
design between 1.80 and 1.92; every point from 1.92 up is beyond), separation >= 4.58 (beyond at 4.08 to 4.54 on
the least conformal close-to-conformal row) and patch size <= 0.315 (beyond at 0.40 to 0.53 on the symmetric
designs)."""


def rule_numbers(pt: dict) -> tuple[float, float, float]:
    """(conformity R/R_convex, separation s/(2a), patch size b/R_convex) of a map point (NaN where unknown)."""
    r1 = pt["numbers"]["radius_convex"]
    s2a = pt["separation_over_contact"]
    b = max((e["half_width"] for e in pt["fem_patches"]), default=math.nan)
    return pt["relative_radius"] / r1, math.nan if s2a is None else float(s2a), b / r1


def in_hertz_region(pt: dict, rule: dict | None = None) -> bool:
    """Whether a point lies where the rule trusts Hertz superposition."""
    rule = HERTZ_RULE if rule is None else rule
    c, s, b = rule_numbers(pt)
    return c <= rule["conformity_max"] and s >= rule["separation_min"] and b <= rule["patch_max"]


def past_limit(pt: dict) -> bool:
    """Whether the interacting-patch model was evaluated at this point past its analytic slope limit."""
    return PAST_LIMIT_NOTE in pt["models"]["interacting"]["note"]


def _err(pt: dict, model: str) -> float:
    from workbench.studies.concave_map_band import effective_error

    return effective_error(pt, model)


def _raw(pt: dict, model: str) -> float:
    v = pt["models"][model]["worst"]
    return math.nan if v is None else float(v)


def _stats(values: list[float]) -> tuple[float, float]:
    v = sorted(values)
    return (v[len(v) // 2], v[-1]) if v else (math.nan, math.nan)


def rule_summary(points: list[dict], rule: dict | None = None) -> dict:
    """What the map measured inside and outside the rule's region (counts and errors; errors are raw worst errors,
    'within' uses the FEM band)."""
    inside = [p for p in points if in_hertz_region(p, rule)]
    outside = [p for p in points if not in_hertz_region(p, rule)]
    ok = lambda p, m: math.isfinite(_err(p, m)) and _err(p, m) <= EDGE  # noqa: E731
    inter = [p for p in outside if math.isfinite(_raw(p, "interacting")) and not past_limit(p)]
    past = [p for p in outside if math.isfinite(_raw(p, "interacting")) and past_limit(p)]
    not_applied = [p for p in outside if not math.isfinite(_raw(p, "interacting"))]
    return {
        "inside": len(inside), "inside_within": sum(ok(p, "hertz_lcp") for p in inside),
        "inside_errors": _stats([_raw(p, "hertz_lcp") for p in inside if math.isfinite(_raw(p, "hertz_lcp"))]),
        "outside": len(outside), "outside_hertz_within": sum(ok(p, "hertz_lcp") for p in outside),
        "outside_hertz_errors": _stats([_raw(p, "hertz_lcp") for p in outside
                                        if math.isfinite(_raw(p, "hertz_lcp"))]),
        "interacting": len(inter), "interacting_within": sum(ok(p, "interacting") for p in inter),
        "interacting_errors": _stats([_raw(p, "interacting") for p in inter]),
        "interacting_P_errors": _stats([float(p["models"]["interacting"]["P"]) for p in inter
                                        if p["models"]["interacting"]["P"] is not None]),
        "past": len(past), "past_within": sum(ok(p, "interacting") for p in past),
        "past_errors": _stats([_raw(p, "interacting") for p in past]),
        "past_P_errors": _stats([float(p["models"]["interacting"]["P"]) for p in past
                                 if p["models"]["interacting"]["P"] is not None]),
        "past_unsolved": sum(past_limit(p) for p in not_applied),
        "refused": sum(p["models"]["interacting"]["note"].startswith("outside the model") for p in not_applied),
        "unsolved": sum(p["models"]["interacting"]["note"].startswith("model not solved") for p in not_applied),
        "no_model": sum(not ok(p, "hertz_lcp") and not ok(p, "interacting") for p in outside),
    }


def _f(v: float) -> str:
    return "-" if not math.isfinite(v) else f"{100 * v:.3g} %"


def rule_lines(points: list[dict], *, source: str) -> list[str]:
    """The report's first lines: the rule, its measured errors and counts, and where the force law must be used."""
    r, s = HERTZ_RULE, rule_summary(points)
    region = (f"R/R_convex <= {r['conformity_max']:g} (the primary pair not close to conformal), s/(2a) >= "
              f"{r['separation_min']:g} (the patches well apart) and b/R_convex <= {r['patch_max']:g} (each patch "
              "small against the particle)")
    med, worst = s["inside_errors"]
    if not s["inside"]:
        first = f"- No point lies where the rule {region} trusts Hertz superposition: no rule ({source})."
    elif s["inside_within"] == s["inside"]:
        first = (f"- **Hertz superposition (eq. 5 at the LCP pairs) can be trusted, within 5 % in patch widths and "
                 f"p0, where {region}**: all {s['inside']} points there, median error {_f(med)}, worst {_f(worst)} "
                 f"({source}).")
    else:
        first = (f"- **The rule is CONTRADICTED by this map**: where {region}, Hertz superposition is within 5 % at "
                 f"only {s['inside_within']} of {s['inside']} points (worst {_f(worst)}) ({source}).")
    med_o, worst_o = s["outside_hertz_errors"]
    med_i, worst_i = s["interacting_errors"]
    med_p, worst_p = s["interacting_P_errors"]
    second = (f"- **Everywhere else ({s['outside']} points) use the interacting-patch model (`workbench forcelaw`)**: "
              f"Hertz superposition is beyond 5 % at {s['outside'] - s['outside_hertz_within']} of them (median "
              f"{_f(med_o)}, worst {_f(worst_o)}); the interacting-patch model is within 5 % at "
              f"{s['interacting_within']} of the {s['interacting']} points where it applies (pairs within its slope "
              f"limit; median {_f(med_i)}, "
              f"worst {_f(worst_i)}; its P(d) median {_f(med_p)}, worst {_f(worst_p)}).")
    lines = [first, second]
    if s["past"] or s["past_unsolved"]:
        med_q, worst_q = s["past_errors"]
        med_qp, worst_qp = s["past_P_errors"]
        lines.append(f"- Past its analytic slope limit (a pair tilted more than 0.1 from the path, evaluated anyway: "
                     f"the close-to-conformal members whose secondary pair tilts 0.10 to 0.14): the interacting-patch "
                     f"model is within 5 % at {s['past_within']} of {s['past']} points (median {_f(med_q)}, worst "
                     f"{_f(worst_q)}; its P(d) median {_f(med_qp)}, worst {_f(worst_qp)})"
                     + (f", unsolved at {s['past_unsolved']}" if s["past_unsolved"] else "")
                     + "; the force law's region takes those the map validated.")
        why = "a pair tilted beyond the slope the map evaluated: every symmetric point, pairs facing 22 deg apart"
    else:
        why = ("a pair's surface tilted more than 0.1 from the path: every symmetric point, and close-to-conformal "
               "members whose secondary pair tilts 0.10 to 0.14")
    lines.append(f"- Not covered: the interacting-patch model refuses {s['refused']} of those points ({why}) and did "
                 f"not converge at {s['unsolved']}; at {s['no_model']} points neither model is validated (Hertz beyond "
                 "5 %, the force law refused, unsolved or beyond 5 %).")
    return lines
