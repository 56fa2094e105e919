"""Westergaard's periodic wavy contact (analytic.westergaard): the exact multi-patch reference.

Requirement (issue 40 acceptance): the periodic-kernel Chebyshev solve matches the closed form
p = 2 p_mean cos(pi x/L) sqrt(sin^2(pi a/L) - sin^2(pi x/L)) / sin^2(pi a/L), p_mean = (pi E* g0/L) sin^2(pi a/L),
to 1e-8 in max |p - p_exact| / p_mean and in a (measured: <= 1e-12 at 256 nodes, up to p_mean/p* = 0.95).
"""

import math

import numpy as np
import pytest

from analytic import westergaard as wg

E_STAR, G0, L = 235000.0, 0.001, 2.0


@pytest.mark.parametrize("fraction", [0.02, 0.3, 0.7, 0.95])
def test_periodic_solve_matches_westergaard(fraction):
    p_star = wg.full_contact_pressure(g0=G0, L=L, E_star=E_STAR)
    p_mean = fraction * p_star
    sol = wg.solve_wavy(g0=G0, L=L, E_star=E_STAR, p_mean=p_mean)
    a = wg.exact_half_width(p_mean=p_mean, g0=G0, L=L, E_star=E_STAR)
    x = np.linspace(-L / 2, L / 2, 4001)
    err = np.max(np.abs(sol.pressure(x) - wg.exact_pressure(x, a=a, p_mean=p_mean, L=L))) / p_mean
    assert err < 1e-8, f"max |p - p_exact| / p_mean = {err:.3g} at p_mean/p* = {fraction}"
    assert abs(sol.a / a - 1.0) < 1e-8, f"a/a_exact - 1 = {sol.a / a - 1:.3g}"
    assert sol.p_mean == pytest.approx(p_mean, rel=1e-12)


def test_full_contact_factor_by_its_own_derivation():
    # p* = pi E* g0 / L with g0 the cosine amplitude: at a -> L/2 the exact p is p_mean (1 + cos(2 pi x / L)),
    # whose cosine part must equal the full-contact pressure E* k g0 / 2 of the half-plane (k = 2 pi / L)
    p_star = wg.full_contact_pressure(g0=G0, L=L, E_star=E_STAR)
    assert p_star == pytest.approx(E_STAR * (2 * math.pi / L) * G0 / 2, rel=1e-15)
    x = np.linspace(-0.9, 0.9, 7)
    p = wg.exact_pressure(x, a=0.5 * L * (1 - 1e-12), p_mean=p_star, L=L)
    assert np.allclose(p, p_star * (1 + np.cos(2 * math.pi * x / L)), rtol=1e-9, atol=0)


def test_a_wrong_factor_would_fail():
    # the numerical p_mean(a) is not the closed form with a factor 2 off: the check above can fail
    sol = wg.solve_wavy(g0=G0, L=L, E_star=E_STAR, p_mean=0.3 * wg.full_contact_pressure(g0=G0, L=L, E_star=E_STAR))
    wrong = wg.exact_half_width(p_mean=0.3 * math.pi * E_STAR * G0 / L / 2, g0=G0, L=L, E_star=E_STAR)
    assert abs(sol.a / wrong - 1.0) > 0.1


@pytest.mark.parametrize("kw, field", [({"p_mean": 1e9}, "p_mean"), ({"g0": -1.0}, "g0"), ({"L": 0.0}, "L")])
def test_bad_input_names_the_field(kw, field):
    args = {"g0": G0, "L": L, "E_star": E_STAR, "p_mean": 10.0} | kw
    with pytest.raises(ValueError, match=field):
        wg.solve_wavy(**args)
