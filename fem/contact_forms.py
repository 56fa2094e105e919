"""UFL weak forms of frictionless contact against a rigid obstacle (penalty and Nitsche).

Notation (units: mm, N, MPa). ``u`` displacement, ``v`` test function, ``a(u, v) = int sigma(u) : eps(v) dx``.
On the candidate contact boundary Gamma_c (reference configuration, outward body normal ``n_b``):

* gap ``g(u)`` (mm), > 0 open, < 0 penetration; contact direction ``n_c`` (unit, from the body towards the
  obstacle, ``n_c = -n_o`` with ``n_o`` the obstacle's outward normal); traction on the body ``t = -p n_c``
  with the contact pressure ``p >= 0`` (compressive).
* kinematics ``small``: gap at the undeformed position, linear in u: ``g = g(X) + n_o(X) . u`` (obstacle mode)
  or ``g = phi(X1) - d - (X2 + u2)`` (half-plane mode). ``convective``: the obstacle is evaluated where the
  material point is, ``x = X + u``: ``g = g(X + u)``, ``n_o = n_o(X + u)``, or ``g = phi(X1 + u1) - d - x2``.
* traction ``obstacle``: ``n_c = -n_o`` (signed distance along the rigid curve's normal); ``halfplane``:
  vertical gap and ``n_c = e_y`` (traction normal to the undeformed flat surface; obstacle moved along -e_y).

Penalty: ``p = kappa [-g]_+``, ``kappa = kappa0 E / h`` (h = cell diameter); residual
``F(u; v) = a(u, v) + int_Gc p (n_c . v) ds``  (= first variation of ``1/2 a(u,u) + int kappa/2 [-g]_+^2``).

Nitsche (Chouly-Hild, frictionless), ``gamma = gamma0 E / h``, ``sigma_n(w) = n_c . sigma(w) n_b``,
``P_gamma(u) = sigma_n(u) + gamma g(u)``, ``P_theta(v) = theta sigma_n(v) - gamma (n_c . v)``:
``F(u; v) = a(u, v) - theta/gamma int sigma_n(u) sigma_n(v) ds + 1/gamma int [P_gamma(u)]_- P_theta(v) ds``,
so ``p = -[P_gamma]_- = [-sigma_n(u) - gamma g]_+``. theta = 1 symmetric, 0 incomplete (= penalty-like
residual with a consistent pressure), -1 skew-symmetric. With theta = 0 both methods share
``F = a + int p (n_c . v)``.

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

__all__ = ["ContactForms", "positive_part", "build_contact_forms", "METHODS", "KINEMATICS", "TRACTIONS"]

METHODS = ("nitsche", "penalty")
KINEMATICS = ("small", "convective")
TRACTIONS = ("obstacle", "halfplane")


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


def positive_part(x):
    """``[x]_+`` as a UFL conditional (derivative: indicator of x > 0)."""
    return ufl.conditional(ufl.gt(x, 0.0), x, 0.0)


def _law(q, X, mask):
    """``[q]_+``, or the prescribed-active-set law while the predictor mask is on."""
    if mask is None:
        return positive_part(q)
    on, lo, hi = mask
    inside = ufl.And(ufl.gt(X[0], lo), ufl.lt(X[0], hi))
    return ufl.conditional(ufl.gt(on, 0.5), ufl.conditional(inside, q, 0.0), positive_part(q))


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
        if kinematics == "small":
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

    if kinematics == "small":
        gap = g_k + ufl.dot(n_k, u)
    else:
        gap = g_k + ufl.dot(n_k, u - u_k)
    return gap, -n_k, update


def build_contact_forms(*, u, obstacle, d, lame: Lame, E: float, method: str, kinematics: str,
                        traction: str, kappa0: float, gamma0: float, theta: float, ds_c, contact_facets,
                        mask=None, v=None, stress_u=None, stress_v=None, bulk=None) -> ContactForms:
    """Assemble the UFL residual/Jacobian of frictionless contact (see module docstring for the weak form).

    Args:
        u: displacement Function (vector Lagrange).
        obstacle: an obstacle from :mod:`fem.obstacles`.
        d: dolfinx Constant, rigid displacement (mm) of the obstacle along ``obstacle.direction``.
        lame: plane-strain Lame parameters.
        E: Young's modulus (MPa) scaling kappa and gamma.
        method, kinematics, traction: see module docstring.
        kappa0, gamma0, theta: penalty / Nitsche parameters (dimensionless).
        ds_c: boundary measure restricted to Gamma_c (with its quadrature degree).
        contact_facets: local facet indices of Gamma_c (needed for Curve obstacles).
        mask: optional Constants ``(on, lo, hi)``: while ``on = 1`` the positive part is replaced by a prescribed
            active set, ``p = q`` for ``lo < X1 < hi`` and 0 elsewhere (the solver's active-set predictor
            iteration); ``on = 0`` gives the true contact law.
        v: test function (default ``TestFunction`` of u's space; a mixed formulation passes its own).
        stress_u, stress_v: UFL stress of the state and of the test field entering the Nitsche terms (default
            ``sigma(u)``, ``sigma(v)``; the mixed u-p formulation passes ``2 mu eps - p I`` and ``2 mu eps(v) -
            q I``). The contact terms are otherwise unchanged.
        bulk: UFL bulk residual replacing ``inner(sigma(u), grad v) dx`` (mixed formulation).
    """
    _check("method", method, METHODS)
    _check("kinematics", kinematics, KINEMATICS)
    _check("traction", traction, TRACTIONS)
    if theta not in (-1, 0, 1, -1.0, 0.0, 1.0):
        raise ValueError(f"theta must be one of (1, 0, -1), got {theta!r}")
    if method == "penalty" and not kappa0 > 0:
        raise ValueError(f"kappa0 must be > 0, got {kappa0}")
    if method == "nitsche" and not gamma0 > 0:
        raise ValueError(f"gamma0 must be > 0, got {gamma0}")
    mesh = u.function_space.mesh
    v = ufl.TestFunction(u.function_space) if v is None else v
    stress_u = sigma(u, lame) if stress_u is None else stress_u
    stress_v = sigma(v, lame) if stress_v is None else stress_v
    X = ufl.SpatialCoordinate(mesh)
    n_b = ufl.FacetNormal(mesh)
    h = ufl.CellDiameter(mesh)
    update = None

    if traction == "halfplane":
        if abs(obstacle.direction[0]) > 1e-14 or obstacle.direction[1] > 0:
            raise ValueError(f"traction='halfplane' needs direction (0, -1), got {obstacle.direction}")
        if not obstacle.analytic:
            raise ValueError("traction='halfplane' needs an analytic obstacle (graph y = phi(x))")
        x1 = X[0] if kinematics == "small" else X[0] + u[0]
        gap = obstacle.halfplane_gap(x1, X[1] + u[1], d=d, xp=ufl)
        n_c = ufl.as_vector((0.0, 1.0))
    elif obstacle.analytic:
        if kinematics == "small":
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

    sig_n = lambda s: ufl.dot(n_c, ufl.dot(s, n_b))  # noqa: E731
    if method == "penalty":
        kappa = kappa0 * E / h
        q = -kappa * gap
        p = _law(q, X, mask)
        F_c = p * ufl.dot(n_c, v) * ds_c
    else:
        gamma = gamma0 * E / h
        P_gamma = sig_n(stress_u) + gamma * gap
        q = -P_gamma
        p = _law(q, X, mask)
        F_c = (-theta / gamma * sig_n(stress_u) * sig_n(stress_v)
               - p / gamma * (theta * sig_n(stress_v) - gamma * ufl.dot(n_c, v))) * ds_c
    F = (ufl.inner(stress_u, ufl.grad(v)) * ufl.dx if bulk is None else bulk) + F_c
    J = ufl.derivative(F, u, ufl.TrialFunction(u.function_space)) if bulk is None else None
    return ContactForms(F=F, J=J, gap=gap, argument=q, pressure=p, n_c=n_c, sigma_nn=-sig_n(stress_u),
                        F_c=F_c, update=update)
