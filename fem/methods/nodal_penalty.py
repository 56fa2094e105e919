"""The stiff penalty's law: ``p = kappa [-g]_+`` at the contact nodes, reached by relaxed Uzawa updates.

Above :data:`fem.methods.penalty.STIFF_KAPPA0` the penalty method (:mod:`fem.methods.penalty`, whose docstring
derives it) solves its law this way: the augmented Lagrangian's nodal multiplier
(:mod:`fem.methods.augmented_lagrangian`) around Newton solves of moderate stiffness ``kappa_s = kappa_solve E* / h``
(MPa/mm), updated by ``lambda <- (1 - kappa_s / kappa) p`` at every contact node, whose fixed point is the nodal
penalty law ``p = -kappa g`` with ``kappa = kappa0 E* / h`` (E* = E/(1 - nu^2)). Units mm, MPa.
"""

from __future__ import annotations

from fem.methods.augmented_lagrangian import AugmentedLagrangian
from fem.methods.base import penalty_stiffness

__all__ = ["NodalPenaltyUzawa"]


class NodalPenaltyUzawa(AugmentedLagrangian):
    """The nodal penalty law of stiffness ``kappa0`` (dimensionless) as the fixed point of relaxed Uzawa updates
    around Newton solves of stiffness ``kappa_solve`` < ``kappa0`` (not registered: the penalty method owns it)."""

    def __init__(self, *, E, E_star, kappa0: float, kappa_solve: float, uzawa_rtol: float = 1e-10,
                 uzawa_max_it: int = 100):
        super().__init__(E=E, E_star=E_star, kappa0=min(kappa0, kappa_solve), uzawa_rtol=uzawa_rtol,
                         uzawa_max_it=uzawa_max_it)
        self.kappa0_law = kappa0
        self.relaxation = 1.0 - kappa_solve / kappa0
        self.label = f"penalty kappa0 = {kappa0:g} (nodal law, Uzawa)"

    def nodal_fields(self, kin) -> dict:
        """The law's stiffness ``kappa = kappa0 E* / h`` (MPa/mm), averaged at the nodes for :meth:`law_gap`."""
        return {"kappa": self.constant(kin, penalty_stiffness(self.kappa0_law, self.E_star, 1.0)) / kin.h}

    def law_gap(self, gap, p):
        """``g_i + p_i / kappa_i`` (mm), kappa_i averaged as the update averages it: 0 at a fixed point where
        p_i > 0."""
        return gap + p / (self._nodal("kappa")[self._idx] / self._w)
