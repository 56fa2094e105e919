"""Convective correction of Ciavarella & Hills (analytic.convective).

Tolerances: closed-form identities at round-off (1e-12..1e-14); solver values against closed forms at
the solver's measured O(N^-2) discretisation error (self-convergence below), stated per test.
"""

import math

import numpy as np
import pytest
from scipy import integrate

from analytic import convective as cv

N_TEST = 16384  # nodes for the accuracy tests: fixed-point b/b0 error ~1e-9 at this N (see self-convergence)


def test_first_order_integrals_of_the_derivation():
    # wedge: int_0^1 s arccosh(1/s)/sqrt(1-s^2) ds = ln 2 ; parabola: int s [G + s sqrt(1-s^2)]/sqrt(1-s^2) = 2
    wedge_int, _ = integrate.quad(
        lambda u: math.cos(u) * math.acosh(1 / math.cos(u)), 0, math.pi / 2, epsabs=0, epsrel=1e-13, limit=200
    )
    assert wedge_int == pytest.approx(math.log(2), rel=1e-10)

    def G(s):
        return 0.5 * (s * math.sqrt(1 - s * s) + math.asin(s))

    par_int, _ = integrate.quad(
        lambda u: math.sin(u) * (G(math.sin(u)) + math.sin(u) * math.cos(u)),
        -math.pi / 2,
        math.pi / 2,
        epsabs=0,
        epsrel=1e-13,
    )
    assert par_int == pytest.approx(2.0, rel=1e-10)


def test_first_order_closed_forms():
    assert cv.wedge_first_order(math.pi / 5, -0.5) == pytest.approx(1 / (1 - 0.2 * math.log(2)), rel=1e-15)
    assert cv.parabola_first_order(0.25, -0.5) == pytest.approx((1 - 1 / (2 * math.pi)) ** -0.5, rel=1e-15)
    # from b0/R: the corrected b/R = q b0/R reproduces the b/R form
    q = cv.parabola_first_order_from_b0(0.25, -0.5)
    assert q == pytest.approx(cv.parabola_first_order(0.25 * q, -0.5), rel=1e-13)


@pytest.mark.parametrize(
    "profile", [cv.wedge_profile(math.pi / 5), cv.parabola_profile(0.25), cv.power_profile(3, 0.25)]
)
def test_beta_zero_reproduces_classical(profile):
    sol = cv.solve(profile, beta=0.0, n_nodes=N_TEST)
    for r in (
        sol.b_over_b0_first_order,
        sol.b_over_b0_first_order_numeric,
        sol.b_over_b0_first_iterate,
        sol.b_over_b0_converged,
    ):
        assert r == pytest.approx(1.0, abs=1e-10)


def test_beta_zero_parabola_pressure_is_hertz():
    sol = cv.solve(cv.parabola_profile(0.1), beta=0.0, n_nodes=N_TEST, n_plot=201)
    hertz = (2 / math.pi) * np.sqrt(np.clip(1 - sol.x**2, 0, None))  # p b0/P of the semi-ellipse
    # the spectral inversion of h' = x/R is exact (one Chebyshev mode); the plot grid interpolates the
    # nodal values linearly, error <= (spacing pi/N)^2 * max|p''| in theta ~ 1e-8 away from the edges
    inside = np.abs(sol.x) < 0.99
    assert np.max(np.abs(sol.p_converged - hertz)[inside]) < 1e-7


def test_beta_zero_nodal_pressure_exact():
    # nodal values (no interpolation): parabola to round-off
    theta, s = cv._nodes(1024)
    w = cv._sine_series(cv._coeffs(0.3 * s))
    assert np.max(np.abs(w - 0.3 * np.sqrt(1 - s * s))) < 1e-14


@pytest.mark.parametrize(
    "profile, beta, tol",
    [
        # O(N^-2 log N) error of the DCT of sign(s)*log-singular p0 at the apex: 3e-9 measured at N = 16384
        (cv.wedge_profile(math.pi / 5), -0.5, 2e-8),
        (cv.wedge_profile(math.pi / 20), -0.1, 2e-8),
        # parabola: the first-order slope has (1-s)^(3/2)-type endpoint terms: O(N^-2), 2e-10 measured
        (cv.parabola_profile(0.25), -0.5, 2e-9),
        (cv.parabola_profile(0.05), -0.25, 2e-9),
    ],
)
def test_first_order_solver_matches_closed_form(profile, beta, tol):
    sol = cv.solve(profile, beta=beta, n_nodes=N_TEST)
    assert sol.b_over_b0_first_order_numeric == pytest.approx(sol.b_over_b0_first_order, abs=tol)


def test_first_iterate_and_fixed_point_agree_with_first_order_to_second_order():
    # b/b0 - first order = O(beta^2): halving beta divides the difference by 4 (+-10 %)
    prof = cv.wedge_profile(math.pi / 5)
    d = {}
    for beta in (-0.02, -0.01):
        sol = cv.solve(prof, beta=beta, n_nodes=N_TEST)
        d[beta] = (
            sol.b_over_b0_first_iterate - sol.b_over_b0_first_order,
            sol.b_over_b0_converged - sol.b_over_b0_first_order,
        )
    for k in range(2):
        assert d[-0.02][k] / d[-0.01][k] == pytest.approx(4.0, rel=0.1)


def test_wedge_depends_on_m_beta_only():
    a = cv.converged_b_over_b0(cv.wedge_profile(math.pi / 10), beta=-0.5, n_nodes=4096)
    b = cv.converged_b_over_b0(cv.wedge_profile(math.pi / 5), beta=-0.25, n_nodes=4096)
    assert a == pytest.approx(b, abs=1e-13)


@pytest.mark.parametrize("profile", [cv.wedge_profile(math.pi / 5), cv.parabola_profile(0.25)])
def test_self_convergence(profile):
    rows = cv.self_convergence(profile, beta=-0.5, n_nodes=(1024, 2048, 4096, 8192, 16384, 32768, 65536))
    changes = np.array([r.change for r in rows[1:]])
    n = np.array([r.n_nodes for r in rows[1:]], dtype=float)
    rate = -np.polyfit(np.log(n[-3:]), np.log(changes[-3:]), 1)[0]
    assert abs(rate - 2.0) < 0.15, f"observed rate {rate:.3f}, expected 2"
    assert changes[-1] <= 1e-8, f"finest change {changes[-1]:.2e} > 1e-8"


def test_convective_widens_contact_for_negative_beta():
    sol = cv.solve(cv.parabola_profile(0.25), beta=-0.5, n_nodes=N_TEST)
    assert 1.0 < sol.b_over_b0_first_iterate < sol.b_over_b0_converged < sol.b_over_b0_first_order
    assert sol.p_converged.max() < sol.p_classical.max()  # shallower profile, lower peak


def test_default_solve_uses_the_full_grid():
    # Not a timed test (the machine may be shared): the speed of the solver is a benchmark figure.
    sol = cv.solve(cv.wedge_profile(math.pi / 5), beta=-0.5)  # default N = 65536
    assert sol.n_nodes == 65536


@pytest.mark.parametrize(
    "call, field",
    [
        (lambda: cv.solve(cv.parabola_profile(0.2), beta=-0.6), "beta"),
        (lambda: cv.parabola_profile(1.2), "b0_over_R"),
        (lambda: cv.wedge_profile(0.0), "m"),
        (lambda: cv.solve(cv.parabola_profile(0.2), beta=-0.1, n_nodes=7), "n_nodes"),
    ],
)
def test_bad_values(call, field):
    with pytest.raises(ValueError, match=rf"^{field} = .* out of range"):
        call()


@pytest.mark.parametrize(
    "profile, tol",
    [
        # independent route: DCT load of the first-iterate slope at N = 2^16 nodes; its error decays slowly
        # (kink of p0 at x = b0 inside the new contact): 2.1e-7 (wedge) and 1.5e-9 (parabola) measured
        (cv.wedge_profile(math.pi / 5), 5e-7),
        (cv.parabola_profile(0.25), 5e-9),
    ],
)
def test_first_iterate_by_independent_quadrature(profile, tol):
    from scipy import optimize

    beta, N = -0.5, 2**16
    _, s = cv._nodes(N)
    w0, W0 = (np.vectorize(f) for f in cv._classical_funcs(profile, N))
    a10 = cv._a1_classical(profile)

    def load(b1):
        x = b1 * s
        F = profile.lam * cv._slope(x + beta * W0(x), profile.n) * (1 + beta * w0(x))
        return b1 * cv._coeffs(F)[1] - a10

    r = optimize.brentq(load, 1.0, 1.5, xtol=1e-14)
    assert cv.solve(profile, beta=beta, n_nodes=4096).b_over_b0_first_iterate == pytest.approx(r, abs=tol)
