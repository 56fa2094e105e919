"""A solve started from converged states of the same problem (``warm_start``): no load path, one solve per level.

What the error budget's iterative term needs (:func:`workbench.error_budget.tight_resolve`): the finest run
solved again with tighter tolerances. From the unloaded state that repeats the whole load path (and at the
stiff two-body cases it diverged after ~40 Newton iterations and 5 cut-backs per tolerance); started from the
converged state it is the same Newton (and Uzawa) iteration continued to the tighter tolerances, which is what
an iterative error is measured against: ``|f(continued) - f(stopped)|``.

* :class:`WarmStart` holds one converged state per level: the final state, or, in displacement control with
  ``record_at``, the state at each recorded displacement (the scene compares every snapshot). A converged
  :class:`fem.solver.ContactResult` carries its own (:func:`warm_start_of`).
* :func:`run_warm` drives a :class:`fem.stepping.LoadStepper` through those levels: each one SNES solve (the
  method's: the augmented Lagrangian's Uzawa loop) at the level's d from its state, with the problem's
  tolerances; force control then corrects d to ``force_rtol`` (tangent, then secant, as a cold solve). No
  cut-backs: a warm level that does not converge raises :class:`fem.errors.ContactSolveError`. SNES tests
  ``snes_rtol`` against the first residual of a solve, which for a warm start is the converged residual itself:
  each level carries the first residual of the solve that reached it, and its warm solve converges at
  ``max(atol, snes_rtol * that residual)``, the test the cold solve met with the same rtol.

The states are local arrays (:meth:`fem.partner_problem.PartnerProblem.get_state`): a warm start applies to the
same mesh read the same way on the same number of processes (the budget re-reads the finest mesh from the cache);
a state of another size is refused (ValueError).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from fem.errors import ContactSolveError, snes_reason_name

__all__ = ["WarmLevel", "WarmStart", "warm_start_of", "run_warm"]


class WarmLevel(NamedTuple):
    """A converged state: the load parameter d (mm), the local state array (u, then the extra unknowns) and the
    first residual norm of the SNES solve that reached it (the reference of its ``snes_rtol``; None: unknown)."""

    d: float
    state: np.ndarray
    first_residual: float | None = None


class WarmStart(NamedTuple):
    """Converged states to start from, one per level (in load order; the last one at the target)."""

    levels: tuple[WarmLevel, ...]


def warm_start_of(stepper) -> WarmStart:
    """The converged states a finished :class:`fem.stepping.LoadStepper` ends with: the one at each ``record_at``
    displacement (displacement control), else the final one."""
    opts, states, r0 = stepper.opts, stepper.states, stepper.first_residuals
    if opts.control == "displacement" and opts.record_at:
        levels = []
        for level in (float(v) for v in opts.record_at):
            i = next(i for i in reversed(range(len(states))) if states[i].d == level)
            levels.append(WarmLevel(float(states[i].d), states[i].x, r0[i]))
        return WarmStart(tuple(levels))
    return WarmStart((WarmLevel(float(states[-1].d), states[-1].x, r0[-1]),))


def run_warm(stepper, warm: WarmStart) -> None:
    """Solve every level of ``warm`` from its state (module docstring); snapshots at recorded displacements,
    the force correction in force control."""
    opts, pb = stepper.opts, stepper.problem
    n = pb.get_state().size
    if any(lv.state.size != n for lv in warm.levels):
        raise ValueError(f"warm_start: a state of {[lv.state.size for lv in warm.levels]} local values for a "
                         f"problem of {n}: not the same mesh and partition")
    recorded = opts.control == "displacement" and bool(opts.record_at)
    if recorded and len(warm.levels) != len(opts.record_at):
        raise ValueError(f"warm_start: {len(warm.levels)} states for {len(opts.record_at)} record_at levels")
    if opts.control == "force":
        pb.set_load_level(opts.target)
    rtol, atol, _, _ = pb.snes.getTolerances()
    for k, (d, x, r0) in enumerate(warm.levels):
        # the SNES rtol of a warm solve would be relative to its own first residual, the converged one's: the
        # level's own reference instead (that of the solve that reached it), as an absolute tolerance
        pb.snes.setTolerances(atol=max(atol, rtol * r0) if r0 else atol)
        try:
            reason, its = stepper.attempt(d, x, "warm", predict_active_set=False)
        finally:
            pb.snes.setTolerances(atol=atol)
        if reason <= 0:
            raise ContactSolveError(f"{opts.case}: warm start at level {k + 1} (d = {d:.6g} mm) diverged: SNES "
                                    f"reason {reason} ({snes_reason_name(reason)}) after {its} iterations")
        if recorded:
            stepper.snapshot(float(opts.record_at[k]))
    if opts.control == "force":
        stepper.correct_force()
