"""The one registry of contact methods: name -> partner kind -> the class that implements the method there.

A method name (:data:`vocabulary.METHODS`) is one contact law, whatever the partner: against a rigid obstacle it is
a :class:`fem.methods.base.ContactMethod` (UFL terms on the body's contact facets, :mod:`fem.methods`), against a
second meshed body a nodal law on the weighted gaps (:class:`fem.two_body.laws.TwoBodyLaw`). Each class names
the kind it serves (``partner``: ``"rigid"`` or ``"meshed"``, :data:`vocabulary.PARTNER_KINDS`) and registers
itself with :func:`register`; :func:`get_method` finds it, refusing a method the partner kind lacks in one line.
Both kinds compute the penalty (and augmentation) stiffness with :func:`fem.methods.base.penalty_stiffness`, so
``kappa0`` means the same on both.

Method modules import :func:`register` from here (not from the package), so that the package's registry
lines (:mod:`fem.methods`) import the methods without an import cycle.
"""

from __future__ import annotations

from vocabulary import MESHED, PARTNER_KINDS, RIGID

__all__ = ["REGISTRY", "register", "method_names", "get_method", "create"]

REGISTRY: dict[str, dict[str, type]] = {}

# Why a method has no implementation for a partner kind (the refusal's reason).
_MISSING_WHY = {MESHED: {"nitsche": "its terms need the slave traction across the non-matching interface"}}
_KIND_WORDS = {RIGID: "a rigid obstacle", MESHED: "two elastic bodies"}


def register(cls: type) -> type:
    """Class decorator: add a method class to :data:`REGISTRY` under ``cls.name`` and ``cls.partner``."""
    name, kind = getattr(cls, "name", ""), getattr(cls, "partner", None)
    if not (isinstance(cls, type) and name and kind in PARTNER_KINDS):
        raise TypeError(f"register needs a method class with a name and a partner kind in {PARTNER_KINDS}, "
                        f"got {cls!r}")
    known = REGISTRY.setdefault(name, {})
    if known.get(kind, cls) is not cls:
        raise ValueError(f"contact method {name!r} is already registered for the {kind} partner ({known[kind]!r})")
    known[kind] = cls
    return cls


def method_names(partner: str | None = None) -> tuple[str, ...]:
    """Registered method names, in registration order (``partner``: those with an implementation for that kind)."""
    return tuple(n for n, kinds in REGISTRY.items() if partner is None or partner in kinds)


def get_method(name: str, partner: str = RIGID) -> type:
    """The class of method ``name`` for the ``partner`` kind (ValueError naming the allowed ones otherwise)."""
    if name in REGISTRY and partner not in REGISTRY[name] and name in _MISSING_WHY.get(partner, {}):
        allowed = " or ".join(repr(n) for n in method_names(partner))
        raise ValueError(f"method={name!r} is not available for {_KIND_WORDS[partner]} "
                         f"({_MISSING_WHY[partner][name]}); use {allowed}")
    if partner not in REGISTRY.get(name, {}):
        where = "" if partner == RIGID else f" for {_KIND_WORDS[partner]}"
        raise ValueError(f"method must be one of {method_names(partner)}{where}, got {name!r}")
    return REGISTRY[name][partner]


def create(name: str, **params):
    """An instance of the rigid-obstacle method ``name``; ``params`` are its keywords (E, E_star, kappa0, ...)."""
    return get_method(name)(**params)
