"""2D Hertz line contact and Table 1 of the close-to-conformal paper (analytic.hertz)."""

import math

import numpy as np
import pytest
from scipy import integrate

from analytic import hertz as hz


def test_pressure_integrates_to_load():
    # requirement: int p dx = P to 1e-10 (quad of a semi-ellipse converges to ~1e-14)
    P, R, E = 5106.0, 5.23, 235000.0
    c = hz.hertz(P, R, E)
    val, _ = integrate.quad(
        lambda x: hz.hertz_pressure(x, a=c.half_width, p0=c.p0),
        -c.half_width,
        c.half_width,
        epsabs=0,
        epsrel=1e-13,
    )
    assert val == pytest.approx(P, rel=1e-10)
    assert c.p0 == pytest.approx(E * c.half_width / (2 * R), rel=1e-14)  # p0 = 2P/(pi a) = E* a/(2R)
    assert c.full_width == 2 * c.half_width
    assert hz.hertz_load_from_half_width(c.half_width, R, E) == pytest.approx(P, rel=1e-14)


def test_pressure_is_zero_outside_and_shifted():
    x = np.array([-3.0, 0.5, 1.0, 2.0, 4.0])
    p = hz.hertz_pressure(x, a=1.5, p0=2.0, center=1.0)
    assert p[0] == 0.0 and p[-1] == 0.0
    assert p[2] == 2.0
    assert p[1] == pytest.approx(2.0 * math.sqrt(1 - (0.5 / 1.5) ** 2), rel=1e-15)


def test_pressure_with_ufl():
    import basix.ufl
    import ufl

    domain = ufl.Mesh(basix.ufl.element("Lagrange", "triangle", 1, shape=(2,)))
    expr = hz.hertz_pressure(ufl.SpatialCoordinate(domain)[0], a=1.0, p0=2.0, xp=ufl)
    assert "max_value" in str(expr) and "sqrt" in str(expr)


def test_relative_radius_concave_negative():
    assert hz.relative_radius(2.96, -6.81) == pytest.approx(1 / (1 / 2.96 - 1 / 6.81), rel=1e-15)
    with pytest.raises(ValueError, match="^R1, R2 = .* out of range"):
        hz.relative_radius(5.0, -4.0)  # concave more curved: no convex contact


def test_table1_patch_sizes_are_full_widths():
    # paper: "0.78 mm" from eq. (4) and "0.76 mm" from eq. (5) for d = 0.60 (full widths 2a)
    rows = hz.table1_patch_sizes()
    first = rows[0]
    assert first.row.d == 0.60 and first.row.config == "symmetrical"
    assert round(first.width_eq4, 2) == 0.78
    assert first.width_eq4 == pytest.approx(4 * 5106 / (math.pi * 8361), rel=1e-15)
    assert round(first.eq5[0].width_eq5_R_printed, 2) == 0.76
    ctc = next(r for r in rows if r.row.config == "close_to_conformal" and r.row.d == 0.46)
    assert round(ctc.width_eq4, 2) == 0.46
    by_pair = {e.pair: e for e in ctc.eq5}
    assert round(by_pair["primary"].width_eq5_R_printed, 2) == 1.02
    assert round(by_pair["intersection"].width_eq5_R_printed, 2) == 0.47
    assert sum(1 for r in rows if not r.eq5) == 7  # "R not published"


def test_paper_radii_flags():
    R = {r.pair + str(r.d): r.R_computed for r in hz.PAPER_RADII}
    assert round(R["primary0.6"], 2) == 5.24  # printed 5.23: agrees to rounding
    assert R["primary0.46"] == pytest.approx(2050 / 9, rel=1e-14)  # 227.8, printed 233: does not follow
    assert R["intersection0.46"] == pytest.approx(1012 / 21, rel=1e-14)  # 48.2, printed 50
