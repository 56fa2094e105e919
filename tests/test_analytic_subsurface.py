"""McEwen's Hertz subsurface field (analytic/subsurface.py) against its textbook landmarks."""

from __future__ import annotations

import numpy as np
import pytest

from analytic.subsurface import hertz_subsurface_stress, von_mises_plane_strain

A, P0, NU = 0.5, 1000.0, 0.3


def test_surface_traction_is_the_hertz_pressure():
    x = np.linspace(-1.5 * A, 1.5 * A, 301)
    s = hertz_subsurface_stress(x, np.zeros_like(x), a=A, p0=P0, nu=NU)
    p = P0 * np.sqrt(np.clip(1.0 - (x / A) ** 2, 0.0, None))
    assert np.allclose(s.szz, -p, atol=1e-9 * P0)
    assert np.allclose(s.sxz, 0.0, atol=1e-9 * P0)
    inside = np.abs(x) < A
    assert np.allclose(s.sxx[inside], -p[inside], atol=1e-9 * P0)  # s_xx = s_zz = -p under the contact


def test_axis_closed_form_and_the_largest_shear():
    z = np.linspace(0.0, 3.0 * A, 30001)
    s = hertz_subsurface_stress(np.zeros_like(z), z, a=A, p0=P0, nu=NU)
    root = np.sqrt(A * A + z * z)
    assert np.allclose(s.szz, -P0 * A / root, rtol=1e-12)
    assert np.allclose(s.sxx, -P0 * ((A * A + 2 * z * z) / (A * root) - 2 * z / A), rtol=1e-10, atol=1e-9 * P0)
    tau = 0.5 * np.abs(s.sxx - s.szz)
    i = int(np.argmax(tau))
    assert tau[i] == pytest.approx(0.300 * P0, abs=1e-3 * P0)
    assert z[i] == pytest.approx(0.786 * A, abs=2e-3 * A)


def test_far_field_decays_and_von_mises_peaks_below_the_surface():
    s_far = hertz_subsurface_stress(np.array([0.0]), np.array([100.0 * A]), a=A, p0=P0, nu=NU)
    assert abs(s_far.szz[0]) < 0.011 * P0
    z = np.linspace(0.0, 3.0 * A, 3001)
    vm = von_mises_plane_strain(hertz_subsurface_stress(np.zeros_like(z), z, a=A, p0=P0, nu=NU))
    assert 0.5 * A < z[int(np.argmax(vm))] < 0.9 * A
    assert vm.max() > vm[0]
