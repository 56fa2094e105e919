"""Stresses inside an elastic half-plane under any symmetric surface pressure (Flamant superposition).

Conventions: x along the surface, z > 0 the depth (mm); stresses in MPa, tension positive; pressure p >= 0
compressive on |x| < b, no shear traction, plane strain (s_yy = nu (s_xx + s_zz)). Johnson, Contact Mechanics,
eq. (2.23):
    s_xx = -(2 z / pi)   int p(s) (x - s)^2 / ((x - s)^2 + z^2)^2 ds,
    s_zz = -(2 z^3 / pi) int p(s)           / ((x - s)^2 + z^2)^2 ds,
    s_xz =  (2 z^2 / pi) int p(s) (x - s)   / ((x - s)^2 + z^2)^2 ds,
with s_xz in the sign of :func:`analytic.subsurface.hertz_subsurface_stress` (McEwen; checked against it in
tests/test_halfplane_theory.py). The integrals are adaptive Gauss-Kronrod (scipy quad) with break points at the
centre (the wedge's log-singular apex) and at x; z > 0 keeps the kernels bounded.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable

import numpy as np

from analytic.subsurface import HalfPlaneStress

__all__ = ["stress_under_pressure"]


def stress_under_pressure(x, z, *, pressure: Callable[[float], float], b: float, nu: float) -> HalfPlaneStress:
    """s_xx, s_zz, s_xz, s_yy (MPa) at the points (x, z), z > 0 (mm), under ``pressure`` (MPa) on |x| < b (mm)."""
    from scipy import integrate  # imported here: a run that never integrates skips its ~20 ms import

    xs = np.atleast_1d(np.asarray(x, dtype=float))
    zs = np.atleast_1d(np.asarray(z, dtype=float))
    xs, zs = np.broadcast_arrays(xs, zs)
    if np.any(zs <= 0.0):
        raise ValueError("z must be > 0 (mm): the Flamant kernels are singular on the surface")
    out = np.zeros((3,) + xs.shape)
    for idx in np.ndindex(xs.shape):
        xv, zv = float(xs[idx]), float(zs[idx])
        pts = sorted({0.0, min(max(xv, -b), b)} - {-b, b})

        def kern(s: float, power: int, xv=xv, zv=zv) -> float:
            d = xv - s
            return pressure(s) * d**power / (d * d + zv * zv) ** 2

        with warnings.catch_warnings():  # a zero-valued integral (s_xz on the axis) cannot meet a relative tolerance
            warnings.simplefilter("ignore", integrate.IntegrationWarning)
            vals = [integrate.quad(kern, -b, b, args=(k,), points=pts, limit=400, epsabs=0.0, epsrel=1e-10)[0]
                    for k in (2, 0, 1)]
        out[0][idx] = -(2.0 * zv / math.pi) * vals[0]
        out[1][idx] = -(2.0 * zv**3 / math.pi) * vals[1]
        out[2][idx] = (2.0 * zv**2 / math.pi) * vals[2]
    sxx, szz, sxz = out
    return HalfPlaneStress(sxx, szz, sxz, nu * (sxx + szz))
