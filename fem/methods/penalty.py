"""Penalty method: ``p = kappa [-g]_+`` with ``kappa = kappa0 E* / h`` (MPa/mm; E* = E/(1 - nu^2) the plane-strain
modulus, as for two bodies, :func:`fem.methods.base.penalty_stiffness`; h = cell diameter, mm).

Residual ``F(u; v) = a(u, v) + int_Gc p (n_c . v) ds`` (= first variation of
``1/2 a(u, u) + int kappa/2 [-g]_+^2 ds``). The constraint holds only as ``kappa -> oo``: the body penetrates
the obstacle by about ``p / kappa`` (mm), a first-order error in ``1 / kappa0`` (flat punch:
``p = M d / H / (1 + M / (kappa H))``). Contact integral: Gauss rule of the solver's ``quadrature_degree``.

Stiff penalties (``kappa0 > STIFF_KAPPA0 = 1e5``). Semismooth Newton on the penalty system itself does not
converge there: measured on the stability study's Hertz scene (P2, h = a/10), kappa0 = 1e6, 1e7, 1e8 end in
SNES DIVERGED_MAX_IT after 5 cut-backs; the Jacobian's condition number grows like kappa0 (cond_1(J) = 3.8e7 at
1e5) and the residual ``kappa g`` of the converged state sits on the round-off of g times kappa. So above
``STIFF_KAPPA0`` the same law is solved the way the augmented Lagrangian is
(:class:`NodalPenaltyUzawa`): the law is collocated at the contact nodes (the augmented Lagrangian's nodal
quadrature, P2: Simpson) and reached by relaxed Uzawa updates of a nodal multiplier around a Newton solve of
moderate stiffness ``kappa_s = kappa_solve E* / h`` (``kappa_solve = min(kappa0, 1e4)``)::

    p = [lambda - kappa_s g]_+ ,      lambda <- (1 - kappa_s / kappa) p      (at every contact node)

A fixed point has ``p = (1 - r) p - kappa_s g`` with ``r = kappa_s / kappa`` on the active nodes, i.e.
``p = -kappa g`` = the nodal penalty law with the requested kappa0, and ``lambda = 0, g >= 0`` elsewhere. Each
Newton solve has the conditioning of kappa_solve; the updates contract like the augmented Lagrangian's.
Stopping: the penalty law holds at the contact nodes to ``uzawa_rtol max|u|`` in gap units
(``|g_i + p_i / kappa_i| <= tol`` where p_i > 0, ``g_i >= -tol`` elsewhere).

Why nodal above the threshold: the Gauss-point penalty's limit oscillates between the quadrature points (the
stability study names 'pressure oscillation' from kappa0 = 1e3 on, RMS/p0 2.3 % at 1e5) while the nodal law
does not (:mod:`fem.methods.augmented_lagrangian`, "Why nodal"). The discrete law therefore changes at the
threshold: kappa0 <= 1e5 is exactly the Gauss-point penalty as before (the default 1e3 is untouched);
kappa0 > 1e5 is the nodal penalty, which tends to the augmented Lagrangian's answer as kappa0 grows (its
penetration p / kappa is 1e-3 of the Gauss-point one at 1e5 already at kappa0 = 1e8). Measured figures are in
``tests/test_fem_penalty_stiff.py`` and the stability study's ``method`` section.
"""

from __future__ import annotations

import ufl

from fem.methods.base import ContactMethod, MethodTerms, contact_law, penalty_stiffness
from fem.methods.registry import register

__all__ = ["Penalty", "STIFF_KAPPA0", "KAPPA_SOLVE"]

STIFF_KAPPA0 = 1e5  # above: the nodal penalty law reached by relaxed Uzawa updates (module docstring)
KAPPA_SOLVE = 1e4  # the Newton stiffness of those updates (dimensionless, as kappa0)


@register
class Penalty(ContactMethod):
    """Penalty method (parameter ``kappa0`` > 0, dimensionless; above ``STIFF_KAPPA0`` solved by relaxed Uzawa
    updates of a nodal law, module docstring)."""

    name = "penalty"

    def __init__(self, *, E, E_star, kappa0: float = 1e3, uzawa_rtol: float = 1e-10, uzawa_max_it: int = 100,
                 **params):
        super().__init__(E=E, E_star=E_star)
        if not kappa0 > 0:
            raise ValueError(f"kappa0 must be > 0, got {kappa0}")
        self.kappa0 = kappa0
        self.stiff = None
        if kappa0 > STIFF_KAPPA0:
            from fem.methods.nodal_penalty import NodalPenaltyUzawa

            self.stiff = NodalPenaltyUzawa(E=E, E_star=E_star, kappa0=kappa0, kappa_solve=KAPPA_SOLVE,
                                           uzawa_rtol=uzawa_rtol, uzawa_max_it=uzawa_max_it)
            self.supports_tangent = False

    def terms(self, kin, *, v, stress_u, stress_v, ds_c, mask) -> MethodTerms:
        if self.stiff is not None:
            return self.stiff.terms(kin, v=v, stress_u=stress_u, stress_v=stress_v, ds_c=ds_c, mask=mask)
        kappa = self.stiffness(kin.h, kin)
        q = -kappa * kin.gap
        p = contact_law(q, kin.X, mask)
        return MethodTerms(argument=q, pressure=kin.current_pressure(p), F_c=p * ufl.dot(kin.n_c, v) * ds_c)

    def stiffness(self, h, kin=None):
        """``kappa = kappa0 E* / h`` (MPa/mm, :func:`fem.methods.base.penalty_stiffness`): of a float h, or with
        ``kin`` the UFL expression of the cell diameter ``h = kin.h`` (``kappa0 E*`` a Constant)."""
        if kin is None:
            return penalty_stiffness(self.kappa0, self.E_star, h)
        return self.constant(kin, penalty_stiffness(self.kappa0, self.E_star, 1.0)) / h

    # -- the stiff penalty's hooks (the base class's defaults otherwise) -------------------------------------
    def measure_metadata(self, *, degree: int, quadrature_degree: int):
        if self.stiff is None:
            return None
        return self.stiff.measure_metadata(degree=degree, quadrature_degree=quadrature_degree)

    def sample_rule(self, *, degree: int):
        return None if self.stiff is None else self.stiff.sample_rule(degree=degree)

    def state_functions(self) -> list:
        return [] if self.stiff is None else self.stiff.state_functions()

    def extra_forms(self) -> dict:
        return {} if self.stiff is None else self.stiff.extra_forms()

    def bind_forms(self, compiled: dict) -> None:
        if self.stiff is not None:
            self.stiff.bind_forms(compiled)

    def solve(self, newton):
        return super().solve(newton) if self.stiff is None else self.stiff.solve(newton)

    def options(self) -> dict:
        if self.stiff is None:
            return {}
        return {"penalty_law": "nodal (Uzawa)", "kappa_solve": KAPPA_SOLVE, **self.stiff.options()}
