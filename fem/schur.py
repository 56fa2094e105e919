"""Exact condensation of a matrix onto some of its unknowns: the Schur complement MUMPS computes while it factors.

For a symmetric positive definite stiffness ``A`` split into kept unknowns ``c`` (e.g. the dofs of the cells on
the contact surface) and the rest ``i``, ``S = A_cc - A_ci A_ii^-1 A_ic`` (dense, ``n_c x n_c``, units of A). A
contact law acting on ``c`` only could then be iterated on ``S`` alone, with one sparse factorisation per
contact solve (issue 38, item 3). :func:`schur_complement` measures what that costs: the factorisation with
the Schur unknowns ordered last, the extraction of the dense ``S`` and its dense LU.

petsc4py 3.25 wraps neither ``MatFactorSetSchurIS`` nor ``MatFactorCreateSchurComplement``; both are called
through ctypes on the libpetsc this process has loaded. One MPI process only (MUMPS's Schur complement is
centralised on the host; the bench measures serially).
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before petsc4py)

import ctypes
import time
from typing import NamedTuple

import numpy as np
from petsc4py import PETSc

__all__ = ["SchurFactor", "schur_complement"]


class SchurFactor(NamedTuple):
    """The dense Schur complement ``S`` (``n x n``, row and column k = ``rows[k]``) and what it cost (s):
    ``factor_s`` the sparse LU with the Schur unknowns last (symbolic + numeric), ``extract_s`` the dense ``S``
    out of MUMPS, ``dense_lu_s`` the LU of ``S`` (LAPACK through scipy)."""

    S: np.ndarray
    factor_s: float
    extract_s: float
    dense_lu_s: float


def _libpetsc() -> ctypes.CDLL:
    """The libpetsc this process has loaded (the one petsc4py uses), from /proc/self/maps."""
    with open("/proc/self/maps") as fh:
        paths = {line.split()[-1] for line in fh if "libpetsc.so" in line}
    if len(paths) != 1:
        raise RuntimeError(f"expected one loaded libpetsc, found {sorted(paths)}")
    return ctypes.CDLL(paths.pop())


def schur_complement(A: PETSc.Mat, rows: np.ndarray) -> SchurFactor:
    """Factor ``A`` (assembled, one process) with MUMPS, the global ``rows`` as Schur unknowns, and return the
    dense Schur complement with the cost of each part (:class:`SchurFactor`). ValueError: more than one process,
    or ``rows`` empty, repeated or outside A."""
    import scipy.linalg

    if A.comm.getSize() != 1:
        raise ValueError("schur_complement runs on one MPI process only")
    rows = np.asarray(rows, dtype=PETSc.IntType)
    n = A.getSize()[0]
    if rows.size == 0 or np.unique(rows).size != rows.size or rows.min() < 0 or rows.max() >= n:
        raise ValueError(f"rows must be distinct indices in [0, {n}), got {rows.size} of them")
    lib = _libpetsc()
    ksp = PETSc.KSP().create(A.comm)
    iset = PETSc.IS().createGeneral(np.sort(rows), comm=A.comm)
    S = ctypes.c_void_p()
    try:
        ksp.setOperators(A)
        ksp.setType("preonly")
        pc = ksp.getPC()
        pc.setType("lu")
        pc.setFactorSolverType("mumps")
        t0 = time.perf_counter()
        pc.setFactorSetUpSolverType()
        F = pc.getFactorMatrix()
        if lib.MatFactorSetSchurIS(ctypes.c_void_p(F.handle), ctypes.c_void_p(iset.handle)) != 0:
            raise RuntimeError("MatFactorSetSchurIS failed")
        pc.setUp()
        t1 = time.perf_counter()
        status = ctypes.c_int()
        if lib.MatFactorCreateSchurComplement(ctypes.c_void_p(F.handle), ctypes.byref(S), ctypes.byref(status)) != 0:
            raise RuntimeError("MatFactorCreateSchurComplement failed")
        m, k = ctypes.c_int(), ctypes.c_int()  # PetscInt is 32-bit in this PETSc build (checked below)
        lib.MatGetSize(S, ctypes.byref(m), ctypes.byref(k))
        if (m.value, k.value) != (rows.size, rows.size):
            raise RuntimeError(f"Schur complement of size {m.value} x {k.value}, expected {rows.size}")
        ptr = ctypes.POINTER(ctypes.c_double)()
        if lib.MatDenseGetArrayRead(S, ctypes.byref(ptr)) != 0:
            raise RuntimeError("MatDenseGetArrayRead failed")
        dense = np.ctypeslib.as_array(ptr, shape=(k.value, m.value)).T.copy()  # column-major storage
        lib.MatDenseRestoreArrayRead(S, ctypes.byref(ptr))
        t2 = time.perf_counter()
        scipy.linalg.lu_factor(dense, check_finite=False)
        t3 = time.perf_counter()
    finally:
        if S.value:
            lib.MatDestroy(ctypes.byref(S))
        iset.destroy()
        ksp.destroy()
    return SchurFactor(S=dense, factor_s=t1 - t0, extract_s=t2 - t1, dense_lu_s=t3 - t2)
