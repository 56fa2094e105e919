"""The bulk constitutive laws of the contact solve: small-strain Hooke, and the finite-strain hyperelastic models.

Units: mm, N, MPa. Plane strain (``F_33 = 1``, ``E_33 = 0``). Every model is parametrised by the small-strain
Young's modulus E and Poisson's ratio nu through the plane-strain Lame parameters ``lambda = E nu / ((1 + nu)
(1 - 2 nu))`` and ``mu = E / (2 (1 + nu))`` (:func:`fem.elasticity.lame`), so all three agree to first order in
the displacement gradient.

Total Lagrangian form: ``F = I + Grad u`` (2 x 2, Grad w.r.t. the reference coordinate X), ``C = F^T F``,
``J = det F``, Green-Lagrange ``E = (C - I) / 2``. The weak form of the bulk is

    a(u; v) = int_Omega0 P(u) : Grad v dX        (N/mm per unit test displacement)

with the first Piola-Kirchhoff stress ``P = F S = dW/dF`` (MPa, force per reference area) of the strain energy
density W (MPa, per unit reference volume):

* ``"linear"`` (small-strain Hooke; kinematics small/convective): ``W = lambda/2 (tr eps)^2 + mu eps : eps``,
  ``eps = sym(grad u)``, ``P = sigma = lambda tr(eps) I + 2 mu eps`` (the linearised stress; no finite strain).
* ``"saint_venant_kirchhoff"``: ``W = lambda/2 (tr E)^2 + mu E : E``, ``S = lambda tr(E) I + 2 mu E``.
  Plane strain is exact in 2D (``E_33 = 0``). Softens in compression (``W`` stays bounded as J -> 0).
* ``"neo_hookean"`` (compressible, the Ciarlet-Simo form): ``W = mu/2 (I_1 - 3) - mu ln J + lambda/2 (ln J)^2``
  with ``I_1 = tr C + 1`` (the plane-strain ``C_33 = 1``), ``P = mu (F - F^-T) + lambda ln(J) F^-T``.

The Cauchy stress is ``sigma = P F^T / J`` (MPa, current configuration); its out-of-plane component is
``sigma_33 = S_33 / J`` with ``S_33 = lambda tr E`` (SVK) or ``lambda ln J`` (neo-Hookean, ``C_33 = 1``).

The residual's Jacobian is the exact Gateaux derivative ``ufl.derivative`` of ``a(u; v)``.
"""

from __future__ import annotations

from typing import NamedTuple

import ufl

from fem.elasticity import Lame, epsilon, sigma
from fem.options import HYPERELASTIC_MODELS, MATERIAL_MODELS

__all__ = ["MATERIAL_MODELS", "HYPERELASTIC_MODELS", "BulkLaw", "bulk_law", "deformation_gradient",
           "first_piola", "strain_energy", "cauchy", "cauchy_zz"]



def deformation_gradient(u):
    """``F = I + Grad u`` (2 x 2, reference gradient)."""
    return ufl.Identity(len(u)) + ufl.grad(u)


def strain_energy(u, model: str, lm: Lame):
    """Strain energy density W (MPa) of ``model`` (module docstring)."""
    if model == "linear":
        eps = epsilon(u)
        return 0.5 * lm.lmbda * ufl.tr(eps) ** 2 + lm.mu * ufl.inner(eps, eps)
    F = deformation_gradient(u)
    C = F.T * F
    if model == "saint_venant_kirchhoff":
        E = 0.5 * (C - ufl.Identity(len(u)))
        return 0.5 * lm.lmbda * ufl.tr(E) ** 2 + lm.mu * ufl.inner(E, E)
    if model == "neo_hookean":
        lnJ = ufl.ln(ufl.det(F))
        return 0.5 * lm.mu * (ufl.tr(C) + 1.0 - 3.0) - lm.mu * lnJ + 0.5 * lm.lmbda * lnJ**2
    raise ValueError(f"material_model must be one of {MATERIAL_MODELS}, got {model!r}")


def first_piola(u, model: str, lm: Lame):
    """First Piola-Kirchhoff stress P (MPa) of ``model``; ``"linear"`` gives the small-strain sigma(u)."""
    if model == "linear":
        return sigma(u, lm)
    F = deformation_gradient(u)
    I = ufl.Identity(len(u))  # noqa: E741
    if model == "saint_venant_kirchhoff":
        E = 0.5 * (F.T * F - I)
        return F * (lm.lmbda * ufl.tr(E) * I + 2.0 * lm.mu * E)
    if model == "neo_hookean":
        F_inv_T = ufl.inv(F).T
        return lm.mu * (F - F_inv_T) + lm.lmbda * ufl.ln(ufl.det(F)) * F_inv_T
    raise ValueError(f"material_model must be one of {MATERIAL_MODELS}, got {model!r}")


def cauchy(u, model: str, lm: Lame):
    """In-plane Cauchy stress (MPa, current configuration): ``P F^T / J`` (the small-strain sigma for linear)."""
    if model == "linear":
        return sigma(u, lm)
    F = deformation_gradient(u)
    return first_piola(u, model, lm) * F.T / ufl.det(F)


def cauchy_zz(u, model: str, lm: Lame, lmbda=None):
    """Out-of-plane Cauchy stress (MPa) of plane strain: ``S_33 / J`` (module docstring); ``lambda tr eps`` for
    linear. ``lmbda``: a dolfinx Constant to use for lambda (so that nu = 0 does not fold the expression to 0)."""
    lmb = lm.lmbda if lmbda is None else lmbda
    if model == "linear":
        return lmb * ufl.tr(epsilon(u))
    F = deformation_gradient(u)
    J = ufl.det(F)
    if model == "saint_venant_kirchhoff":
        return lmb * ufl.tr(0.5 * (F.T * F - ufl.Identity(len(u)))) / J
    if model == "neo_hookean":
        return lmb * ufl.ln(J) / J
    raise ValueError(f"material_model must be one of {MATERIAL_MODELS}, got {model!r}")


class BulkLaw(NamedTuple):
    """The bulk law of one solve (what :class:`fem.problem.ContactProblem` and the contact methods use).

    Attributes:
        model: one of :data:`MATERIAL_MODELS`.
        stress: UFL stress of the state entering ``a(u; v) = int stress : Grad v dX`` (sigma(u), or P(u)).
        stress_v: UFL stress of the test field for the Nitsche terms: sigma(v) (linear), or the Gateaux
            derivative ``dP(u)[v]`` (finite strain; :mod:`fem.contact_forms`).
        finite: True for a hyperelastic model (total Lagrangian, P is the first Piola-Kirchhoff stress).
    """

    model: str
    stress: object
    stress_v: object
    finite: bool


def bulk_law(u, v, model: str, lm: Lame) -> BulkLaw:
    """The :class:`BulkLaw` of ``model`` for the displacement ``u`` and the test function ``v``."""
    if model == "linear":
        return BulkLaw(model, sigma(u, lm), sigma(v, lm), False)
    P = first_piola(u, model, lm)
    return BulkLaw(model, P, ufl.derivative(P, u, v), True)
