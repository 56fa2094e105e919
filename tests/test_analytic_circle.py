"""The exact-circle half-plane contact (analytic/circle.py): Hertz limit, two independent load formulas, and the
wide contact that Hertz misreads (issue: a/R = 0.17 gave the FEM 'FAIL' against Hertz)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from analytic.circle import circle_contact, circle_load, circle_pressure
from analytic.hertz import hertz
from analytic.materials import plane_strain_modulus


def test_hertz_limit():
    """b/R = 1e-3: the exact circle is Hertz to O((b/R)^2)."""
    E_star, R = 2.3e5, 10.0
    P = 1.0e3 * hertz(1.0, R, E_star).P  # any load; scaled below to b/R ~ 1e-3
    h = hertz(P, R, E_star)
    c = circle_contact(P, R, E_star)
    k = h.half_width / R
    assert abs(c.half_width / h.half_width - 1.0) < 2.0 * k**2
    assert abs(c.p0 / h.p0 - 1.0) < 2.0 * k**2


def test_load_from_the_series_equals_the_elliptic_integrals():
    """P = (pi/2) b a_1 / A from the Chebyshev pressure, integrated, equals E* R (K - E) to round-off."""
    E_star, R, b = 1.0e3, 4.0, 2.0
    x = b * np.cos(np.linspace(0.0, math.pi, 20001))
    p = circle_pressure(x, b=b, R=R, E_star=E_star)
    P_int = float(np.trapezoid(p[::-1], x[::-1]))
    assert P_int == pytest.approx(circle_load(b, R, E_star), rel=1e-7)


def test_first_correction_to_hertz():
    """At a given load the exact circle's b is smaller than Hertz's by about 3 k^2 / 16 (module docstring)."""
    E_star, R = 1.0e3, 10.0
    c = circle_contact(5.0, R, E_star)
    h = hertz(5.0, R, E_star)
    k = c.half_width / R
    assert 1.0 - c.half_width / h.half_width == pytest.approx(3.0 * k**2 / 16.0, rel=0.05)


def test_wide_contact_of_two_identical_cylinders():
    """R = 8 mm pairs, E = 200 MPa, nu = 0.3, P = 10 N/mm, as the rigid equivalent R = 4, E = 100: Hertz gives
    b = 0.6808 mm and p0 = 9.351 MPa; the exact circle gives b = 0.6771 mm (-0.54 %) and p0 = 9.368 MPa. The FEM
    reported 0.6768 and 9.373, i.e. it matches the exact circle, not Hertz."""
    E_star = plane_strain_modulus(100.0, 0.3)
    c = circle_contact(10.0, 4.0, E_star)
    h = hertz(10.0, 4.0, E_star)
    assert c.half_width == pytest.approx(0.677084, abs=2e-6)
    assert c.p0 == pytest.approx(9.36833, abs=2e-5)
    assert (c.half_width - h.half_width) / h.half_width == pytest.approx(-0.005426, abs=2e-6)
    assert abs(0.6768 / c.half_width - 1.0) < 1e-3 and abs(9.373 / c.p0 - 1.0) < 1e-3


@pytest.mark.parametrize("kwargs", [dict(P=-1.0, R=1.0, E_star=1.0), dict(P=1.0, R=0.0, E_star=1.0),
                                    dict(P=1e9, R=1.0, E_star=1.0)])
def test_bad_values_are_refused_by_name(kwargs):
    with pytest.raises(ValueError, match=r"out of range|must be|> 0"):
        circle_contact(**kwargs)
