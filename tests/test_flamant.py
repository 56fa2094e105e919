"""Flamant's half-plane line load (analytic/flamant.py): strains of the displacement give the closed-form stress,
the stress is in equilibrium, the surface is traction-free, the resultant on a half circle is P, and the
quadrupole term is the second x-derivative of the field (all by finite differences)."""

import numpy as np
import pytest

from analytic.flamant import (
    flamant_displacement,
    flamant_quadrupole_displacement,
    flamant_stress,
    plane_strain_stress,
)

E, NU, P, R_REF = 2.1e5, 0.3, 150.0, 40.0
rng = np.random.default_rng(12)
X = rng.uniform(-3.0, 3.0, 40)
Y = -rng.uniform(0.2, 3.0, 40)


def _grad(f, x, y, h=1e-5):
    """Central differences (df/dx, df/dy) of a scalar field."""
    return (f(x + h, y) - f(x - h, y)) / (2 * h), (f(x, y + h) - f(x, y - h)) / (2 * h)


def _stress_from_displacement(x, y):
    ux = lambda x, y: flamant_displacement(x, y, P=P, E=E, nu=NU, r_ref=R_REF)[0]  # noqa: E731
    uy = lambda x, y: flamant_displacement(x, y, P=P, E=E, nu=NU, r_ref=R_REF)[1]  # noqa: E731
    (uxx, uxy), (uyx, uyy) = _grad(ux, x, y), _grad(uy, x, y)
    return plane_strain_stress(uxx, uyy, 0.5 * (uxy + uyx), E=E, nu=NU)


@pytest.mark.parametrize("comp", ["sxx", "syy", "sxy"])
def test_strains_of_the_displacement_give_the_closed_form_stress(comp):
    fd = getattr(_stress_from_displacement(X, Y), comp)
    ex = getattr(flamant_stress(X, Y, P=P), comp)
    scale = 2 * P / (np.pi * np.hypot(X, Y))  # |sigma_rr|
    assert np.max(np.abs(fd - ex) / scale) < 1e-6


def test_stress_is_in_equilibrium():
    """div sigma = 0 (Navier's equations, as the stress comes from the displacement)."""
    s = lambda c: (lambda x, y: getattr(flamant_stress(x, y, P=P), c))  # noqa: E731
    dsxx_dx, _ = _grad(s("sxx"), X, Y)
    dsxy_dx, dsxy_dy = _grad(s("sxy"), X, Y)
    _, dsyy_dy = _grad(s("syy"), X, Y)
    scale = 2 * P / (np.pi * np.hypot(X, Y) ** 2)
    assert np.max(np.abs(dsxx_dx + dsxy_dy) / scale) < 1e-6
    assert np.max(np.abs(dsxy_dx + dsyy_dy) / scale) < 1e-6


def test_sigma_rr_is_the_radial_field():
    r, phi = np.hypot(X, Y), np.arctan2(X, -Y)  # phi from the downward vertical
    s = flamant_stress(X, Y, P=P)
    er = np.array([np.sin(phi), -np.cos(phi)])
    srr = s.sxx * er[0] ** 2 + 2 * s.sxy * er[0] * er[1] + s.syy * er[1] ** 2
    et = np.array([np.cos(phi), np.sin(phi)])
    srt = s.sxx * er[0] * et[0] + s.sxy * (er[0] * et[1] + er[1] * et[0]) + s.syy * er[1] * et[1]
    np.testing.assert_allclose(srr, -2 * P * np.cos(phi) / (np.pi * r), rtol=1e-12)
    assert np.max(np.abs(srt)) < 1e-12 * P


def test_surface_is_traction_free():
    """On y = 0, x != 0: sigma_yy = sigma_xy = 0, also from the displacement's strains (one-sided limit)."""
    x = np.array([-2.0, -0.5, 0.3, 1.7])
    s = flamant_stress(x, np.zeros_like(x), P=P)
    assert np.all(s.syy == 0) and np.all(s.sxy == 0)
    fd = _stress_from_displacement(x, -np.full_like(x, 2e-5))
    assert np.max(np.abs(fd.syy)) < 1e-3 * P and np.max(np.abs(fd.sxy)) < 1e-3 * P


@pytest.mark.parametrize("radius", [0.5, 7.0])
def test_resultant_on_a_half_circle_is_P(radius):
    """The traction sigma.n on the half circle (n outward) sums to (0, +P): the outer body holds the half disc,
    loaded by P down at the origin, with P up."""
    t = np.linspace(-np.pi / 2, np.pi / 2, 20001)
    x, y = radius * np.sin(t), -radius * np.cos(t)
    n = np.array([np.sin(t), -np.cos(t)])
    s = flamant_stress(x, y, P=P)
    tx, ty = s.sxx * n[0] + s.sxy * n[1], s.sxy * n[0] + s.syy * n[1]
    fx, fy = np.trapezoid(tx, t) * radius, np.trapezoid(ty, t) * radius
    assert abs(fx) < 1e-9 * P
    assert abs(fy - P) < 1e-7 * P


def test_reference_depth_is_where_uy_vanishes_and_the_field_is_symmetric():
    ux, uy = flamant_displacement(0.0, -R_REF, P=P, E=E, nu=NU, r_ref=R_REF)
    assert ux == 0.0 and abs(uy) < 1e-18
    a = flamant_displacement(X, Y, P=P, E=E, nu=NU, r_ref=R_REF)
    b = flamant_displacement(-X, Y, P=P, E=E, nu=NU, r_ref=R_REF)
    np.testing.assert_allclose(a[0], -b[0], rtol=1e-13)
    np.testing.assert_allclose(a[1], b[1], rtol=1e-13)
    # the surface slides towards the load by (1 - 2 nu)(1 + nu) P / (2 E)
    ux_s, _ = flamant_displacement(np.array([1.0, -2.0]), np.zeros(2), P=P, E=E, nu=NU, r_ref=R_REF)
    np.testing.assert_allclose(ux_s, np.array([-1, 1]) * (1 - 2 * NU) * (1 + NU) * P / (2 * E), rtol=1e-13)


def test_quadrupole_is_the_second_moment_of_a_spread_load():
    """Two loads P/2 at +-c (M2 = P c^2) against P at the origin plus the quadrupole: the rest is O(c^4 / r^4)."""
    c = 0.05
    for comp in (0, 1):
        two = sum(flamant_displacement(X - s, Y, P=P / 2, E=E, nu=NU, r_ref=R_REF)[comp] for s in (-c, c))
        mono = flamant_displacement(X, Y, P=P, E=E, nu=NU, r_ref=R_REF)[comp]
        quad = flamant_quadrupole_displacement(X, Y, M2=P * c * c, E=E, nu=NU)[comp]
        r = np.hypot(X, Y)
        K = P * (1 + NU) / (np.pi * E)
        assert np.max(np.abs(two - mono - quad) / (K * (c / r) ** 4)) < 10.0
        assert np.max(np.abs(two - mono) / (K * (c / r) ** 2)) > 0.1  # the quadrupole is not trivially small
