"""Load stepping of a contact problem: steps, cut-backs, force control and predictors.

The stepper uses its problem through the declared protocol :class:`fem.partner_problem.PartnerProblem` only, so
the rigid obstacle's :class:`fem.problem.ContactProblem` and the two bodies'
:class:`fem.two_body.problem.TwoBodyProblem` are driven by the same code.

Because small-strain frictionless contact is path independent, the cost is all in the active set. Measured on
the Hertz scene, semismooth Newton started from a predicted u whose active set is decided by the sign of its
tiny gaps releases about one quadrature point per iteration (10-25 iterations per step). So every solve
starts with ONE Newton iteration on a prescribed active set ``lo < X1 < hi`` (the Hertz zone of the load
level, or the contact edges of the last two states extrapolated linearly in d), then the true law:

* predictor ``hertz`` (force control, circle/parabola, direction (0, -1); :mod:`fem.predictor`): u from a
  linear solve with the Hertz pressure as a Neumann load, d from its displacement at the first-contact point;
* predictor ``extrapolate``: the state (u, and the mixed pressure or a method's multiplier) linear in d from the
  last two converged states; without history a short first step at ``first_step_fraction`` of the first level.

Reported ``iterations`` count that predictor iteration too (1 = the prescribed active set was already right).

* ``control="displacement"``: the obstacle moves by ``d_k = target k / n_steps`` along its direction
  (``record_at``: through the recorded displacements, a :class:`Snapshot` at each).
* ``control="force"``: load levels ``P_k = target k / n_steps`` (N/mm, full body); d from the Hertz predictor or
  the secant through the last two (d, P) states (the first from a stiffness guess 0.3 E'); the last level is
  corrected on d until ``|P - target| <= force_rtol target`` (each a separate record, kind ``force-correction``).
  For a fixed active set the small-strain equations are linear in (u, d), so a correction first tries the
  tangent of the last converged state with the LU factors the Newton solve already holds
  (:meth:`fem.problem.ContactProblem.tangent`): ``Delta d = (target - P) / (dP/dd)``, ``u + Delta d t``; that
  state then goes through the same SNES solve (true law, same tolerances and converged-reason checks), which
  accepts it without iterating (0 iterations recorded) when the active set did not change, and may take one
  Newton iteration otherwise. When the tangent does not apply (mixed formulation, finite strain, curve obstacles,
  a method with its own multiplier loop, a miss above 1 % of the target), its solve needs more than one iteration
  (discarded), or it needed one or cut the force miss less than tenfold (an active-set change between the factored
  J and the converged state), the remaining corrections are secant steps through the last two (d, P) states.

* A first level from the Hertz zone (``predictor="hertz_zone"``) and a start from a coarser mesh (``nested_start``)
  in force control are solved with d an unknown of every Newton iteration (:mod:`fem.force_newton`: the load
  row and the dF/dd column border the Jacobian), where the tangent applies and ``active_set_update`` is
  ``"newton"``: one record, no separate force correction. Otherwise (or when it does not converge) the solve
  goes the way above, from the prescribed active set moved along its tangent (:meth:`LoadStepper.prescribed_start`).

Divergence (SNES converged reason <= 0) restores the last converged state and halves the increment, up to
``max_cutbacks`` times per step, then raises :class:`fem.errors.ContactSolveError` naming the reason (e.g.
``-5 (DIVERGED_MAX_IT)``).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from fem.active_set_update import (
    MERGE_POINTS,
    accelerated_runs,
    extrapolated_runs,
    merged_runs,
    safeguarded_runs,
    same_active_points,
    sign_runs,
)
from fem.errors import ContactSolveError, snes_reason_name
from fem.partner_problem import PartnerProblem
from fem.postprocess import Patch, SurfaceSamples, find_patches
from fem.problem import MAX_ZONES
from vocabulary import FINITE

__all__ = ["LoadStepper", "ConvergedState", "Snapshot"]

MAX_FORCE_CORRECTIONS = 30
# active_set="geometry": the first active set of a first contact is the rigid overlap of the undeformed body at
# the new d, each run shrunk about its centre by this factor. Measured on the six scenes of make run (predictor
# "extrapolate"): 1.0 (the plain overlap) gives the first contact solve 7-10 Newton iterations, 0.7 gives 5-8,
# 0.5 gives 3-4 (a Hertz patch is narrower than the rigid overlap; a/c = 1/sqrt(2) in 3D Hertz).
GEOMETRIC_SHRINK = 0.5
# active_set_update="edge_fit": at most this many prescribed-active-set iterations before the true law
EDGE_FIT_MAX = 8
# kinematics="finite" only (unless petsc_options names a line search): the problem's ``finite_line_search``
# (:class:`fem.newton_controls.NewtonControls`: "bt" unless the problem class names its own).
# kinematics="finite" only: a load step's displacement increment is at most this many times the last converged
# one (the rest in sub-steps). Without it the force control's first level follows a short first step with a
# 37-fold larger increment (theta = pi/4, nu = 0, a/h = 8: 0.014 mm then 0.52 mm), whose extrapolated start
# already has inverted apex cells.
FINITE_STEP_GROWTH = 2.0


class Snapshot(NamedTuple):
    """Surface state at one recorded displacement (``record_at``): d (mm), P and P_pressure (N/mm, full
    body), surface samples, patches, the Newton iterations of the solve that reached it, and the named
    warnings of that state (as :attr:`fem.solver.ContactResult.warnings`)."""

    d: float
    P: float
    P_pressure: float
    samples: SurfaceSamples
    patches: list[Patch]
    iterations: int
    warnings: tuple = ()


class ConvergedState(NamedTuple):
    """A converged state: d (mm), P (N/mm), the unknowns (:meth:`ContactProblem.get_state`) and its contact runs
    ((lo, hi), ...) in X1 for the active-set predictor (empty: no contact; None: unknown)."""

    d: float
    P: float
    x: np.ndarray
    zone: tuple | None


def _single(zone) -> bool:
    """True for the runs of a state with exactly one contact run."""
    return zone is not None and len(zone) == 1


def _origin(run: tuple, before: tuple | None) -> tuple:
    """Where ``run`` came from in the runs ``before``: the envelope of those it overlaps; else a point at its
    centre (its end 0 for a run from the first sample)."""
    lo, hi = run
    hit = [r for r in (before or ()) if r[0] < hi and lo < r[1]]
    if hit:
        return (min(r[0] for r in hit), max(r[1] for r in hit))
    return (lo, 0.0) if np.isinf(lo) else (0.5 * (lo + hi),) * 2


def _grow(r1: tuple, r2: tuple, f: float) -> tuple:
    """The run r2 extrapolated by f intervals from r1: centre linear, squared half-width linear (a run from the
    first sample: its squared end)."""
    (a1, b1), (a2, b2) = r1, r2
    if np.isinf(a2):
        return (-np.inf, float(np.sqrt(max(b2 * b2 + f * (b2 * b2 - b1 * b1), 0.0))))
    c1, c2, w1, w2 = 0.5 * (a1 + b1), 0.5 * (a2 + b2), 0.5 * (b1 - a1), 0.5 * (b2 - a2)
    c, w = c2 + f * (c2 - c1), float(np.sqrt(max(w2 * w2 + f * (w2 * w2 - w1 * w1), 0.0)))
    return (c - w, c + w)


def _merged(runs: tuple) -> tuple:
    """Runs sorted by their start, overlapping ones merged."""
    out: list = []
    for lo, hi in sorted(runs, key=lambda r: r[0]):
        if out and lo <= out[-1][1]:
            out[-1] = (out[-1][0], max(out[-1][1], hi))
        else:
            out.append((lo, hi))
    return tuple(out)


class LoadStepper:
    """Drives a :class:`fem.partner_problem.PartnerProblem` through the load levels (module docstring).

    Attributes:
        problem: the contact problem.
        states: converged states, the unloaded one first.
        records: one dict per converged solve: d (mm), P, P_pressure (N/mm), iterations, time (s), kind, reason
            (plus the method's entries, e.g. ``uzawa``).
        failures: one dict per solve that did not converge: d (mm), kind, iterations, time (s), reason.
        snapshots: :class:`Snapshot` per ``record_at`` displacement.
        hertz: the Hertz predictor, or None.
        factored: the SNES's KSP holds LU factors of a Jacobian of this problem.
        on_step: callbacks ``f(record)`` called after every converged solve (:meth:`add_step_callback`).
    """

    def __init__(self, problem: PartnerProblem, *, on_step: Callable | None = None):
        self.problem = pb = problem
        self.opts = opts = problem.options
        self.states = [ConvergedState(0.0, 0.0, pb.get_state() * 0.0, None)]
        # the first residual norm of the last SNES solve that reached each state (None: the unloaded one): the
        # reference of snes_rtol, which a warm re-solve of that state tests against (fem.warm_start)
        self.first_residuals: list[float | None] = [None]
        pb.snes.setConvergenceHistory(reset=True)
        self.records: list[dict] = []
        # one dict per solve that did not converge (d, kind, iterations, time, reason): the cost the records leave
        # out (a failed attempt's iterates can be wild and slow; its cut-back retries are records of their own)
        self.failures: list[dict] = []
        self.snapshots: list[Snapshot] = []
        self.on_step: list[Callable] = [] if on_step is None else [on_step]
        self.factored = False
        self.start_zone = None  # the prescribed runs of the hertz_zone start (hertz_zone_start)
        self.t_start = time.perf_counter()
        self.wall_time_s = 0.0
        hertz_ok = opts.control == "force" and pb.hertz_applicable
        if opts.predictor in ("hertz", "hertz_zone") and not hertz_ok:
            raise ValueError(f"predictor={opts.predictor!r} needs control='force', a circle/parabola obstacle and "
                             "direction (0, -1)")
        # the tangent correction measures dP/dd as P(t), which needs P linear in u: not for finite strain
        self.tangent_ok = pb.tangent_applies
        # hertz_zone: the Hertz zone from the unloaded state, d an unknown of the Newton iterations
        # (fem.force_newton) or the tangent of that prescribed-set solve (no stiffness solve); where the tangent
        # does not apply, the Hertz predictor.
        # "auto": that start wherever the force-controlled Newton takes it (fem.force_newton: one factorisation where
        # the Hertz predictor's stiffness solve and the Newton iterations made two or more)
        # the force-controlled Newton applies: the problem's hook, the tangent, semismooth Newton's own updates
        self.force_newton_ok = (getattr(pb, "force_newton", None) is not None and self.tangent_ok
                                and opts.active_set_update == "newton")
        self.zone_start = self.tangent_ok and (opts.predictor == "hertz_zone"
                                               or (opts.predictor == "auto" and hertz_ok and self.force_newton_ok))
        self.finite = opts.kinematics == FINITE
        if self.finite and "snes_linesearch_type" not in (opts.petsc_options or {}):
            pb.snes.getLineSearch().setType(pb.finite_line_search)
        use_hertz = opts.predictor in ("hertz", "hertz_zone") or (opts.predictor == "auto" and hertz_ok)
        self.hertz = pb.hertz_predictor() if use_hertz else None

    def add_step_callback(self, fn: Callable[[dict], None]) -> None:
        """Call ``fn(record)`` after every converged solve (after the ones already registered)."""
        self.on_step.append(fn)

    # -- predictors -----------------------------------------------------------------------------------------
    def extrapolate(self, d_new: float) -> np.ndarray:
        """State linear in d through the last two converged states; without history the problem's guess for
        the unloaded state moved to d_new (:meth:`fem.problem.ContactProblem.unloaded_guess`)."""
        if len(self.states) == 1:
            return self.problem.unloaded_guess(d_new, self.states[-1].x)
        (d1, _, u1, _), (d2, _, u2, _) = self.states[-2], self.states[-1]
        if d2 == d1:
            return u2
        return u2 + (d_new - d2) / (d2 - d1) * (u2 - u1)

    def predicted_zone(self, d_new: float, x_pred: np.ndarray | None = None) -> tuple | None:
        """Contact runs ((lo, hi), ...) at d_new for the prescribed-active-set iteration (None: no prediction).

        ``active_set="extrapolate"``: single-patch states only, the edges of the last two states extrapolated
        linearly in d (from the unloaded state: a zone grown from the first-contact point); no prediction for the
        first step or several patches. ``active_set="geometry"`` (:meth:`predicted_runs`) adds the first contact
        from the geometry and several patches.
        """
        if self.opts.active_set == "geometry":
            return self.predicted_runs(d_new, x_pred)
        if len(self.states) < 2 or not _single(self.states[-1].zone):
            return None
        (d1, _, _, z1), (d2, _, _, z2) = self.states[-2], self.states[-1]
        e2, e1 = z2[0], (z1[0] if _single(z1) else None)
        if e1 is None and len(self.states) == 2:  # from the unloaded state: a zone shrunk to the first-contact point
            c = 0.0 if np.isinf(e2[0]) else 0.5 * (e2[0] + e2[1])
            e1 = (e2[0] if np.isinf(e2[0]) else c, c)
        if e1 is None:
            return None
        if d2 == d1:
            return (e2,)
        f = (d_new - d2) / (d2 - d1)
        lo = -np.inf if np.isinf(e2[0]) else e2[0] + f * (e2[0] - e1[0])
        return ((lo, e2[1] + f * (e2[1] - e1[1])),)

    def predicted_runs(self, d_new: float, x_pred: np.ndarray | None) -> tuple | None:
        """``active_set="geometry"``: contact runs ((lo, hi), ...) at d_new (None: no prediction).

        * the last state touches: each of its runs extrapolated in d from its origin in the state before (the
          envelope of the runs it overlaps there; none: its centre, or its end for a run from the first sample):
          the centre linearly, the squared half-width linearly (a Hertz-like run grows as sqrt(d); measured on
          close_to_conformal, linear edges over-predicted the 0.5 -> 0.7 mm growth twofold); predicted runs
          that overlap are merged;
        * no state touches yet (the first step, or all earlier states open), with ``x_pred``: the geometry, the
          runs of the overlap of the predicted state at d_new (the rigid overlap of the undeformed body when it
          is unloaded), each shrunk by :data:`GEOMETRIC_SHRINK` (:meth:`geometric_zone`);
        """
        if len(self.states) >= 2 and self.states[-1].zone:
            (d1, _, _, e1), (d2, _, _, e2) = self.states[-2], self.states[-1]
            if d2 == d1:
                return e2
            f = (d_new - d2) / (d2 - d1)
            return _merged(tuple(_grow(_origin(r2, e1), r2, f) for r2 in e2))
        if x_pred is None:
            return None
        return self.geometric_zone(d_new, x_pred)

    def geometric_zone(self, d_new: float, x_pred: np.ndarray) -> tuple | None:
        """Runs of the overlap of the state ``x_pred`` at d_new, each shrunk about its centre (a run from the
        first sample: about that end) by :data:`GEOMETRIC_SHRINK`; None when nothing overlaps."""
        pb = self.problem
        pb.d.value = d_new
        pb.set_state(x_pred, self.states[-1].x)
        pb.refresh()
        runs = pb.contact_zones()
        if not runs:
            return None
        f = GEOMETRIC_SHRINK
        return tuple((lo, f * hi) if np.isinf(lo) else (0.5 * (lo + hi) - 0.5 * f * (hi - lo),
                                                        0.5 * (lo + hi) + 0.5 * f * (hi - lo)) for lo, hi in runs)

    def secant(self, P_goal: float) -> float:
        """d for load P_goal (N/mm) through the last two (d, P) states (first: stiffness guess 0.3 E')."""
        (d1, P1, _, _), (d2, P2, _, _) = self.states[-2], self.states[-1]
        if P2 == P1:
            return d2 * P_goal / P2 if P2 > 0 else self.stiffness_guess(P_goal)
        return d2 + (P_goal - P2) * (d2 - d1) / (P2 - P1)

    # -- solves ---------------------------------------------------------------------------------------------
    def attempt(self, d_new, x_pred, kind, zone=None, predict_active_set=True, done_its=0,
                solved_zone=None) -> tuple[int, int]:
        """One solve at d_new from x_pred; on convergence append the state and the record and call on_step.
        ``done_its``: Newton iterations already spent on this solve (counted in the record). ``solved_zone``: the
        prescribed runs x_pred already solves (at d_new); with ``active_set_update`` other than ``"newton"`` the
        active-set updates start from it (:meth:`solve_edge_fit`), else it is not used."""
        t0 = time.perf_counter()
        pb = self.problem
        if zone is None and predict_active_set and self.opts.active_set_predictor:
            zone = self.predicted_zone(d_new, x_pred)
        use_zone = (zone is not None and self.opts.active_set_predictor and predict_active_set
                    and len(zone) <= MAX_ZONES)
        if solved_zone is not None and self.opts.active_set_update != "newton":
            reason, its, extra = self.solve_edge_fit(d_new, x_pred, solved_zone, solved=True)
        elif use_zone and self.opts.active_set_update != "newton":
            reason, its, extra = self.solve_edge_fit(d_new, x_pred, zone)
        else:
            reason, its, extra = pb.solve_once(d_new, x_pred, rest=self.states[-1].x,
                                               zone=zone if use_zone else None)
        its += done_its + pb.take_start_iterations()
        self.factored = self.factored or its > 0
        if reason <= 0:
            if self.finite:
                # A failed finite-strain iterate may hold inverted cells (det F <= 0: ln J is NaN); MUMPS then
                # fails its analysis and PETSc skips every later numeric factorisation of the same pattern
                # (measured: each cut-back ended with DIVERGED_LINEAR_SOLVE after 0 iterations). Reset the PC so
                # the next solve factorises afresh.
                pb.snes.getKSP().getPC().reset()
            self.failures.append({"d": d_new, "kind": kind, "iterations": its, "time": time.perf_counter() - t0,
                                  "reason": reason})
            return reason, its
        history = pb.snes.getConvergenceHistory()[0]
        self.accept(d_new, kind, its=its, reason=reason, t0=t0, extra=extra,
                    first_residual=float(history[0]) if len(history) else None)
        return reason, its

    def accept(self, d_new: float, kind: str, *, its: int, reason: int, t0: float, extra: dict,
               first_residual: float | None) -> None:
        """Keep the problem's current (converged) state at d_new: its state, record (time since ``t0``) and the
        on_step callbacks. ``first_residual``: the first residual norm of the solve that reached it."""
        pb = self.problem
        P, Pp = pb.measure()
        zone_now = pb.contact_zones() if self.opts.active_set_predictor else None
        self.states.append(ConvergedState(d_new, P, pb.get_state(), zone_now))
        self.first_residuals.append(first_residual)
        rec = {"d": d_new, "P": P, "P_pressure": Pp, "iterations": its, "time": time.perf_counter() - t0,
               "kind": kind, "reason": reason, **extra}
        self.records.append(rec)
        for fn in self.on_step:
            fn(rec)

    def solve_edge_fit(self, d_new: float, x_pred: np.ndarray, zone: tuple,
                       solved: bool = False) -> tuple[int, int, dict]:
        """``active_set_update`` other than ``"newton"``: iterations on prescribed active sets until the set of
        contact points of the iterate's own sign change equals the prescribed one (or the next prescribed set
        repeats, or :data:`EDGE_FIT_MAX` iterations); then the method's solve with the true law decides the answer.

        ``"edge_fit"``: the next runs are the edges extrapolated from the pressure of the last iterate
        (:func:`fem.active_set_update.extrapolated_runs`), an edge whose fit moves against the sign change taking
        the sign change (:func:`fem.active_set_update.safeguarded_runs`); fragments of a run (the sign of tiny gaps)
        are merged (:func:`fem.active_set_update.merged_runs`), and an edge converging linearly over several
        quadrature points takes the secant step (:func:`fem.active_set_update.accelerated_runs`; at 88k dofs
        without a predictor a too-large set halved its excess per iteration). A secant on every edge (tried) was
        worse on the coarse scenes (concave_symmetric 3.33 -> 4.17 per solve).
        Measured (make run's six scenes, ``predictor="extrapolate"``, ``active_set="geometry"``): mean Newton
        iterations per solve 1.83 / 2.57 / 3.20 / 2.14 / 3.00 / 3.67 (hertz_cylinder, wedge, wedge_convective,
        parabola_convective, concave_symmetric, close_to_conformal) against 2.33 / 3.43 / 3.67 / 2.43 / 3.33 /
        5.00 with ``"newton"`` (near convergence the sign-change edge is not a smooth function of the prescribed
        edge: it moves by whole quadrature points). ``solved``: x_pred already solves
        the prescribed ``zone`` at d_new (no iteration on it). Returns as :meth:`ContactProblem.solve_once`."""
        pb = self.problem
        pb.d.value = d_new
        pb.set_state(x_pred, self.states[-1].x)
        pb.refresh()
        pre, sets, hist = 0, 0, None  # Newton iterations, prescribed sets solved
        while zone is not None and sets < EDGE_FIT_MAX:
            if not solved:
                pre += pb.predictor_iteration(zone)
                sets += 1
            solved = False
            smp = pb.law_samples()
            sign = sign_runs(smp.s, smp.q)
            if not sign or same_active_points(smp.s, sign, zone):
                break  # the iterate's own active set is the prescribed one: the true law accepts it
            h = float(np.median(np.diff(smp.s))) if smp.s.size > 1 else 0.0
            fit = extrapolated_runs(smp.s, smp.q, zone=zone)
            if len(sign) > 1:  # fragments of one run (the sign of tiny gaps): their envelope
                sign, fit = merged_runs(sign, MERGE_POINTS * h), merged_runs(fit, MERGE_POINTS * h)
                if len(sign) != len(fit):
                    fit = sign
            new = safeguarded_runs(zone, sign, fit)
            if hist is not None:
                new = accelerated_runs(hist[0], hist[1], zone, sign, new, h)
            if len(new) > MAX_ZONES or same_active_points(smp.s, new, zone):
                break
            hist, zone = (zone, sign), new
        reason, its, extra = pb.method.solve(pb.newton)
        return reason, its + pre, extra

    def reach(self, d_target, step, kind, x_pred=None, zone=None) -> None:
        """Reach d_target from the last converged state, halving the increment on divergence.

        Finite strain: first through intermediate displacements, each increment at most
        :data:`FINITE_STEP_GROWTH` times the last converged one (:meth:`finite_substeps`)."""
        if self.finite:
            for d_sub in self.finite_substeps(d_target):
                self.reach_once(d_sub, step, "substep")
                x_pred = zone = None
        self.reach_once(d_target, step, kind, x_pred, zone)

    def finite_substeps(self, d_target: float) -> list[float]:
        """Intermediate displacements before ``d_target`` (finite strain): increments growing at most
        :data:`FINITE_STEP_GROWTH`-fold from the last converged increment (none without two states)."""
        if len(self.states) < 2:
            return []
        d1, d2 = self.states[-2].d, self.states[-1].d
        inc, out, d = abs(d2 - d1), [], d2
        if inc == 0.0:
            return []
        sign = 1.0 if d_target >= d2 else -1.0
        while True:
            inc *= FINITE_STEP_GROWTH
            if abs(d_target - d) <= inc:
                return out
            d += sign * inc
            out.append(d)

    def reach_once(self, d_target, step, kind, x_pred=None, zone=None) -> None:
        """:meth:`reach` without the finite-strain sub-steps."""
        cut = 0
        while True:
            d_prev = self.states[-1].d
            d_try = d_target if cut == 0 else d_prev + (d_target - d_prev) / 2.0**cut
            guess = x_pred if (cut == 0 and x_pred is not None) else self.extrapolate(d_try)
            reason, its = self.attempt(d_try, guess, kind if cut == 0 else "cutback", zone if cut == 0 else None)
            if reason > 0:
                if d_try == d_target:
                    return
                cut = 0
                x_pred = zone = None
                continue
            cut += 1
            if cut > self.opts.max_cutbacks:
                raise ContactSolveError(f"{self.opts.case}: load step {step} (d = {d_try:.6g} mm) diverged: SNES "
                                        f"reason {reason} ({snes_reason_name(reason)}) after {its} iterations and "
                                        f"{self.opts.max_cutbacks} cut-backs")

    def tangent_correction(self, P_goal: float) -> bool:
        """One force correction along the tangent of the last converged state (module docstring).

        Returns True when it produced a converged state; False (state restored) when the tangent does not
        apply or its SNES solve did not converge within one iteration, so the caller falls back to the secant.
        """
        if not (self.tangent_ok and self.factored):
            return False
        pb = self.problem
        d0, P0, u0, _ = self.states[-1]
        tan = pb.tangent(u0, d0)
        if tan is None:
            return False
        t_arr, dP = tan
        dd = (P_goal - P0) / dP
        if not abs(dd) <= 0.5 * abs(d0):
            return False
        # At most one Newton iteration from the tangent state: more means the active set moved, which the
        # secant step with its active-set predictor handles in fewer iterations than semismooth Newton does.
        with pb.max_iterations(1):
            reason, _ = self.attempt(d0 + dd, u0 + dd * t_arr, "force-correction", predict_active_set=False)
        if reason > 0:
            return True
        pb.d.value = d0
        pb.set_state(u0)
        return False

    # -- drivers --------------------------------------------------------------------------------------------
    def run(self) -> None:
        """Step to the target (displacement, recorded displacements or force control), or solve the levels of
        ``warm_start`` from their converged states (:func:`fem.warm_start.run_warm`), or the target once from a
        coarser mesh's solution (``nested_start``, :meth:`run_nested`)."""
        opts = self.opts
        if opts.nested_start is not None and (opts.warm_start is not None or opts.record_at):
            raise ValueError("nested_start starts one solve of the target: not with warm_start or record_at")
        if opts.warm_start is not None:  # from converged states: no load path (fem.warm_start)
            from fem.warm_start import run_warm

            run_warm(self, opts.warm_start)
        elif opts.nested_start is not None:  # from a coarser mesh's solution: no load path (fem.nested_start)
            self.run_nested(opts.nested_start)
        elif opts.control == "displacement" and opts.record_at:
            self.run_recorded()
        elif opts.control == "displacement":
            self.run_displacement()
        else:
            self.run_force()
            self.correct_force()
        self.wall_time_s = time.perf_counter() - self.t_start

    def run_nested(self, start) -> None:
        """The target solved once from a coarser mesh's converged state (:mod:`fem.nested_start`): its
        interpolation, its contact runs as the first prescribed active set and, in force control, its d, then the
        force correction."""
        opts, pb = self.opts, self.problem
        guess = getattr(pb, "nested_guess", None)
        if guess is None:
            raise ValueError(f"nested_start: {type(pb).__name__} has no nested_guess (no nested iteration for it)")
        x0 = guess(start)
        zone = tuple(start.zones) or None
        if opts.control == "force":
            pb.set_load_level(opts.target)
            if zone and self.force_newton(zone, start.d, x0, opts.target, "nested"):
                self.correct_force()
                return
            # the coarse active set moved along its tangent to the target load first; where that does not apply or
            # does not converge, the coarse d and active set as they are
            moved = self.prescribed_start(zone, start.d, x0, opts.target) if zone and self.tangent_ok else None
            if moved is None or self.attempt(*moved, "nested", predict_active_set=False, done_its=1,
                                             solved_zone=zone)[0] <= 0:
                self.reach(start.d, 1, "nested", x0, zone)
            self.correct_force()
        else:
            self.reach(opts.target, 1, "nested", x0, zone)

    def run_displacement(self) -> None:
        """``d_k = target k / n_steps`` (after a first step at ``first_step_fraction`` of the first one)."""
        opts = self.opts
        if opts.first_step_fraction < 1.0:
            self.reach(opts.first_step_fraction * opts.target / opts.n_steps, 0, "first")
        for k in range(1, opts.n_steps + 1):
            self.reach(opts.target * k / opts.n_steps, k, "step")

    def run_recorded(self) -> None:
        """Step through the recorded displacements in turn (n_steps sub-steps to the first one, one step between
        the others, cut back as needed) and keep a snapshot of the surface at each."""
        opts = self.opts
        levels = [float(v) for v in opts.record_at]
        for k in range(1, opts.n_steps + 1):
            self.reach(levels[0] * k / opts.n_steps, k, "step")
        for k, level in enumerate(levels):
            if k > 0:
                self.reach(level, opts.n_steps + k, "step")
            self.snapshot(level)

    def snapshot(self, level: float) -> None:
        """Keep a :class:`Snapshot` of the current (converged) state at the recorded displacement ``level``."""
        opts, pb = self.opts, self.problem
        smp = pb.sample()
        P_k, Pp_k = pb.measure()
        self.snapshots.append(Snapshot(d=level, P=float(P_k), P_pressure=float(Pp_k), samples=smp,
                                       patches=find_patches(smp, half=opts.symmetric_half),
                                       iterations=int(self.records[-1]["iterations"]) if self.records else 0,
                                       warnings=tuple(pb.quality_warnings(smp, level))))

    def run_force(self) -> None:
        """Load levels ``P_k = target k / n_steps``: d from the Hertz predictor or the secant."""
        opts = self.opts
        for k in range(1, opts.n_steps + 1):
            P_goal = opts.target * k / opts.n_steps
            self.problem.set_load_level(P_goal)  # halfplane supports: Flamant's field of this level
            zone = None
            if self.zone_start and len(self.states) == 1:
                # d an unknown of the Newton iterations from the Hertz zone (fem.force_newton), where it applies
                zone0, d0 = (self.hertz.zone(P_goal, half=opts.symmetric_half),), self.stiffness_guess(P_goal)
                if self.force_newton(zone0, d0, self.states[-1].x, P_goal, "step"):
                    continue
                start = self.hertz_zone_start(zone0, d0, P_goal)
                if start is not None:
                    d_next, x_next = start
                    reason, _ = self.attempt(d_next, x_next, "step", predict_active_set=False, done_its=1,
                                             solved_zone=self.start_zone)
                    if reason > 0:
                        continue
                self.problem.set_state(self.states[-1].x)
            if self.hertz is not None:
                d_next, u_next, hertz_zone = self.hertz(P_goal, half=opts.symmetric_half)
                zone = (hertz_zone,)
            else:
                if len(self.states) == 1 and opts.first_step_fraction < 1.0:
                    self.reach(self.stiffness_guess(opts.first_step_fraction * P_goal), 0, "first")
                d_next = self.stiffness_guess(P_goal) if len(self.states) == 1 else self.secant(P_goal)
                u_next = None
            self.reach(d_next, k, "step", u_next, zone)

    def stiffness_guess(self, P_goal: float) -> float:
        """d (mm) of the load P_goal (N/mm) from the unloaded state with the stiffness guess ``0.3 E'``."""
        return P_goal / (0.3 * self.problem.E_star)

    def hertz_zone_start(self, zone: tuple, d0: float, P_goal: float) -> tuple[float, np.ndarray] | None:
        """``predictor="hertz_zone"``, first load level from the unloaded state where the force-controlled Newton
        does not apply: (d, state) of the prescribed active set ``zone`` = the Hertz zone of P_goal
        (:meth:`fem.predictor.HertzPredictor.zone`), without a stiffness solve: :meth:`prescribed_start` from the
        unloaded state at the guess ``d0`` (:meth:`stiffness_guess`)."""
        self.start_zone = zone
        return self.prescribed_start(zone, d0, self.states[-1].x, P_goal)

    def force_newton(self, zone: tuple, d0: float, x0: np.ndarray, P_goal: float, kind: str) -> bool:
        """The load P_goal solved with d an unknown of every Newton iteration (:mod:`fem.force_newton`), the first
        on the prescribed active set ``zone``, from ``x0`` at ``d0``; on convergence the state is kept (one record
        of ``kind``) and True returned. False (the problem back at ``x0``, ``d0``) where it does not apply (no
        tangent: finite strain, a mixed formulation, a method's own loop; a problem without the hook) or did not
        converge within ``max_it``."""
        pb, opts = self.problem, self.opts
        if not self.force_newton_ok:
            return False
        t0 = time.perf_counter()
        res = pb.force_newton(P_goal=P_goal, d0=d0, x0=x0, zone=zone, max_it=opts.max_it)
        self.factored = True
        if not res.converged:
            self.failures.append({"d": res.d, "kind": kind, "iterations": res.iterations,
                                  "time": time.perf_counter() - t0, "reason": -5})
            pb.d.value = d0
            pb.set_state(x0, self.states[-1].x)
            return False
        reason = 2 if res.residual <= pb.snes.getTolerances()[1] else 3  # SNES's FNORM_ABS / FNORM_RELATIVE
        self.accept(res.d, kind, its=res.iterations, reason=reason, t0=t0, extra={"krylov": list(res.krylov)},
                    first_residual=res.first_residual)
        return True

    def prescribed_start(self, zone: tuple, d0: float, x0: np.ndarray,
                         P_goal: float) -> tuple[float, np.ndarray] | None:
        """(d, state) of the prescribed active set ``zone`` at the load P_goal: one Newton iteration on that set
        from ``x0`` at ``d0`` gives u0; for a fixed active set the small-strain equations are linear in (u, d), so
        the tangent ``t = du/dd`` of that set (the same factorisation) moves it to the d of ``P = P_goal``:
        ``d = d0 + (P_goal - P(u0)) / (dP/dd)``, ``u = u0 + (d - d0) t``. None when the tangent fails (the
        problem's state is then u0). Used from the unloaded state with the Hertz zone (:meth:`hertz_zone_start`)
        and from a coarser mesh's active set and d (:meth:`run_nested`)."""
        pb = self.problem
        pb.d.value = d0
        pb.set_state(x0, self.states[-1].x)
        with pb.prescribed_active_set(zone):
            with pb.max_iterations(1):
                pb.newton()
            u0 = pb.get_state()
            P0 = pb.measure()[0]
            tan = pb.tangent(u0, d0, fixed_set=True)
        self.factored = True
        if tan is None:
            return None
        t_arr, dP = tan
        dd = (P_goal - P0) / dP
        moved = u0.copy()
        moved[:t_arr.size] += dd * t_arr  # the displacement moves; a law's own unknowns (if any) stay
        return d0 + dd, moved

    def correct_force(self) -> None:
        """Correct d at the last level until ``|P - target| <= force_rtol target`` (tangent, then secant)."""
        opts = self.opts
        target = opts.target
        use_tangent = True
        for _ in range(MAX_FORCE_CORRECTIONS):
            miss = abs(self.states[-1].P - target)
            if miss <= opts.force_rtol * target:
                return
            # The tangent is tried for a small miss only (<= 1 %: the step came from the Hertz predictor or a
            # secant); a large one moves the active set by many points and needs the active-set predictor.
            if use_tangent and miss <= 1e-2 * target and self.tangent_correction(target):
                # A tangent state that needed a Newton iteration sits across an active-set change (the factored
                # J is not the one of the converged state), and so will the next one: the secant takes over.
                use_tangent = self.records[-1]["iterations"] == 0 and abs(self.states[-1].P - target) <= 0.1 * miss
            else:
                use_tangent = False
                self.reach(self.secant(target), opts.n_steps, "force-correction")
        raise ContactSolveError(f"{opts.case}: force control did not reach P = {target} N/mm (last P = "
                                f"{self.states[-1].P:.10g}) in {MAX_FORCE_CORRECTIONS} secant corrections")
