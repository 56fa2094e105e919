"""Flamant's solution: the elastic half-plane under a normal line load (plane strain), and its quadrupole term.

Coordinates as the block scenes (:mod:`meshes.block`): x along the surface, y up, the body is ``y <= 0``; the
depth is ``z = -y``. A line load ``P`` (N/mm, > 0) pushes the surface down (along -y) at the origin. Units mm,
N, MPa. Stresses are positive in tension.

Stresses (Johnson, Contact Mechanics, eqs. 2.15): purely radial, ``sigma_rr = -2 P cos(phi) / (pi r)`` with
``phi`` the angle from the downward vertical, i.e.::

    sigma_xx = -2 P x^2 z / (pi r^4),  sigma_zz = -2 P z^3 / (pi r^4),  sigma_xz = -2 P x z^2 / (pi r^4)

and in the (x, y) frame ``sigma_yy = sigma_zz``, ``sigma_xy = -sigma_xz``. The surface z = 0, x != 0 is
traction-free; the resultant over any half circle about the origin is P (upward on the body's cut, balancing the
load).

Displacements (plane strain; integrated from the strains ``eps = ((1 + nu)/E) ((1 - nu) sigma - nu tr)`` and
checked symbolically: the remaining shear condition leaves only a rigid motion)::

    u_x = K [ x z / r^2 - (1 - 2 nu) atan2(x, z) ]
    u_z = K [ -x^2 / r^2 - 2 (1 - nu) ln(r / r_ref) ]          (u_z positive into the body, u_y = -u_z)
    K = P (1 + nu) / (pi E)

A 2D half-plane's displacement grows like ln r and is defined only up to a rigid motion. The reference chosen
here: no horizontal translation and no rotation (the field is symmetric: u_x odd, u_z even in x), and u_z = 0 at
the depth ``r_ref`` on the axis (the point (0, -r_ref)). Under force control a different ``r_ref`` only moves
the body rigidly, which the indenter's approach d absorbs: the contact quantities do not depend on it (tested in
``tests/test_far_field.py``). On the surface ``u_x = -(1 - 2 nu)(1 + nu) P sign(x) / (2 E)`` (towards the load).

Quadrupole term: a symmetric pressure p(s) of resultant P and second moment ``M2 = int p s^2 ds`` displaces the
half-plane as ``int p(s) G(x - s) ds = P G + (M2 / 2) d^2 G / dx^2 + O(a^4 / r^4)`` (G: the field of a unit
load; the first moment vanishes by symmetry). :func:`flamant_quadrupole_displacement` is ``(M2/2) d^2 u / dx^2``
per unit P; it has no log and needs no reference.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["FlamantStress", "flamant_displacement", "flamant_quadrupole_displacement", "flamant_stress",
           "plane_strain_stress"]


class FlamantStress(NamedTuple):
    """In-plane stresses (MPa) in the (x, y) frame, y up."""

    sxx: np.ndarray
    syy: np.ndarray
    sxy: np.ndarray


def flamant_displacement(x, y, *, P: float, E: float, nu: float, r_ref: float) -> tuple[np.ndarray, np.ndarray]:
    """Displacement (u_x, u_y) in mm at points (x, y <= 0) of the half-plane under the line load P at the origin.

    Args:
        x, y: coordinates (mm), y <= 0 (not both zero).
        P: line load (N/mm, full body), pushing along -y.
        E, nu: Young's modulus (MPa) and Poisson's ratio (plane strain).
        r_ref: depth (mm) on the axis where u_y = 0 (the rigid-motion reference, module docstring).
    """
    x, z = np.asarray(x, dtype=float), -np.asarray(y, dtype=float)
    r2 = x * x + z * z
    K = P * (1.0 + nu) / (np.pi * E)
    ux = K * (x * z / r2 - (1.0 - 2.0 * nu) * np.arctan2(x, z))
    uz = K * (-x * x / r2 - (1.0 - nu) * np.log(r2 / r_ref**2))
    return ux, -uz


def flamant_quadrupole_displacement(x, y, *, M2: float, E: float, nu: float) -> tuple[np.ndarray, np.ndarray]:
    """``(M2 / 2) d^2/dx^2`` of the unit-load displacement: the second-moment correction (mm).

    ``M2 = int p s^2 ds`` (N mm) of a symmetric pressure about the origin (second derivatives checked
    symbolically)::

        d2u_x/dx2 = K [ 2 x z (x^2 - 3 z^2) / r^6 + 2 (1 - 2 nu) x z / r^4 ]
        d2u_z/dx2 = K [ -2 z^2 (z^2 - 3 x^2) / r^6 - 2 (1 - nu) (z^2 - x^2) / r^4 ],   K = (1 + nu) / (pi E)
    """
    x, z = np.asarray(x, dtype=float), -np.asarray(y, dtype=float)
    r2 = x * x + z * z
    K = (1.0 + nu) / (np.pi * E)
    # d2/dx2 [x z / r^2] = 2 x z (x^2 - 3 z^2) / r^6 ; d2/dx2 atan2(x, z) = -2 x z / r^4
    d2ux = 2.0 * x * z * (x * x - 3.0 * z * z) / r2**3 + (1.0 - 2.0 * nu) * 2.0 * x * z / r2**2
    # d2/dx2 [-x^2 / r^2] = -2 z^2 (z^2 - 3 x^2) / r^6 ; d2/dx2 ln(r^2) = 2 (z^2 - x^2) / r^4
    d2uz = -2.0 * z * z * (z * z - 3.0 * x * x) / r2**3 - (1.0 - nu) * 2.0 * (z * z - x * x) / r2**2
    s = 0.5 * M2 * K
    return s * d2ux, -s * d2uz


def flamant_stress(x, y, *, P: float) -> FlamantStress:
    """Closed-form stresses (MPa) at points (x, y <= 0): the radial field ``sigma_rr = -2 P cos(phi) / (pi r)``."""
    x, z = np.asarray(x, dtype=float), -np.asarray(y, dtype=float)
    r4 = (x * x + z * z) ** 2
    c = -2.0 * P / np.pi
    return FlamantStress(sxx=c * x * x * z / r4, syy=c * z**3 / r4, sxy=-c * x * z * z / r4)


def plane_strain_stress(exx, eyy, exy, *, E: float, nu: float) -> FlamantStress:
    """Hooke's law in plane strain from the strains (exy the tensor component, half the engineering shear)."""
    lam = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    mu = E / (2.0 * (1.0 + nu))
    tr = exx + eyy
    return FlamantStress(sxx=lam * tr + 2.0 * mu * exx, syy=lam * tr + 2.0 * mu * eyy, sxy=2.0 * mu * exy)
