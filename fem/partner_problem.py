"""What the load stepping asks of a contact problem, whatever the partner: :class:`PartnerProblem`.

:class:`fem.stepping.LoadStepper` (load steps, cut-backs, force control, the predictors and the prescribed active
set) and :func:`fem.solver.solve_problem` (the result) use a contact problem through this protocol only. Two
problems implement it: :class:`fem.problem.ContactProblem` (one body against a rigid analytic obstacle: dolfinx
forms on the body's contact facets) and :class:`fem.two_body.problem.TwoBodyProblem` (two meshed elastic bodies:
the weighted-gap coupling across non-matching facets). A new kind of partner is a new problem class with these
members, dispatched in :func:`fem.partners.contact_problem`; ``tests/test_partner_protocol.py`` checks both
implement every member.

Units mm, N, MPa; the load parameter ``d`` (mm) is the obstacle's displacement (rigid) or the driven group's (two
bodies) along the loading direction; P in N/mm, full body. A state is the local array of the unknowns
(displacement, then a mixed pressure or a method's multiplier).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from contextlib import AbstractContextManager
from typing import Any, Protocol, runtime_checkable

import numpy as np

__all__ = ["PartnerProblem", "LoadParameter"]


class LoadParameter(Protocol):
    """The load parameter: ``value`` (mm), read and set by the stepper."""

    value: Any


@runtime_checkable
class PartnerProblem(Protocol):
    """A contact problem the load stepper can drive (module docstring).

    Attributes:
        options: the solve's :class:`fem.options.ContactOptions`.
        d: the load parameter (:class:`LoadParameter`, mm).
        E_star: the pair's plane-strain modulus (MPa; the force control's first stiffness guess 0.3 E*).
        method: the contact law (its ``solve(newton)`` is one Newton solve or an outer loop of them;
            ``options()`` adds its entries to the result).
        snes: the PETSc SNES of the Newton iterations.
        u: the displacement Function (mm).  forms, lame: what the output needs (the contact forms or the bodies,
            the Lame parameters).
        supports: physical group -> support kind.  prefix: the PETSc options prefix.
        qdeg, sdeg: the contact quadrature degree and the default sample degree (reported with the result).
        ndofs: global number of unknowns.
        tangent_applies: the force control's tangent correction applies (P linear in the state for a fixed
            active set, no outer multiplier loop, no gap data to refresh).
        pressure_field: the mixed formulation's pressure Function, or None.
    """

    options: Any
    d: LoadParameter
    E_star: float
    method: Any
    snes: Any
    u: Any
    forms: Any
    lame: Any
    finite_line_search: str
    supports: dict
    prefix: str
    qdeg: int
    sdeg: int

    @property
    def ndofs(self) -> int: ...

    @property
    def tangent_applies(self) -> bool: ...

    @property
    def pressure_field(self) -> Any: ...

    # -- state ----------------------------------------------------------------------------------------------
    def get_state(self) -> np.ndarray:
        """The local array of the unknowns."""

    def set_state(self, arr: np.ndarray, rest: np.ndarray | None = None) -> None:
        """Set the unknowns (a displacement-only ``arr`` takes the others from ``rest``)."""

    def unloaded_guess(self, d_value: float, unloaded: np.ndarray) -> np.ndarray:
        """The start of the first solve at ``d_value`` from the unloaded state."""

    def set_load_level(self, P: float) -> None:
        """Force control: the load level P (N/mm) about to be solved (e.g. a far field scaled by it)."""

    # -- solves ---------------------------------------------------------------------------------------------
    def refresh(self) -> None:
        """Before a solve: data that depend on the state (e.g. a curve obstacle's nodal gaps)."""

    def newton(self, *, force_iteration: bool = False) -> tuple[int, int]:
        """One SNES solve from the current state: (converged reason, iterations)."""

    def solve_once(self, d_value: float, state: np.ndarray, *, rest=None, zone=None) -> tuple[int, int, dict]:
        """One load level at ``d_value`` from ``state`` (:class:`fem.newton_controls.NewtonControls`)."""

    def predictor_iteration(self, zones: Sequence[tuple[float, float]]) -> int:
        """The solve on the prescribed active set ``lo_k < X1 < hi_k`` (one Newton iteration where the equations are
        linear in u): its Newton iterations."""

    def take_start_iterations(self) -> int:
        """The Newton iterations spent on the next solve's start (e.g. a small-strain solve) since the last call."""

    def max_iterations(self, n: int) -> AbstractContextManager:
        """While inside: at most ``n`` Newton iterations."""

    def line_search(self, kind: str) -> AbstractContextManager:
        """While inside: the SNES line search ``kind``."""

    def prescribed_active_set(self, zones: Sequence[tuple[float, float]]) -> AbstractContextManager:
        """While inside: the contact law holds on the prescribed runs of X1 instead of its own sign."""

    def tangent(self, state: np.ndarray, d0: float, *, fixed_set: bool = False) -> tuple[np.ndarray, float] | None:
        """The tangent ``du/dd`` of a converged state for its active set and ``dP/dd``, or None (``fixed_set``: the
        active set is prescribed, not the law's)."""

    def hertz_predictor(self) -> Callable | None:
        """The Hertz predictor (:class:`fem.predictor.HertzPredictor`) when the partner is a rigid circle or
        parabola pressed along (0, -1), else None."""

    # -- measures -------------------------------------------------------------------------------------------
    def measure(self) -> tuple[float, float]:
        """(P, P_pressure) in N/mm, full body."""

    def sample(self, degree: int | None = None, rule=None) -> Any:
        """Surface samples (:class:`fem.postprocess.SurfaceSamples`) of the current state."""

    def law_samples(self) -> Any:
        """Surface samples where the discrete contact law holds (its active set is decided there)."""

    def contact_zones(self) -> tuple[tuple[float, float], ...]:
        """The contact runs (lo, hi) in X1 of the current state (lo = -inf: from the first sample)."""

    def quality_warnings(self, smp, d_now: float) -> list[str]:
        """Named warnings of a converged state."""
