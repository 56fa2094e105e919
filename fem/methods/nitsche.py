"""Nitsche's method (Chouly-Hild, frictionless), ``gamma = gamma0 E / h`` (MPa/mm; h = cell diameter, mm).

With ``sigma_n(w) = n_c . sigma(w) n_b`` (MPa), ``P_gamma(u) = sigma_n(u) + gamma g(u)`` and
``P_theta(v) = theta sigma_n(v) - gamma (n_c . v)``::

    F(u; v) = a(u, v) - theta/gamma int sigma_n(u) sigma_n(v) ds + 1/gamma int [P_gamma(u)]_- P_theta(v) ds

so ``p = -[P_gamma]_- = [-sigma_n(u) - gamma g]_+``. theta = 1 symmetric, 0 incomplete (= penalty-like residual
with a consistent pressure), -1 skew-symmetric. With theta = 0 penalty and Nitsche share
``F = a + int p (n_c . v)``. Consistent: an exact solution in the discrete space (flat punch) is reproduced to
round-off. Contact integral: Gauss rule of the solver's ``quadrature_degree``.

Finite kinematics (:mod:`fem.contact_forms`): ``sigma_n(u) = n_c . P(u) N / (ds/dS)`` is the current normal
traction from the first Piola-Kirchhoff stress, ``sigma_n(v)`` uses the Gateaux derivative ``dP(u)[v]`` at fixed
``n_c`` and ``ds/dS``, and the integrand is pulled back with ``ds/dS``. The method stays consistent for any test
expression in place of ``sigma_n(v)``: its factor ``theta/gamma ([P_gamma]_- - sigma_n(u))`` vanishes at an exact
solution (in contact ``P_gamma = sigma_n <= 0``, out of contact ``sigma_n = 0`` and ``P_gamma > 0``).
"""

from __future__ import annotations

import ufl

from fem.methods.base import ContactMethod, MethodTerms, contact_law
from fem.methods.registry import register

__all__ = ["Nitsche"]


@register
class Nitsche(ContactMethod):
    """Nitsche's method (parameters ``gamma0`` > 0 dimensionless, ``theta`` in {1, 0, -1})."""

    name = "nitsche"

    def __init__(self, *, E, E_star, gamma0: float = 10.0, theta: float = 1.0, **params):
        super().__init__(E=E, E_star=E_star)
        if theta not in (-1, 0, 1, -1.0, 0.0, 1.0):
            raise ValueError(f"theta must be one of (1, 0, -1), got {theta!r}")
        if not gamma0 > 0:
            raise ValueError(f"gamma0 must be > 0, got {gamma0}")
        self.gamma0, self.theta = gamma0, theta

    def terms(self, kin, *, v, stress_u, stress_v, ds_c, mask) -> MethodTerms:
        theta = self.constant(kin, self.theta)
        gamma = self.constant(kin, self.gamma0 * self.E) / kin.h
        sig_n = kin.sigma_n
        P_gamma = sig_n(stress_u) + gamma * kin.gap
        q = -P_gamma
        p = contact_law(q, kin.X, mask)
        F_c = kin.on_surface(-theta / gamma * sig_n(stress_u) * sig_n(stress_v)
                             - p / gamma * (theta * sig_n(stress_v) - gamma * ufl.dot(kin.n_c, v))) * ds_c
        return MethodTerms(argument=q, pressure=p, F_c=F_c)
