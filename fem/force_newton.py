"""Force-controlled semismooth Newton: the load parameter d is an unknown of every Newton iteration (issue 38).

Force control used to be a solve at a guessed d, then corrections of d along the tangent ``du/dd`` of the
converged state, each a Newton solve of its own: a contact solve from a prescribed active set cost a Newton
iteration on that set, its tangent, the true law's Newton iteration, a second tangent and its Newton iteration
(11 triangular solves and 3 Jacobians on the bench's graded 88k-dof mesh). Here the force constraint is part of
every Newton step.

Small-strain frictionless contact with a linear bulk (the displacement formulation, a method without an outer
loop: :attr:`fem.problem.ContactProblem.tangent_applies`): on a fixed active set the residual ``F(u, d)`` is
affine in (u, d) and the load ``P(u)`` (N/mm, :meth:`fem.problem.ContactProblem.measure`) is linear in u. The
bordered Newton step for (u, d) under ``P(u) = P_goal``::

    J du + F_d dd = -F,        P(u + du) = P_goal

is two solves with the same Jacobian ``J`` (N/mm per mm): ``J z = -F``, ``J w = -F_d`` (``F_d = dF/dd`` a forward
difference of the residual in d, exact on the fixed set: ``ContactProblem.load_derivative_into``), then
``dd = (P_goal - P(u + z)) / P(w)`` and ``du = z + dd w``. The first iteration holds the prescribed active set
(``zone``: the coarse mesh's contact runs of a nested start, or the Hertz zone), the later ones the true law's set
at the iterate (semismooth Newton). On a prescribed set the first step lands on that set's solution at
``P = P_goal`` exactly; when the true law's set at that state is the same, the residual is zero up to the linear
solver's round-off and the solve is done after ONE Jacobian. Otherwise each further iteration changes the set
at its edge points.

Linear solver: the first Jacobian is factored (or, GAMG, set up); a later iteration's Jacobian differs from it by
the contact rows of the points that changed state, so with ``lu_reuse`` / ``gamg`` (:mod:`fem.linear_solver`)
the two solves run preconditioned by the first factor (FGMRES / GMRES, ``w`` started from the last ``w``) and
the factor is rebuilt only when a Krylov solve fails or needs more than the kind's limit. ``lu`` factors every
Jacobian. With a new factor, z and w are one solve with it (two right-hand sides: the factor is read once,
:meth:`ForceNewton._factored_pair`).

Convergence: the true law's residual ``||F(u, d)||`` (l2, N) at most ``snes_atol``, or ``snes_rtol`` times its
value at the start (as the SNES tests) after one refinement step: the same J and tangent, one more triangular
solve (with a factor; with ``gamg`` one more bordered Krylov solve). The step on the right active set normally
meets ``snes_atol`` itself: with a factor the triangular solves are exact to round-off, and the bordered Krylov
solve goes to half ``snes_atol`` (``BORDERED_ATOL_FRACTION``). What used to stop it above ``snes_atol`` was the
round-off of ``dF/dd`` (its step was ``1e-6 |d|`` everywhere): on the bench's 161k-dof uniform mesh from the Hertz
zone the step left 9e-6 N against a linear residual of 1e-7 N, and a refinement solve (9 more GMRES iterations,
or one more triangular solve) took it below ``snes_atol`` = 2.1e-7 N; with the difference's step ``|d|`` on the
prescribed set the step leaves 5.7e-8 N (GAMG) and 9.5e-10 N (LU). Stopping at ``snes_rtol`` instead let the peak
pressure differ from the load-stepped path's by 1.4e-8 (the Hertz scene of ``tests/test_fem_linear_solver.py``).
The load then equals ``P_goal`` to round-off (the last step solved for it).
The converged state is exactly what the SNES would accept; the stepper records it without another SNES solve.
"""

from __future__ import annotations

from contextlib import nullcontext
from typing import NamedTuple

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

__all__ = ["ForceNewton", "ForceNewtonResult", "CHORD_STEPS"]

# The iterations after the first keep the first one's tangent w (a chord in d) for this many iterations: no second
# right-hand side, no dF/dd. The residual this leaves is dd (J_k - J_0) w, an active-set change times the small
# d correction of a late iteration. Later iterations solve for w again (full Newton in (u, d)). Measured: the
# bench's graded 173k-dof mesh nested from h x 16 converges after one chord step ([2] iterations); the nested
# test of tests/test_nested_start.py (h x 8 at a/32) leaves 4.97 -> 0.0147 -> 4.3e-5 N through two chord steps
# (tolerance 3.3e-5 N, a linear rate of 3e-3) and then needs a full step: 2 chord steps made it 4 iterations, 1
# makes it 3.
CHORD_STEPS = 1
# The bordered Krylov solve (gamg) of every step goes to this fraction of snes_atol, below the Newton tolerance: a
# step on the right active set is then the last one (no refinement solve, which restarts GMRES: measured at 161k
# dofs, 28 iterations to 1e-11 of the start's residual and 9 more in the refinement). A step that changes the set
# pays the few iterations below the Newton tolerance for nothing.
BORDERED_ATOL_FRACTION = 0.5
# ... or to this fraction of its right-hand side, whichever it meets first: a floor above GMRES's round-off
# stagnation, so a snes_atol below what double precision can reach ends in the refinement step, not in 1000 stored
# Krylov vectors (restart = max_it). Half snes_atol is 5.6e-13 and 3.5e-13 of the first residual on the bench's
# uniform 161k- and 1M-dof meshes (32 GMRES iterations each).
BORDERED_RTOL = 1e-13
# The solve of z stops at this fraction of the Newton tolerance max(snes_atol, snes_rtol ||F_0||) (besides the
# kind's own relative tolerance): a late step's right-hand side is already near it.
KRYLOV_FRACTION = 0.1


class ForceNewtonResult(NamedTuple):
    """Outcome of :meth:`ForceNewton.solve`.

    Attributes:
        converged: the residual met the tolerances within ``max_it`` iterations.
        iterations: Newton iterations (Jacobians assembled).
        d: the load parameter of the last iterate (mm).
        first_residual: ``||F||`` of the true law at the start (N), the reference of ``snes_rtol``.
        residual: ``||F||`` of the true law at the last iterate (N).
        krylov: Krylov iterations of each solve (z, then w when the iteration solves for it; 1 each with a fresh
            factor).
    """

    converged: bool
    iterations: int
    d: float
    first_residual: float
    residual: float
    krylov: tuple[int, ...]


class ForceNewton:
    """The force-controlled Newton of a :class:`fem.problem.ContactProblem` (module docstring): uses its SNES's
    residual and Jacobian callbacks and its KSP, its ``d``, ``measure``, state and ``prescribed_active_set``.

    Args:
        problem: the contact problem (``tangent_applies`` must hold).
        reuse: later Jacobians are solved with the first one's preconditioner (``lu_reuse``, ``gamg``);
            False: every Jacobian is factored (``lu``).
        bordered: each step is one Krylov solve of the bordered system (:mod:`fem.bordered_krylov`; ``gamg``)
            instead of two solves with J (a factor: one two-column triangular solve, the cheaper).
        max_krylov: with ``reuse``, a Krylov solve above this many iterations rebuilds the preconditioner at the
            next Jacobian.
    """

    def __init__(self, problem, *, reuse: bool, max_krylov: int, bordered: bool = False):
        self.problem = problem
        self.reuse = reuse
        self.max_krylov = max_krylov
        self.bordered = bordered
        self._system = None  # fem.bordered_krylov.BorderedSystem, built at its first use
        self._columns = None  # the dense right-hand sides and solutions of _factored_pair, built at its first use
        self._w_arr, self._P_w = None, 1.0  # the last tangent w = du/dd (array) and its load dP/dd (N/mm per mm)
        pb = problem.problem  # dolfinx's NonlinearProblem: its x, b (residual), A (Jacobian)
        self.x, self.b, self.A = pb.x, pb.b, pb.A
        self.P_mat = pb.P_mat if getattr(pb, "P_mat", None) is not None else pb.A

    # -- pieces --------------------------------------------------------------------------------------------
    def _residual(self, out) -> float:
        """``F`` at the current x and d into ``out``; its l2 norm."""
        self.problem.residual_into(out)
        return out.norm()

    def _linear_solve(self, rhs, sol, *, fresh: bool, guess: bool, atol: float = 0.0) -> int:
        """``J sol = rhs`` with the KSP (``fresh``: a new factor of the current J, else the kept one; ``guess``:
        ``sol`` is the initial guess, a Krylov kind only; ``atol``: the Krylov solve may stop at this residual
        norm, where its norm is the residual's: FGMRES, not GMRES's preconditioned one). Returns the Krylov
        iterations (-1: failed)."""
        ksp = self.problem.snes.getKSP()
        ksp.setOperators(self.A, self.P_mat)
        ksp.getPC().setReusePreconditioner(not fresh)
        ksp.setInitialGuessNonzero(guess and self.reuse)
        rtol, atol0, divtol, max_it = ksp.getTolerances()
        if ksp.getNormType() == PETSc.KSP.NormType.UNPRECONDITIONED:  # FGMRES: the residual itself (N)
            ksp.setTolerances(atol=atol)
        try:
            ksp.solve(rhs, sol)
        finally:
            ksp.setInitialGuessNonzero(False)
            ksp.setTolerances(rtol=rtol, atol=atol0, divtol=divtol, max_it=max_it)
        return ksp.getIterationNumber() if ksp.getConvergedReason() > 0 else -1

    def _factored_pair(self, F, Fd, z, w) -> tuple[int, int]:
        """``J z = F`` and ``J w = Fd`` with a new factor of the current J, both right-hand sides in ONE solve with
        the factor (MUMPS's MatMatSolve of a two-column dense matrix: the factor, 150 MB at 173k P2 dofs, is read
        once; measured 0.054-0.063 s against 0.096-0.103 s for two MatSolves on the bench's graded 173k-dof mesh,
        the same numbers to the last bit). With an exact factor a Krylov solve would take one iteration and land
        on the same vector, so the KSP is only set up (the factorisation), not run: (1, 1), or (-1, -1) when the
        factorisation failed on any process."""
        ksp = self.problem.snes.getKSP()
        ksp.setOperators(self.A, self.P_mat)
        pc = ksp.getPC()
        pc.setReusePreconditioner(False)
        ksp.setUp()
        if self.x.comm.tompi4py().allreduce(int(pc.getFailedReason()), op=MPI.MAX) != 0:
            return -1, -1
        if self._columns is None:
            size = ((F.getLocalSize(), F.getSize()), (PETSc.DECIDE, 2))
            self._columns = tuple(PETSc.Mat().createDense(size, comm=F.comm) for _ in range(2))
            for M in self._columns:
                M.setUp()
        B, X = self._columns
        rhs = B.getDenseArray()
        rhs[:, 0], rhs[:, 1] = F.getArray(readonly=True), Fd.getArray(readonly=True)
        B.assemble()
        pc.matApply(B, X)
        ksp.viewFromOptions("-ksp_view")  # what KSPSolve prints at its end (-<prefix>ksp_view), as if it had run
        sol = X.getDenseArray(readonly=True)
        z.getArray()[:], w.getArray()[:] = sol[:, 0], sol[:, 1]
        return 1, 1

    def _pair(self, F, Fd, z, w, *, fresh: bool, w_guess: bool, atol: float) -> tuple[int, ...]:
        """The step's solves ``J z = F`` (to the residual ``atol``) and, unless ``Fd`` is None, ``J w = Fd`` (the
        right-hand sides already signed): z from 0, w from the last w (``w_guess``; else from 0) with the factor
        z's solve used; with a new factor both in one solve (:meth:`_factored_pair`). Krylov iterations of each
        (-1: failed)."""
        if fresh and Fd is not None:
            return self._factored_pair(F, Fd, z, w)
        z.set(0.0)
        n_z = self._linear_solve(F, z, fresh=fresh, guess=False, atol=atol)
        if Fd is None:
            return (n_z,)
        if not w_guess:
            w.set(0.0)
        return n_z, (self._linear_solve(Fd, w, fresh=False, guess=w_guess) if n_z >= 0 else -1)

    def _measure_field(self, arr: np.ndarray) -> float:
        """The load of the displacement field ``arr`` (P is linear in u): N/mm."""
        self.problem.set_state(arr)
        return float(self.problem.measure()[0])

    def _two_solve_step(self, F, Fd, z, w, P_goal, state, *, fresh, new_tangent, its, atol):
        """The step from the solves ``J z = -F`` and (``new_tangent``) ``J w = -dF/dd``, else the last w (a chord):
        (Krylov counts, du array or None on failure, dd)."""
        pb = self.problem
        F.scale(-1.0)
        rhs_d = Fd if new_tangent else None
        counts = last = self._pair(F, rhs_d, z, w, fresh=fresh or not self.reuse, w_guess=its > 0, atol=atol)
        if min(last) < 0 and not fresh and self.reuse:  # the kept factor failed: a new one
            last = self._pair(F, rhs_d, z, w, fresh=True, w_guess=False, atol=atol)
            counts += last
        if min(last) < 0:
            return counts, None, 0.0
        z_arr = pb.displacement_of(z)
        if new_tangent:
            self._w_arr = pb.displacement_of(w)
            self._P_w = self._measure_field(self._w_arr)
            if not (np.isfinite(self._P_w) and self._P_w > 0):
                return counts, None, 0.0
        dd = (P_goal - self._measure_field(state + z_arr)) / self._P_w
        return counts, z_arr + dd * self._w_arr, dd

    def _bordered_step(self, F, Fd, P_goal, *, fresh, atol):
        """The step as one Krylov solve of the bordered system (:mod:`fem.bordered_krylov`), preconditioned by the
        Newton KSP's preconditioner of J (set up again when ``fresh``): (Krylov counts, du array or None, dd)."""
        from fem.bordered_krylov import BorderedSystem
        from fem.linear_solver import GAMG_KSP_MAX_IT

        pb = self.problem
        P_now = float(pb.measure()[0])
        ksp = pb.snes.getKSP()
        ksp.setOperators(self.A, self.P_mat)
        ksp.getPC().setReusePreconditioner(not fresh)
        ksp.setUp()
        if self._system is None:
            self._system = BorderedSystem(A=self.A, pc=ksp.getPC(), rtol=BORDERED_RTOL, max_it=GAMG_KSP_MAX_IT)
        p = self.x.duplicate()
        try:
            pb.load_gradient(p)
            F.scale(-1.0)
            its, dd = self._system.solve(r_u=F, r_d=P_goal - P_now, g=Fd, g_scale=-1.0, p=p, atol=atol)
        finally:
            p.destroy()
        if its < 0:
            return (its,), None, 0.0
        return (its,), pb.displacement_of(F), dd

    # -- the solve ------------------------------------------------------------------------------------------
    def solve(self, *, P_goal: float, d0: float, x0: np.ndarray, zone: tuple | None,
              max_it: int) -> ForceNewtonResult:
        """Newton iterations for (u, d) at the load ``P_goal`` (N/mm) from the displacement ``x0`` at ``d0`` (mm),
        the first on the prescribed active set ``zone`` (None: the true law throughout). The problem holds the last
        iterate afterwards (u and d)."""
        pb = self.problem
        snes = pb.snes
        rtol, atol, _, _ = snes.getTolerances()
        F, Fd = self.b.duplicate(), self.b.duplicate()
        z, w = self.x.duplicate(), self.x.duplicate()
        krylov: list[int] = []
        state, d = np.array(x0[:pb.n_u], dtype=float), float(d0)
        try:
            pb.d.value = d
            pb.load_solver_state(state)
            with pb.prescribed_active_set(zone) if zone is not None else nullcontext():
                first = self._residual(F)
            tol = max(atol, rtol * first)
            norm, its = first, 0
            fresh, refine = True, False
            while its < max_it:
                prescribed = zone is not None and its == 0
                new_tangent = (its == 0 or its > CHORD_STEPS or self.bordered) and not refine
                with pb.prescribed_active_set(zone) if prescribed else nullcontext():
                    if not refine:
                        snes.computeJacobian(self.x, self.A, self.P_mat)
                    if new_tangent:
                        pb.load_derivative_into(Fd, d=d, F=F, fixed_set=prescribed)
                    if self.bordered:
                        counts, du, dd = self._bordered_step(F, Fd, P_goal, fresh=fresh and not refine,
                                                             atol=BORDERED_ATOL_FRACTION * atol)
                    else:
                        counts, du, dd = self._two_solve_step(F, Fd, z, w, P_goal, state, fresh=fresh,
                                                              new_tangent=new_tangent, its=its,
                                                              atol=KRYLOV_FRACTION * (atol if refine else tol))
                    krylov += counts
                    if du is None:
                        break
                    fresh = self.reuse and max(counts) > self.max_krylov
                    its += 0 if refine else 1
                    state = state + du
                    d += dd
                pb.d.value = d
                pb.load_solver_state(state)
                norm = self._residual(F)
                if norm <= atol or (norm <= tol and refine):
                    return ForceNewtonResult(True, its, d, first, norm, tuple(krylov))
                # converged (snes_rtol) but above snes_atol: one refinement with the J and tangent held (a
                # triangular solve), so the answer does not depend on how far its start was
                refine = norm <= tol
            return ForceNewtonResult(False, its, d, first, norm, tuple(krylov))
        finally:
            pb.snes.getKSP().getPC().setReusePreconditioner(False)
            for vec in (F, Fd, z, w):
                vec.destroy()
            if self._system is not None:
                self._system.destroy()
                self._system = None
            for M in self._columns or ():
                M.destroy()
            self._columns = None


