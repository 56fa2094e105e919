"""What the load stepper asks of every contact problem's Newton solve (:class:`fem.stepping.LoadStepper`).

A contact problem (the rigid obstacle's :class:`fem.problem.ContactProblem`, the two bodies'
:class:`fem.two_body.problem.TwoBodyProblem`) owns a PETSc SNES (``self.snes``), its options
(``self.options.max_it``), the load parameter ``self.d`` (``.value``, mm), its state (``set_state``), a Newton
solve ``newton()``, a context ``prescribed_active_set(zones)`` and its contact method or law (``self.method``, whose
``solve(newton)`` is one Newton solve or an outer loop of them); this mixin adds the solve of one load level built
on them, the same for every partner.
"""

from __future__ import annotations

from collections.abc import Sequence
from contextlib import contextmanager

import numpy as np

__all__ = ["NewtonControls"]


class NewtonControls:
    """Mixin: temporary iteration limits, the prescribed-active-set predictor iteration and one load level's solve.

    ``start_iterations``: Newton iterations a problem spent building the start of its next solve (e.g. the
    small-strain solve of :meth:`fem.two_body.finite_problem.FiniteTwoBodyProblem.unloaded_guess`); the load stepper
    counts them with that solve (:meth:`take_start_iterations`)."""

    start_iterations: int = 0
    # kinematics="finite": the SNES line search the load stepper sets (unless petsc_options names one). Backtracking:
    # the full Newton step of a sharp wedge's first contact moves the apex nodes so far that cells invert (det F <=
    # 0, the neo-Hookean ln J is NaN: SNES reason -4 at the first step, d = 0.009 mm of a 1.34 mm wedge, theta =
    # pi/10, nu = 0.3, a/h = 16); "bt" shortens such steps (NaN/Inf residuals count as a failed decrease). A problem
    # class may name its own (two meshed bodies: "l2", :class:`fem.two_body.finite_problem.FiniteTwoBodyProblem`).
    finite_line_search: str = "bt"

    def take_start_iterations(self) -> int:
        """The Newton iterations spent on the next solve's start since the last call (then reset to 0)."""
        n, self.start_iterations = self.start_iterations, 0
        return n

    @contextmanager
    def max_iterations(self, n: int):
        """Temporarily limit the SNES to ``n`` iterations."""
        self.snes.setTolerances(max_it=n)
        try:
            yield
        finally:
            self.snes.setTolerances(max_it=self.options.max_it)

    @contextmanager
    def line_search(self, kind: str):
        """Temporarily the SNES line search ``kind`` (PETSc's names: ``basic``, ``bt``, ``l2``, ``cp``)."""
        ls = self.snes.getLineSearch()
        before = ls.getType()
        ls.setType(kind)
        try:
            yield
        finally:
            ls.setType(before)

    def predictor_iteration(self, zones: Sequence[tuple[float, float]]) -> int:
        """One Newton iteration with the prescribed active set ``lo_k < X1 < hi_k`` (the solve of that set where the
        equations are linear in u); the law is the true one afterwards. Returns the Newton iterations (1)."""
        with self.prescribed_active_set(zones), self.max_iterations(1):
            self.newton()
        return 1

    def refresh(self) -> None:
        """Hook before a solve (a problem whose gap data depend on the state refreshes them); default nothing."""

    def solve_once(self, d_value: float, state: np.ndarray, *, rest=None, zone=None) -> tuple[int, int, dict]:
        """Solve at load parameter ``d_value`` (mm: the obstacle's or the driven body's displacement) from
        ``state``.

        With ``zone`` (a sequence of runs (lo, hi)) one prescribed-active-set iteration comes first (counted).
        Then the method's solve (one Newton solve, or the augmented Lagrangian's Uzawa loop). Returns (SNES
        converged reason, Newton iterations, the method's extra record entries).
        """
        self.d.value = d_value
        self.set_state(state, rest)
        self.refresh()
        pre = 0 if zone is None else self.predictor_iteration(zone)
        reason, its, extra = self.method.solve(self.newton)
        return reason, its + pre, extra
