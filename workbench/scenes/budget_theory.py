"""Smooth measures of a contact pressure and their half-plane theory values (pure numpy; no dolfinx).

The zero crossing of the contact law moves between quadrature points as the mesh is refined, so the FEM
half-width oscillates by ~1e-3 and cannot be extrapolated. The moment half-width

    w = sqrt(M2 / M0),    M_k = int p(x) (x - c)^k dx,   c = M1 / M0,

is an integral of the pressure and converges smoothly (Hertz: w = a/2). Every measure here is divided by the
classical half-width at the run's measured load, so a value is dimensionless and the theory value is computed
from the same functional of the theory's pressure. Units: mm, MPa.
"""

from __future__ import annotations

import math

import numpy as np

from analytic.circle import circle_pressure
from measures.contact import moment_half_width

__all__ = ["moment_half_width", "circle_moment_half_width", "curve_moment_half_width"]


def circle_moment_half_width(*, b: float, R: float, E_star: float, n: int = 4000) -> float:
    """sqrt(M2/M0) of the exact circle's pressure with half-width b (Gauss-Chebyshev in x = b cos t: the
    square-root edges become smooth, so n = 4000 is converged to round-off)."""
    t = (np.arange(n) + 0.5) * math.pi / n
    x = b * np.cos(t)
    w = b * np.sin(t) * math.pi / n
    p = circle_pressure(x, b=b, R=R, E_star=E_star)
    return math.sqrt(float(np.sum(w * p * x**2)) / float(np.sum(w * p)))


def curve_moment_half_width(x: np.ndarray, p: np.ndarray) -> float:
    """sqrt(M2/M0) of a pressure on a fine grid (trapezoid; e.g. the Ciavarella-Hills solution on 64001
    points, where it is converged to ~1e-7 relative despite the log apex of the wedge)."""
    M0 = float(np.trapezoid(p, x))
    c = float(np.trapezoid(p * x, x)) / M0
    return math.sqrt(float(np.trapezoid(p * (x - c) ** 2, x)) / M0)
