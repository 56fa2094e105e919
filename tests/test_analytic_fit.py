"""Semi-elliptical least-squares fit (analytic.fit)."""

import numpy as np
import pytest

from analytic.fit import fit_elliptical, initial_guess
from analytic.hertz import hertz_pressure


def test_recovers_exact_parameters():
    # exact semi-elliptical data: the least-squares optimum is the truth; 1e-10 relative allows the
    # Levenberg-Marquardt stopping tolerance (1e-15) times the conditioning of the edge samples
    s = np.linspace(-1.0, 2.0, 301)
    p = hertz_pressure(s, a=0.73, p0=812.0, center=0.41)
    f = fit_elliptical(s[::-1], p[::-1])  # any sample order
    assert f.center == pytest.approx(0.41, rel=1e-10)
    assert f.half_width == pytest.approx(0.73, rel=1e-10)
    assert f.p_max == pytest.approx(812.0, rel=1e-10)
    assert f.rms_over_p0 < 1e-10


def test_reports_rms_over_p0_on_perturbed_data():
    s = np.linspace(-1.0, 2.0, 301)
    exact = hertz_pressure(s, a=0.73, p0=812.0, center=0.41)
    p = exact + np.where(exact > 0, 5.0 * np.sin(37.0 * s), 0.0)
    f = fit_elliptical(s, p)
    # independent evaluation of the documented measure: RMS over samples inside the fit OR with p > 0
    diff = hertz_pressure(s, a=f.half_width, p0=f.p_max, center=f.center) - p
    patch = (np.abs(s - f.center) <= f.half_width) | (p > 0)
    expected = np.sqrt(np.mean(diff[patch] ** 2)) / p.max()
    assert f.rms_over_p0 == pytest.approx(expected, rel=1e-12)
    assert f.n_samples == patch.sum()
    # a 5 MPa ripple on an 812 MPa ellipse: RMS ~ 5/sqrt(2) -> rms/p0 ~ 4.3e-3
    assert 3e-3 < f.rms_over_p0 < 6e-3
    assert f.half_width == pytest.approx(0.73, rel=1e-2)


def test_initial_guess_from_moments_is_close():
    s = np.linspace(-1.0, 1.0, 4001)
    g = initial_guess(s, hertz_pressure(s, a=0.5, p0=3.0, center=0.1))
    assert g.center == pytest.approx(0.1, abs=1e-6)
    assert g.half_width == pytest.approx(0.5, rel=1e-3)
    assert g.p_max == pytest.approx(3.0, rel=1e-3)


def test_bad_input():
    with pytest.raises(ValueError, match="^s, p sizes = .* out of range"):
        fit_elliptical(np.zeros(3), np.zeros(3))
    with pytest.raises(ValueError, match="^p out of range"):
        fit_elliptical(np.linspace(0, 1, 10), np.zeros(10))
