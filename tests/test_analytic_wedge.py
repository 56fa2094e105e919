"""Classical rigid wedge on a half-plane (analytic.wedge)."""

import math

import numpy as np
import pytest
from scipy import integrate

from analytic import wedge as wd


@pytest.mark.parametrize("m", [0.05, math.pi / 5, math.tan(math.pi / 5)])
def test_pressure_integrates_to_load(m):
    # int p = E* m b to 1e-10 (quad handles the integrable log singularity at the apex to ~1e-14)
    E, P = 210000.0, 100.0
    c = wd.wedge(P, m, E)
    val, _ = integrate.quad(
        lambda x: wd.wedge_pressure(x, b=c.half_width, m=m, E_star=E),
        0.0,
        c.half_width,
        epsabs=0,
        epsrel=1e-13,
        limit=200,
    )
    assert 2 * val == pytest.approx(P, rel=1e-10)
    assert wd.wedge_load_from_half_width(c.half_width, m, E) == pytest.approx(P, rel=1e-14)


def test_pressure_formula_and_support():
    b, m, E = 0.5, 0.3, 1e5
    x = np.array([-0.7, -0.2, 0.25, 0.5])
    p = wd.wedge_pressure(x, b=b, m=m, E_star=E)
    assert p[0] == 0.0 and p[3] == 0.0
    assert p[1] == pytest.approx(E * m / math.pi * math.acosh(b / 0.2), rel=1e-14)


def test_slope_conventions():
    assert wd.wedge_slope(0.3, convention="paper") == 0.3
    assert wd.wedge_slope(0.3, convention="exact") == pytest.approx(math.tan(0.3), rel=1e-15)
    with pytest.raises(ValueError, match="^theta = .* out of range"):
        wd.wedge_slope(math.pi / 2, convention="exact")
    with pytest.raises(ValueError, match="^convention = .* out of range"):
        wd.wedge_slope(0.3, convention="small")
