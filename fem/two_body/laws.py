"""Contact laws on the weighted gaps of two meshed bodies (numpy only), registered with the rigid obstacle's methods.

Units mm, MPa. ``g~_i`` is the weighted gap of contact node i (> 0 open; :mod:`fem.two_body.weighted_gap`),
``p_i >= 0`` its pressure (compressive), ``kappa`` (MPa/mm) the penalty stiffness, uniform along the surface:
``kappa = kappa0 E* / h`` with ``E*`` the combined plane-strain modulus of the two bodies
(``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2``) and h the shortest slave facet: the stiffness of the rigid
obstacle's methods, :func:`fem.methods.base.penalty_stiffness` (E* = E/(1 - nu^2) when the partner is rigid).
A uniform kappa keeps a uniform penalty overlap under a uniform pressure, which the patch test needs.

* ``penalty``: ``p = kappa [-g~]_+`` (one Newton solve per load level; overlap ``p / kappa``);
* ``augmented_lagrangian``: ``p = [lambda - kappa g~]_+`` with Uzawa updates ``lambda <- p`` after each Newton
  solve, until the discrete contact conditions hold to ``tol = uzawa_rtol max|u|`` (``|g~_i| <= tol`` where
  ``p_i > 0``, ``g~_i >= -tol`` elsewhere): no penalty error.

Which of the rigid-obstacle methods carry over: ``penalty`` and ``augmented_lagrangian`` (above), registered under
the same names in the one registry of contact methods (:mod:`fem.methods.registry`, partner kind ``"meshed"``).
``nitsche`` does not: its terms need the slave traction ``sigma_n(u)`` at the mortar points, i.e. the gradient of
the slave displacement across the non-matching interface, which is not built here; it is refused in one line.

While the prescribed active set is on (the load stepper's predictor iteration), the law is the linear branch
``p = q`` on the nodes whose X1 lies in one of the runs, and 0 elsewhere (as :func:`fem.methods.base.contact_law`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import ClassVar

import numpy as np

from fem.errors import ContactSolveError
from fem.methods.base import penalty_stiffness
from fem.methods.registry import get_method, register
from vocabulary import AUGMENTED_LAGRANGIAN, MESHED, PENALTY

__all__ = ["TwoBodyLaw", "PenaltyLaw", "AugmentedLagrangianLaw", "law_for"]


class TwoBodyLaw:
    """A contact law ``p(g~)`` on the nodal weighted gaps (base class: the penalty law).

    Args:
        kappa0: penalty stiffness factor (dimensionless).  E_star: the pair's plane-strain modulus (MPa).
        h: the contact element size (mm): ``kappa = kappa0 E* / h`` (:func:`fem.methods.base.penalty_stiffness`).

    Attributes:
        kappa: penalty stiffness (MPa/mm).  lam: nodal multiplier (MPa; zeros for the penalty law).
        zones: the prescribed active set (runs (lo, hi) of X1) or None (the true law).
    """

    name: ClassVar[str] = PENALTY
    partner: ClassVar[str] = MESHED
    supports_tangent: ClassVar[bool] = True

    def __init__(self, *, kappa0: float, E_star: float, h: float, n_nodes: int, X1: np.ndarray,
                 uzawa_rtol: float = 1e-10, uzawa_max_it: int = 100):
        kappa = penalty_stiffness(kappa0, E_star, h)
        if not kappa > 0:
            raise ValueError(f"kappa0 must be > 0, got kappa = {kappa}")
        self.kappa = float(kappa)
        self.lam = np.zeros(n_nodes)
        self.X1 = X1
        self.zones = None
        self.uzawa_rtol, self.uzawa_max_it = uzawa_rtol, uzawa_max_it
        self.gap: Callable[[], np.ndarray] = lambda: np.zeros(n_nodes)
        self.scale: Callable[[], float] = lambda: 1.0

    def bind(self, *, gap: Callable[[], np.ndarray], scale: Callable[[], float]) -> None:
        """Give the law the problem's current weighted gaps (mm) and displacement scale max|u| (mm)."""
        self.gap, self.scale = gap, scale

    def argument(self, g: np.ndarray) -> np.ndarray:
        """The pressure argument q (MPa): p = [q]_+."""
        return self.lam - self.kappa * g

    def active(self, q: np.ndarray) -> np.ndarray:
        """Nodes on the linear branch of the law (prescribed runs while the predictor is on)."""
        if self.zones is None:
            return q > 0.0
        inside = np.zeros(q.shape, dtype=bool)
        for lo, hi in self.zones:
            inside |= (self.X1 > lo) & (self.X1 < hi)
        return inside

    def pressure(self, g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(p, dp/dg~) at the weighted gaps g (MPa, MPa/mm)."""
        q = self.argument(g)
        act = self.active(q)
        return np.where(act, q, 0.0), np.where(act, -self.kappa, 0.0)

    def state(self) -> np.ndarray:
        """The law's own unknowns (saved and extrapolated with u by the load stepper)."""
        return np.zeros(0)

    def set_state(self, arr: np.ndarray) -> None:
        return None

    def solve(self, newton: Callable[..., tuple[int, int]]) -> tuple[int, int, dict]:
        """One load level: one Newton solve."""
        reason, its = newton()
        return reason, its, {}

    def options(self) -> dict:
        return {"kappa": self.kappa}


@register
class PenaltyLaw(TwoBodyLaw):
    """``p = kappa [-g~]_+`` (module docstring)."""


@register
class AugmentedLagrangianLaw(TwoBodyLaw):
    """``p = [lambda - kappa g~]_+`` with Uzawa updates (module docstring)."""

    name: ClassVar[str] = AUGMENTED_LAGRANGIAN
    supports_tangent: ClassVar[bool] = False

    def state(self) -> np.ndarray:
        return self.lam.copy()

    def set_state(self, arr: np.ndarray) -> None:
        self.lam[:] = arr

    def solve(self, newton):
        gap, scale = self.gap, self.scale
        reason, total = newton()
        if reason <= 0:
            return reason, total, {}
        for k in range(1, self.uzawa_max_it + 1):
            g = gap()
            p, _ = self.pressure(g)
            tol = self.uzawa_rtol * scale()
            violation = float(max(np.max(np.abs(g[p > 0]), initial=0.0), np.max(-g, initial=0.0)))
            change = float(np.max(np.abs(p - self.lam), initial=0.0))
            if violation <= tol:
                return reason, total, {"uzawa": k, "uzawa_gap": violation / max(scale(), 1e-300),
                                       "uzawa_change": change / max(float(np.max(p, initial=0.0)), 1e-300)}
            self.lam[:] = p
            reason, its = newton(force_iteration=True)
            total += its
            if reason <= 0:
                return reason, total, {}
        raise ContactSolveError(f"augmented Lagrangian: the Uzawa loop did not reach uzawa_rtol = {self.uzawa_rtol:g} "
                                f"in uzawa_max_it = {self.uzawa_max_it} updates (gap violation {violation:.3g} mm)")

    def options(self) -> dict:
        return {"kappa": self.kappa, "uzawa_rtol": self.uzawa_rtol}


def law_for(method: str) -> type[TwoBodyLaw]:
    """The law class of a two-body method name (the registry's, :func:`fem.methods.registry.get_method`;
    ValueError naming the allowed ones)."""
    return get_method(method, MESHED)
