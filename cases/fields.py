"""A case file's tables turned into records, field by field: unknown keys, required fields, types, allowed values
and ranges, each refused with one line (:class:`cases.records.CaseError`). The allowed words are the bottom
layer's (:mod:`vocabulary`); a scene's geometry keys take their choices and ranges from its
:class:`cases.scene_schema.SceneSchema`.
"""

from __future__ import annotations

import math
from dataclasses import MISSING, fields
from typing import Any

import cases.scene_schema as registry
from cases.records import (
    E_MAX,
    E_MIN,
    FACTOR_RANGE,
    MAX_LIST,
    MAX_SIZE_FACTOR,
    Analytic,
    CaseError,
    Discretisation,
    Geometry,
    Loading,
    Material,
    Solver,
)
from cases.records import short_repr as _r
from cases.scene_schema import _geometry_choices, _geometry_range, _geometry_specs
from vocabulary import (
    CASE_CONTROLS,
    CASE_FORMULATIONS,
    HALFPLANE,
    KINEMATICS,
    LINEAR_SOLVERS,
    MATERIAL_MODELS,
    METHODS,
    OBSTACLE,
)

_SECTIONS = {
    "material": Material,
    "geometry": Geometry,
    "loading": Loading,
    "discretisation": Discretisation,
    "solver": Solver,
    "analytic": Analytic,
}
_REQUIRED_SECTIONS = ("geometry", "loading")  # and [material] or [[body]] (_check_bodies)

# allowed values and ranges, checked per field (a scene's geometry keys: SceneSchema.choices / ranges)
_CHOICES = {
    ("loading", "control"): CASE_CONTROLS,
    ("discretisation", "degree"): (1, 2),
    ("solver", "method"): METHODS,
    ("material", "model"): MATERIAL_MODELS,
    ("solver", "kinematics"): KINEMATICS,
    ("solver", "traction"): (HALFPLANE, OBSTACLE),
    ("solver", "theta"): (1, 0, -1),
    ("solver", "formulation"): CASE_FORMULATIONS,
    ("solver", "linear_solver"): LINEAR_SOLVERS,
}
# (low, high, low_inclusive, high_inclusive, text)
_RANGES = {
    ("material", "E"): (E_MIN, E_MAX, True, True, f"E > 0, {E_MIN:g} <= E <= {E_MAX:g} (MPa)"),
    ("material", "nu"): (-1.0, 0.5, False, False, "-1 < nu < 0.5"),
    ("loading", "P"): (0.0, math.inf, False, False, "P > 0 (N/mm)"),
    ("loading", "half_width"): (0.0, math.inf, False, False, "half_width > 0 (mm)"),
    ("loading", "steps"): (1, 1000, True, True, "1 <= steps <= 1000"),
    ("discretisation", "h_contact"): (0.0, 1.0, False, True, "0 < h_contact <= 1 (fraction of half-width)"),
    ("discretisation", "ci_level"): (0.0, 1.0, False, True, "0 < ci_level <= 1"),
    ("discretisation", "growth"): (1.05, 2.0, True, True, "1.05 <= growth <= 2"),
    ("solver", "kappa0"): (*FACTOR_RANGE, True, True, f"kappa0 > 0, {FACTOR_RANGE[0]:g} <= kappa0 <= "
                           f"{FACTOR_RANGE[1]:g} (the LU solve resolves the bulk up to eps x kappa0)"),
    ("solver", "gamma0"): (*FACTOR_RANGE, True, True, f"gamma0 > 0, {FACTOR_RANGE[0]:g} <= gamma0 <= "
                           f"{FACTOR_RANGE[1]:g} (the LU solve resolves the bulk up to eps x gamma0)"),
}
_SEQ_RANGES = {
    ("loading", "d"): (0.0, math.inf, False, False, "every d > 0 (mm)"),
    ("discretisation", "levels"): (0.0, 1.0, False, True, "every level in (0, 1]"),
    ("discretisation", "budget_levels"): (0.0, 1.0, False, True, "every budget level in (0, 1]"),
    ("discretisation", "budget_widths"): (10.0, MAX_SIZE_FACTOR, True, True,
                                          f"every budget width in [10, {MAX_SIZE_FACTOR:g}] (W/a)"),
}
def _coerce(value: Any, annotation: str, where: str) -> Any:
    """Check ``value`` against a field annotation string (postponed annotations) and coerce it."""
    if not isinstance(annotation, str):  # a scene module without postponed annotations
        annotation = annotation.__name__ if isinstance(annotation, type) else str(annotation)
    ann = annotation.replace(" ", "")
    optional = ann.endswith("|None")
    base = ann.removesuffix("|None")
    if value is None:
        if optional:
            return None
        raise CaseError(f"{where} must not be empty")
    if base == "float":
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise CaseError(f"{where} = {_r(value)} has the wrong type; expected a number")
        if not math.isfinite(value):
            raise CaseError(f"{where} = {_r(value)} must be a finite number")
        return float(value)
    if base == "int":
        if isinstance(value, bool) or not isinstance(value, int):
            raise CaseError(f"{where} = {_r(value)} has the wrong type; expected an integer")
        return value
    if base == "bool":
        if not isinstance(value, bool):
            raise CaseError(f"{where} = {_r(value)} has the wrong type; expected true or false")
        return value
    if base == "str":
        if not isinstance(value, str):
            raise CaseError(f"{where} = {_r(value)} has the wrong type; expected a string")
        return value
    if base == "tuple[float,...]":
        if not isinstance(value, list | tuple) or any(
            isinstance(v, bool) or not isinstance(v, int | float) for v in value
        ):
            raise CaseError(f"{where} = {_r(value)} has the wrong type; expected a list of numbers")
        if len(value) > MAX_LIST:
            raise CaseError(f"{where} has {len(value)} entries; allowed: at most {MAX_LIST}")
        if not all(math.isfinite(v) for v in value):
            raise CaseError(f"{where} = {_r(value)} must hold finite numbers")
        return tuple(float(v) for v in value)
    if base == "tuple[str,...]":
        if not isinstance(value, list | tuple) or any(not isinstance(v, str) for v in value):
            raise CaseError(f"{where} = {_r(value)} has the wrong type; expected a list of strings")
        if len(value) > MAX_LIST:
            raise CaseError(f"{where} has {len(value)} entries; allowed: at most {MAX_LIST}")
        return tuple(value)
    raise AssertionError(f"unhandled annotation {annotation}")  # pragma: no cover


def _in_range(value: float, spec: tuple) -> bool:
    lo, hi, lo_inc, hi_inc, _ = spec
    ok_lo = value >= lo if lo_inc else value > lo
    ok_hi = value <= hi if hi_inc else value < hi
    return ok_lo and ok_hi


def _build(cls: type, table: Any, where: str, *, partial_ok: bool = False) -> Any:
    """Build a section record from a TOML table, validating keys, types and ranges."""
    if not isinstance(table, dict):
        raise CaseError(f"{where} must be a table")
    section = where.rsplit(": ", 1)[-1]
    if cls is Geometry:
        return _build_geometry(table, where)
    known = {f.name: f for f in fields(cls)}
    values = _table_values(table, known, where, choices=lambda name: _CHOICES.get((section, name)),
                           value_range=lambda name: _RANGES.get((section, name)),
                           item_range=lambda name: _SEQ_RANGES.get((section, name)))
    return cls(**values)


def _table_values(table: dict, known: dict, where: str, *, choices, value_range, item_range=None) -> dict:
    """The values of a TOML table for the fields ``known`` (name -> dataclass Field): unknown keys, missing required
    fields, types (:func:`_coerce`), ``choices(name)``, ``value_range(name)`` and the range of every item of a
    sequence ``item_range(name)`` checked in field order, each refused with one line (:class:`CaseError`)."""
    for key in table:
        if key not in known:
            raise CaseError(f"{where}.{_r(key)[1:-1]} is an unknown key; allowed keys: {', '.join(known)}")
    values = {}
    for name, f in known.items():
        if name in table:
            raw = table[name]
        elif f.default is not MISSING or f.default_factory is not MISSING:
            continue
        else:
            raise CaseError(f"{where}.{name} is a required field and is missing")
        value = _coerce(raw, f.type, f"{where}.{name}")
        if value is not None:
            allowed = choices(name)
            if allowed is not None and value not in allowed:
                text = ", ".join(repr(c) for c in allowed)
                raise CaseError(f"{where}.{name} = {_r(value)} is not allowed; allowed values: {text}")
            spec = value_range(name)
            if spec is not None and not _in_range(value, spec):
                raise CaseError(f"{where}.{name} = {_r(value)} is out of range; allowed: {spec[4]}")
            spec = item_range(name) if item_range is not None else None
            if spec is not None and not all(_in_range(v, spec) for v in value):
                raise CaseError(f"{where}.{name} = {_r(list(value))} is out of range; allowed: {spec[4]}")
        values[name] = value
    return values


def _build_geometry(table: dict, where: str) -> Geometry:
    """The ``[geometry]`` record of a run: the keys of every registered scene are validated (type, choices, range)
    in the order of :func:`_geometry_specs`; the scene's record is built from its own keys (a given key it does not
    read is refused later, :func:`_check_used_geometry`)."""
    scene = table.get("scene")
    scene = scene if isinstance(scene, str) and scene in registry._SCENE_SCHEMAS else None
    known = _geometry_specs(scene)
    values = _table_values(table, known, where, choices=lambda name: _geometry_choices(scene, name),
                           value_range=lambda name: _geometry_range(scene, name))
    cls = registry.scene_schema(values["scene"]).geometry
    own = {f.name for f in fields(cls)}
    return cls(**{k: v for k, v in values.items() if k in own})


