"""grid_study names a sequence whose differences grow on refinement (no positive order fits it)."""

from __future__ import annotations

import math

import pytest

from workbench.error_budget import FS, grid_study


@pytest.mark.parametrize("h", [(0.1, 0.2, 0.4), (0.1, 0.17, 0.4)])
def test_growing_differences_are_diverging_not_an_order(h):
    # f = 1 - 0.01 h^-1: monotone, but the differences grow as h shrinks (the Hertz sample peak of issue 12)
    f = tuple(1.0 - 0.01 / hi for hi in h)
    g = grid_study(h, f)
    assert g.status == "diverging" and math.isnan(g.observed_order) and g.extrapolated == f[0]
    assert g.gci == pytest.approx(FS * abs(f[2] - f[0]) / abs(f[0]))


def test_slow_but_converging_sequence_keeps_its_order():
    h = (0.1, 0.2, 0.4)
    f = tuple(2.0 + 0.5 * hi**0.2 for hi in h)
    g = grid_study(h, f)
    assert g.status == "asymptotic" and g.observed_order == pytest.approx(0.2, rel=1e-9)
    assert g.extrapolated == pytest.approx(2.0, rel=1e-12)
