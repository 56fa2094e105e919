"""Plane-strain isotropic linear elasticity in UFL (units: mm, N, MPa).

``sigma(u) = lambda tr(eps) I + 2 mu eps`` with ``eps = sym(grad u)``, plane strain
(``lambda = E nu / ((1 + nu)(1 - 2 nu))``, ``mu = E / (2 (1 + nu))``); the out-of-plane stress
``sigma_zz = lambda tr(eps)`` enters the von Mises stress.

Mixed (u-p) form, locking-free as nu -> 1/2: the extra unknown ``p = -lambda tr(eps(u))`` (MPa) gives
``sigma(u, p) = 2 mu eps(u) - p I`` (the same stress), weak form (Taylor-Hood P2 u / P1 p)::

    int 2 mu eps(u) : eps(v) - p div v dx + (boundary terms) = 0             for all v
    -int q (lambda div u + p) / (lambda + mu) dx = 0                          for all q

(the second line is ``div u + p / lambda = 0`` scaled by ``lambda / (lambda + mu)`` so that it stays finite
for nu = 0, where it gives p = 0, and for nu -> 1/2, where it tends to ``div u = 0``).
"""

from __future__ import annotations

from typing import NamedTuple

import ufl

from analytic import materials

__all__ = ["Lame", "lame", "epsilon", "sigma", "sigma_mixed", "mixed_constraint", "von_mises",
           "plane_strain_modulus"]


class Lame(NamedTuple):
    """Lame parameters (MPa)."""

    lmbda: float
    mu: float


def lame(*, E: float, nu: float) -> Lame:
    """Plane-strain Lame parameters from Young's modulus E (MPa) and Poisson's ratio -1 < nu < 0.5 (the case
    schema's range; lambda < 0 for nu < 0, while mu > 0 and lambda + mu > 0 keep the plane-strain energy
    positive)."""
    if not E > 0:
        raise ValueError(f"E must be > 0 MPa, got {E}")
    if not -1.0 < nu < 0.5:
        raise ValueError(f"nu must be in (-1, 0.5), got {nu}")
    return Lame(E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu)))


def plane_strain_modulus(*, E: float, nu: float) -> float:
    """E* = E / (1 - nu^2) (MPa): the one formula lives in :func:`analytic.materials.plane_strain_modulus`."""
    return materials.plane_strain_modulus(E, nu)


def epsilon(u):
    """Small strain ``sym(grad u)``."""
    return ufl.sym(ufl.grad(u))


def sigma(u, lm: Lame):
    """In-plane Cauchy stress (MPa)."""
    eps = epsilon(u)
    return lm.lmbda * ufl.tr(eps) * ufl.Identity(len(u)) + 2.0 * lm.mu * eps


def sigma_mixed(u, p, lm: Lame):
    """In-plane Cauchy stress (MPa) of the mixed form: ``2 mu eps(u) - p I`` with ``p = -lambda tr eps``."""
    return 2.0 * lm.mu * epsilon(u) - p * ufl.Identity(len(u))


def mixed_constraint(u, p, q, lm: Lame):
    """Pressure equation of the mixed form (UFL integrand): ``-q (lambda div u + p) / (lambda + mu)``."""
    return -q * (lm.lmbda * ufl.div(u) + p) / (lm.lmbda + lm.mu)


def von_mises(u, lm: Lame, p=None):
    """Von Mises stress (MPa) including the plane-strain ``sigma_zz = lambda tr(eps)`` (``= -p`` when the
    mixed pressure ``p`` is given)."""
    s = sigma(u, lm) if p is None else sigma_mixed(u, p, lm)
    szz = lm.lmbda * ufl.tr(epsilon(u)) if p is None else -p
    sxx, syy, sxy = s[0, 0], s[1, 1], s[0, 1]
    return ufl.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3.0 * sxy**2)
