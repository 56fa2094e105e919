"""Numbers in the UFL forms: dolfinx Constants, so that a form compiles once per structure, never per value.

FFCx compiles a form (or an Expression) into a C module keyed by the form's signature, and a Python float in
the form is part of that signature: with E = 210000.0 written into ``lambda tr(eps)``, every new E, nu, radius,
penalty stiffness or load is a new C module (measured on a new machine: a ``hertz_cylinder`` copy with only E
changed took 14.4 s warm against 4.0 s, most of it the compiler). A dolfinx ``Constant`` enters the signature as
"a constant of this shape", and its value is read at assembly time: the form compiles once per (scene, method,
degree, kinematics, material model, traction), whatever the numbers.

Every number that a case or a study varies goes through here: the Lame parameters (:func:`lame_constants`), the
rigid obstacle's geometry (:meth:`fem.obstacles.AnalyticObstacle.with_constants`), the contact method's
parameters (``kappa0 E*``, ``gamma0 E``, ``theta``: :mod:`fem.methods`), the load (the obstacle's displacement
``d``, the Hertz predictor's ``a`` and ``p0``). Structural choices stay Python values: the loading direction,
the quadrature degree, the method, the kinematics and the material model (each is a different form anyway).

Values are unchanged: a Constant holds the same double the float literal held (``kappa0 * E`` is multiplied in
Python as before), so results move by the round-off of a different order of operations in the generated code
at most (``make check-numbers``).
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

import dolfinx

from fem.elasticity import Lame

__all__ = ["scalar", "lame_constants", "is_constant"]


def scalar(mesh, value: float) -> dolfinx.fem.Constant:
    """A real scalar ``Constant`` on ``mesh`` holding ``value`` (set ``.value`` to change it, no recompile)."""
    return dolfinx.fem.Constant(mesh, dolfinx.default_scalar_type(float(value)))


def is_constant(value) -> bool:
    """True for a dolfinx Constant (a number that is already a coefficient of the form)."""
    return isinstance(value, dolfinx.fem.Constant)


def lame_constants(mesh, lm: Lame) -> Lame:
    """``lm`` (MPa) as Constants on ``mesh`` (a Lame of Constants or of UFL fields is returned unchanged)."""
    if is_constant(lm.lmbda) or not isinstance(lm.lmbda, int | float):
        return lm
    return Lame(scalar(mesh, lm.lmbda), scalar(mesh, lm.mu))
