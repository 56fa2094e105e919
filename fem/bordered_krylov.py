"""One Krylov solve of the force-controlled Newton step: the Jacobian bordered by the load row and column.

The step of :mod:`fem.force_newton` for (du, dd) is the bordered system::

    [ J    g ] [du]   [r_u]        g = dF/dd (N/mm),  p = dP/du (N/mm per mm),
    [ p^T  0 ] [dd] = [r_d]        r_u = -F (N),      r_d = P_goal - P(u) (N/mm).

With a multigrid preconditioner (``gamg``) two separate solves (``J z = r_u``, ``J w = g``) cost two Krylov solves of
about 30 iterations each (measured on the bench's 642k-dof uniform mesh: 29 and 29). Here the bordered system is
solved once, by GMRES, preconditioned by the block factorisation with ``M ~ J^-1`` (the Newton KSP's own
preconditioner, one application per iteration)::

    a = M r_u,   y_d = (p . a - r_d) / sigma,   y_u = a - y_d w_M,      w_M = M g,  sigma = p . w_M,

which is ``B^-1`` exactly when ``M = J^-1`` (then ``B y = r``). ``w_M`` and ``sigma`` cost one more application
per Newton iteration. GMRES preconditioned on the right tests the true residual of the bordered system (the
preconditioner is a fixed linear operator: GAMG's Chebyshev/Jacobi cycles; FGMRES would store two vectors per
iteration instead of one, 0.45 GB more at 1M dofs), whose load
row is in N/mm against N in the others: both are forces of the model (the load P is a few thousandths of ``||F||``
at the start), so one Euclidean norm serves.

Layout: a bordered vector holds the process's owned displacement dofs, then, on process 0 only, dd.
"""

from __future__ import annotations

import numpy as np
from petsc4py import PETSc

__all__ = ["BorderedSystem"]


class BorderedSystem:
    """The bordered operator, its block preconditioner and the GMRES that solves it.

    Args:
        A: the Jacobian J (assembled; its row layout is the displacement's).
        pc: the preconditioner ``M`` of J (set up by the caller).
        rtol, max_it: GMRES's relative tolerance and iteration limit (also its restart).
    """

    def __init__(self, *, A, pc, rtol: float, max_it: int):
        self.A, self.pc = A, pc
        comm = A.getComm()
        self.rank = comm.getRank()
        self.n = A.getLocalSize()[0]
        n_b = self.n + (1 if self.rank == 0 else 0)
        self.ua, self.ub = A.createVecs()
        self.g, self.p, self.w_M = A.createVecLeft(), A.createVecLeft(), A.createVecLeft()
        self.sigma = 1.0
        op = PETSc.Mat().createPython(((n_b, PETSc.DECIDE), (n_b, PETSc.DECIDE)), context=_Operator(self), comm=comm)
        op.setUp()
        self.rhs, self.sol = op.createVecs()
        self.ksp = PETSc.KSP().create(comm)
        self.ksp.setType("gmres")
        self.ksp.setPCSide(PETSc.PC.Side.RIGHT)  # the true residual's norm; one stored vector per iteration
        self.ksp.setOperators(op)
        self.ksp.getPC().setType("python")
        self.ksp.getPC().setPythonContext(_Preconditioner(self))
        self.ksp.setTolerances(rtol=rtol, atol=0.0, max_it=max_it)
        self.ksp.setGMRESRestart(max_it)
        self.op = op

    def _dd(self, arr: np.ndarray) -> float:
        """The load parameter entry of a bordered array (process 0's last), on every process."""
        return self.A.getComm().tompi4py().bcast(float(arr[-1]) if self.rank == 0 else None, root=0)

    def apply_operator(self, x, y) -> None:
        """``y = B x``."""
        xa = x.getArray(readonly=True)
        self.ua.getArray()[:] = xa[:self.n]
        dd = self._dd(xa)
        self.A.mult(self.ua, self.ub)
        self.ub.axpy(dd, self.g)
        row = self.p.dot(self.ua)
        ya = y.getArray()
        ya[:self.n] = self.ub.getArray(readonly=True)
        if self.rank == 0:
            ya[-1] = row

    def apply_preconditioner(self, x, y) -> None:
        """``y = P^-1 x``, the block factorisation with M (module docstring)."""
        xa = x.getArray(readonly=True)
        self.ua.getArray()[:] = xa[:self.n]
        r_d = self._dd(xa)
        self.pc.apply(self.ua, self.ub)
        y_d = (self.p.dot(self.ub) - r_d) / self.sigma
        self.ub.axpy(-y_d, self.w_M)
        ya = y.getArray()
        ya[:self.n] = self.ub.getArray(readonly=True)
        if self.rank == 0:
            ya[-1] = y_d

    def solve(self, *, r_u, r_d: float, g, p, atol: float, g_scale: float = 1.0) -> tuple[int, float]:
        """Solve the bordered system for ``r_u`` (PETSc vector, displacement layout) and ``r_d`` with the border
        ``g_scale g``, ``p`` (copied), the Krylov solve to the residual norm ``atol`` (or the relative tolerance);
        the displacement part of the solution is left in ``r_u``. Returns (Krylov iterations, -1 on failure;
        dd)."""
        g.copy(self.g)
        self.g.scale(g_scale)
        p.copy(self.p)
        self.pc.apply(self.g, self.w_M)
        self.sigma = self.p.dot(self.w_M)
        if not (np.isfinite(self.sigma) and self.sigma != 0.0):
            return -1, 0.0
        ra = self.rhs.getArray()
        ra[:self.n] = r_u.getArray(readonly=True)
        if self.rank == 0:
            ra[-1] = r_d
        self.sol.set(0.0)
        self.ksp.setTolerances(atol=atol)
        self.ksp.solve(self.rhs, self.sol)
        sa = self.sol.getArray(readonly=True)
        r_u.getArray()[:self.n] = sa[:self.n]
        its = self.ksp.getIterationNumber() if self.ksp.getConvergedReason() > 0 else -1
        return its, self._dd(sa)

    def destroy(self) -> None:
        for obj in (self.ksp, self.op, self.rhs, self.sol, self.ua, self.ub, self.g, self.p, self.w_M):
            obj.destroy()


class _Operator:
    """petsc4py Python context of the bordered matrix."""

    def __init__(self, system: BorderedSystem):
        self.system = system

    def mult(self, mat, x, y) -> None:
        self.system.apply_operator(x, y)


class _Preconditioner:
    """petsc4py Python context of the block preconditioner."""

    def __init__(self, system: BorderedSystem):
        self.system = system

    def apply(self, pc, x, y) -> None:
        self.system.apply_preconditioner(x, y)
