"""Stress field inside an elastic half-plane under Hertz's line-contact pressure (McEwen 1949).

Conventions: x along the surface, z >= 0 the depth below the undeformed surface (mm); stresses in MPa,
tension positive (so the contact stresses are negative); plane strain, ``s_yy = nu (s_xx + s_zz)`` is the
out-of-plane stress. The surface carries ``p(x) = p0 sqrt(1 - x^2/a^2)`` on |x| < a and nothing else; no
friction. With (Johnson, Contact Mechanics, eq. 4.49)

    m^2 = 1/2 [ sqrt((a^2 - x^2 + z^2)^2 + 4 x^2 z^2) + (a^2 - x^2 + z^2) ],
    n^2 = 1/2 [ sqrt((a^2 - x^2 + z^2)^2 + 4 x^2 z^2) - (a^2 - x^2 + z^2) ],   m >= 0, sign(n) = sign(x),

    s_xx = -(p0/a) [ m (1 + (z^2 + n^2)/(m^2 + n^2)) - 2 z ],
    s_zz = -(p0/a)   m (1 - (z^2 + n^2)/(m^2 + n^2)),
    s_xz =  (p0/a)   n (m^2 - z^2)/(m^2 + n^2)            (Johnson's sign: shear on planes z = const).

On the axis x = 0: s_xx = -p0 [(a^2 + 2 z^2)/(a sqrt(a^2 + z^2)) - 2 z/a], s_zz = -p0 a/sqrt(a^2 + z^2); the
largest shear (s_xx - s_zz)/2 in magnitude is 0.300 p0 at z = 0.786 a.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["HalfPlaneStress", "hertz_subsurface_stress", "von_mises_plane_strain"]


class HalfPlaneStress(NamedTuple):
    """In-plane stresses s_xx, s_zz, s_xz and the out-of-plane s_yy (MPa, tension positive) at the points."""

    sxx: np.ndarray
    szz: np.ndarray
    sxz: np.ndarray
    syy: np.ndarray


def hertz_subsurface_stress(x, z, *, a: float, p0: float, nu: float) -> HalfPlaneStress:
    """McEwen's field at abscissa x and depth z >= 0 (mm) under Hertz's pressure of half-width a and peak p0."""
    x = np.asarray(x, dtype=float)
    z = np.asarray(z, dtype=float)
    c = a * a - x * x + z * z
    r = np.sqrt(c * c + 4.0 * x * x * z * z)
    m = np.sqrt(np.maximum(0.5 * (r + c), 0.0))
    n = np.sign(x) * np.sqrt(np.maximum(0.5 * (r - c), 0.0))
    q = m * m + n * n
    ratio = np.divide(z * z + n * n, q, out=np.ones_like(q), where=q > 0)
    sxx = -(p0 / a) * (m * (1.0 + ratio) - 2.0 * z)
    szz = -(p0 / a) * m * (1.0 - ratio)
    sxz = (p0 / a) * np.divide(n * (m * m - z * z), q, out=np.zeros_like(q), where=q > 0)
    return HalfPlaneStress(sxx, szz, sxz, nu * (sxx + szz))


def von_mises_plane_strain(s: HalfPlaneStress) -> np.ndarray:
    """Von Mises stress (MPa) of the plane-strain state, the out-of-plane s_yy included."""
    return np.sqrt(0.5 * ((s.sxx - s.szz) ** 2 + (s.szz - s.syy) ** 2 + (s.syy - s.sxx) ** 2) + 3.0 * s.sxz**2)
