"""Registry of the frictionless contact methods, one module each (the asimov-contact ``one_sided/`` layout).

A method is a :class:`fem.methods.base.ContactMethod` subclass in its own module, decorated with
:func:`register`; it is known to the solver once its module is imported by the registry line at the end of
this file. ``solve_contact(method=name)`` then builds it with :func:`create`.

Adding a method::

    # fem/methods/my_method.py
    from fem.methods import register
    from fem.methods.base import ContactMethod, MethodTerms, contact_law

    @register
    class MyMethod(ContactMethod):
        name = "my_method"

        def __init__(self, *, E, kappa0=1e3, **params):   # validate what you use (ValueError)
            super().__init__(E=E)
            ...

        def terms(self, kin, *, v, stress_u, stress_v, ds_c, mask):
            q = ...                                            # pressure argument (MPa)
            p = contact_law(q, kin.X, mask)                    # p = [q]_+ (or the predictor's active set)
            return MethodTerms(argument=q, pressure=p, F_c=p * ufl.dot(kin.n_c, v) * ds_c)

and append ``my_method`` to the import line below.
"""

from __future__ import annotations

from fem.methods.base import ContactMethod, MethodTerms, SampleRule, contact_law, positive_part

__all__ = ["REGISTRY", "register", "method_names", "get_method", "create", "ContactMethod", "MethodTerms",
           "SampleRule", "contact_law", "positive_part"]

REGISTRY: dict[str, type[ContactMethod]] = {}


def register(cls: type[ContactMethod]) -> type[ContactMethod]:
    """Class decorator: add a :class:`ContactMethod` subclass to :data:`REGISTRY` under ``cls.name``."""
    if not (isinstance(cls, type) and issubclass(cls, ContactMethod) and cls.name):
        raise TypeError(f"register needs a ContactMethod subclass with a name, got {cls!r}")
    if REGISTRY.get(cls.name, cls) is not cls:
        raise ValueError(f"contact method {cls.name!r} is already registered ({REGISTRY[cls.name]!r})")
    REGISTRY[cls.name] = cls
    return cls


def method_names() -> tuple[str, ...]:
    """Registered method names, in registration order."""
    return tuple(REGISTRY)


def get_method(name: str) -> type[ContactMethod]:
    """The method class registered as ``name`` (ValueError naming the known ones otherwise)."""
    if name not in REGISTRY:
        raise ValueError(f"method must be one of {method_names()}, got {name!r}")
    return REGISTRY[name]


def create(name: str, **params) -> ContactMethod:
    """An instance of method ``name``; ``params`` are the method keywords of ``solve_contact`` (E, kappa0, ...)."""
    return get_method(name)(**params)


# The registry lines: one module per method (each registers its class on import).
from fem.methods import nitsche, penalty  # noqa: E402,F401,I001
from fem.methods import augmented_lagrangian  # noqa: E402,F401
