"""The registry of contact methods: name -> :class:`fem.methods.base.ContactMethod` subclass.

Method modules import :func:`register` from here (not from the package), so that the package's registry
lines (:mod:`fem.methods`) import the methods without an import cycle.
"""

from __future__ import annotations

from fem.methods.base import ContactMethod

__all__ = ["REGISTRY", "register", "method_names", "get_method", "create"]

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
