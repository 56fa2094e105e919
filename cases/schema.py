"""Typed, frozen case records loaded from ``cases/<name>.toml``.

A case names its geometry, material, loading, discretisation, solver method, which analytic
predictions apply and the tolerances it must meet. Units: mm, N, MPa; loads are per unit thickness
(N/mm); angles are in radians.

Validation is strict: an unknown key, a wrong type, a missing required field or an out-of-range value
raises :class:`CaseError` whose message is ONE line naming the file, the field and the allowed range.
The command-line layer turns it into exit code 2 before anything is written. Values and keys are cut to
``MAX_ECHO`` characters in messages, so a huge value is never echoed back whole.

Every accepted field is used, or refused here: ``[case] name`` is a slug (it names the output folder);
``[analytic] predictions`` must be ones the scene and indenter compute; a geometry field the scene or indenter
ignores is refused when given; each scene names the load controls it supports; ``[solver] formulation`` switches
itself to the mixed one from ``nu >= NU_MIXED`` (``"auto"``), and an explicit ``"displacement"`` beyond
``NU_DISPLACEMENT_MAX`` is refused with that advice. The model hierarchy (``docs/models.md``): ``[material] model``
(linear or a hyperelastic model) goes with ``[solver] kinematics`` (small/convective or finite), and finite
kinematics needs ``traction = "obstacle"``, the displacement formulation and a scene that supports it; other
combinations are refused. Magnitudes the solver cannot represent are refused with their cause (E beyond
``E_MAX``; a scene adds its own, e.g. a contact too small for the indenter's size).

Bodies: a single-body scene takes its material from ``[material]``. A scene with several elastic bodies
(:attr:`SceneSchema.bodies` names their roles, in order) takes them from a ``[[body]]`` array of tables instead, one
per body in that order, each with ``name`` (its label in reports and ``metrics.json``: 1 to 64 letters, digits,
``_`` or ``-``, distinct), ``E``, ``nu`` and ``model`` (ranges and choices as ``[material]``'s); ``[material]`` and
``[[body]]`` are never both given, and ``run.material`` is the first body's material (the body the solver options'
E and nu describe). A variant overrides bodies with ``body = [{...}, {...}]``: one table per body, in order, each
holding only the fields it changes (``{}`` keeps a body as it is).

A case may carry ``[[variant]]`` tables. Each variant overrides fields of the base case (same section
layout, e.g. ``[variant.solver] kinematics = "convective"``) and is run as its own FEM run; the case's
``metrics.json`` holds one entry per variant.

Scenes: this module names none. Each scene module (``workbench/scenes/<scene>.py``) registers a
:class:`SceneSchema` with :func:`register_scene_schema` when it is imported (``import workbench.scenes`` imports
them all; every entry point that loads a case does it first, and so does ``tests/conftest.py``). The schema holds:

* ``geometry``: the scene's geometry record, a frozen dataclass subclassing :class:`Geometry` (``scene``,
  ``indenter``) whose further fields, each with a default and a plain annotation (``float``, ``int``, ``bool``,
  ``str``, optionally ``| None``), are the scene's ``[geometry]`` keys; ``run.geometry`` is an instance of it;
* ``indenters``: indenter -> the geometry keys a run with it reads (a key given but not read is refused);
  ``predictions``: indenter -> the analytic predictions the scene computes for it;
* ``choices`` / ``ranges`` of its geometry keys, the load ``controls`` it supports, its ``tolerances`` keys and
  ``band_quantities``, and what the solver supports on it (``finite``, ``mixed``, ``budget_widths``);
* three hooks raising :class:`CaseError`: ``check_geometry(run, where)`` (before the loading's checks),
  ``check_load(run, where)`` (after them) and ``check_case(case, runs, where)`` (after the predictions' check).

A new scene registers its own schema; it touches neither this file nor another scene's module. A case whose
``[geometry] scene`` names no registered scene is refused in one line listing the registered ones.
"""
from __future__ import annotations

import copy
import math
import tomllib
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from cases.checks import (
    _check_bands,
    _check_predictions,
    _check_run,
    _check_used_geometry,
    effective_formulation,
)
from cases.fields import (  # noqa: F401
    _CHOICES,
    _RANGES,
    _REQUIRED_SECTIONS,
    _SECTIONS,
    _SEQ_RANGES,
    _build,
    _coerce,
    _table_values,
)
from cases.records import (  # noqa: F401  (the records and limits: cases.schema re-exports them)  # noqa: F401
    BAND_KINDS,
    BUDGET_SPAN,
    CASE_DIR,
    CASE_LEVEL_DEFAULTS,
    CASE_NAME_RE,
    COMMAND_PREFIXES,
    CONTROL_NEEDS,
    E_MAX,
    E_MIN,
    FACTOR_RANGE,
    MAX_DESCRIPTION,
    MAX_ECHO,
    MAX_FILE_BYTES,
    MAX_LABEL,
    MAX_LIST,
    MAX_SIZE_FACTOR,
    MAX_TOLERANCE,
    MAX_VARIANTS,
    NU_DISPLACEMENT_MAX,
    NU_MIXED,
    RESERVED_NAMES,
    Analytic,
    Body,
    CaseError,
    Discretisation,
    Geometry,
    Loading,
    Material,
    Run,
    Solver,
    _path_repr,
    _r,
    short_repr,
)
from cases.scene_schema import (  # noqa: F401
    _SCENE_SCHEMAS,
    SceneSchema,
    _tolerance_keys,
    register_scene_schema,
    scene_schema,
    scene_schemas,
)

__all__ = [
    "CASE_DIR",
    "CONTROL_NEEDS",
    "SceneSchema",
    "register_scene_schema",
    "scene_schema",
    "scene_schemas",
    "short_repr",
    "CASE_LEVEL_DEFAULTS",
    "Analytic",
    "Body",
    "Case",
    "CaseError",
    "Discretisation",
    "Geometry",
    "Loading",
    "Material",
    "Run",
    "Solver",
    "case_names",
    "effective_formulation",
    "load_case",
    "CASE_NAME_RE",
    "MAX_ECHO",
    "RESERVED_NAMES",
    "COMMAND_PREFIXES",
    "label_folder",
]


@dataclass(frozen=True)
class Case:
    """A verification scene as loaded from ``cases/<name>.toml``."""

    name: str
    path: Path
    description: str
    material: Material
    geometry: Geometry
    loading: Loading
    discretisation: Discretisation
    solver: Solver
    analytic: Analytic
    tolerances: dict[str, float] = field(default_factory=dict)
    bands: dict[str, tuple[str, ...]] = field(default_factory=dict)
    variants: tuple[dict[str, Any], ...] = ()
    bodies: tuple[Body, ...] = ()

    def runs(self, *, h_contact: float | None = None) -> tuple[Run, ...]:
        """The runs of this case: one per variant (or the base case alone), optionally at another h_c."""
        out = []
        raw_variants = self.variants or ({"label": "base"},)
        for i, var in enumerate(raw_variants):
            where = f"{self.path.name}: variant[{i}]"
            sections = {}
            for name, cls in _SECTIONS.items():
                if name == "analytic":
                    continue
                base = getattr(self, name)
                over = var.get(name, {})
                merged = {f.name: getattr(base, f.name) for f in fields(base)} | over
                sections[name] = _build(cls, merged, f"{where}: {name}", partial_ok=False)
            if h_contact is not None:
                d = sections["discretisation"]
                sections["discretisation"] = replace(d, h_contact=h_contact)
            bodies = _variant_bodies(self.bodies, var.get("body"), where)
            if bodies:
                sections["material"] = bodies[0].material
            run = Run(label=str(var.get("label", f"variant{i}")), **sections, bodies=bodies)
            _check_run(run, where)
            out.append(run)
        return tuple(out)


def label_folder(label: str) -> str:
    """The folder (and file-name part) of a run label: ``vtk/<folder>/``, ``render_<folder>.png``.

    ASCII letters, digits, ``-``, ``_`` and ``.`` are kept, every other character becomes ``_``, and a leading
    ``.`` becomes ``_`` (never ``.``, ``..`` or a hidden name). Two labels of one case that map to the same
    folder are refused by :func:`load_case`.
    """
    text = "".join(c if (c.isascii() and c.isalnum()) or c in "-_." else "_" for c in str(label))
    return "_" + text[1:] if text.startswith(".") else text


KNOWN_CASES_CHARS = 160  # the known-case names an error line lists, at most (the line stays one short line)


def _known_cases() -> str:
    """The shipped case names for an error line: all of them while they fit in ``KNOWN_CASES_CHARS``, else the
    first ones and how many there are (``workbench list`` shows them all)."""
    names = case_names()
    if not names:
        return "none"
    text = ", ".join(names)
    if len(text) <= KNOWN_CASES_CHARS:
        return text
    head = text[:KNOWN_CASES_CHARS].rsplit(", ", 1)[0]
    return f"{head}, ... ({len(names)} in all: `workbench list`)"


def load_case(path: str | Path) -> Case:
    """Load and validate a case file.

    Args:
        path: A path to a TOML file, or a case name resolved as ``cases/<name>.toml``.

    Returns:
        The frozen :class:`Case` record.

    Raises:
        CaseError: One line naming the file, the field and the allowed range.
    """
    known = _known_cases()
    p = Path(path)
    if p.suffix != ".toml":
        if not CASE_NAME_RE.fullmatch(str(path)):
            try:
                kind = ("is a folder" if p.is_dir() else "is not a regular file (a FIFO, a device or a socket)"
                        if p.exists() and not p.is_file() else "is not a .toml file" if p.exists() else None)
            except OSError:
                kind = None
            what = kind or "no such case file"
            raise CaseError(f"{_path_repr(str(path))}: {what}; known cases: {known} (or a path to a .toml file)")
        p = CASE_DIR / f"{path}.toml"
    where = _r(p.name)[1:-1]
    raw = _read_toml(p, str(path), known)
    allowed_top = {"case", *_SECTIONS, "tolerances", "bands", "variant", "body"}
    for key in raw:
        if key not in allowed_top:
            raise CaseError(f"{where}: {_r(key)[1:-1]} is an unknown key; "
                            f"allowed keys: {', '.join(sorted(allowed_top))}")
    head = raw.get("case", {})
    if not isinstance(head, dict):
        raise CaseError(f"{where}: case must be a table")
    for key in head:
        if key not in ("name", "description"):
            raise CaseError(f"{where}: case.{_r(key)[1:-1]} is an unknown key; allowed keys: name, description")
    name = head.get("name", p.stem)
    if not isinstance(name, str) or not CASE_NAME_RE.fullmatch(name):
        field_ = "case.name" if "name" in head else "case.name (the file name)"
        raise CaseError(f"{where}: {field_} = {_r(name)} is not allowed; allowed: 1 to 64 letters, digits, '_' "
                        "or '-' (it names the output folder)")
    if name.lower() in RESERVED_NAMES:
        field_ = "[case] name" if "name" in head else "[case] name (the file name)"
        raise CaseError(f"{where}: {field_} = {_r(name)} is reserved (the workbench's own folders and files under "
                        f"--out: {', '.join(RESERVED_NAMES)}); allowed: any other name")
    if name.lower().startswith(COMMAND_PREFIXES):
        field_ = "[case] name" if "name" in head else "[case] name (the file name)"
        raise CaseError(f"{where}: {field_} = {_r(name)} starts with a reserved prefix (the folders of workbench "
                        f"score, export, external and forcelaw under --out: "
                        f"{', '.join(p + '<case>' for p in COMMAND_PREFIXES)}); allowed: any other name")
    for sec in _REQUIRED_SECTIONS:
        if sec not in raw:
            raise CaseError(f"{where}: [{sec}] is a required section and is missing")
    bodies = _parse_bodies(raw, where)
    records = {
        sec: _build(cls, raw.get(sec, {}), f"{where}: {sec}") for sec, cls in _SECTIONS.items()
        if sec != "material" or sec in raw
    }
    _check_bodies(records["geometry"].scene, bodies, "material" in raw, where)
    if bodies:
        records["material"] = bodies[0].material
    tolerances = raw.get("tolerances", {})
    if not isinstance(tolerances, dict):
        raise CaseError(f"{where}: tolerances must be a table")
    tol = {}
    for key, value in tolerances.items():
        if key not in _tolerance_keys():
            raise CaseError(f"{where}: tolerances.{_r(key)[1:-1]} is an unknown key; "
                            f"allowed keys: {', '.join(_tolerance_keys())}")
        if (isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value)
                or not 0 < value <= MAX_TOLERANCE):
            raise CaseError(f"{where}: tolerances.{key} = {_r(value)} is out of range; allowed: a finite number "
                            f"with 0 < {key} <= {MAX_TOLERANCE:g}")
        tol[key] = float(value)
    variants = raw.get("variant", [])
    if not isinstance(variants, list) or any(not isinstance(v, dict) for v in variants):
        raise CaseError(f"{where}: variant must be an array of tables ([[variant]])")
    if len(variants) > MAX_VARIANTS:
        raise CaseError(f"{where}: {len(variants)} [[variant]] tables; allowed: at most {MAX_VARIANTS}")
    description = head.get("description", "")
    if not isinstance(description, str) or len(description) > MAX_DESCRIPTION:
        raise CaseError(f"{where}: case.description is not allowed ({type(description).__name__} of "
                        f"{len(description) if isinstance(description, str) else '?'} characters); allowed: a string "
                        f"of at most {MAX_DESCRIPTION} characters")
    for i, var in enumerate(variants):
        for key, value in var.items():
            if key == "label":
                if not isinstance(value, str) or not 0 < len(value) <= MAX_LABEL or not value.isprintable():
                    raise CaseError(f"{where}: variant[{i}].label = {_r(value)} is not allowed; allowed: a string of "
                                    f"1 to {MAX_LABEL} printable characters")
            elif key == "body" and bodies:
                continue  # checked with the runs (_variant_bodies)
            elif key in ("body", "material") and (key == "body") != bool(bodies):
                allowed = ("material (a single-body case)" if key == "body"
                           else "body = [{...}, ...] (one table per body)")
                raise CaseError(f"{where}: variant[{i}].{key} is not allowed in a case with "
                                f"{'[material]' if key == 'body' else '[[body]]'}; allowed: {allowed}")
            elif key not in _SECTIONS or key == "analytic":
                raise CaseError(
                    f"{where}: variant[{i}].{_r(key)[1:-1]} is an unknown key; allowed keys: label, "
                    + ", ".join(s for s in _SECTIONS if s != "analytic")
                )
            elif not isinstance(value, dict):
                raise CaseError(f"{where}: variant[{i}].{key} must be a table")
    case = Case(
        name=name,
        path=p,
        description=description,
        tolerances=tol,
        bands=_parse_bands(raw.get("bands", {}), where),
        variants=tuple(copy.deepcopy(variants)),
        bodies=bodies,
        **records,
    )
    runs = case.runs()  # validate every variant now, so no run starts on a bad file
    labels = [r.label for r in runs]
    if len(set(labels)) != len(labels):
        raise CaseError(f"{where}: variant labels must be unique; got {_r(labels)}")
    folders: dict[str, int] = {}
    for i, label in enumerate(labels):  # each run writes vtk/<folder>/: two labels must not share one
        j = folders.setdefault(label_folder(label), i)
        if j != i:
            raise CaseError(f"{where}: variant[{i}].label = {_r(label)} and variant[{j}].label = {_r(labels[j])} "
                            f"both name the run folder {_r(label_folder(label))}; allowed: labels that differ in "
                            "their ASCII letters, digits, '-', '_' or '.' (other characters become '_')")
    for i, run in enumerate(runs):
        given = set(raw.get("geometry", {})) | set((variants[i] if variants else {}).get("geometry", {}))
        _check_used_geometry(run, given, f"{where}: variant[{i}]" if variants else where)
    _check_predictions(case, runs, where)
    _check_bands(case, runs, where)
    return case


def _read_toml(p: Path, given: str, known: str) -> dict:
    """Read and parse a case file: one line for a folder, a missing file, a file too large, bytes that are not
    UTF-8 (with the byte offset) or TOML nested too deeply. A UTF-8 byte-order mark is accepted."""
    where = _r(p.name)[1:-1]
    if p.is_dir():
        raise CaseError(f"{_r(given)}: is a folder, not a case file; allowed: a .toml file or a case name ({known})")
    try:
        if p.exists() and not p.is_file():  # never opened: reading a FIFO would hang, a device never end
            raise CaseError(f"{where}: is not a regular file (a FIFO, a device or a socket); allowed: a .toml "
                            "file or a case name")
        found = p.is_file()
        size = p.stat().st_size if found else 0
        if size > MAX_FILE_BYTES:
            raise CaseError(f"{where}: the case file has {size} bytes; allowed: at most {MAX_FILE_BYTES} bytes")
        data = p.read_bytes() if found else b""
    except OSError as exc:
        raise CaseError(f"{_r(given)}: cannot read the case file: {_r(exc.strerror or str(exc))[1:-1]}") from None
    if not found:
        raise CaseError(f"{_r(given)}: no such case file; known cases: {known}")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise CaseError(f"{where}: the case file is not UTF-8 text: byte 0x{data[exc.start]:02x} at byte offset "
                        f"{exc.start}; allowed: a UTF-8 text file") from None
    text = text.removeprefix("\ufeff")  # a byte-order mark (some editors write one): accepted
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise CaseError(f"{where}: malformed TOML: {_r(str(exc).splitlines()[0])[1:-1]}") from None
    except RecursionError:
        raise CaseError(f"{where}: malformed TOML: arrays or tables nested too deeply; allowed: a case file "
                        "(its deepest nesting is 3)") from None
    return raw


_BODY_FIELDS = {f.name: f for f in fields(Body)}


def _body(table: Any, where: str) -> Body:
    """One ``[[body]]`` table: keys, types, the material's choices and ranges, and a slug ``name``."""
    if not isinstance(table, dict):
        raise CaseError(f"{where} must be a table (name, E, nu, model)")
    values = _table_values(table, _BODY_FIELDS, where, choices=lambda n: _CHOICES.get(("material", n)),
                           value_range=lambda n: _RANGES.get(("material", n)))
    if not CASE_NAME_RE.fullmatch(values["name"]):
        raise CaseError(f"{where}.name = {_r(values['name'])} is not allowed; allowed: 1 to 64 letters, digits, '_' "
                        "or '-' (it labels the body in reports)")
    return Body(**values)


def _parse_bodies(raw: dict, where: str) -> tuple[Body, ...]:
    """The ``[[body]]`` array of tables (empty if not given)."""
    if "body" not in raw:
        return ()
    tables = raw["body"]
    if not isinstance(tables, list) or not tables or len(tables) > MAX_LIST:
        raise CaseError(f"{where}: body must be an array of tables ([[body]], 1 to {MAX_LIST} entries)")
    bodies = tuple(_body(t, f"{where}: body[{i}]") for i, t in enumerate(tables))
    names = [b.name for b in bodies]
    if len(set(names)) != len(names):
        raise CaseError(f"{where}: body names must be distinct; got {_r(names)}")
    return bodies


def _check_bodies(scene: str, bodies: tuple[Body, ...], material_given: bool, where: str) -> None:
    """A scene with several bodies takes exactly its number of ``[[body]]`` tables and no ``[material]``; any other
    scene takes ``[material]`` and no ``[[body]]``."""
    roles = scene_schema(scene).bodies
    if bodies and material_given:
        raise CaseError(f"{where}: [material] and [[body]] are both given; allowed: one of them ([[body]] for a "
                        f"{scene} scene)" if roles else f"{where}: [material] and [[body]] are both given; allowed: "
                        f"[material] (the {scene} scene has one body)")
    if not roles:
        if bodies:
            raise CaseError(f"{where}: [[body]] is not allowed for the {scene} scene (one body); allowed: [material]")
        if not material_given:
            raise CaseError(f"{where}: [material] is a required section and is missing")
        return
    if len(bodies) != len(roles):
        got = f"{len(bodies)} [[body]] tables" if bodies else "[material]" if material_given else "no [[body]]"
        raise CaseError(f"{where}: the {scene} scene needs {len(roles)} [[body]] tables (name, E, nu, model), in "
                        f"order: {'; '.join(roles)}; got {got}")


def _variant_bodies(base: tuple[Body, ...], over: Any, where: str) -> tuple[Body, ...]:
    """The bodies of a variant: ``body = [{...}, ...]`` (one table per body, in order) overrides the given fields."""
    if over is None:
        return base
    if not isinstance(over, list) or len(over) != len(base) or any(not isinstance(t, dict) for t in over):
        raise CaseError(f"{where}: body = {_r(over)} is not allowed; allowed: a list of {len(base)} tables (one per "
                        "[[body]], in order; {} keeps a body)")
    bodies = tuple(_body({f.name: getattr(b, f.name) for f in fields(b)} | t, f"{where}: body[{i}]")
                   for i, (b, t) in enumerate(zip(base, over, strict=True)))
    if len({b.name for b in bodies}) != len(bodies):
        raise CaseError(f"{where}: body names must be distinct; got {_r([b.name for b in bodies])}")
    return bodies


def _parse_bands(raw: Any, where: str) -> dict[str, tuple[str, ...]]:
    """``[bands]``: ``contain_theory`` / ``exclude_alt`` = lists of budget quantities (see BAND_KINDS)."""
    if not isinstance(raw, dict):
        raise CaseError(f"{where}: bands must be a table; allowed keys: {', '.join(BAND_KINDS)}")
    out = {}
    for key, value in raw.items():
        if key not in BAND_KINDS:
            raise CaseError(f"{where}: bands.{_r(key)[1:-1]} is an unknown key; allowed keys: {', '.join(BAND_KINDS)}")
        if (not isinstance(value, list) or not value or any(not isinstance(v, str) for v in value)
                or len(set(value)) != len(value)):
            raise CaseError(f"{where}: bands.{key} = {_r(value)} is not allowed; allowed: a non-empty list of "
                            "distinct budget quantity names")
        out[key] = tuple(value)
    return out


def case_names() -> list[str]:
    """Names of the case files in ``cases/``."""
    return sorted(p.stem for p in CASE_DIR.glob("*.toml"))

