"""The concave map's FEM band (issue 40, item 2): the two-grid GCI by hand, patch matching, and the rule that a model
within the band counts as within. Pure Python, no FEM."""

from __future__ import annotations

import math

import pytest

from workbench.error_budget import FORMAL_ORDER_EDGE
from workbench.studies.concave_map_band import (
    ASSUMED_ORDER,
    FS_TWO_GRID,
    REFINEMENT,
    attach_bands,
    effective_error,
    point_band,
    within_band,
)


def _pt(P, p_max, widths, *, design="d", approach=0.01, models=None):
    return {"design": design, "approach_mm": approach, "P_fem": P, "p_max_fem": p_max,
            "fem_patches": [{"center": float(k), "half_width": w / 2, "p_max": p_max, "P": P} for k, w in
                            enumerate(widths)],
            "models": models or {}}


def test_the_assumed_order_is_the_budgets_edge_order():
    assert ASSUMED_ORDER == FORMAL_ORDER_EDGE and REFINEMENT == 2.0 and FS_TWO_GRID == 3.0


def test_two_grid_band_by_hand():
    fine, coarse = _pt(100.0, 500.0, [1.0, 0.2]), _pt(101.0, 480.0, [1.02, 0.21])
    b = point_band(fine, coarse)
    k = 3.0 / (2.0**1.5 - 1.0)
    assert b["P"] == pytest.approx(k * 0.01) and b["p0"] == pytest.approx(k * 0.04)
    assert b["width"] == pytest.approx(k * 0.05)  # the largest patch band (0.21 against 0.2)
    # a different number of patches: the widths have no band, and nothing is rescued by width
    b = point_band(fine, _pt(101.0, 480.0, [1.02]))
    assert b["width"] is None and (b["n_patches_fine"], b["n_patches_coarse"]) == (2, 1)
    assert not within_band({"P": math.nan, "width": 0.0, "p0": 0.0}, b)


def test_within_band_and_the_effective_error():
    band = {"P": 0.02, "p0": 0.1, "width": 0.08}
    assert within_band({"P": None, "width": 0.07, "p0": 0.09}, band)   # P not compared (a Hertz model)
    assert not within_band({"P": 0.03, "width": 0.07, "p0": 0.09}, band)
    assert not within_band({"P": None, "width": 0.07, "p0": 0.09}, None)
    assert not within_band({"P": None, "width": None, "p0": None}, band)  # nothing compared: nothing rescued
    fine = _pt(100.0, 500.0, [1.0], models={
        "m": {"P": None, "width": 0.07, "p0": 0.02, "worst": 0.07, "class": "10%"},
        "n": {"P": None, "width": 0.2, "p0": 0.02, "worst": 0.2, "class": "beyond"}})
    other = _pt(1.0, 1.0, [1.0], design="not solved coarse")
    assert attach_bands([fine, other], [_pt(101.0, 520.0, [1.05])]) == 1
    assert other["fem_band"] is None and not other["models"]
    assert fine["models"]["m"]["within_fem_band"] and not fine["models"]["n"]["within_fem_band"]
    assert effective_error(fine, "m") == 0.0 and effective_error(fine, "n") == 0.2
