"""Plane-strain isotropic linear elasticity in UFL (units: mm, N, MPa).

``sigma(u) = lambda tr(eps) I + 2 mu eps`` with ``eps = sym(grad u)``, plane strain
(``lambda = E nu / ((1 + nu)(1 - 2 nu))``, ``mu = E / (2 (1 + nu))``); the out-of-plane stress
``sigma_zz = lambda tr(eps)`` enters the von Mises stress.
"""

from __future__ import annotations

from typing import NamedTuple

import ufl

__all__ = ["Lame", "lame", "epsilon", "sigma", "von_mises", "plane_strain_modulus"]


class Lame(NamedTuple):
    """Lame parameters (MPa)."""

    lmbda: float
    mu: float


def lame(*, E: float, nu: float) -> Lame:
    """Plane-strain Lame parameters from Young's modulus E (MPa) and Poisson's ratio nu in [0, 0.5)."""
    if not E > 0:
        raise ValueError(f"E must be > 0 MPa, got {E}")
    if not 0.0 <= nu < 0.5:
        raise ValueError(f"nu must be in [0, 0.5), got {nu}")
    return Lame(E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu)))


def plane_strain_modulus(*, E: float, nu: float) -> float:
    """``E' = E / (1 - nu^2)`` (MPa): the contact modulus E* of an elastic body against a rigid one."""
    return E / (1.0 - nu * nu)


def epsilon(u):
    """Small strain ``sym(grad u)``."""
    return ufl.sym(ufl.grad(u))


def sigma(u, lm: Lame):
    """In-plane Cauchy stress (MPa)."""
    eps = epsilon(u)
    return lm.lmbda * ufl.tr(eps) * ufl.Identity(len(u)) + 2.0 * lm.mu * eps


def von_mises(u, lm: Lame):
    """Von Mises stress (MPa) including the plane-strain ``sigma_zz = lambda tr(eps)``."""
    s = sigma(u, lm)
    szz = lm.lmbda * ufl.tr(epsilon(u))
    sxx, syy, sxy = s[0, 0], s[1, 1], s[0, 1]
    return ufl.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3.0 * sxy**2)
