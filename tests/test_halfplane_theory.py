"""analytic.halfplane: the exact circle, Hertz and the wedge on a half-plane, classical and convective.

The circle is checked against an independent second solution of the same integral equation (adaptive
Gauss-Kronrod quadrature of the Shtaerman load and of the singularity-subtracted inversion, no Chebyshev series)
and against the elliptic closed form of :mod:`analytic.circle`; its spectral convergence is measured.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from analytic import circle, convective, halfplane, hertz, materials
from analytic.__main__ import main

E_STAR = materials.plane_strain_modulus(100.0, 0.3)


@pytest.mark.parametrize("b_over_R", [0.01, 0.17, 0.4, 0.8])
def test_circle_agrees_with_the_quadrature_solution_and_the_elliptic_load(b_over_R):
    R = 4.0
    P = circle.circle_load(b_over_R * R, R, E_STAR)
    prof = halfplane.profile("circle", R=R)
    spec = halfplane.solve_halfplane(prof, P=P, E_star=E_STAR)
    x = np.linspace(-0.95, 0.95, 7) * spec.half_width
    quad = halfplane.classical_by_quadrature(prof, P=P, E_star=E_STAR, x=x)
    assert spec.half_width == pytest.approx(b_over_R * R, rel=1e-12)
    assert spec.half_width == pytest.approx(quad.half_width, rel=1e-12)
    assert spec.p_max == pytest.approx(quad.p_centre, rel=1e-10)
    np.testing.assert_allclose(spec.pressure(x), quad.p, rtol=1e-9, atol=1e-12 * spec.p_max)
    assert spec.p_max == pytest.approx(circle.circle_contact(P, R, E_STAR).p0, rel=1e-10)


def test_circle_spectral_convergence_is_geometric():
    R, P = 4.0, 10.0
    prof = halfplane.profile("circle", R=R)
    ref = halfplane.solve_halfplane(prof, P=P, E_star=E_STAR, n_nodes=4096)
    errs = [abs(halfplane.solve_halfplane(prof, P=P, E_star=E_STAR, n_nodes=n).p_max / ref.p_max - 1.0)
            for n in (64, 256, 1024)]
    assert max(errs) < 1e-13, errs
    # a very wide contact (b/R = 0.99) peaks off the centre and needs more terms, but converges
    P9 = circle.circle_load(0.99 * R, R, E_STAR)
    peaks = {n: halfplane.solve_halfplane(prof, P=P9, E_star=E_STAR, n_nodes=n).p_max for n in (64, 256, 4096)}
    assert abs(peaks[256] / peaks[4096] - 1.0) < 1e-12 < 1e-6 < abs(peaks[64] / peaks[4096] - 1.0)
    centre = halfplane.solve_halfplane(prof, P=P9, E_star=E_STAR).pressure([0.0])[0]
    assert peaks[4096] > 1.4 * centre


def test_parabola_reproduces_hertz_to_1e_10():
    for R, P in ((4.0, 10.0), (10.0, 1e3), (1e3, 0.01)):
        s = halfplane.solve_halfplane(halfplane.profile("parabola", R=R), P=P, E_star=E_STAR)
        h = hertz.hertz(P, R, E_STAR)
        assert s.half_width == pytest.approx(h.half_width, rel=1e-10)
        assert s.p_max == pytest.approx(h.p0, rel=1e-10)
        assert s.moment_half_width == pytest.approx(h.half_width, rel=1e-10)


def test_circle_is_narrower_than_hertz_by_three_sixteenths_k_squared():
    R = 10.0
    for k in (1e-3, 1e-2):
        P = hertz.hertz_load_from_half_width(k * R, R, E_STAR)
        s = halfplane.solve_halfplane(halfplane.profile("circle", R=R), P=P, E_star=E_STAR)
        assert 1.0 - s.half_width / (k * R) == pytest.approx(3.0 * k * k / 16.0, rel=2e-2)


def test_wedge_classical_and_convective_match_the_closed_form_and_ciavarella_hills():
    m = math.pi / 5
    prof = halfplane.profile("wedge", m=m)
    s0 = halfplane.solve_halfplane(prof, P=10.0, E_star=E_STAR)
    assert s0.half_width == pytest.approx(10.0 / (E_STAR * m), rel=1e-14)
    assert s0.moment_half_width / s0.half_width == pytest.approx(2.0 / math.sqrt(6.0), rel=1e-5)
    assert math.isinf(s0.p_max)
    s = halfplane.solve_halfplane(prof, P=10.0, E_star=E_STAR, beta=-0.5, n_nodes=4096)
    ref = convective.converged_b_over_b0(convective.wedge_profile(m), beta=-0.5, n_nodes=4096)
    assert s.half_width / s.b_classical == pytest.approx(ref, rel=1e-12)


def test_convective_parabola_matches_ciavarella_hills_and_the_circle_differs():
    bR = 0.2
    P = math.pi * E_STAR * bR**2 / 4.0  # classical Hertz b0 = 0.2 R, R = 1
    par = halfplane.solve_halfplane(halfplane.profile("parabola", R=1.0), P=P, E_star=E_STAR, beta=-0.5,
                                    n_nodes=4096)
    ref = convective.converged_b_over_b0(convective.parabola_profile(bR), beta=-0.5, n_nodes=4096)
    assert par.half_width / par.b_classical == pytest.approx(ref, rel=1e-12)
    cir = halfplane.solve_halfplane(halfplane.profile("circle", R=1.0), P=P, E_star=E_STAR, beta=-0.5)
    assert cir.iterations > 1
    # the convective ratio of the exact circle is close to, but not, the parabola's
    assert abs(cir.half_width / cir.b_classical / (par.half_width / par.b_classical) - 1.0) < 5e-3
    assert cir.half_width / cir.b_classical != pytest.approx(par.half_width / par.b_classical, rel=1e-6)


def test_cli_json_circle(capsys):
    assert main(["halfplane", "--profile", "circle", "--R", "4", "--E", "100", "--nu", "0.3", "--P", "10",
                 "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    c = circle.circle_contact(10.0, 4.0, E_STAR)
    assert d["half_width"] == pytest.approx(c.half_width, rel=1e-12)
    assert d["p_max"] == pytest.approx(c.p0, rel=1e-10)
    assert d["half_width_over_hertz"] < 1.0 < d["p_max_over_hertz"]


@pytest.mark.parametrize("args", [
    ["--profile", "circle", "--E", "100", "--nu", "0.3", "--P", "10"],
    ["--profile", "circle", "--R", "-1", "--E", "100", "--nu", "0.3", "--P", "10"],
    ["--profile", "circle", "--R", "4", "--E", "100", "--nu", "0.3", "--P", "1e5"],
    ["--profile", "circle", "--R", "4", "--E", "100", "--nu", "0.3", "--P", "0"],
    ["--profile", "circle", "--R", "4", "--E", "100", "--nu", "0.5", "--P", "10"],
    ["--profile", "circle", "--R", "4", "--E", "100", "--nu", "0.3", "--P", "10", "--beta", "-0.7"],
    ["--profile", "circle", "--R", "4", "--theta", "0.3", "--E", "100", "--nu", "0.3", "--P", "10"],
    ["--profile", "wedge", "--R", "4", "--E", "100", "--nu", "0.3", "--P", "10"],
    ["--profile", "wedge", "--theta", "2", "--E", "100", "--nu", "0.3", "--P", "10"],
    ["--profile", "ellipse", "--R", "4", "--E", "100", "--nu", "0.3", "--P", "10"],
    ["--profile", "circle", "--R", "4", "--E", "100", "--nu", "0.3", "--P", "10", "--pressure", "1"],
])
def test_cli_bad_arguments_one_line_exit_2(args, capsys):
    try:
        code = main(["halfplane", *args])
    except SystemExit as exc:
        code = exc.code
    err = capsys.readouterr()
    assert code == 2
    assert err.out == ""
    assert len(err.err.strip().splitlines()) == 1, err.err


def test_flamant_superposition_reproduces_mcewen_off_the_axis():
    from analytic.halfplane_stress import stress_under_pressure
    from analytic.subsurface import hertz_subsurface_stress

    x = np.array([0.0, 0.3, 0.9, 1.5, -0.7])
    z = np.array([0.2, 0.5, 0.1, 1.0, 0.8])
    s = stress_under_pressure(x, z, pressure=lambda t: 2.0 * math.sqrt(max(1.0 - t * t, 0.0)), b=1.0, nu=0.3)
    e = hertz_subsurface_stress(x, z, a=1.0, p0=2.0, nu=0.3)
    for k in ("sxx", "szz", "sxz", "syy"):
        np.testing.assert_allclose(getattr(s, k), getattr(e, k), atol=1e-9)
