"""The Newton Jacobian as the elastic stiffness, assembled once, plus the contact terms, assembled per iteration.

Displacement formulation (small strain): the Jacobian of ``F(u; v) = int sigma(u) : grad v dx + F_c(u; v)`` is
``J(u) = K + J_c(u)`` with the constant stiffness ``K = int sigma(du) : grad v dx`` (N/mm^2 per unit thickness:
the bilinear form is linear in du and v) and ``J_c = dF_c/du [du]``, an integral over the contact boundary only
(:mod:`fem.contact_forms`). :class:`SplitJacobian` assembles the first J the usual way (Dirichlet rows and columns
zero, 1 on their diagonal) and keeps ``K = J - J_c`` of that state (a copy of J: its sparsity pattern; Dirichlet
rows as in J); each later Newton iteration copies K into J (same pattern: a copy of the values) and adds J_c over
the contact facets (Dirichlet rows and columns zero, nothing on their diagonal). The result is J to round-off (the
sums are ordered differently); only the cost changes: one bulk assembly per problem instead of one per Newton
iteration.
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
        Jc_form: the compiled contact Jacobian (:meth:`ufl_forms`).
        J_form: the compiled full Jacobian form (its sparsity pattern is the matrix's).
        bcs: Dirichlet conditions.
    """

    @staticmethod
    def ufl_forms(*, u, contact_residual) -> dict:
        """The UFL ``J_c`` (``contact_residual``: ``F_c(u; v)``, contact boundary integrals only), to compile with
        the problem's other forms (:mod:`fem.compiled_forms`); K needs no form of its own (``K = J - J_c``)."""
        du = ufl.TrialFunction(u.function_space)
        return {"Jc": ufl.derivative(contact_residual, u, du)}

    def __init__(self, *, u, Jc_form, J_form, bcs):
        self.u, self.bcs = u, bcs
        self.Jc_form = Jc_form
        self.K = None  # built from the first J (_stiffness_from)
        self.J_form = J_form

    def _add_contact(self, M) -> None:
        """``M += J_c(u)`` (the C++ assembler: Dirichlet rows and columns skipped, no diagonal inserted)."""
        _cpp_assemble_matrix(M, self.Jc_form._cpp_object, pack_constants(self.Jc_form),
                             pack_coefficients(self.Jc_form), [bc._cpp_object for bc in self.bcs])

    def _stiffness_from(self, J) -> None:
        """``K = J - J_c(u)`` of the state J was assembled at: a copy of J (its pattern and values) and one
        contact-boundary assembly, instead of a second bulk assembly (at 88k P2 dofs that was 0.043 s of a 0.32 s
        linear solve). K's Dirichlet rows keep J's 1 on the diagonal."""
        self.K = J.duplicate(copy=True)
        self.K.scale(-1.0)
        self._add_contact(self.K)
        self.K.assemble()
        self.K.scale(-1.0)

    def __call__(self, snes, x, J, P) -> None:
        """Assemble ``J = K + J_c(u(x))`` (SNES Jacobian callback signature)."""
        x.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)
        dolfinx.fem.petsc.assign(x, self.u)
        if self.K is None:  # the first J the usual way (it fixes J's nonzero pattern), then K from it
            J.zeroEntries()
            dolfinx.fem.petsc.assemble_matrix(J, self.J_form, bcs=self.bcs, diag=1.0)
            J.assemble()
            self._stiffness_from(J)
            return
        self.K.copy(J, structure=PETSc.Mat.Structure.SAME_NONZERO_PATTERN)  # K has J's pattern (a copy of it)
        self._add_contact(J)  # K's 1 at the constrained dofs stays
        J.assemble()

    def destroy(self) -> None:
        self.K.destroy()
