"""The linear solver of the contact Newton iterations (and of the Hertz predictor): PETSc options and set-up.

Every Newton iteration of :class:`fem.problem.ContactProblem` solves ``J(u) du = -F(u)`` with the exact
Jacobian ``J = K + C(u)``: ``K`` the elastic stiffness (unchanged between iterations and load steps for small
strain) plus the contact terms ``C(u)`` on Gamma_c, which change only at the quadrature points whose contact
state changes (and, for curved obstacles, smoothly with u). Kinds (``linear_solver`` of ContactOptions):

* ``"lu"`` (default): ``preonly`` + MUMPS LU of every Jacobian (PETSc keeps the symbolic analysis: the pattern
  does not change). ``"auto"`` as the default was measured (``make run`` on a fresh clone, cold caches, 2 cores):
  the concave scenes' cases (displacement control through many recorded steps) took 106 s and 111 s instead of
  58 s and 68 s, the others 0.7-1.4 times their ``"lu"`` time, 9 min 36 s in all against 8 min 30 s; so the
  default stays ``"lu"``.
* ``"lu_reuse"``: FGMRES (``ksp_rtol`` :data:`REUSE_KSP_RTOL`) preconditioned by the MUMPS LU of an EARLIER
  Jacobian (``snes_lag_preconditioner -2`` with ``snes_lag_preconditioner_persists``: the factor outlives the
  SNES solve, so it serves every load step, force correction and tangent). ``K^-1``-like preconditioning of
  a low-rank change needs about one Krylov iteration per changed contact row; when the last Krylov solve needed
  more than :data:`REUSE_MAX_KRYLOV` iterations (or failed), the next Jacobian is factored again
  (:func:`configure`). A Krylov solve that hits ``ksp_max_it`` is not a Newton failure: the Newton step is then
  inexact and the next Jacobian is factored. FGMRES, not GMRES: it preconditions on the right and keeps the
  preconditioned directions, so k Krylov iterations cost k triangular solves (PETSc's GMRES, preconditioned on
  the left, applies the LU once more for the initial residual: an exact factor cost 2 solves instead of 1).
  Measured on the bench's uniform 161k-dof row (one process, warm): 3 triangular solves per contact solve
  against 6, contact solve 1.32 s against 1.41 s.
* ``"gamg"``: GMRES preconditioned by PETSc's smoothed-aggregation algebraic multigrid of an earlier Jacobian
  (kept as for ``lu_reuse``; set up again after a Krylov solve above :data:`GAMG_MAX_KRYLOV` iterations) with the
  plane rigid-body near-nullspace (translations ``(1, 0)``, ``(0, 1)`` and the rotation ``(-y, x)`` about the centroid,
  :func:`rigid_body_modes`); no factorisation, memory ~ linear in the dofs. The Hertz predictor's linear solve
  uses it too. Displacement formulation only (the mixed u-p system is a saddle point).
* ``"auto"``: chosen by the global number of unknowns
  ``ndofs`` (:func:`resolve`): ``"lu_reuse"`` with MUMPS's AMF ordering (``mat_mumps_icntl_7`` =
  :data:`AUTO_MUMPS_ORDERING`) up to :data:`AUTO_GAMG_NDOFS`, ``"gamg"`` above (never for a saddle point, never
  without ``ndofs``); ``"lu"`` with that ordering for a hyperelastic or finite-strain bulk below that size (its
  Jacobian changes everywhere at every Newton iteration: an earlier factor preconditions it poorly). AMF against
  MUMPS's own choice (METIS here), one run each on a loaded 2-core machine, P2 plane elasticity: graded 173k
  dofs (bench mesh h_c = a/2560) analysis 0.086 s against 0.48 s, factor entries 18.6M against 19.6M, numeric
  factorisation 0.34 s both; uniform 161k dofs analysis 0.059 s against 0.46 s, factor entries 29.0M against
  31.4M (QAMD: 37.6M, slower numeric factorisation). A different ordering changes the factors' round-off, so
  ``"auto"`` is a kind of its own: ``"lu"`` and ``"lu_reuse"`` keep MUMPS's default.

PETSc keeps MUMPS's symbolic analysis across Newton iterations and load steps (the Jacobian's nonzero state does
not change: :class:`fem.split_jacobian.SplitJacobian` copies K's values into J): one ``MatLUFactorSymbolic`` per
KSP (measured with PETSc's log events: the SNES's KSP and the Hertz predictor's, 2 per contact solve where the
Hertz predictor runs, 1 with the ``"hertz_zone"`` start, which ``"auto"`` takes where the force-controlled Newton
of :mod:`fem.force_newton` applies), one ``MatLUFactorNumeric`` per Newton iteration (``"lu"``). The
force-controlled Newton solves with the SNES's KSP and its factor (two right-hand sides per factorisation, in one
MatMatSolve).

The converged Newton answer does not depend on the kind (SNES checks the same nonlinear residual tolerances);
the Krylov tolerances are well below the Newton ones.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

import numpy as np
from petsc4py import PETSc

from vocabulary import LINEAR_SOLVERS

__all__ = ["LINEAR_SOLVERS", "AUTO_GAMG_NDOFS", "AUTO_MUMPS_ORDERING", "resolve",
           "REUSE_KSP_RTOL", "REUSE_MAX_KRYLOV", "GAMG_KSP_RTOL", "snes_options",
           "linear_options", "configure", "rigid_body_modes", "set_near_nullspace"]

# auto: GAMG above this many unknowns (global), LU below. Chosen by MEMORY, not time: by time MUMPS LU beat GAMG
# at every size measured (one linear solve, P2, one run each, loaded 2-core machine: GAMG cost 2.0-5.9 LU solves
# on the graded bench meshes 2.6k-173k dofs, 3.2-4.2 on uniform meshes 41k-362k, about 1.5-2 at 642k), but
# the LU's peak memory after one contact solve reached 1.38 GB at 362k uniform dofs and one linear LU solve
# 3.5-4.2 GB at 642k, against the 2 GB budget at 1M dofs (GAMG: 1.7 GB at 1M).
AUTO_GAMG_NDOFS = 400_000
# auto: MUMPS ordering of its LU kind (ICNTL(7) = 2: AMF; MUMPS's default ICNTL(7) = 7 chose METIS here)
AUTO_MUMPS_ORDERING = 2
# lu_reuse: relative Krylov tolerance of a Newton step (the Newton tolerance is snes_rtol 1e-10).
REUSE_KSP_RTOL = 1e-12
# lu_reuse: a Krylov solve that needed more iterations than this factors the next Jacobian again. A MUMPS
# triangular solve costs about 1/6 of a numeric factorisation at 88k P2 dofs (measured 34 ms against 220 ms).
REUSE_MAX_KRYLOV = 12
REUSE_KSP_MAX_IT = 60
# gamg: the multigrid of an earlier Jacobian is kept the same way; set up again after a Krylov solve above this.
GAMG_MAX_KRYLOV = 80
GAMG_KSP_RTOL = 1e-11
GAMG_KSP_MAX_IT = 1000

_MUMPS = {"ksp_type": "preonly", "pc_type": "lu", "pc_factor_mat_solver_type": "mumps"}


def resolve(kind: str, *, ndofs: int | None = None, saddle: bool = False, linear_bulk: bool = True) -> str:
    """The concrete kind (``"lu"``, ``"lu_reuse"`` or ``"gamg"``) of ``kind`` for a system of ``ndofs`` global
    unknowns (``saddle``: the mixed u-p system, no GAMG; ``linear_bulk`` False: a hyperelastic or finite-strain
    bulk, whose Jacobian changes everywhere at every Newton iteration, so an earlier factor is no preconditioner
    and ``"auto"`` factors every Jacobian, ``"lu"``); only ``"auto"`` depends on them (module docstring)."""
    if kind not in LINEAR_SOLVERS:
        raise ValueError(f"linear_solver must be one of {LINEAR_SOLVERS}, got {kind!r}")
    if kind != "auto":
        return kind
    if ndofs is not None and ndofs > AUTO_GAMG_NDOFS and not saddle:
        return "gamg"
    return "lu_reuse" if linear_bulk else "lu"


def _auto_extra(kind: str, concrete: str) -> dict:
    """The options ``"auto"`` adds to its concrete kind: the AMF ordering of its MUMPS LU."""
    return {"mat_mumps_icntl_7": AUTO_MUMPS_ORDERING} if kind == "auto" and concrete != "gamg" else {}


def snes_options(kind: str, *, ndofs: int | None = None, saddle: bool = False, linear_bulk: bool = True) -> dict:
    """PETSc options (without prefix) of the Newton iterations' KSP/PC (and SNES lagging) for ``kind`` (``ndofs``,
    ``saddle``, ``linear_bulk``: :func:`resolve`)."""
    concrete = resolve(kind, ndofs=ndofs, saddle=saddle, linear_bulk=linear_bulk)
    return {**_snes_options(concrete), **_auto_extra(kind, concrete)}


def _snes_options(kind: str) -> dict:
    if kind == "lu":
        return dict(_MUMPS)
    if kind == "lu_reuse":
        return {"ksp_type": "fgmres", "pc_type": "lu", "pc_factor_mat_solver_type": "mumps",
                "ksp_rtol": REUSE_KSP_RTOL, "ksp_atol": 0.0, "ksp_max_it": REUSE_KSP_MAX_IT,
                "ksp_gmres_restart": REUSE_KSP_MAX_IT, "snes_lag_preconditioner": -2,
                "snes_lag_preconditioner_persists": True, "snes_max_linear_solve_fail": 10**6}
    if kind == "gamg":
        return {**_gamg(), "snes_lag_preconditioner": -2, "snes_lag_preconditioner_persists": True,
                "snes_max_linear_solve_fail": 10**6}
    raise ValueError(f"linear_solver must be one of {LINEAR_SOLVERS}, got {kind!r}")


def linear_options(kind: str, *, ndofs: int | None = None) -> dict:
    """PETSc options of a plain linear elastic solve (the Hertz predictor) of ``ndofs`` global unknowns for
    ``kind`` (lu_reuse: LU; auto: :func:`resolve`, with its ordering)."""
    concrete = resolve(kind, ndofs=ndofs)
    return _gamg() if concrete == "gamg" else {**_MUMPS, **_auto_extra(kind, concrete)}


def _gamg() -> dict:
    return {"ksp_type": "gmres", "ksp_rtol": GAMG_KSP_RTOL, "ksp_atol": 0.0, "ksp_max_it": GAMG_KSP_MAX_IT,
            "ksp_gmres_restart": 200, "pc_type": "gamg", "pc_gamg_type": "agg", "pc_gamg_agg_nsmooths": 1,
            "pc_gamg_threshold": 0.01, "pc_gamg_square_graph": 1, "mg_levels_ksp_type": "chebyshev",
            "mg_levels_pc_type": "jacobi", "mg_levels_ksp_max_it": 3}


def rigid_body_modes(A, V) -> list:
    """The plane rigid-body modes of the vector space ``V`` (P_k, 2 components, the row layout of ``A``) as
    orthonormal PETSc vectors: translations along x and y and the rotation ``(-(y - y_c), x - x_c)`` about the
    dofs' centroid."""
    from mpi4py import MPI

    index_map, bs = V.dofmap.index_map, V.dofmap.index_map_bs
    n = index_map.size_local
    x = V.tabulate_dof_coordinates()[:n, :2]
    centre = V.mesh.comm.allreduce(x.sum(axis=0), op=MPI.SUM) / max(index_map.size_global, 1)
    vecs = [A.createVecLeft() for _ in range(3)]
    for k, vec in enumerate(vecs):
        arr = np.zeros((n, bs))
        if k < 2:
            arr[:, k] = 1.0
        else:
            arr[:, 0], arr[:, 1] = -(x[:, 1] - centre[1]), x[:, 0] - centre[0]
        vec.setArray(arr.reshape(-1))
    for i, v in enumerate(vecs):  # modified Gram-Schmidt
        for w in vecs[:i]:
            v.axpy(-v.dot(w), w)
        v.normalize()
    return vecs


def set_near_nullspace(A, V) -> None:
    """Attach the rigid-body modes of ``V`` to the matrix ``A`` as its near-nullspace (for GAMG)."""
    ns = PETSc.NullSpace().create(vectors=rigid_body_modes(A, V), comm=A.comm)
    A.setNearNullSpace(ns)


def configure(snes, A, V, kind: str, *, ndofs: int | None = None, saddle: bool = False,
              linear_bulk: bool = True) -> None:
    """Set-up beyond the options: ``lu_reuse`` refactors adaptively (module docstring); ``gamg`` attaches the
    near-nullspace to the Jacobian matrix ``A`` of the displacement space ``V`` (``auto``: :func:`resolve` with
    ``ndofs``, ``saddle`` and ``linear_bulk``, as for :func:`snes_options`)."""
    kind = resolve(kind, ndofs=ndofs, saddle=saddle, linear_bulk=linear_bulk)
    if kind == "gamg":
        set_near_nullspace(A, V)
        snes.setUpdate(_rebuild_when_slow(GAMG_MAX_KRYLOV))
    elif kind == "lu_reuse":
        snes.setUpdate(_rebuild_when_slow(REUSE_MAX_KRYLOV))


def _rebuild_when_slow(max_krylov: int):
    """SNES update hook (before every Newton step): set the preconditioner up again (a new factorisation or
    multigrid) at the next Jacobian when the last Krylov solve of this problem needed more than ``max_krylov``
    iterations or did not converge."""

    def update(snes, it: int) -> None:
        ksp = snes.getKSP()
        if ksp.getConvergedReason() < 0 or ksp.getIterationNumber() > max_krylov:
            ksp.getPC().reset()  # the next KSPSetOperators of this Newton step sets it up again

    return update
