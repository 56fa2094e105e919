"""The Newton Jacobian as the elastic stiffness, assembled once, plus the contact terms, assembled per iteration.

Displacement formulation (small strain): the Jacobian of ``F(u; v) = int sigma(u) : grad v dx + F_c(u; v)`` is
``J(u) = K + J_c(u)`` with the constant stiffness ``K = int sigma(du) : grad v dx`` (N/mm^2 per unit thickness:
the bilinear form is linear in du and v) and ``J_c = dF_c/du [du]``, an integral over the contact boundary only
(:mod:`fem.contact_forms`). :class:`SplitJacobian` assembles K once (Dirichlet rows and columns zero, 1 on their
diagonal, exactly as dolfinx assembles J) into a matrix of J's sparsity pattern; each Newton iteration copies K
into J (same pattern: a copy of the values) and adds J_c over the contact facets (Dirichlet rows and columns
zero, nothing on their diagonal). The result is J to round-off (the sums are ordered differently); only the
cost changes: one bulk assembly per problem instead of one per Newton iteration.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

import dolfinx
import dolfinx.fem.petsc
import ufl
from dolfinx.cpp.fem.petsc import assemble_matrix as _cpp_assemble_matrix
from dolfinx.fem.assemble import pack_coefficients, pack_constants
from petsc4py import PETSc

__all__ = ["SplitJacobian"]


class SplitJacobian:
    """SNES Jacobian callback ``J = K + J_c(u)`` (module docstring) for the displacement Function ``u``.

    Args:
        u: displacement Function (the SNES unknown).
        K_form, Jc_form: the compiled stiffness and contact Jacobian (:meth:`ufl_forms`).
        J_form: the compiled full Jacobian form (its sparsity pattern is the matrix's).
        bcs: Dirichlet conditions.
    """

    @staticmethod
    def ufl_forms(*, u, bulk_residual, contact_residual) -> dict:
        """The UFL ``K`` (``bulk_residual``: ``int sigma(u) : grad v dx``, linear in u) and ``J_c``
        (``contact_residual``: ``F_c(u; v)``, contact boundary integrals only), to compile with the problem's
        other forms (:mod:`fem.compiled_forms`)."""
        du = ufl.TrialFunction(u.function_space)
        return {"K": ufl.derivative(bulk_residual, u, du), "Jc": ufl.derivative(contact_residual, u, du)}

    def __init__(self, *, u, K_form, Jc_form, J_form, bcs):
        self.u, self.bcs = u, bcs
        self.K_form, self.Jc_form = K_form, Jc_form
        self.K = dolfinx.fem.petsc.create_matrix(J_form)
        self.J_form = J_form
        self._assembled = False
        self._structure = None

    def _assemble_K(self) -> None:
        self.K.zeroEntries()
        dolfinx.fem.petsc.assemble_matrix(self.K, self.K_form, bcs=self.bcs, diag=1.0)
        self.K.assemble()
        self._assembled = True

    def __call__(self, snes, x, J, P) -> None:
        """Assemble ``J = K + J_c(u(x))`` (SNES Jacobian callback signature)."""
        x.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)
        dolfinx.fem.petsc.assign(x, self.u)
        if not self._assembled:
            self._assemble_K()
        if not self._structure:  # the first J the usual way: it fixes J's nonzero pattern
            J.zeroEntries()
            dolfinx.fem.petsc.assemble_matrix(J, self.J_form, bcs=self.bcs, diag=1.0)
            J.assemble()
            info = PETSc.Mat.InfoType.GLOBAL_SUM  # the same decision on every rank
            same = J.getInfo(info)["nz_used"] == self.K.getInfo(info)["nz_used"]
            self._structure = (PETSc.Mat.Structure.SAME_NONZERO_PATTERN if same
                               else PETSc.Mat.Structure.SUBSET_NONZERO_PATTERN)
            return
        self.K.copy(J, structure=self._structure)
        # the C++ assembler adds the element matrices (Dirichlet rows and columns skipped) and, unlike
        # dolfinx.fem.petsc.assemble_matrix, does not insert a diagonal: K's 1 at the constrained dofs stays
        _cpp_assemble_matrix(J, self.Jc_form._cpp_object, pack_constants(self.Jc_form),
                             pack_coefficients(self.Jc_form), [bc._cpp_object for bc in self.bcs])
        J.assemble()

    def destroy(self) -> None:
        self.K.destroy()
