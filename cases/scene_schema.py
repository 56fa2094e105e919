"""What the case schema knows of each scene: :class:`SceneSchema`, registered by the scene's module.

A scene (``workbench/scenes/<name>.py``) registers its schema with :func:`register_scene_schema` at import; the
case loader (:mod:`cases.schema`) and its checks (:mod:`cases.fields`, :mod:`cases.checks`) read the registry.
This module names no scene.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import MISSING, dataclass, field, fields
from typing import Any

from cases.records import CONTROL_NEEDS, Geometry

__all__ = ["SceneSchema", "register_scene_schema", "scene_schemas", "scene_schema"]


@dataclass(frozen=True)
class SceneSchema:
    """What the case schema knows of one scene, registered by the scene's module (:func:`register_scene_schema`).

    Attributes:
        name: The ``[geometry] scene`` value.
        geometry: The scene's geometry record: a frozen dataclass subclassing :class:`Geometry`; its further fields
            (each with a default) are the scene's ``[geometry]`` keys.
        indenters: Indenter -> the geometry keys a run with it reads (besides ``scene`` and ``indenter``); its keys
            are the scene's indenters, in order.
        predictions: Indenter -> the analytic predictions the scene computes for it (``[analytic] predictions``).
        controls: The ``loading.control`` values the scene supports (keys of :data:`CONTROL_NEEDS`).
        choices: Geometry key -> its allowed values.
        ranges: Geometry key -> ``(low, high, low_inclusive, high_inclusive, text)``.
        tolerances: ``[tolerances]`` key -> its meaning (the keys the scene's checks read).
        band_quantities: The error-budget quantities ``[bands]`` may name.
        band_note: How a band quantity may be qualified on this scene (e.g. ``"optionally name[k], patch k"``), or "".
        finite: The scene supports ``solver.kinematics = "finite"``.
        mixed: The scene supports the mixed formulation (it needs an analytic obstacle).
        budget_widths: None if the scene's error budget takes ``budget_widths`` (then required with
            ``budget_levels``), else the reason it refuses them.
        bodies: The roles of the scene's elastic bodies, in ``[[body]]`` order (one text each), or empty: a
            single-body scene whose material is ``[material]``.
        check_geometry: ``(run, where) -> None``: the scene's own checks of a run, before the loading's.
        check_load: ``(run, where) -> None``: the scene's checks of the load, after the loading's.
        check_case: ``(case, runs, where) -> None``: case-level checks (e.g. a prediction that compares two runs).
    """

    name: str
    geometry: type
    indenters: dict[str, frozenset]
    predictions: dict[str, tuple[str, ...]]
    controls: tuple[str, ...]
    choices: dict[str, tuple] = field(default_factory=dict)
    ranges: dict[str, tuple] = field(default_factory=dict)
    tolerances: dict[str, str] = field(default_factory=dict)
    band_quantities: tuple[str, ...] = ()
    band_note: str = ""
    finite: bool = False
    mixed: bool = False
    budget_widths: str | None = None
    bodies: tuple[str, ...] = ()
    check_geometry: Callable[[Any, str], None] | None = None
    check_load: Callable[[Any, str], None] | None = None
    check_case: Callable[[Any, tuple, str], None] | None = None

    def geometry_fields(self) -> dict[str, Any]:
        """The scene's own geometry fields (name -> dataclass Field), in declaration order."""
        return {f.name: f for f in fields(self.geometry) if f.name not in ("scene", "indenter")}


_SCENE_SCHEMAS: dict[str, SceneSchema] = {}


def register_scene_schema(schema: SceneSchema) -> SceneSchema:
    """Register a scene's case schema under ``schema.name`` (the scene module calls it at import).

    Registering the same name again replaces the entry (a module reloaded). The geometry record must subclass
    :class:`Geometry`, every geometry field must have a default, and every indenter's keys must be its fields.
    """
    if not (isinstance(schema.geometry, type) and issubclass(schema.geometry, Geometry)):
        raise TypeError(f"scene {schema.name!r}: geometry must be a dataclass subclassing cases.schema.Geometry")
    own = schema.geometry_fields()
    for name, f in own.items():
        if f.default is MISSING and f.default_factory is MISSING:
            raise TypeError(f"scene {schema.name!r}: geometry field {name!r} needs a default")
    for indenter, keys in schema.indenters.items():
        if not set(keys) <= set(own):
            raise TypeError(f"scene {schema.name!r}: indenter {indenter!r} reads {sorted(set(keys) - set(own))}, "
                            f"which are not fields of {schema.geometry.__name__}")
    if not set(schema.controls) <= set(CONTROL_NEEDS):
        raise TypeError(f"scene {schema.name!r}: controls must be among {tuple(CONTROL_NEEDS)}")
    _SCENE_SCHEMAS[schema.name] = schema
    return schema


def scene_schemas() -> tuple[SceneSchema, ...]:
    """The registered scene schemas, in registration order."""
    if not _SCENE_SCHEMAS:
        raise RuntimeError("no scene is registered with cases.schema: import workbench.scenes (each scene module "
                           "registers its SceneSchema) before loading a case")
    return tuple(_SCENE_SCHEMAS.values())


def scene_schema(name: str) -> SceneSchema:
    """The registered schema of scene ``name`` (KeyError if none)."""
    scene_schemas()
    return _SCENE_SCHEMAS[name]


def _geometry_specs(scene: str | None) -> dict[str, Any]:
    """Every registered geometry key -> its dataclass Field (``scene``, ``indenter``, then each scene's fields in
    registration order; a key two scenes declare takes the Field of ``scene`` if it is one of them)."""
    specs = {f.name: f for f in fields(Geometry)}
    for sch in scene_schemas():
        for name, f in sch.geometry_fields().items():
            specs.setdefault(name, f)
    if scene in _SCENE_SCHEMAS:
        specs |= _SCENE_SCHEMAS[scene].geometry_fields()
    return specs


def _geometry_choices(scene: str | None, name: str) -> tuple | None:
    """The allowed values of geometry key ``name`` (the scene's own, else the first scene that declares it)."""
    schemas = scene_schemas()
    if name == "scene":
        return tuple(s.name for s in schemas)
    if name == "indenter":
        return tuple(dict.fromkeys(i for s in schemas for i in s.indenters))
    own = _SCENE_SCHEMAS.get(scene)
    if own is not None and name in own.geometry_fields():
        return own.choices.get(name)
    return next((s.choices.get(name) for s in schemas if name in s.geometry_fields()), None)


def _geometry_range(scene: str | None, name: str) -> tuple | None:
    """The range of geometry key ``name`` (the scene's own, else the first scene that declares it)."""
    own = _SCENE_SCHEMAS.get(scene)
    if own is not None and name in own.geometry_fields():
        return own.ranges.get(name)
    return next((s.ranges.get(name) for s in scene_schemas() if name in s.geometry_fields()), None)


def _tolerance_keys() -> dict[str, str]:
    """Every registered scene's ``[tolerances]`` keys (registration order)."""
    out: dict[str, str] = {}
    for sch in scene_schemas():
        for key, text in sch.tolerances.items():
            out.setdefault(key, text)
    return out


