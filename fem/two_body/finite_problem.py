"""Two hyperelastic bodies in frictionless contact at finite strain (plane strain, total Lagrangian; dolfinx 0.11).

Units mm, N, MPa; loads per unit thickness (N/mm). The small-strain problem (:mod:`fem.two_body.problem`) with
two changes:

* the bulk: each body its own hyperelastic law (``Body.material_model``: ``"saint_venant_kirchhoff"`` or
  ``"neo_hookean"``, from its E and nu; :mod:`fem.hyperelastic`),

      F_b(u; v) = sum_bodies int_O0k P_k(u) : Grad v dX ,

  assembled with its exact Gateaux derivative every Newton iteration into the matrix whose pattern holds the
  contact blocks;
* the contact: mortar in the current configuration (:mod:`fem.two_body.finite_contact`): the weighted gap along
  the deformed master normal, the traction along it, the pressure per deformed length, exact Jacobian.

Residual ``F_b(u) - T(u)^T p`` with the support rows ``u_i - u_i^prescribed``; Jacobian ``dF_b/du`` + the contact
Jacobian, with the supports' rows and columns set to the identity. P (the load) is measured as in small strain: the
reaction along ``direction`` of the driven group (or of the softer body's supports). Degree 1 (P1) and mortar only.
The load stepper's tangent force correction does not apply (P is not linear in u).

Two hooks of the load stepper differ from small strain (docs/models.md, the finite-strain section): the first start
from the unloaded state is the small-strain solution of the same grid at that d (:meth:`unloaded_guess`), and a
prescribed active set is solved to convergence, not with one Newton iteration (:meth:`predictor_iteration`).

Measured (force control, one step with the stepper's cut-backs, P1, h_c = a/10, penalty kappa0 = 1e3): the shipped
elastic cylinder loads (R = 40 mm, a = 0.5 mm, W = H = 40 a) are reached, steel on steel (neo-Hookean) in 48 s,
aluminium on steel (Saint Venant-Kirchhoff) in 60 s, with 12 and 14 Newton solves (cut-backs included).
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

from typing import ClassVar

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import ufl
from petsc4py import PETSc

from fem.compiled_forms import compile_forms
from fem.elasticity import lame
from fem.hyperelastic import first_piola
from fem.two_body.finite_contact import FiniteContact
from fem.two_body.geometry import mortar_points
from fem.two_body.problem import TwoBodyProblem
from fem.two_body.surfaces import cell_data

__all__ = ["FiniteTwoBodyProblem"]


class FiniteTwoBodyProblem(TwoBodyProblem):
    """Two hyperelastic bodies (module docstring): a :class:`fem.partner_problem.PartnerProblem`.

    ``finite_line_search``: the SNES line search the load stepper sets (unless ``petsc_options`` names one):
    ``"l2"`` (the rigid obstacle's finite runs use ``"bt"``, :class:`fem.newton_controls.NewtonControls`). Measured on
    the two-half-planes case at its CI level (h_c = b0/10, W = 160 b0, 2.5k unknowns, force control to 3299 N/mm):
    neo-Hookean 17 solve attempts (cut-backs included) in 23 s with "l2" against 52 in 85 s with "bt"; Saint
    Venant-Kirchhoff, both at once, 43 attempts in 61 s against 62 in 118 s; "basic" and "cp" did not reach the
    load (5 cut-backs). ``prescribed_max_it``: the Newton iterations of one prescribed-set solve
    (:meth:`predictor_iteration`).
    """

    finite_line_search: str = "l2"
    prescribed_max_it: ClassVar[int] = 12
    _small: bool = False  # while True, the SNES solves the small-strain equations (:meth:`unloaded_guess`)

    def _build_space(self) -> None:
        super()._build_space()
        md = self.mesh_data
        dx = ufl.Measure("dx", domain=self.mesh, subdomain_data=md.cell_tags)
        v, du = ufl.TestFunction(self.V), ufl.TrialFunction(self.V)
        F = sum(ufl.inner(first_piola(self.u, b.material_model, lame(E=b.E, nu=b.nu)), ufl.grad(v))
                * dx(md.physical_groups[b.name].tag) for b in self.setup.bodies)
        forms = compile_forms({"F": F, "J": ufl.derivative(F, self.u, du)}, comm=self.comm)
        self.F_form, self.J_form = forms["F"], forms["J"]

    def _build_pairing(self) -> None:
        super()._build_pairing()  # the reference mortar pairing: the contact nodes, W_ref, the law
        opts = self.options
        pts = mortar_points(self.slave_geom, self.master_geom, n_gauss=opts.degree + 1)
        self.conv = FiniteContact(pts, self.gap, slave=self.slave_geom, slave_cells=cell_data(self.V, self.slave_geom),
                                  master=self.master_geom, master_cells=cell_data(self.V, self.master_geom),
                                  n_dofs=self.n_u)
        self.conv.bind_reference(self.V.tabulate_dof_coordinates()[:, :2].copy())

    # -- residual and Jacobian -----------------------------------------------------------------------------
    def bulk_residual(self, u: np.ndarray) -> np.ndarray:
        """``F_b(u)`` (N/mm per dof, no supports)."""
        self.u.x.array[:] = u
        vec = dolfinx.fem.petsc.assemble_vector(self.F_form)
        out = vec.getArray().copy()
        vec.destroy()
        return out

    def contact_residual(self, u: np.ndarray) -> np.ndarray:
        """``F_c = -T^T p`` (N/mm per dof): the traction's virtual-work matrix and the gaps only (no derivatives)."""
        g, _, _, T = self.conv.linearise(u, derivatives=False)
        return -(T.T @ self.method.pressure(g)[0])

    def _residual(self, snes, x, b) -> None:
        if self._small:
            return self._small_residual(x, b)
        arr = self._take(x).copy()
        out = b.getArray()
        out[:] = self.bulk_residual(arr) + self.contact_residual(arr)
        out[self.bc_dofs] = arr[self.bc_dofs] - self.d.value * self.bc_per_d

    def _jacobian(self, snes, x, J, P) -> None:
        if self._small:
            return self._small_jacobian(x, J)
        arr = self._take(x).copy()
        J.zeroEntries()
        dolfinx.fem.petsc.assemble_matrix(J, self.J_form)
        J.assemble()
        self.add_free_block(J, self.contact_jacobian(arr), new_nonzeros=True)
        J.zeroRowsColumns(self.bc_dofs.astype(np.int32), diag=1.0)

    # -- the small-strain start ----------------------------------------------------------------------------
    def _small_residual(self, x, b) -> None:
        """Linear elasticity and the reference pairing's gap (small kinematics on this mesh):
        ``K0 u - D^T p(g~(u))`` with the support rows."""
        arr = self._take(x)
        self.K0.mult(x, b)
        out = b.getArray()
        out += self.reference_contact_residual(arr)
        out[self.bc_dofs] = arr[self.bc_dofs] - self.d.value * self.bc_per_d

    def _small_jacobian(self, x, J) -> None:
        arr = self._take(x)
        J.zeroEntries()
        self.K_bc.copy(J, structure=PETSc.Mat.Structure.SUBSET_NONZERO_PATTERN)
        self.add_free_block(J, self.reference_contact_jacobian(arr), new_nonzeros=True)

    def unloaded_guess(self, d_value: float, unloaded: np.ndarray) -> np.ndarray:
        """The small-strain solution at ``d_value`` on this mesh (linear elasticity, the reference pairing, the
        penalty branch of the law; from the rigid translation of :meth:`TwoBodyProblem.unloaded_guess`), with the
        law's multiplier set to its pressure: the start of the first finite-strain solve. The rigid translation
        when that solve fails."""
        guess = super().unloaded_guess(d_value, unloaded)
        self._small = True
        try:
            with self.line_search("basic"):  # the small-strain equations: Newton's full steps
                self.d.value = d_value
                self.set_state(guess)
                reason, its = self.newton()
        finally:
            self._small = False
        self.start_iterations += int(its)
        if reason <= 0:
            return guess
        u = self.u.x.array.copy()
        has_lam = self.method.state().size > 0
        lam = self.method.pressure(self.gap.gap(u))[0] if has_lam else np.zeros(0)
        return np.concatenate([u, lam])

    # -- the partner protocol --------------------------------------------------------------------------------
    def predictor_iteration(self, zones) -> int:
        """The solve on the prescribed active set ``lo_k < X1 < hi_k`` (at most :attr:`prescribed_max_it` Newton
        iterations; converged or not, the law is the true one afterwards): its Newton iterations.

        At finite strain one Newton iteration does not solve a prescribed set (the equations are not linear in u),
        and the load stepper's edge fit (:meth:`fem.stepping.LoadStepper.solve_edge_fit`) would read its next set
        from the pressure of an unconverged iterate."""
        with self.prescribed_active_set(zones), self.max_iterations(self.prescribed_max_it):
            _, its = self.newton()
        return max(int(its), 1)

    @property
    def tangent_applies(self) -> bool:
        """False: at finite strain P is not linear in u for a fixed active set."""
        return False

    def tangent(self, state: np.ndarray, d0: float):
        return None

    def sample(self, degree: int | None = None, rule=None):
        """The small-strain samples (:meth:`TwoBodyProblem.sample`: at the slave contact nodes, sorted by their
        material abscissa X1, ``s = X1``) with the weights on the CURRENT slave length: ``p`` is the pressure per
        deformed length, so ``sum(p weight)`` is the contact force and the moments ``sum(p weight s^k)`` are those
        of the force per reference length of the slave body (its material abscissa, as the small-strain runs
        measure it)."""
        smp = super().sample(degree, rule)
        order = np.argsort(self.gap.X[:, 0], kind="stable")
        return smp._replace(weight=self.conv.current_weights(self.u.x.array.copy())[order])

    def measure(self) -> tuple[float, float]:
        """(P, P_pressure) in N/mm, full body (as :meth:`TwoBodyProblem.measure`, with the hyperelastic bulk)."""
        u = self.u.x.array.copy()
        rc = self.contact_residual(u)
        rb = self.bulk_residual(u)
        P = self.mult * float(np.dot(rb + rc, self.reaction_dir))
        Pp = self.mult * float(np.dot(-rc, self.other_dir))
        return P, Pp
