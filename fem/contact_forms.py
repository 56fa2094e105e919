"""UFL weak forms of frictionless contact against a rigid obstacle: the kinematics, and the method terms.

Notation (units: mm, N, MPa). ``u`` displacement, ``v`` test function, ``a(u, v) = int sigma(u) : eps(v) dx``.
On the candidate contact boundary Gamma_c (reference configuration, outward body normal ``n_b``):

* gap ``g(u)`` (mm), > 0 open, < 0 penetration; contact direction ``n_c`` (unit, from the body towards the
  obstacle, ``n_c = -n_o`` with ``n_o`` the obstacle's outward normal); traction on the body ``t = -p n_c``
  with the contact pressure ``p >= 0`` (compressive).
* kinematics ``small``: gap at the undeformed position, linear in u: ``g = g(X) + n_o(X) . u`` (obstacle mode)
  or ``g = phi(X1) - d - (X2 + u2)`` (half-plane mode). ``convective``: the obstacle is evaluated where the
  material point is, ``x = X + u``: ``g = g(X + u)``, ``n_o = n_o(X + u)``, or ``g = phi(X1 + u1) - d - x2``.
* kinematics ``finite`` (finite-strain hyperelasticity, total Lagrangian, :mod:`fem.hyperelastic`): the gap and
  normal are the convective ones at ``x = X + u`` (obstacle traction only); the pressure p is the current
  configuration's (force per deformed area), so every contact integral over the reference Gamma_c carries the
  surface Jacobian ``ds/dS = J |F^-T N|`` (``N = n_b``): ``int_gamma p n_c . v ds = int_Gamma p n_c . v (ds/dS)
  dS``, and the stress-based normal traction is ``sigma_n(P) = n_c . P N / (ds/dS)`` (the current traction
  ``t = P N dS/ds``). The Nitsche test stress is the Gateaux derivative ``dP(u)[v]`` (:mod:`fem.methods.nitsche`).
  Penalty and augmented Lagrangian state their law per reference length, ``p_ref = [q]_+`` with
  ``F_c = int_Gamma p_ref (n_c . v) dS``, and report the current pressure ``p = p_ref / (ds/dS)`` (the same
  traction; only the penalty stiffness is measured per reference length). Why: with the law per current length,
  the residual's derivative carries ``p d(ds/dS)[du]``, which at the first iterate of a load step (the rigid
  overlap of the undeformed body, p = kappa d) is far too large; measured on the flat-punch patch test the
  semismooth Newton then cycled between "all in contact" and "all open" (a 4e-8 mm overshoot of a 1e-3 mm step).
* traction ``obstacle``: ``n_c = -n_o`` (signed distance along the rigid curve's normal); ``halfplane``:
  vertical gap and ``n_c = e_y`` (traction normal to the undeformed flat surface; obstacle moved along -e_y).

Contact methods (:mod:`fem.methods`, one module each, registered by name) turn the gap into a pressure
argument ``q``, the pressure ``p = [q]_+`` and the contact residual ``F_c``; the residual is
``F(u; v) = a(u, v) + F_c(u; v)``:

* ``penalty`` (:mod:`fem.methods.penalty`): ``p = kappa [-g]_+``, ``kappa = kappa0 E* / h`` (E* = E/(1 - nu^2),
  h = cell diameter), ``F_c = int_Gc p (n_c . v) ds`` (= first variation of ``int kappa/2 [-g]_+^2``).
* ``nitsche`` (:mod:`fem.methods.nitsche`, Chouly-Hild, frictionless), ``gamma = gamma0 E / h``,
  ``sigma_n(w) = n_c . sigma(w) n_b``, ``P_gamma(u) = sigma_n(u) + gamma g(u)``,
  ``P_theta(v) = theta sigma_n(v) - gamma (n_c . v)``:
  ``F(u; v) = a(u, v) - theta/gamma int sigma_n(u) sigma_n(v) ds + 1/gamma int [P_gamma(u)]_- P_theta(v) ds``,
  so ``p = -[P_gamma]_- = [-sigma_n(u) - gamma g]_+``. theta = 1 symmetric, 0 incomplete (= penalty-like
  residual with a consistent pressure), -1 skew-symmetric. With theta = 0 both methods share
  ``F = a + int p (n_c . v)``.
* ``augmented_lagrangian`` (:mod:`fem.methods.augmented_lagrangian`): ``p = [lambda - kappa g]_+`` with a nodal
  multiplier ``lambda`` updated to ``p`` (Uzawa) until the constraint holds; no infinite penalty.

For a :class:`fem.obstacles.CurveObstacle` the gap and normal are nodal Functions (``g_k``, ``n_k``) updated from
the current iterate ``u_k`` every residual evaluation, with ``g(u) = g_k + n_k . (u - u_k)`` (convective) or
``g(u) = g_0 + n_0 . u`` (small, projection of the undeformed nodes).

The Jacobian is the exact Gateaux derivative (semismooth Newton: the derivative of ``[x]_+`` is the indicator
of ``x > 0``).
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

from collections.abc import Callable
from typing import Any, NamedTuple

import dolfinx
import ufl

from fem.elasticity import Lame, sigma
from fem.methods import ContactMethod, create, method_names
from fem.methods.base import positive_part
from vocabulary import FINITE, HALFPLANE, KINEMATICS, OBSTACLE, SMALL, TRACTIONS

__all__ = ["ContactForms", "ContactKinematics", "positive_part", "contact_kinematics", "build_contact_forms",
           "METHODS", "KINEMATICS", "TRACTIONS"]

METHODS = method_names()  # the registry of fem.methods (vocabulary.METHODS)


class ContactForms(NamedTuple):
    """UFL pieces of the contact problem.

    Attributes:
        F: residual form (N/mm per unit test displacement).
        J: Jacobian form (None when ``bulk`` is given: the mixed solver forms its blocks).
        gap: UFL gap g(u) (mm).
        argument: UFL pressure argument q with ``p = [q]_+`` (MPa).
        pressure: UFL contact pressure p >= 0 (MPa).
        n_c: UFL unit contact direction (body -> obstacle).
        sigma_nn: UFL ``-n_c . sigma(u) n_b`` (MPa, > 0 compressive), the stress-based pressure.
        F_c: the contact part of the residual (form in v).
        update: callable(u_function) refreshing nodal gap data (Curve obstacles) or None.
        method: the :class:`fem.methods.base.ContactMethod` instance that built ``F_c``.
        ds_c: the contact measure of ``F_c`` (the method's quadrature; resultants of p use it too).
        ds_scale: UFL surface Jacobian ds/dS of finite kinematics (current over reference length), None for
            small and convective kinematics (1): resultants of p are ``int p (...) ds_scale dS``.
    """

    F: Any
    J: Any
    gap: Any
    argument: Any
    pressure: Any
    n_c: Any
    sigma_nn: Any
    F_c: Any
    update: Callable | None
    method: Any = None
    ds_c: Any = None
    ds_scale: Any = None

    def on_surface(self, integrand):
        """``integrand`` times the surface Jacobian ds/dS (unchanged for small and convective kinematics)."""
        return integrand if self.ds_scale is None else integrand * self.ds_scale


class ContactKinematics(NamedTuple):
    """What every method needs on Gamma_c (module docstring).

    Attributes:
        gap: UFL gap g(u) (mm, > 0 open).
        n_c: UFL unit contact direction (body -> obstacle).
        n_b: UFL outward body normal (reference configuration).
        X: UFL material coordinate (mm).
        h: UFL cell diameter (mm), the scale of the penalty/Nitsche parameters.
        update: callable(u_function) refreshing nodal gap data (Curve obstacles) or None.
        u: the displacement Function (its space and mesh, for methods with unknowns of their own).
        ds_scale: surface Jacobian ``ds/dS = J |F^-T N|`` of finite kinematics (UFL), None otherwise (= 1).
    """

    gap: Any
    n_c: Any
    n_b: Any
    X: Any
    h: Any
    update: Callable | None
    u: Any
    ds_scale: Any = None

    def sigma_n(self, stress):
        """``n_c . stress n_b`` (MPa); finite kinematics: the current normal traction ``n_c . P N / (ds/dS)``
        from the first Piola-Kirchhoff stress P."""
        s_n = ufl.dot(self.n_c, ufl.dot(stress, self.n_b))
        return s_n if self.ds_scale is None else s_n / self.ds_scale

    def on_surface(self, integrand):
        """``integrand`` of a current-configuration contact integral pulled back to the reference Gamma_c:
        times ``ds/dS`` for finite kinematics, unchanged otherwise (module docstring)."""
        return integrand if self.ds_scale is None else integrand * self.ds_scale

    def current_pressure(self, p_ref):
        """The current-configuration pressure (MPa, per deformed length) of a pressure ``p_ref`` per reference
        length: ``p_ref / (ds/dS)`` for finite kinematics, unchanged otherwise. Penalty and augmented Lagrangian
        state their law per reference length (``F_c = int p_ref (n_c . v) dS``, module docstring)."""
        return p_ref if self.ds_scale is None else p_ref / self.ds_scale


def _check(name, value, allowed):
    if value not in allowed:
        raise ValueError(f"{name} must be one of {allowed}, got {value!r}")


def _curve_gap(*, u, obstacle, d, contact_facets, kinematics):
    """Nodal gap/normal Functions for a Curve obstacle and their update callback."""
    V = u.function_space
    mesh = V.mesh
    deg = V.ufl_element().embedded_superdegree
    Q = dolfinx.fem.functionspace(mesh, ("Lagrange", deg))
    g_k = dolfinx.fem.Function(Q, name="gap_nodal")
    n_k = dolfinx.fem.Function(V, name="normal_nodal")
    u_k = dolfinx.fem.Function(V, name="u_linearisation")
    fdim = mesh.topology.dim - 1
    dofs = dolfinx.fem.locate_dofs_topological(Q, fdim, contact_facets)
    X = Q.tabulate_dof_coordinates()[dofs, :2]
    state = {"d": None}

    def update(u_now):
        dval = float(d.value)
        if kinematics == SMALL:
            if state["d"] == dval:
                return
            pts = X
        else:
            u_k.x.array[:] = u_now.x.array
            pts = X + u_now.x.array.reshape(-1, 2)[dofs]
        gp = obstacle.signed_distance(pts[:, 0], pts[:, 1], d=dval)
        g_k.x.array[dofs] = gp.g
        n_arr = n_k.x.array.reshape(-1, 2)
        n_arr[dofs, 0] = gp.n1
        n_arr[dofs, 1] = gp.n2
        state["d"] = dval

    if kinematics == SMALL:
        gap = g_k + ufl.dot(n_k, u)
    else:
        gap = g_k + ufl.dot(n_k, u - u_k)
    return gap, -n_k, update


def contact_kinematics(*, u, obstacle, d, kinematics: str, traction: str, contact_facets) -> ContactKinematics:
    """Gap and contact direction of ``kinematics`` / ``traction`` (module docstring).

    Args:
        u: displacement Function.  obstacle: an obstacle from :mod:`fem.obstacles`.
        d: dolfinx Constant, rigid displacement (mm) of the obstacle along ``obstacle.direction``.
        kinematics: ``"small"``, ``"convective"`` or ``"finite"``.  traction: ``"obstacle"`` or ``"halfplane"``
            (finite: obstacle only).
        contact_facets: local facet indices of Gamma_c (needed for Curve obstacles).
    """
    _check("kinematics", kinematics, KINEMATICS)
    _check("traction", traction, TRACTIONS)
    mesh = u.function_space.mesh
    X = ufl.SpatialCoordinate(mesh)
    n_b = ufl.FacetNormal(mesh)
    h = ufl.CellDiameter(mesh)
    update = None
    ds_scale = None
    if kinematics == FINITE:
        if traction != OBSTACLE:
            raise ValueError(f"kinematics='finite' needs traction='obstacle', got {traction!r}")
        F = ufl.Identity(2) + ufl.grad(u)
        ds_scale = ufl.det(F) * ufl.sqrt(ufl.dot(ufl.inv(F).T * n_b, ufl.inv(F).T * n_b))
    if traction == HALFPLANE:
        if abs(obstacle.direction[0]) > 1e-14 or obstacle.direction[1] > 0:
            raise ValueError(f"traction='halfplane' needs direction (0, -1), got {obstacle.direction}")
        if not obstacle.analytic:
            raise ValueError("traction='halfplane' needs an analytic obstacle (graph y = phi(x))")
        x1 = X[0] if kinematics == SMALL else X[0] + u[0]
        gap = obstacle.halfplane_gap(x1, X[1] + u[1], d=d, xp=ufl)
        n_c = ufl.as_vector((0.0, 1.0))
    elif obstacle.analytic:
        if kinematics == SMALL:
            g0 = obstacle.signed_distance(X[0], X[1], d=d, xp=ufl)
            n_o = ufl.as_vector((g0.n1, g0.n2))
            gap = g0.g + ufl.dot(n_o, u)
        else:
            x = X + u
            gx = obstacle.signed_distance(x[0], x[1], d=d, xp=ufl)
            n_o = ufl.as_vector((gx.n1, gx.n2))
            gap = gx.g
        n_c = -n_o
    else:
        gap, n_c, update = _curve_gap(u=u, obstacle=obstacle, d=d, contact_facets=contact_facets,
                                      kinematics=kinematics)
    return ContactKinematics(gap=gap, n_c=n_c, n_b=n_b, X=X, h=h, update=update, u=u, ds_scale=ds_scale)


def build_contact_forms(*, u, obstacle, d, lame: Lame, E: float, method: str | ContactMethod, kinematics: str,
                        traction: str, kappa0: float = 1e3, gamma0: float = 10.0, theta: float = 1.0, ds_c,
                        contact_facets, mask=None, v=None, stress_u=None, stress_v=None, bulk=None,
                        **method_params) -> ContactForms:
    """Assemble the UFL residual/Jacobian of frictionless contact (see module docstring for the weak form).

    Args:
        u: displacement Function (vector Lagrange).
        obstacle: an obstacle from :mod:`fem.obstacles`.
        d: dolfinx Constant, rigid displacement (mm) of the obstacle along ``obstacle.direction``.
        lame: plane-strain Lame parameters.
        E: Young's modulus (MPa) scaling kappa and gamma.
        method: a registered method name (:mod:`fem.methods`) or a method instance.
        kinematics, traction: see module docstring.
        kappa0, gamma0, theta: penalty / Nitsche / augmentation parameters (dimensionless); with
            ``method_params`` (e.g. ``uzawa_rtol``) passed to the method's constructor when ``method`` is a name.
        ds_c: boundary measure restricted to Gamma_c (with its quadrature degree); a method with its own contact
            quadrature (:meth:`fem.methods.base.ContactMethod.measure_metadata`) gets it re-built from this one.
        contact_facets: local facet indices of Gamma_c (needed for Curve obstacles).
        mask: optional Constants ``(on, lo_0, hi_0, ...)``: while ``on = 1`` the positive part is replaced by a
            prescribed active set, ``p = q`` where ``lo_k < X1 < hi_k`` for some k and 0 elsewhere (the solver's
            active-set predictor iteration); ``on = 0`` gives the true contact law.
        v: test function (default ``TestFunction`` of u's space; a mixed formulation passes its own).
        stress_u, stress_v: UFL stress of the state and of the test field entering the bulk and the Nitsche terms
            (default ``sigma(u)``, ``sigma(v)``; the mixed u-p formulation passes ``2 mu eps - p I`` and
            ``2 mu eps(v) - q I``; finite kinematics the first Piola-Kirchhoff ``P(u)`` and ``dP(u)[v]``,
            :func:`fem.hyperelastic.bulk_law`). The contact terms are otherwise unchanged.
        bulk: UFL bulk residual replacing ``inner(sigma(u), grad v) dx`` (mixed formulation).
    """
    if isinstance(method, str):
        _check("method", method, METHODS)
    kin = contact_kinematics(u=u, obstacle=obstacle, d=d, kinematics=kinematics, traction=traction,
                             contact_facets=contact_facets)
    if isinstance(method, str):
        method = create(method, E=E, kappa0=kappa0, gamma0=gamma0, theta=theta, **method_params)
    v = ufl.TestFunction(u.function_space) if v is None else v
    stress_u = sigma(u, lame) if stress_u is None else stress_u
    stress_v = sigma(v, lame) if stress_v is None else stress_v
    ds_c = _method_measure(ds_c, method, u)
    terms = method.terms(kin, v=v, stress_u=stress_u, stress_v=stress_v, ds_c=ds_c, mask=mask)
    F_bulk = ufl.inner(stress_u, ufl.grad(v)) * ufl.dx if bulk is None else bulk
    F = F_bulk + terms.F_c
    J = ufl.derivative(F, u, ufl.TrialFunction(u.function_space)) if bulk is None else None
    return ContactForms(F=F, J=J, gap=kin.gap, argument=terms.argument, pressure=terms.pressure, n_c=kin.n_c,
                        sigma_nn=-kin.sigma_n(stress_u), F_c=terms.F_c, update=kin.update, method=method,
                        ds_c=ds_c, ds_scale=kin.ds_scale)


def _method_measure(ds_c, method, u):
    """``ds_c`` with the method's contact quadrature (unchanged when the method keeps the Gauss rule)."""
    degree = u.function_space.ufl_element().embedded_superdegree
    want = method.measure_metadata(degree=degree, quadrature_degree=ds_c.metadata().get("quadrature_degree"))
    return ds_c if want is None else ds_c.reconstruct(metadata=want)
