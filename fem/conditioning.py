"""Condition-number estimate of the contact Jacobian at a converged state (serial, small meshes).

The Jacobian ``J = dF/du`` of :mod:`fem.contact_forms` is assembled at the solution of a
:class:`fem.solver.ContactResult` (displacement formulation), converted to ``scipy.sparse``, and the
Dirichlet-constrained dofs are removed (their unit diagonal rows would mix units with the ~E entries).
The 1-norm condition number ``kappa_1 = ||J||_1 ||J^-1||_1`` is estimated with Hager-Higham
(:func:`scipy.sparse.linalg.onenormest`; ``J^-1`` applied through a sparse LU), for ``J`` and for the elastic
stiffness ``K`` alone (same mesh, same supports), so ``kappa_1(J) / kappa_1(K)`` isolates what the contact
terms (penalty kappa or Nitsche gamma) add. The estimate is a lower bound, usually within a factor 3.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

from typing import NamedTuple

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
import ufl

from fem.elasticity import sigma

__all__ = ["ConditionEstimate", "jacobian_condition", "condition_1norm"]


class ConditionEstimate(NamedTuple):
    """1-norm condition estimates (dimensionless) of the free-dof Jacobian and of the elastic stiffness."""

    cond_jacobian: float
    cond_elastic: float
    ratio: float
    n_free: int


def _to_scipy(A) -> sp.csr_matrix:
    indptr, indices, data = A.getValuesCSR()
    return sp.csr_matrix((data, indices, indptr), shape=A.getSize())


def condition_1norm(A: sp.spmatrix) -> float:
    """Hager-Higham estimate of ``||A||_1 ||A^-1||_1`` (sparse LU for the inverse)."""
    A = sp.csc_matrix(A)
    lu = spla.splu(A)
    inv = spla.LinearOperator(A.shape, matvec=lu.solve, rmatvec=lambda x: lu.solve(x, trans="T"),
                              dtype=A.dtype)
    return float(spla.onenormest(A) * spla.onenormest(inv))


def jacobian_condition(result, mesh_data) -> ConditionEstimate:
    """Condition estimate of the contact Jacobian at ``result``'s converged state (serial only).

    Args:
        result: a :class:`fem.solver.ContactResult` with the displacement formulation.
        mesh_data: the ``MeshData`` it was solved on (for the support facets).

    Raises:
        ValueError: mixed formulation or more than one MPI process.
    """
    u = result.u
    V = u.function_space
    mesh = V.mesh
    if mesh.comm.size != 1:
        raise ValueError(f"jacobian_condition runs on one MPI process, got {mesh.comm.size}")
    if result.forms.J is None:
        raise ValueError("jacobian_condition needs the displacement formulation (forms.J is None for 'mixed')")
    fdim = mesh.topology.dim - 1
    fixed = []
    for name, kind in result.options["supports"].items():
        comps = {"clamped": (0, 1), "roller_x": (0,), "roller_y": (1,), "free": ()}[kind]
        facets = mesh_data.facet_tags.find(mesh_data.physical_groups[name].tag)
        for c in comps:
            Vc, _ = V.sub(c).collapse()
            fixed.append(dolfinx.fem.locate_dofs_topological((V.sub(c), Vc), fdim, facets)[0])
    fixed = np.unique(np.concatenate(fixed)) if fixed else np.zeros(0, dtype=np.int32)
    free = np.setdiff1d(np.arange(V.dofmap.index_map.size_local * 2), fixed)

    def cond(form):
        A = dolfinx.fem.petsc.assemble_matrix(dolfinx.fem.form(form))
        A.assemble()
        M = _to_scipy(A)[free][:, free]
        A.destroy()
        return condition_1norm(M)

    v, du = ufl.TestFunction(V), ufl.TrialFunction(V)
    cj = cond(result.forms.J)
    ck = cond(ufl.inner(sigma(du, result.lame), ufl.grad(v)) * ufl.dx)
    return ConditionEstimate(cond_jacobian=cj, cond_elastic=ck, ratio=cj / ck, n_free=int(free.size))
