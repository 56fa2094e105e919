"""Elastic constants (analytic.materials) against hand values; tolerances are round-off (1e-14 relative)."""

import pytest

from analytic import materials as mt

RTOL = 1e-14  # every check is a closed-form identity evaluated in double precision


def test_composite_modulus_rigid_indenter_matches_paper():
    # close-to-conformal paper: E = 214 GPa, nu = 0.3, rigid particle -> E* = 235 GPa (printed, rounded)
    E_star = mt.composite_modulus(214000.0, 0.3)
    assert E_star == pytest.approx(214000.0 / 0.91, rel=RTOL)
    assert round(E_star / 1000.0) == 235
    assert mt.compliance(214000.0, 0.3) == pytest.approx(2.0 / E_star, rel=RTOL)


def test_two_identical_bodies_halve_plane_strain_modulus():
    E, nu = 210000.0, 0.3
    assert mt.composite_modulus(E, nu, E1=E, nu1=nu) == pytest.approx(
        0.5 * mt.plane_strain_modulus(E, nu), rel=RTOL
    )


def test_kolosov_plane_strain_and_stress():
    assert mt.kolosov(0.25) == pytest.approx(2.0, rel=RTOL)
    assert mt.kolosov(0.25, plane="stress") == pytest.approx(2.75 / 1.25, rel=RTOL)


@pytest.mark.parametrize("nu", [0.0, 0.1, 0.25, 0.3, 0.49])
def test_dundurs_rigid_indenter(nu):
    d = mt.dundurs(1000.0, nu)
    assert d.alpha == pytest.approx(-1.0, rel=RTOL)
    assert d.beta == pytest.approx(mt.beta_rigid_indenter(nu), rel=RTOL, abs=1e-15)
    assert d.beta == pytest.approx(-(1 - 2 * nu) / (2 * (1 - nu)), rel=RTOL, abs=1e-15)


def test_beta_extreme_is_minus_half_and_swap_antisymmetry():
    assert mt.beta_rigid_indenter(0.0) == -0.5  # C&H eq. (7)
    assert mt.dundurs(210000.0, 0.3, E1=210000.0, nu1=0.3) == pytest.approx((0.0, 0.0), abs=1e-15)
    a = mt.dundurs(70000.0, 0.33, E1=210000.0, nu1=0.3)
    b = mt.dundurs(210000.0, 0.3, E1=70000.0, nu1=0.33)
    assert (a.alpha, a.beta) == pytest.approx((-b.alpha, -b.beta), rel=1e-13)


@pytest.mark.parametrize(
    "call, field",
    [
        (lambda: mt.composite_modulus(-1.0, 0.3), "E2"),
        (lambda: mt.composite_modulus(1.0, 0.5), "nu2"),
        (lambda: mt.kolosov(-1.0), "nu"),
        (lambda: mt.kolosov(0.3, plane="shell"), "plane"),
    ],
)
def test_bad_values_name_the_field(call, field):
    with pytest.raises(ValueError, match=rf"^{field} = .* out of range"):
        call()
