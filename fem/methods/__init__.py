"""Registry of the frictionless contact methods, one module each (the asimov-contact ``one_sided/`` layout).

One registry for both partners (:mod:`fem.methods.registry`): a method name maps to its rigid-obstacle class (here)
and, where it has one, its law between two meshed bodies (:mod:`fem.two_body.laws`, imported by the registry
lines below); the names are :data:`vocabulary.METHODS`.

A method is a :class:`fem.methods.base.ContactMethod` subclass in its own module, decorated with
:func:`register`; it is known to the solver once its module is imported by the registry line at the end of
this file. ``solve_contact(method=name)`` then builds it with :func:`create`.

Adding a method::

    # fem/methods/my_method.py
    from fem.methods.registry import register
    from fem.methods.base import ContactMethod, MethodTerms, contact_law

    @register
    class MyMethod(ContactMethod):
        name = "my_method"

        def __init__(self, *, E, E_star, kappa0=1e3, **params):   # validate what you use (ValueError)
            super().__init__(E=E, E_star=E_star)              # kappa: base.penalty_stiffness(kappa0, E_star, h)
            ...

        def terms(self, kin, *, v, stress_u, stress_v, ds_c, mask):
            q = ...                                            # pressure argument (MPa)
            p = contact_law(q, kin.X, mask)                    # p = [q]_+ (or the predictor's active set)
            return MethodTerms(argument=q, pressure=p, F_c=p * ufl.dot(kin.n_c, v) * ds_c)

and append ``my_method`` to the import line below.

Finite kinematics (:mod:`fem.contact_forms`): a contact integral over the reference Gamma_c of a
current-configuration pressure carries the surface Jacobian (``kin.on_surface(...)``), or the law is stated per
reference length and the current pressure reported as ``kin.current_pressure(p_ref)``; a method that does this
is listed in :data:`fem.options.FINITE_METHODS` (the others are refused with kinematics="finite").
"""

from __future__ import annotations

from fem.methods.base import ContactMethod, MethodTerms, SampleRule, contact_law, positive_part
from fem.methods.registry import REGISTRY, create, get_method, method_names, register

__all__ = ["REGISTRY", "register", "method_names", "get_method", "create", "ContactMethod", "MethodTerms",
           "SampleRule", "contact_law", "positive_part"]

# The registry lines: one module per method (each registers its class on import).
from fem.methods import nitsche, penalty  # noqa: E402,F401,I001
from fem.methods import augmented_lagrangian  # noqa: E402,F401
from fem.two_body import laws  # noqa: E402,F401  (the same methods between two meshed bodies)
