"""Augmented Lagrangian method: Uzawa updates of a nodal contact multiplier around the penalty Newton solve.

Units mm, N, MPa. Gap ``g(u)`` (mm, > 0 open), contact direction ``n_c`` (body -> obstacle), traction on the
body ``t = -p n_c`` with the pressure ``p >= 0`` (MPa, compressive), as in :mod:`fem.contact_forms`.

Unknowns: the displacement u and a multiplier ``lambda`` (MPa), a scalar Lagrange function of the displacement
degree whose nodal values on Gamma_c are the contact pressures (0 elsewhere). With ``kappa = kappa0 E* / h``
(MPa/mm, E* = E/(1 - nu^2) the plane-strain modulus, as for two bodies; h = cell diameter) the contact law and
the residual are

    p = [lambda - kappa g(u)]_+ ,        F(u; v) = a(u, v) + int_Gc^nodal p (n_c . v) ds ,

where ``int^nodal`` is the interpolatory quadrature on the Lagrange nodes of each facet (P1: trapezoid,
P2: Simpson 1/6, 2/3, 1/6): the law is evaluated at the contact nodes only, and the nodal force on node i is
``p_i w_i`` with ``w_i = int N_i ds > 0``. For a fixed lambda this is the penalty method (Newton, exact Jacobian).
After each converged Newton solve the multiplier is set to the nodal pressure (Uzawa)

    lambda_i <- (int^nodal p N_i ds) / w_i     (= [lambda_i - kappa g_i]_+ , kappa averaged over the facets at i)

and the penalty solve repeated. A fixed point has ``g_i = 0`` where ``lambda_i > 0`` and ``g_i >= 0`` where
``lambda_i = 0``: the constraint holds exactly at the contact nodes for ANY kappa0 > 0, so there is no
penalty error ``M / (kappa H)`` and no infinite penalty; kappa0 only sets the convergence rate (the error in
lambda contracts per update by about ``1 / (1 + c kappa0)``) and the conditioning of each Newton solve.

Why nodal: a multiplier at the Gauss points of the contact integral converges to the ``kappa -> oo`` limit of the
Gauss-point penalty, whose pressure oscillates (measured on the Hertz scene, P2, h = a/20: penalty kappa0 = 1e4
has 22 local maxima in 46 samples and RMS/p0 2.1 %). Collocation at the nodes is a Dirichlet-like condition
on the active trace dofs and does not oscillate (measured kappa0 = 1e6 nodal penalty: p_max +0.06 %, RMS 0.14 %).
With a Gauss-point law but a nodal multiplier the answer would keep a ``kappa g`` error between the nodes.

Stopping criterion per load level: the discrete KKT conditions hold to a gap tolerance, ``|g_i| <= tol`` at
the nodes that carry pressure and ``g_i >= -tol`` at all contact nodes, with ``tol = uzawa_rtol max|u|`` (mm;
default 1e-10 of the largest displacement: the gap error enters the load-approach relation as ``tol / d``,
and it stays 1e3 above the round-off of g). ``p >= 0`` holds exactly. A criterion on the relative multiplier
change (``kappa |g_i| / p_max``) would stall at the round-off of ``kappa g``: measured 3e-9 at kappa0 = 1e5
(Hertz, h = a/10). At most ``uzawa_max_it`` updates, then :class:`fem.errors.ContactSolveError`. The converged
state keeps the multiplier of its last Newton solve, so P and P_pressure stay in equilibrium.
Each load step records ``uzawa`` (Newton solves), ``uzawa_gap`` (the last gap violation / max|u|) and
``uzawa_change`` (the last multiplier change / p_max). The surface is sampled at the contact nodes (where the
law holds), a node shared by two facets once.

Known limit: a :class:`fem.obstacles.CurveObstacle` with ``kinematics="convective"`` (nodal gap re-projected in
every residual) did not converge on the Hertz scene under displacement control (SNES DIVERGED_MAX_IT at
d = 0.01 mm, h = a/10); the same curve with ``small`` kinematics and the exact circle with ``convective`` do.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

import basix
import dolfinx
import numpy as np
import ufl
from mpi4py import MPI

from fem.errors import ContactSolveError
from fem.methods.base import ContactMethod, MethodTerms, SampleRule, contact_law, penalty_stiffness
from fem.methods.registry import register

__all__ = ["AugmentedLagrangian", "nodal_rule"]


def nodal_rule(degree: int) -> tuple[np.ndarray, np.ndarray]:
    """Interpolatory quadrature on the nodes of the degree-``degree`` Lagrange interval (dolfinx's default
    GLL-warped variant): points (n, 1) on [0, 1] and weights ``int N_i`` (positive, sum 1)."""
    el = basix.create_element(basix.ElementFamily.P, basix.CellType.interval, degree,
                              basix.LagrangeVariant.gll_warped)
    qp, qw = basix.make_quadrature(basix.CellType.interval, 2 * degree)
    weights = qw @ el.tabulate(0, qp)[0, :, :, 0]
    return np.asarray(el.points, dtype=float), np.asarray(weights, dtype=float)


@register
class AugmentedLagrangian(ContactMethod):
    """Augmented Lagrangian (Uzawa) with a nodal multiplier (parameters kappa0 > 0, uzawa_rtol > 0,
    uzawa_max_it >= 1)."""

    name = "augmented_lagrangian"
    supports_tangent = False  # the multiplier changes with d too: force corrections use the secant
    # Uzawa update ``lambda <- relaxation * p`` (1: the augmented Lagrangian; a stiff penalty relaxes it,
    # :class:`fem.methods.penalty.NodalPenaltyUzawa`) and the name used in its error messages.
    relaxation: float = 1.0
    label: str = "augmented Lagrangian"

    def __init__(self, *, E, E_star, kappa0: float = 1e3, uzawa_rtol: float = 1e-10, uzawa_max_it: int = 100,
                 **params):
        super().__init__(E=E, E_star=E_star)
        if not kappa0 > 0:
            raise ValueError(f"kappa0 must be > 0, got {kappa0}")
        if not uzawa_rtol > 0:
            raise ValueError(f"uzawa_rtol must be > 0, got {uzawa_rtol}")
        if int(uzawa_max_it) < 1:
            raise ValueError(f"uzawa_max_it must be >= 1, got {uzawa_max_it}")
        self.kappa0, self.uzawa_rtol, self.uzawa_max_it = kappa0, float(uzawa_rtol), int(uzawa_max_it)
        self.multiplier = None

    def measure_metadata(self, *, degree: int, quadrature_degree: int) -> dict:
        pts, wts = nodal_rule(degree)
        return {"quadrature_rule": "custom", "quadrature_points": pts, "quadrature_weights": wts,
                "quadrature_degree": degree}

    def sample_rule(self, *, degree: int) -> SampleRule:
        pts, wts = nodal_rule(degree)
        return SampleRule(points=pts, weights=wts, points_per_facet=degree)

    def terms(self, kin, *, v, stress_u, stress_v, ds_c, mask) -> MethodTerms:
        V = kin.u.function_space
        Q = dolfinx.fem.functionspace(V.mesh, ("Lagrange", V.ufl_element().embedded_superdegree))
        self.multiplier = lam = dolfinx.fem.Function(Q, name="contact_multiplier")
        kappa = self.constant(kin, penalty_stiffness(self.kappa0, self.E_star, 1.0)) / kin.h  # kappa0 E* a Constant
        q = lam - kappa * kin.gap
        p = contact_law(q, kin.X, mask)
        vq = ufl.TestFunction(Q)
        fields = {"w": 1.0, "p": p, "g": kin.gap} | self.nodal_fields(kin)
        self._ufl_forms = {f"nodal_{name}": f * vq * ds_c for name, f in fields.items()}
        self._forms = None  # compiled with the problem's forms (bind_forms), or alone at the first use
        self._n_owned = Q.dofmap.index_map.size_local
        self._comm = V.mesh.comm
        self._u = kin.u
        self._u_owned = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
        return MethodTerms(argument=q, pressure=kin.current_pressure(p), F_c=p * ufl.dot(kin.n_c, v) * ds_c)

    def extra_forms(self) -> dict:
        """The nodal averages ``int^nodal f N_i ds`` of ``w`` (= 1), ``p``, ``g`` and :meth:`nodal_fields`."""
        return dict(self._ufl_forms)

    def bind_forms(self, compiled: dict) -> None:
        """The compiled nodal forms; the contact dofs are those with a positive nodal weight ``w_i``."""
        self._forms = {name[len("nodal_"):]: form for name, form in compiled.items()}
        w = self._nodal("w")
        self._idx = np.flatnonzero(w > 0)  # owned contact dofs
        self._w = w[self._idx]

    def nodal_fields(self, kin) -> dict:
        """Extra UFL fields f whose nodal averages ``int^nodal f N_i ds / w_i`` :meth:`law_gap` reads (none)."""
        return {}

    def law_gap(self, gap: np.ndarray, p: np.ndarray) -> np.ndarray:
        """The nodal gaps (mm) that must meet the contact conditions at a fixed point, from the nodal gaps and
        pressures (MPa): the gaps themselves (the constraint ``g_i = 0`` where ``p_i > 0``)."""
        return gap

    def state_functions(self) -> list:
        return [self.multiplier]

    def options(self) -> dict:
        return {"uzawa_rtol": self.uzawa_rtol, "uzawa_max_it": self.uzawa_max_it}

    # -- Uzawa ----------------------------------------------------------------------------------------------
    def _nodal(self, name: str) -> np.ndarray:
        """Owned entries of ``int^nodal f N_i ds`` (assembled, ghost contributions added)."""
        if self._forms is None:  # built outside a ContactProblem: each form compiled on its own
            self.bind_forms({k: dolfinx.fem.form(f) for k, f in self._ufl_forms.items()})
        vec = dolfinx.fem.assemble_vector(self._forms[name])
        vec.scatter_reverse(dolfinx.la.InsertMode.add)
        return vec.array[:self._n_owned].copy()

    def _max(self, arr: np.ndarray) -> float:
        return self._comm.allreduce(float(np.max(arr)) if arr.size else 0.0, op=MPI.MAX)

    def update(self) -> tuple[float, float, np.ndarray]:
        """Candidate multiplier from the current state: (largest nodal gap violation relative to max|u|, relative
        multiplier change, the new nodal values, not yet assigned)."""
        p_nodal = self._nodal("p")[self._idx] / self._w
        new = self.relaxation * p_nodal
        old = self.multiplier.x.array[self._idx]
        gap = self.law_gap(self._nodal("g")[self._idx] / self._w, p_nodal)
        scale = self._max(new)
        change = self._max(np.abs(new - old))
        violation = self._max(np.concatenate([np.abs(gap[new > 0]), np.maximum(-gap, 0.0)]))
        u_max = self._max(np.abs(self._u.x.array[:self._u_owned]))
        return (violation / u_max if u_max > 0 else 0.0), (change / scale if scale > 0 else 0.0), new

    def solve(self, newton) -> tuple[int, int, dict]:
        """Newton solves with Uzawa updates in between until the constraint holds (module docstring)."""
        reason, its = newton()
        n, gap, change = 1, 0.0, 0.0
        while reason > 0:
            gap, change, new = self.update()
            if gap <= self.uzawa_rtol:
                break
            if n >= self.uzawa_max_it:
                raise ContactSolveError(f"{self.label}: the gap violation is still {gap:.3g} max|u| "
                                        f"(> uzawa_rtol = {self.uzawa_rtol:g}) after {n} Uzawa iterations; "
                                        "raise kappa0 or uzawa_max_it")
            self.multiplier.x.array[self._idx] = new
            self.multiplier.x.scatter_forward()
            reason, k = newton(force_iteration=True)  # a small multiplier change can sit below snes_atol
            its += k
            n += 1
        return reason, its, {"uzawa": n, "uzawa_gap": gap, "uzawa_change": change}
