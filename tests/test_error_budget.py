"""The three-grid arithmetic (workbench/error_budget.py) on sequences with known limits."""

from __future__ import annotations

import math

import pytest

from workbench.error_budget import FS, grid_study


@pytest.mark.parametrize("p", [0.5, 1.0, 2.0, 3.0])
@pytest.mark.parametrize("h", [(0.1, 0.2, 0.4), (0.1, 0.17, 0.4)])  # constant and non-constant ratio
def test_exact_power_law_gives_its_order_and_limit(p, h):
    f = tuple(1.1646 + 0.3 * hi**p for hi in h)
    g = grid_study(h, f, expected_order=p)
    assert g.observed_order == pytest.approx(p, rel=1e-9)
    assert g.extrapolated == pytest.approx(1.1646, rel=1e-12)
    assert g.status == "asymptotic"
    r = h[1] / h[0]
    assert g.gci == pytest.approx(FS * abs(f[1] - f[0]) / f[0] / (r**p - 1.0), rel=1e-9)
    assert g.contains(1.1646)


def test_order_of_unsorted_input_and_the_named_cases():
    g = grid_study((0.4, 0.1, 0.2), (1.0 + 0.16, 1.0 + 0.01, 1.0 + 0.04))
    assert g.observed_order == pytest.approx(2.0) and g.fine == pytest.approx(1.01)
    osc = grid_study((0.1, 0.2, 0.4), (1.1634, 1.1635, 1.1618))  # the wedge b/b0 of the issue: not monotone
    assert osc.status == "oscillating" and math.isnan(osc.observed_order) and osc.extrapolated == 1.1634
    assert osc.gci == pytest.approx(FS * (1.1634 - 1.1618) / 1.1634)
    flat = grid_study((0.1, 0.2, 0.4), (2.0, 2.0, 2.0))
    assert flat.status == "converged" and flat.gci == 0.0
    wrong = grid_study((0.1, 0.2, 0.4), (1.0 + 1e-3, 1.0 + 2e-3, 1.0 + 4e-3), expected_order=2.0)
    assert wrong.status == "not asymptotic" and wrong.observed_order == pytest.approx(1.0)


@pytest.mark.parametrize("h, f", [((0.1, 0.2), (1.0, 1.1)), ((0.1, 0.1, 0.2), (1, 2, 3)),
                                  ((0.1, 0.2, 0.4), (1.0, math.nan, 1.2)), ((0.0, 0.2, 0.4), (1, 2, 3))])
def test_bad_input_is_refused(h, f):
    with pytest.raises(ValueError):
        grid_study(h, f)
