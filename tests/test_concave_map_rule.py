"""The concave map's rule (issue 40, item 3): the design numbers of a point, the region, and the report's first lines
by hand on made-up points (no FEM)."""

from __future__ import annotations

import math

import pytest

from workbench.studies.concave_map_rule import HERTZ_RULE, in_hertz_region, rule_lines, rule_numbers, rule_summary


def _pt(*, R, r1, s2a, b, hertz, inter=math.nan, note="", in_band=False):
    def model(e, note=""):
        return {"P": None, "width": e, "p0": e, "worst": None if math.isnan(e) else e, "class": "-", "note": note,
                "within_fem_band": in_band}

    return {"numbers": {"radius_convex": r1}, "relative_radius": R, "separation_over_contact": s2a,
            "fem_patches": [{"half_width": b / 2}, {"half_width": b}],
            "models": {"hertz_lcp": model(hertz), "interacting": model(inter, note)}}


def test_rule_numbers_and_region():
    p = _pt(R=5.0, r1=3.0, s2a=6.0, b=0.9, hertz=0.01)
    assert rule_numbers(p) == pytest.approx((5 / 3, 6.0, 0.3))  # b: the largest patch
    assert in_hertz_region(p)
    assert not in_hertz_region(_pt(R=6.0, r1=3.0, s2a=6.0, b=0.9, hertz=0.01))    # conformity 2 > 1.8
    assert not in_hertz_region(_pt(R=5.0, r1=3.0, s2a=4.5, b=0.9, hertz=0.01))    # separation 4.5 < 4.6
    assert not in_hertz_region(_pt(R=5.0, r1=3.0, s2a=6.0, b=1.2, hertz=0.01))    # patch 0.4 > 0.32
    assert HERTZ_RULE == {"conformity_max": 1.8, "separation_min": 4.6, "patch_max": 0.32}


def test_summary_and_first_lines():
    pts = [_pt(R=5.0, r1=3.0, s2a=6.0, b=0.9, hertz=0.01),
           _pt(R=5.0, r1=3.0, s2a=8.0, b=0.3, hertz=0.03),
           _pt(R=300.0, r1=41.0, s2a=1.0, b=0.5, hertz=0.8, inter=0.02),
           _pt(R=300.0, r1=41.0, s2a=0.5, b=0.5, hertz=1.2, inter=0.2),
           _pt(R=300.0, r1=41.0, s2a=0.5, b=0.5, hertz=1.2, note="outside the model: tilt"),
           _pt(R=300.0, r1=41.0, s2a=0.5, b=0.5, hertz=1.2, note="model not solved: root")]
    s = rule_summary(pts)
    assert (s["inside"], s["inside_within"], s["outside"], s["outside_hertz_within"]) == (2, 2, 4, 0)
    assert (s["interacting"], s["interacting_within"], s["refused"], s["unsolved"], s["no_model"]) == (2, 1, 1, 1, 3)
    assert s["inside_errors"] == (0.03, 0.03)
    lines = rule_lines(pts, source="made up")
    assert lines[0].startswith("- **Hertz superposition (eq. 5 at the LCP pairs) can be trusted")
    assert "all 2 points" in lines[0]
    assert "within 5 % at 1 of the 2 points" in lines[1]
    # an inside point beyond 5 % contradicts the rule, unless it lies within the FEM's band
    bad = _pt(R=5.0, r1=3.0, s2a=6.0, b=0.9, hertz=0.08)
    assert "CONTRADICTED" in rule_lines([*pts, bad], source="made up")[0]
    bad = _pt(R=5.0, r1=3.0, s2a=6.0, b=0.9, hertz=0.08, in_band=True)
    assert "can be trusted" in rule_lines([*pts, bad], source="made up")[0]


def test_points_past_the_slope_limit_are_counted_apart():
    """A point the interacting-patch model was evaluated at past its analytic slope limit (its note says so) counts
    in its own line, not among the points where it applies, and no longer as refused."""
    from workbench.studies.concave_map_rule import PAST_LIMIT_NOTE, past_limit

    pts = [_pt(R=300.0, r1=41.0, s2a=1.0, b=0.5, hertz=0.8, inter=0.02),
           _pt(R=300.0, r1=41.0, s2a=1.0, b=0.5, hertz=0.8, inter=0.03, note=f"{PAST_LIMIT_NOTE} (tilt 0.12)"),
           _pt(R=300.0, r1=41.0, s2a=1.0, b=0.5, hertz=0.8, inter=0.07, note=f"{PAST_LIMIT_NOTE} (tilt 0.13)"),
           _pt(R=300.0, r1=41.0, s2a=1.0, b=0.5, hertz=0.8, note=f"model not solved: root; {PAST_LIMIT_NOTE} (0.11)"),
           _pt(R=300.0, r1=41.0, s2a=1.0, b=0.5, hertz=0.8, note="outside the model: tilt 0.41")]
    assert [past_limit(p) for p in pts] == [False, True, True, True, False]
    s = rule_summary(pts)
    assert (s["interacting"], s["interacting_within"]) == (1, 1)
    assert (s["past"], s["past_within"], s["past_unsolved"]) == (2, 1, 1)
    assert (s["refused"], s["unsolved"], s["no_model"]) == (1, 1, 3)
    lines = rule_lines(pts, source="made up")
    assert "within 5 % at 1 of the 1 points where it applies" in lines[1]
    assert lines[2].startswith("- Past its analytic slope limit") and "within 5 % at 1 of 2 points" in lines[2]
    assert "unsolved at 1" in lines[2] and "refuses 1 of those points" in lines[3]
