"""What a contact method is: the method-specific part of the frictionless contact weak form.

The kinematics (gap ``g`` in mm, > 0 open; unit contact direction ``n_c`` from the body towards the obstacle;
outward body normal ``n_b``) are built once in :mod:`fem.contact_forms` and handed to the method as a
:class:`fem.contact_forms.ContactKinematics`. A method turns them into the pressure argument ``q`` (MPa), the
contact pressure ``p = [q]_+ >= 0`` (MPa, compressive; the traction on the body is ``t = -p n_c``) and the
contact part ``F_c(u; v)`` of the residual ``F = a(u, v) + F_c`` (N/mm per unit test displacement).

A method may also

* choose its contact quadrature (:meth:`ContactMethod.measure_metadata`) and the points where the surface is
  sampled (:meth:`ContactMethod.sample_rule`; default: the Gauss points of the contact integral);
* carry unknowns of its own between solves (:meth:`ContactMethod.state_functions`, e.g. a multiplier); they
  are saved, restored and extrapolated with the displacement by the load stepper;
* wrap the Newton solve of each load level (:meth:`ContactMethod.solve`, e.g. Uzawa updates of a multiplier).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, ClassVar, NamedTuple

import ufl

from vocabulary import RIGID

__all__ = ["ContactMethod", "MethodTerms", "SampleRule", "positive_part", "contact_law", "penalty_stiffness"]


def penalty_stiffness(kappa0, E_star, h):
    """The penalty (and augmentation) stiffness ``kappa = kappa0 E* / h`` (MPa/mm), the one meaning of kappa0.

    ``kappa0`` is dimensionless; ``E*`` (MPa) the plane-strain modulus of the contact pair,
    ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2`` (:func:`analytic.materials.composite_modulus`), against a rigid
    obstacle ``E* = E/(1 - nu^2)``; ``h`` (mm) the contact element size (a rigid obstacle's methods: the cell
    diameter, a UFL expression; two bodies: the shortest slave facet). Works on floats and on UFL expressions.
    """
    return kappa0 * E_star / h


class MethodTerms(NamedTuple):
    """UFL pieces a method contributes: pressure argument q and pressure p = [q]_+ (MPa), contact residual F_c."""

    argument: Any
    pressure: Any
    F_c: Any


class SampleRule(NamedTuple):
    """Surface sample points of a method on the reference facet [0, 1].

    Attributes:
        points: (n, 1) reference coordinates.
        weights: (n,) weights (sum 1).
        points_per_facet: distinct samples per facet after merging points shared by neighbouring facets
            (used to turn sample weights into facet sizes, :func:`fem.postprocess.facets_across`).
    """

    points: Any
    weights: Any
    points_per_facet: int


def positive_part(x):
    """``[x]_+`` as a UFL conditional (derivative: indicator of x > 0)."""
    return ufl.conditional(ufl.gt(x, 0.0), x, 0.0)


def contact_law(q, X, mask):
    """``[q]_+``, or the prescribed-active-set law while the predictor mask is on.

    ``mask = (on, lo_0, hi_0, lo_1, hi_1, ...)`` (dolfinx Constants): while ``on = 1`` the pressure is ``q`` where
    ``lo_k < X1 < hi_k`` for some k and 0 elsewhere (the solver's active-set predictor iteration; an unused
    interval has ``lo_k = hi_k``); ``on = 0`` gives the true law ``[q]_+``.
    """
    if mask is None:
        return positive_part(q)
    on, *edges = mask
    inside = None
    for lo, hi in zip(edges[0::2], edges[1::2], strict=True):
        run = ufl.And(ufl.gt(X[0], lo), ufl.lt(X[0], hi))
        inside = run if inside is None else ufl.Or(inside, run)
    return ufl.conditional(ufl.gt(on, 0.5), ufl.conditional(inside, q, 0.0), positive_part(q))


class ContactMethod:
    """Base class of a contact method (one instance per contact problem; it may hold Functions).

    Subclasses set ``name`` and implement :meth:`terms`; the constructor receives every method parameter of
    :func:`fem.solver.solve_contact` as keywords and validates the ones it uses (``ValueError``): the body's
    Young's modulus ``E`` (MPa; Nitsche's ``gamma = gamma0 E / h``) and the pair's plane-strain modulus ``E_star``
    (MPa; ``E/(1 - nu^2)`` against the rigid obstacle: the penalty stiffness :func:`penalty_stiffness`).

    Attributes:
        name: registry name (``solve_contact(method=name)``).
        partner: the partner kind it serves (:mod:`fem.methods.registry`): a rigid obstacle.
        supports_tangent: the force-control tangent correction applies (the residual depends on u and d only;
            a method with an outer multiplier loop sets False).
    """

    name: ClassVar[str] = ""
    partner: ClassVar[str] = RIGID
    supports_tangent: ClassVar[bool] = True

    def __init__(self, *, E: float, E_star: float, **params):
        self.E, self.E_star = E, E_star

    @staticmethod
    def constant(kin, value: float):
        """``value`` as a dolfinx Constant on the contact mesh: a method's parameters (``kappa0 E*``, ``gamma0 E``,
        ``theta``) enter its terms this way, so another value reuses the compiled form (:mod:`fem.coefficients`)."""
        from fem.coefficients import scalar

        return scalar(kin.u.function_space.mesh, value)

    # -- the weak form ---------------------------------------------------------------------------------------
    def terms(self, kin, *, v, stress_u, stress_v, ds_c, mask) -> MethodTerms:
        """The method's UFL terms from the kinematics ``kin`` (:class:`fem.contact_forms.ContactKinematics`).

        Args:
            kin: gap, contact direction, body normal, coordinates, cell size.
            v: test function.  stress_u, stress_v: UFL stress of the state and of the test field (MPa).
            ds_c: contact measure (built with :meth:`measure_metadata`).
            mask: active-set predictor Constants ``(on, lo_0, hi_0, ...)`` or None (see :func:`contact_law`).
        """
        raise NotImplementedError

    # -- optional hooks --------------------------------------------------------------------------------------
    def measure_metadata(self, *, degree: int, quadrature_degree: int) -> dict | None:
        """UFL measure metadata of the contact integral; None (default): the Gauss rule of ``quadrature_degree``
        the solver's contact measure already has."""
        return None

    def sample_rule(self, *, degree: int) -> SampleRule | None:
        """Where the solver samples the surface by default; None: the Gauss points of the contact integral."""
        return None

    def state_functions(self) -> list:
        """dolfinx Functions of the method's own unknowns, saved and extrapolated with u (default none)."""
        return []

    def extra_forms(self) -> dict:
        """UFL forms of the method's own (name -> form, e.g. nodal averages), compiled with the problem's forms
        into one module (:mod:`fem.compiled_forms`) and handed back through :meth:`bind_forms` (default none)."""
        return {}

    def bind_forms(self, compiled: dict) -> None:
        """Receive the compiled :meth:`extra_forms` (name -> ``dolfinx.fem.Form``), before the first solve."""

    def solve(self, newton: Callable[..., tuple[int, int]]) -> tuple[int, int, dict]:
        """Solve one load level: ``newton(force_iteration=False)`` runs the SNES solve from the current state and
        returns (converged reason, iterations); ``force_iteration=True`` does at least one Newton iteration.

        Returns (reason, total Newton iterations, extra record entries). Default: one Newton solve.
        """
        reason, its = newton()
        return reason, its, {}

    def options(self) -> dict:
        """Extra entries of :attr:`fem.solver.ContactResult.options` (parameters beyond the common ones)."""
        return {}
