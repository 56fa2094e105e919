"""Frictionless contact of two elastic bodies on non-matching meshes (plane strain, small strain; dolfinx 0.11).

Units mm, N, MPa; loads P per unit thickness (N/mm). Both bodies live in one dolfinx mesh as two cell groups
that share no node (each its own gmsh surface, meshed with its own sizes, so the contact surfaces do not
match). One vector Lagrange space V (degree 1 or 2) holds both bodies' displacements; the materials are cell
constants (each body its E and nu).

Weak form: find u with the supports such that for every admissible v

    F(u; v) = int_O1+O2 sigma(u) : eps(v) dx  +  F_c(u; v) = 0 ,      F_c = -(D v) . p(g~(u))

with the weighted gaps ``g~ = (G0 + D u) / W`` of the slave surface's nodes (:mod:`fem.two_body.weighted_gap`,
pairing by :mod:`fem.two_body.geometry`, fixed in the reference configuration: ``small`` kinematics; or, for
``convective``, re-paired in the current configuration by :mod:`fem.two_body.convective`, so that D = D(u) and the
Jacobian carries the pairing's second derivative) and the nodal contact law ``p`` (:mod:`fem.two_body.laws`:
penalty or augmented Lagrangian). Convective kinematics needs a flat slave surface (normal (0, 1)); measured
limit: a soft master with kappa0 = 1e3 diverged, kappa0 = 1e2 converged (tests/test_two_body_convective.py).

Assembly (what a dolfinx form cannot express: the contact couples dofs of both bodies across non-matching
facets): the bulk stiffness K is a dolfinx form; its sparsity pattern is extended by the paired slave-master
node blocks (``SparsityPattern.insert``), the PETSc matrix is created from it
(``dolfinx.cpp.la.petsc.create_matrix``), K is assembled into it once with the supports' rows and columns set to
the identity, and every Newton iteration copies it and adds the contact Jacobian ``D^T diag(-dp/dg~ / W) D``
(supports' rows and columns left out). The residual is ``K0 u - D^T p`` (K0: K without supports) with the
support rows ``u_i - u_i^prescribed``. The Jacobian is exact (a test compares it with finite differences).

Loading: the ``driven`` facet group (e.g. the top of the upper body) is moved by ``d`` along ``direction``
(displacement control; the load stepper's force control drives d). Measured load P: the support reaction along
``direction`` on the softer body (N/mm, full body for a half model): of the driven group, or, when the other body
is the softer one, minus the reaction of that body's supports; ``P_pressure``: the resultant of the contact
forces on the other body along ``direction``; the two agree up to the residual.

This object offers the interface :class:`fem.stepping.LoadStepper` drives (the rigid obstacle's
:class:`fem.problem.ContactProblem` offers the same), so load steps, cut-backs, force control and the
prescribed-active-set predictor are the same code for both kinds of contact partner.

Serial only: the pairing needs both surfaces on one process (refused on more, in one line).
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

import itertools
from contextlib import contextmanager
from dataclasses import dataclass
from typing import NamedTuple

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import scipy.sparse as sp
import ufl
from petsc4py import PETSc

from analytic import materials
from fem.compiled_forms import compile_forms
from fem.elasticity import Lame
from fem.linear_solver import configure as configure_linear_solver
from fem.linear_solver import snes_options
from fem.newton_controls import NewtonControls
from fem.options import ContactOptions
from fem.postprocess import LOCKING_NU, SurfaceSamples, contact_edges, oscillation_warnings, resolution_warnings
from fem.supports import COMPONENTS, group_facets, resolve_supports
from fem.two_body.checks import check_two_body
from fem.two_body.geometry import exact_master_gaps, mortar_points, node_points
from fem.two_body.laws import law_for
from fem.two_body.surfaces import cell_data, surface_of_group, tabulate2
from fem.two_body.weighted_gap import WeightedGap, assemble_weighted_gap
from vocabulary import CONVECTIONS, CONVECTIVE, FINITE, PAIRINGS, TWO_BODY_TRACTIONS

__all__ = ["Body", "MeshedPartner", "TwoBodyProblem", "CONVECTIONS", "PAIRINGS", "TWO_BODY_TRACTIONS"]

# convective kinematics: a slave point's partner may move this many master facets from its reference partner
# before the Jacobian needs an entry outside the preallocated pattern (then PETSc allocates it, counted)
CONVECTIVE_WINDOW = 3
_counter = itertools.count()


@dataclass(frozen=True, kw_only=True)
class Body:
    """One elastic body: its cell physical group, Young's modulus E (MPa), Poisson's ratio nu, the label the
    output names it by (default: the group's name), and its bulk law (``"linear"``; kinematics ``"finite"``:
    ``"saint_venant_kirchhoff"`` or ``"neo_hookean"``, :mod:`fem.two_body.finite_problem`)."""

    name: str
    E: float
    nu: float
    label: str = ""
    material_model: str = "linear"


@dataclass(frozen=True, kw_only=True)
class MeshedPartner:
    """The deformable contact partner: a second meshed elastic body (the rigid partner is an analytic curve of
    :mod:`fem.obstacles`). Everything the two-body problem needs beyond :class:`fem.options.ContactOptions`.

    Attributes:
        bodies: the two bodies (cell groups of the mesh).
        slave, master: facet groups of the two contact surfaces; the slave side carries the integration.
        driven: facet group moved by d along ``direction`` (components ``driven_components``; the others free).
        driven_body: name of the body that owns ``driven`` (the load is measured on it).
        pairing: ``"mortar"`` (segment-to-segment) or ``"node_to_segment"``.
        direction: unit loading direction (default (0, -1)).
        master_surface: the master body's exact reference surface (e.g.
            :class:`fem.two_body.geometry.CircleSurface`) to measure the initial gap to, or None (its facets).
        traction: the direction the contact traction acts along: ``"halfplane"`` (the slave normal, on both
            bodies: the half-plane theory's and Ciavarella-Hills's frictionless surfaces, with either kinematics)
            or ``"master_normal"`` (convective kinematics only: the deformed master's normal, the gradient of the
            contact energy; :mod:`fem.two_body.convective`).
        convection: what convective kinematics moves (:data:`CONVECTIONS`): ``"pairing"`` (a slave point meets the
            master particle at its current abscissa; displacements and forces there: :mod:`fem.two_body.convective`)
            or ``"profile"`` (Ciavarella and Hills's eq. (8): the reference pairing of small kinematics, the
            master's profile read at the convected abscissa: :mod:`fem.two_body.profile_convection`; needs
            ``master_surface`` and ``traction = "halfplane"``). The two coincide for a rigid master.
        cut_kinks: mortar pairing: cut the slave's segments at the projections of ``master_surface.kinks()`` (a
            wedge's apex), so that no Gauss segment straddles a jump of the profile's slope (False: for measuring
            what the kink costs).
    """

    bodies: tuple[Body, Body]
    slave: str
    master: str
    driven: str
    driven_body: str
    driven_components: tuple[int, ...] = (0, 1)
    pairing: str = "mortar"
    direction: tuple[float, float] = (0.0, -1.0)
    master_surface: object | None = None
    traction: str = "halfplane"
    convection: str = "pairing"
    cut_kinks: bool = True

    def combined_modulus(self) -> float:
        """E* (MPa): ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2`` (:mod:`analytic.materials`)."""
        b1, b2 = self.bodies
        return materials.composite_modulus(b2.E, b2.nu, E1=b1.E, nu1=b1.nu)


class TwoBodyForms(NamedTuple):
    """The bodies for the output: ``body_index`` (DG0: the index of each cell's body in ``body_names``), ``E`` (MPa)
    and ``nu`` (DG0)."""

    body_index: object = None
    body_names: tuple[str, ...] = ()
    E: object = None
    nu: object = None


class _Value:
    """A mutable scalar with ``.value`` (the rigid problem's dolfinx Constant d has the same interface)."""

    def __init__(self, value: float = 0.0):
        self.value = value


class TwoBodyProblem(NewtonControls):
    """Two elastic bodies in frictionless contact (module docstring): a :class:`fem.partner_problem.PartnerProblem`.

    Attributes (main ones):
        u: displacement Function of both bodies (mm).  d: the driven displacement (``d.value``, mm).
        gap: the :class:`fem.two_body.weighted_gap.WeightedGap`.  method: the contact law.
        snes: the PETSc SNES; A: the Jacobian matrix (extended sparsity); K0: stiffness without supports.
    """

    def __init__(self, mesh_data, setup: MeshedPartner, options: ContactOptions):
        self.options = opts = options
        self.setup = setup
        self.mesh_data, self.mesh = mesh_data, mesh_data.mesh
        self.comm = self.mesh.comm
        check_two_body(setup, opts, mesh_data)
        self.E_star = setup.combined_modulus()
        self.mult = 2.0 if opts.symmetric_half else 1.0
        self.d = _Value(0.0)
        self.prefix = opts.petsc_prefix or f"fem_two_body_{next(_counter)}_"
        self.qdeg = self.sdeg = opts.degree  # the law holds at the slave nodes: degree points per facet
        self._build_space()
        self.forms = TwoBodyForms(body_index=self.body_id, E=self.E_fun, nu=self.nu_fun,
                                  body_names=tuple(b.label or b.name for b in self.setup.bodies))
        self._build_pairing()
        self._build_supports()
        self._build_matrices()
        self._build_solver()

    # -- construction ---------------------------------------------------------------------------------------
    def _build_space(self) -> None:
        opts, mesh, md = self.options, self.mesh, self.mesh_data
        self.V = dolfinx.fem.functionspace(mesh, ("Lagrange", opts.degree, (2,)))
        self.u = dolfinx.fem.Function(self.V, name="displacement")
        Q = dolfinx.fem.functionspace(mesh, ("DG", 0))
        self.E_fun, self.nu_fun = dolfinx.fem.Function(Q, name="E"), dolfinx.fem.Function(Q, name="nu")
        self.body_id = dolfinx.fem.Function(Q, name="body")
        self.body_nodes = {}
        for k, body in enumerate(self.setup.bodies):
            cells = md.cell_tags.find(md.physical_groups[body.name].tag)
            self.body_id.x.array[cells] = float(k)
            self.E_fun.x.array[cells] = body.E
            self.nu_fun.x.array[cells] = body.nu
            self.body_nodes[body.name] = np.unique(self.V.dofmap.list[cells])
        E, nu = self.E_fun, self.nu_fun
        lmbda, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
        du, v = ufl.TrialFunction(self.V), ufl.TestFunction(self.V)

        def eps(w):
            return ufl.sym(ufl.grad(w))

        self.lame = Lame(lmbda, mu)  # cell-wise (UFL), for the output's stress fields
        self.stress = lmbda * ufl.tr(eps(self.u)) * ufl.Identity(2) + 2 * mu * eps(self.u)
        sig = lmbda * ufl.tr(eps(du)) * ufl.Identity(2) + 2 * mu * eps(du)
        self.a_form = compile_forms({"a": ufl.inner(sig, eps(v)) * ufl.dx}, comm=self.comm)["a"]
        self.n_u = self.u.x.array.size

    def _build_pairing(self) -> None:
        opts, st = self.options, self.setup
        self.slave_geom = surface_of_group(self.mesh_data, st.slave)
        self.master_geom = surface_of_group(self.mesh_data, st.master)
        if st.pairing == "mortar":
            kinks = st.master_surface.kinks() if st.master_surface is not None and st.cut_kinks else None
            pts = mortar_points(self.slave_geom, self.master_geom, n_gauss=opts.degree + 1,
                                cuts=(0.5,) if opts.degree == 2 else (), kinks=kinks)
        else:
            pts = node_points(self.slave_geom, self.master_geom, degree=opts.degree)
        pts = exact_master_gaps(pts, st.master_surface)
        self.gap: WeightedGap = assemble_weighted_gap(
            pts, slave=self.slave_geom, slave_cells=cell_data(self.V, self.slave_geom),
            master_cells=cell_data(self.V, self.master_geom), n_dofs=self.n_u, degree=opts.degree)
        if self.gap.nodes.size == 0:
            raise ValueError(f"the contact surfaces {st.slave!r} and {st.master!r} do not face each other")
        self.conv = None
        if opts.kinematics == CONVECTIVE and st.convection == "profile":
            from fem.two_body.profile_convection import ProfileConvection

            self.conv = ProfileConvection(pts, self.gap, slave=self.slave_geom,
                                          slave_cells=cell_data(self.V, self.slave_geom),
                                          master_cells=cell_data(self.V, self.master_geom),
                                          surface=st.master_surface, degree=opts.degree, n_dofs=self.n_u)
        elif opts.kinematics == CONVECTIVE:
            from fem.two_body.convective import ConvectiveGap, MasterCells

            self.conv = ConvectiveGap(pts, self.gap, slave=self.slave_geom,
                                      slave_cells=cell_data(self.V, self.slave_geom),
                                      master_geom=self.master_geom,
                                      master=MasterCells(cell_data(self.V, self.master_geom),
                                                         tabulate2(self.V), st.master_surface),
                                      degree=opts.degree, n_dofs=self.n_u, traction=st.traction)
        h = float(np.min(self.slave_geom.length))
        self.method = law_for(opts.method)(kappa0=opts.kappa0, E_star=self.E_star, h=h, n_nodes=self.gap.nodes.size,
                                           X1=self.gap.X[:, 0], uzawa_rtol=opts.uzawa_rtol,
                                           uzawa_max_it=opts.uzawa_max_it)
        self.method.bind(gap=lambda: self.weighted_gaps(self.u.x.array),
                         scale=lambda: float(np.max(np.abs(self.u.x.array), initial=0.0)))

    def _build_supports(self) -> None:
        """Supports (unrolled dof indices, prescribed value per unit d) and the driven group."""
        opts, st, fdim = self.options, self.setup, self.mesh.topology.dim - 1
        self.supports = supports = resolve_supports(self.mesh_data, opts.supports, opts.symmetric_half)
        dofs, per_d = [], []
        for name, kind in list(supports.items()) + [(st.driven, "driven")]:
            facets = group_facets(self.mesh_data, name)
            comps = st.driven_components if kind == "driven" else COMPONENTS[kind]
            for c in comps:
                nodes = dolfinx.fem.locate_dofs_topological(self.V, fdim, facets)
                dofs.append(2 * nodes + c)
                per_d.append(np.full(nodes.size, st.direction[c] if kind == "driven" else 0.0))
        all_dofs = np.concatenate(dofs)
        all_per_d = np.concatenate(per_d)
        self.bc_dofs, first = np.unique(all_dofs, return_index=True)
        self.bc_per_d = all_per_d[first]  # a dof both supported and driven keeps its first (support) entry
        self.free = np.ones(self.n_u, dtype=bool)
        self.free[self.bc_dofs] = False
        driven_facets = self.mesh_data.facet_tags.find(self.mesh_data.physical_groups[st.driven].tag)
        nodes = dolfinx.fem.locate_dofs_topological(self.V, fdim, driven_facets)
        self.reaction_dir = np.zeros(self.n_u)
        for c in range(2):
            self.reaction_dir[2 * nodes + c] = st.direction[c]
        other = next(b.name for b in st.bodies if b.name != st.driven_body)
        self.other_dir = np.zeros(self.n_u)
        for c in range(2):
            self.other_dir[2 * self.body_nodes[other] + c] = st.direction[c]
        # P is measured on the softer body: the reaction of a much stiffer body sums K u terms of size E_stiff |u|
        # whose round-off (measured: 1e-9 of P at E ratio 1e6) stalls the force control's 1e-10 tolerance
        E_of = {b.name: b.E for b in st.bodies}
        if E_of[other] < E_of[st.driven_body]:
            on_other = np.zeros(self.n_u, dtype=bool)
            on_other[2 * self.body_nodes[other]] = on_other[2 * self.body_nodes[other] + 1] = True
            supported = np.zeros(self.n_u, dtype=bool)
            supported[self.bc_dofs] = True
            self.reaction_dir = np.where(on_other & supported, -self.other_dir, 0.0)

    def _build_matrices(self) -> None:
        """K0 (no supports), and the Jacobian pattern: K's plus the contact node blocks."""
        self.K0 = dolfinx.fem.petsc.assemble_matrix(self.a_form)
        self.K0.assemble()
        pattern = dolfinx.fem.create_sparsity_pattern(self.a_form)
        D = self.gap.D.tocsr() if self.conv is None else self.conv.pattern(window=CONVECTIVE_WINDOW)
        for i in range(D.shape[0]):
            blocks = np.unique(D.indices[D.indptr[i]:D.indptr[i + 1]] // 2).astype(np.int32)
            pattern.insert(blocks, blocks)
        pattern.finalize()
        self.K_bc = dolfinx.cpp.la.petsc.create_matrix(self.comm, pattern)
        # explicit zeros at every contact block, so that assembly keeps them in the pattern
        Dabs = abs(D)
        self.K_bc.zeroEntries()
        _add_csr(self.K_bc, (Dabs.T @ Dabs).tocsr(), scale=0.0)
        dolfinx.fem.petsc.assemble_matrix(self.K_bc, self.a_form)
        self.K_bc.assemble()
        self.K_bc.setOption(PETSc.Mat.Option.KEEP_NONZERO_PATTERN, True)
        self.K_bc.zeroRowsColumns(self.bc_dofs.astype(np.int32), diag=1.0)
        self.A = self.K_bc.duplicate(copy=True)
        self.b = self.A.createVecLeft()
        self.x = self.A.createVecRight()

    @property
    def _solver_kw(self) -> dict:
        """What linear_solver="auto" decides by (:func:`fem.linear_solver.resolve`): the size, and whether the bulk
        is linear (small or convective kinematics; the bodies are hyperelastic at finite strain only)."""
        return {"ndofs": self.ndofs, "linear_bulk": self.options.kinematics != FINITE}

    def _build_solver(self) -> None:
        opts = self.options
        x_all = self.mesh.geometry.x
        L = float(np.max(np.ptp(x_all[:, :2], axis=0)))
        E_max = max(b.E for b in self.setup.bodies)
        petsc = {"snes_type": "newtonls", "snes_linesearch_type": "basic",
                 **snes_options(opts.linear_solver, **self._solver_kw),
                 "snes_rtol": opts.snes_rtol, "snes_atol": 1e-13 * E_max * L, "snes_stol": 0.0,
                 "snes_max_it": opts.max_it, **(opts.petsc_options or {})}
        self.snes = PETSc.SNES().create(self.comm)
        self.snes.setOptionsPrefix(self.prefix)
        o = PETSc.Options()
        for k, v in petsc.items():
            o[f"{self.prefix}{k}"] = v
        self.snes.setFunction(self._residual, self.b)
        self.snes.setJacobian(self._jacobian, self.A, self.A)
        self.snes.setFromOptions()
        configure_linear_solver(self.snes, self.A, self.V, opts.linear_solver, **self._solver_kw)
        for k in petsc:
            o.delValue(f"{self.prefix}{k}")

    # -- residual and Jacobian -----------------------------------------------------------------------------
    def _take(self, x) -> np.ndarray:
        arr = x.getArray(readonly=True)
        self.u.x.array[:] = arr
        return arr

    def weighted_gaps(self, u: np.ndarray) -> np.ndarray:
        """The nodal weighted gaps g~ (mm) of the dof array u (small or convective kinematics)."""
        if self.conv is None:
            return self.gap.gap(u)
        return self.conv.gaps(u) if hasattr(self.conv, "gaps") else self.conv.linearise(u)[0]

    def contact_residual(self, u: np.ndarray) -> np.ndarray:
        """``F_c = -T^T p`` (N/mm per dof) of the dof array u (T = D for small kinematics; convective: the traction's
        virtual-work matrix of :mod:`fem.two_body.convective`)."""
        if self.conv is None:
            return self.reference_contact_residual(u)
        g, _, _, T = self.conv.linearise(u)
        p, _ = self.method.pressure(g)
        return -(T.T @ p)

    def reference_contact_residual(self, u: np.ndarray) -> np.ndarray:
        """``F_c = -D^T p`` with the reference pairing's gaps (small kinematics; :mod:`fem.two_body.weighted_gap`)."""
        return -(self.gap.D.T @ self.method.pressure(self.gap.gap(u))[0])

    def reference_contact_jacobian(self, u: np.ndarray) -> sp.csr_matrix:
        """``D^T diag(-dp/dg~ / W) D`` of the reference pairing (small kinematics), all dofs."""
        _, dp = self.method.pressure(self.gap.gap(u))
        D = self.gap.D
        return (D.T @ sp.diags(-dp / self.gap.W) @ D).tocsr()

    def contact_jacobian(self, u: np.ndarray) -> sp.csr_matrix:
        """``dF_c/du = D^T diag(-dp/dg~ / W) D`` (small); convective (:mod:`fem.two_body.convective`):
        ``T^T diag(-dp/dg~ / W) D - sum_i p_i dT_i/du`` with the traction's virtual-work matrix T; exact, sparse,
        all dofs."""
        if self.conv is None:
            return self.reference_contact_jacobian(u)
        g, D, H, T = self.conv.linearise(u, hessian_weights=lambda gaps: -self.method.pressure(gaps)[0])
        _, dp = self.method.pressure(g)
        J = T.T @ sp.diags(-dp / self.gap.W) @ D
        return (J if H is None else J + H).tocsr()

    def _residual(self, snes, x, b) -> None:
        arr = self._take(x)
        self.K0.mult(x, b)
        out = b.getArray()
        out += self.contact_residual(arr)
        out[self.bc_dofs] = arr[self.bc_dofs] - self.d.value * self.bc_per_d

    def _jacobian(self, snes, x, J, P) -> None:
        arr = self._take(x)
        structure = PETSc.Mat.Structure  # convective pairs may couple beyond the window: K_bc's pattern is a subset
        self.K_bc.copy(J, structure=structure.SAME_NONZERO_PATTERN if self.conv is None
                       else structure.SUBSET_NONZERO_PATTERN)
        self.add_free_block(J, self.contact_jacobian(arr), new_nonzeros=self.conv is not None)

    def add_free_block(self, J, Jc: sp.spmatrix, *, new_nonzeros: bool) -> None:
        """Add the contact Jacobian ``Jc`` (all dofs) to J on the free dofs only (rows and columns of the supports
        dropped), then assemble J; ``new_nonzeros``: entries outside J's pattern are allowed (else an error)."""
        free = sp.diags(self.free.astype(float))
        Jc = (free @ Jc @ free).tocsr()
        Jc.eliminate_zeros()
        J.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, not new_nonzeros)
        _add_csr(J, Jc)
        J.assemble()

    # -- the partner protocol (fem.partner_problem.PartnerProblem) ----------------------------------------------
    @property
    def tangent_applies(self) -> bool:
        """The tangent correction applies unless the law has an outer multiplier loop (small and convective
        kinematics, the displacement formulation: the residual is a function of u and d)."""
        return self.method.supports_tangent

    @property
    def pressure_field(self):
        """None: two bodies have no mixed pressure."""
        return None

    def set_load_level(self, P: float) -> None:
        """Force control's load level: nothing to update (the supports hold no far field; ``halfplane`` is
        refused)."""

    @property
    def hertz_applicable(self) -> bool:
        """False: the Hertz predictor needs a rigid circle or parabola."""
        return False

    def hertz_predictor(self):
        raise ValueError("the Hertz predictor needs a rigid circle or parabola obstacle, not a meshed partner")

    def law_samples(self) -> SurfaceSamples:
        """The samples at the slave contact nodes, where the nodal law holds (:meth:`sample`)."""
        return self.sample()

    # -- state ----------------------------------------------------------------------------------------------
    @property
    def ndofs(self) -> int:
        return self.V.dofmap.index_map.size_global * 2

    def get_state(self) -> np.ndarray:
        return np.concatenate([self.u.x.array, self.method.state()])

    def unloaded_guess(self, d_value: float, unloaded: np.ndarray) -> np.ndarray:
        """The unloaded state with the driven body translated rigidly by ``d_value`` along ``direction``: its
        overlap with the other body is the first active set of the geometric predictor."""
        guess = unloaded.copy()
        for c in range(2):
            guess[2 * self.body_nodes[self.setup.driven_body] + c] += d_value * self.setup.direction[c]
        return guess

    def nested_source(self, *, d: float, P: float, zones: tuple | None = None):
        """The converged state as the start of a finer mesh's solve (:class:`fem.nested_start.NestedStart`):
        ``u`` is this problem's displacement Function itself (the result's; the solve is over), ``zones`` the
        stepper's contact runs of that state (None: sampled here)."""
        from fem.nested_start import NestedStart

        md = self.mesh_data
        cells = tuple(md.cell_tags.find(md.physical_groups[b.name].tag) for b in self.setup.bodies)
        X1 = self.gap.X[:, 0]
        order = np.argsort(X1, kind="stable")
        surface = self.method.state()  # a copy (the law's own)
        return NestedStart(d=d, P=P, u=self.u, body_cells=cells, X1=X1[order],
                           surface=surface[order] if surface.size else surface,
                           zones=self.contact_zones() if zones is None else zones)

    def nested_guess(self, start) -> np.ndarray:
        """The state interpolated from a coarser mesh's converged one (:mod:`fem.nested_start`): each body's
        displacement from its own coarse cells, the method's nodal unknowns linearly in X1 (0 outside)."""
        from fem.nested_start import evaluate_in_cells

        X = self.V.tabulate_dof_coordinates()
        u = np.zeros((X.shape[0], 2))
        for body, cells in zip(self.setup.bodies, start.body_cells, strict=True):
            nodes = self.body_nodes[body.name]
            u[nodes] = evaluate_in_cells(start.u, X[nodes], cells)[:, :2]
        surface = self.method.state()
        if surface.size and start.surface.size:
            surface = np.interp(self.gap.X[:, 0], start.X1, start.surface, left=0.0, right=0.0)
        return np.concatenate([u.ravel(), surface])

    def set_state(self, arr: np.ndarray, rest: np.ndarray | None = None) -> None:
        n = self.n_u
        self.u.x.array[:] = arr[:n]
        src = arr if arr.size > n else rest
        if src is not None and src.size > n:
            self.method.set_state(src[n:])

    def measure(self) -> tuple[float, float]:
        """(P, P_pressure) in N/mm, full body (module docstring)."""
        u = self.u.x.array
        self.x.setArray(u)
        r = self.K0.createVecLeft()
        self.K0.mult(self.x, r)
        rc = self.contact_residual(u)
        P = self.mult * float(np.dot(r.getArray() + rc, self.reaction_dir))
        Pp = self.mult * float(np.dot(-rc, self.other_dir))
        r.destroy()
        return P, Pp

    # -- surface --------------------------------------------------------------------------------------------
    def sample(self, degree: int | None = None, rule=None) -> SurfaceSamples:
        """Samples at the slave contact nodes (where the law holds), sorted by X1."""
        g = self.weighted_gaps(self.u.x.array)
        q = self.method.argument(g)
        p, _ = self.method.pressure(g)
        X = self.gap.X
        nodes = self.gap.nodes
        ux = self.u.x.array.reshape(-1, 2)[nodes]
        order = np.argsort(X[:, 0], kind="stable")
        return SurfaceSamples(s=X[order, 0], X=X[order], x=(X + ux)[order], p=p[order], q=q[order],
                              sigma_nn=np.full(order.size, np.nan), gap=g[order], weight=self.gap.W[order])

    def contact_zones(self) -> tuple[tuple[float, float], ...]:
        smp = self.sample()
        return tuple(((-np.inf if i == 0 else left), right) for left, right, i, _ in contact_edges(smp.s, smp.q))

    def quality_warnings(self, smp: SurfaceSamples, d_now: float) -> list[str]:
        opts = self.options
        out = resolution_warnings(smp, quadrature_degree=opts.degree, half=opts.symmetric_half,
                                  min_facets_across=opts.min_facets_across, points_per_facet=opts.degree)
        out += oscillation_warnings(smp)
        for b in self.setup.bodies:
            if b.nu >= LOCKING_NU:
                out.append(f"near-incompressible: body {b.name!r} has nu = {b.nu:g} >= {LOCKING_NU} with the "
                           "displacement formulation (volumetric locking; the mixed formulation is not available "
                           "for two bodies)")
        return out

    # -- solves ---------------------------------------------------------------------------------------------
    def newton(self, *, force_iteration: bool = False) -> tuple[int, int]:
        """One SNES solve from the current state: (converged reason, iterations)."""
        u = self.u.x.array
        u[self.bc_dofs] = self.d.value * self.bc_per_d
        self.x.setArray(u)
        self.snes.setForceIteration(bool(force_iteration))
        try:
            self.snes.solve(None, self.x)
        finally:
            self.snes.setForceIteration(False)
        self.u.x.array[:] = self.x.getArray(readonly=True)
        return self.snes.getConvergedReason(), self.snes.getIterationNumber()

    @contextmanager
    def prescribed_active_set(self, zones):
        self.method.zones = tuple(zones)
        try:
            yield
        finally:
            self.method.zones = None

    def tangent(self, state: np.ndarray, d0: float, *, fixed_set: bool = False):
        """Tangent ``t = du/dd`` of the converged state for its active set and ``dP/dd`` (as the rigid
        problem's: ``J t = -dF/dd`` with the factors the last Newton solve left in the KSP). ``dF/dd`` is exact here
        (the support rows' displacement per unit d), so ``fixed_set`` (the protocol's: the rigid problem's
        difference step on a prescribed set) changes nothing."""
        self.set_state(state)
        Jc = self.contact_jacobian(self.u.x.array.copy())
        rhs = np.zeros(self.n_u)
        rhs[self.bc_dofs] = self.bc_per_d  # dF/dd = -bc_per_d at the support rows
        f, t = self.x.duplicate(), self.x.duplicate()
        try:
            f.setArray(rhs)
            self.snes.getKSP().solve(f, t)
            t_arr = t.getArray(readonly=True).copy()
        finally:
            f.destroy()
            t.destroy()
        self.u.x.array[:] = t_arr
        # P is linear in u for a fixed active set: dP/dd is the reaction of t with the linearised contact law
        self.x.setArray(t_arr)
        r = self.K0.createVecLeft()
        self.K0.mult(self.x, r)
        dP = self.mult * float(np.dot(r.getArray() + Jc @ t_arr, self.reaction_dir))
        r.destroy()
        self.set_state(state)
        if not (np.all(np.isfinite(t_arr)) and np.isfinite(dP) and dP > 0):
            return None
        return t_arr, dP

    def destroy(self) -> None:
        for obj in (self.snes, self.A, self.K_bc, self.K0, self.b, self.x):
            obj.destroy()


def _add_csr(M, C: sp.csr_matrix, *, scale: float = 1.0) -> None:
    """Add the scipy CSR matrix ``scale C`` to the PETSc matrix M (same global numbering: serial)."""
    for i in np.flatnonzero(np.diff(C.indptr)):
        lo, hi = C.indptr[i], C.indptr[i + 1]
        M.setValues(int(i), C.indices[lo:hi].astype(np.int32), scale * C.data[lo:hi], addv=PETSc.InsertMode.ADD)
