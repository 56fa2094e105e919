"""Theory of the minimal scene: an elastic block compressed by a rigid flat plane, in plane strain.

The block (width W, height H, mm) stands on rollers (its bottom moves only along x, its symmetry edge x = 0 only
along y) and its sides are free; a frictionless rigid plane pushes its top down by d (mm). The stress is uniaxial
and uniform: sigma_yy = -p, sigma_xx = 0, eps_zz = 0 (plane strain), so eps_yy = -d / H and

    p = E d / ((1 - nu^2) H)   (MPa),      P = p W   (N/mm, per unit thickness).

Linear elements carry this field exactly, and a consistent contact law (Nitsche) imposes it exactly: the FEM
must reproduce p and P to round-off.
"""

from __future__ import annotations

from typing import NamedTuple

__all__ = ["UniformCompression", "uniform_compression"]


class UniformCompression(NamedTuple):
    """The exact solution: pressure ``p`` (MPa, uniform over the top) and load ``P`` (N/mm)."""

    p: float
    P: float


def uniform_compression(*, E: float, nu: float, width: float, height: float, d: float) -> UniformCompression:
    """The uniform pressure and load of the block pressed by ``d`` (module docstring; E in MPa, lengths in mm)."""
    p = E * d / ((1.0 - nu**2) * height)
    return UniformCompression(p, p * width)
