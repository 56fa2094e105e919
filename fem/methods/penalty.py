"""Penalty method: ``p = kappa [-g]_+`` with ``kappa = kappa0 E / h`` (MPa/mm; h = cell diameter, mm).

Residual ``F(u; v) = a(u, v) + int_Gc p (n_c . v) ds`` (= first variation of
``1/2 a(u, u) + int kappa/2 [-g]_+^2 ds``). The constraint holds only as ``kappa -> oo``: the body penetrates
the obstacle by about ``p / kappa`` (mm), a first-order error in ``1 / kappa0`` (flat punch:
``p = M d / H / (1 + M / (kappa H))``). Contact integral: Gauss rule of the solver's ``quadrature_degree``.
"""

from __future__ import annotations

import ufl

from fem.methods.base import ContactMethod, MethodTerms, contact_law
from fem.methods.registry import register

__all__ = ["Penalty"]


@register
class Penalty(ContactMethod):
    """Penalty method (parameter ``kappa0`` > 0, dimensionless)."""

    name = "penalty"

    def __init__(self, *, E, kappa0: float = 1e3, **params):
        super().__init__(E=E)
        if not kappa0 > 0:
            raise ValueError(f"kappa0 must be > 0, got {kappa0}")
        self.kappa0 = kappa0

    def terms(self, kin, *, v, stress_u, stress_v, ds_c, mask) -> MethodTerms:
        kappa = self.kappa0 * self.E / kin.h
        q = -kappa * kin.gap
        p = contact_law(q, kin.X, mask)
        return MethodTerms(argument=q, pressure=p, F_c=p * ufl.dot(kin.n_c, v) * ds_c)
