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
import re
import tomllib
from collections.abc import Callable
from dataclasses import MISSING, dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from vocabulary import (
    CASE_CONTROLS,
    CASE_FORMULATIONS,
    FINITE,
    HALFPLANE,
    KINEMATICS,
    LINEAR,
    LINEAR_SOLVERS,
    MATERIAL_MODELS,
    METHODS,
    OBSTACLE,
    model_conflict,
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

CASE_DIR = Path(__file__).resolve().parent

# A case name names its output folder and its mesh-cache files: a slug, nothing path-like.
CASE_NAME_RE = re.compile(r"[A-Za-z0-9_-]{1,64}")
# Names the workbench gives its own folders and files under the output folder (``workbench.paths``): no case may
# take one (its results folder would replace them). Compared case-insensitively.
RESERVED_NAMES = ("mesh_cache", "analytic", "logs", "ci", "ci_report", "convergence", "stability", "bench",
                  "validity", "report", "results", "faults", "vtk")
# The folders of ``workbench score``, ``export`` and ``external`` are ``<prefix><case>``: no case name may start
# with one (a case named ``score_x`` would replace the score of case x). Compared case-insensitively.
COMMAND_PREFIXES = ("score_", "export_", "external_")
MAX_LABEL = 64  # characters of a [[variant]] label (it names files: cut in file names, refused beyond)
MAX_ECHO = 60  # characters of a value or key echoed in an error message
# Near-incompressibility (fem.postprocess.LOCKING_NU: the solver's 'near-incompressible' warning starts there).
# formulation = "auto" uses the Taylor-Hood mixed formulation from NU_MIXED on; an explicit "displacement"
# is refused above NU_DISPLACEMENT_MAX (the stability study: P2 displacement at nu = 0.4999 diverged, at 0.499
# it converged with RMS/p0 8 % and named warnings).
NU_MIXED = 0.45
NU_DISPLACEMENT_MAX = 0.499
# Extreme magnitudes. E: kappa = kappa0 E / h and the SNES tolerance 1e-13 E L must stay finite (E = 1e300
# gave inf/NaN residuals); the stability study's scale sweep covers 1e-3 ... 1e6 MPa.
E_MAX = 1e12
# A body's size over the contact half-width (scenes whose body is sized from the contact, and the budget's
# truncation study): a size of 1e6 a (height 40 a) gave a 1.9 % load-balance error with no warning; 1e5 a x 1e5 a
# measured 7.5e-13. Sizes beyond 1e4 a are refused.
MAX_SIZE_FACTOR = 1e4
BUDGET_SPAN = 8.0  # error budget: largest over smallest level (the grading is refined with h_c)
# [bands]: checks whose tolerance is the error budget's band (make run only). A listed quantity selects every
# budget row of that quantity (one per run, or one per step and patch, as the scene's budget has them);
# "name[k]" selects the rows of patch k only. The quantities are the scene's (SceneSchema.band_quantities).
BAND_KINDS = {
    "contain_theory": "the band (GCI + truncation) of the quantity contains its theory",
    "exclude_alt": "the band of the quantity excludes its alternative theory (e.g. first order, Hertz)",
    "exclude_theory": "the band of the quantity excludes its theory (a theory the scene shows to fail)",
}
# Penalty / Nitsche factors: the contact terms add kappa0 (gamma0) times the bulk stiffness entries of the contact
# rows (kappa = kappa0 E / h integrated over an edge of length h ~ kappa0 E). LU resolves the bulk part of those
# rows to about eps * kappa0 relative (eps = 2.2e-16): at the upper bound 1e12 that is 2e-4, beyond it the bulk is
# lost in round-off (1e303 even overflows to inf in the compiled form). The stability study sweeps 1e0 ... 1e10.
# Below 1e-6 the contact term is a millionth of the bulk stiffness: penetrations of 1e6 times the elastic approach,
# no contact to speak of. Between 1e-6 and ~1 a Nitsche factor may lose coercivity and the solve diverges: a named
# solver failure (exit 1, logs/<case>.log; tests/test_stability_faults.py provokes it with gamma0 = 1e-6).
FACTOR_RANGE = (1e-6, 1e12)
# Limits no real case reaches (the largest case file is 3 kB): refused in one line, so a huge file is never copied.
MAX_FILE_BYTES = 1_000_000
MAX_DESCRIPTION = 2000  # characters
MAX_LIST = 100  # entries of levels, d, budget lists
MAX_VARIANTS = 100
MAX_TOLERANCE = 10.0  # a relative error of 1000 %: anything above checks nothing
E_MIN = 1e-6  # MPa: the stability study's scale sweep starts at 1e-3
# What each load control needs (the loading checks; a scene names the controls it supports).
CONTROL_NEEDS = {"force": "with P or half_width", "displacement": "with d"}


def short_repr(value: Any) -> str:
    """``repr(value)`` cut to MAX_ECHO characters (a 200 kB string is never echoed back whole)."""
    text = repr(value)
    return text if len(text) <= MAX_ECHO else text[:MAX_ECHO - 3] + "..."


_r = short_repr


def _path_repr(text: str) -> str:
    """A path quoted for an error line: at most MAX_ECHO characters, cut in the middle (its file name stays)."""
    text = repr(str(text))
    if len(text) <= MAX_ECHO:
        return text
    head = MAX_ECHO // 3
    return text[:head] + "..." + text[len(text) - (MAX_ECHO - head - 3):]

class CaseError(ValueError):
    """A case file is malformed or holds an out-of-range value (one-line message)."""


# --- records -----------------------------------------------------------------------------------


@dataclass(frozen=True)
class Material:
    """Elastic material of the deformable body (the indenter is rigid), plane strain.

    Attributes:
        E: Young's modulus in MPa, E > 0 (the small-strain modulus of every model).
        nu: Poisson's ratio, -1 < nu < 0.5 (the small-strain ratio of every model).
        model: ``"linear"`` (small-strain Hooke, with solver.kinematics "small" or "convective"),
            ``"saint_venant_kirchhoff"`` or ``"neo_hookean"`` (hyperelastic, with solver.kinematics = "finite"
            only; :mod:`fem.hyperelastic`, ``docs/models.md``).
    """

    E: float
    nu: float
    model: str = "linear"


@dataclass(frozen=True)
class Body:
    """One elastic body of a scene with several (``[[body]]``), plane strain.

    Attributes:
        name: Its label in reports and ``metrics.json`` (1 to 64 letters, digits, ``_`` or ``-``; distinct).
        E, nu, model: Its material, with the ranges and choices of :class:`Material`.
    """

    name: str
    E: float
    nu: float
    model: str = "linear"

    @property
    def material(self) -> Material:
        """The body's material record."""
        return Material(E=self.E, nu=self.nu, model=self.model)


@dataclass(frozen=True)
class Geometry:
    """Scene geometry: what every scene's has. A scene's own geometry record subclasses this one with its fields
    (:attr:`SceneSchema.geometry`); ``run.geometry`` is an instance of the scene's record.

    Attributes:
        scene: The registered scene (:func:`scene_schemas`).
        indenter: One of the scene's indenters (:attr:`SceneSchema.indenters`).
    """

    scene: str
    indenter: str


@dataclass(frozen=True)
class Loading:
    """Loading of the rigid body.

    Exactly one of ``P`` (target load per unit thickness, N/mm) and ``half_width`` (target classical
    contact half-width b0 in mm, from which P follows by the analytic theory) sets a force-controlled
    load; ``d`` (list of rigid-body displacements in mm, recorded in order) sets displacement control.

    Attributes:
        control: ``"force"`` or ``"displacement"``.
        P: Target load per unit thickness in N/mm, > 0.
        half_width: Target classical half-width b0 in mm, > 0.
        d: Displacements of the rigid body in mm (increasing, > 0), displacement control only.
        steps: Number of load steps to the target (force control), >= 1.
    """

    control: str
    P: float | None = None
    half_width: float | None = None
    d: tuple[float, ...] = ()
    steps: int = 4


@dataclass(frozen=True)
class Discretisation:
    """Mesh and element choice.

    Attributes:
        degree: Lagrange degree of the displacement, 1 or 2.
        h_contact: Element size in the contact zone as a fraction of the contact half-width, in (0, 1].
        levels: Refinement levels for studies, as h_contact fractions, coarse to fine.
        ci_level: Fraction used by ``make ci`` (the coarsest that still meets the tolerances).
        growth: Element-to-element size ratio of the mesh grading away from the contact, in [1.05, 2].
        budget_levels: Three h_contact fractions of the error budget (``make run`` solves each run on all
            three, scenes with a truncation study on their largest body), or empty for no budget.
        budget_widths: Three body sizes W/a (width = height, in [10, MAX_SIZE_FACTOR]) of the budget's
            truncation study (at the finest budget level); required with ``budget_levels`` on a scene whose
            budget takes them, refused on the others (:attr:`SceneSchema.budget_widths` says why).
    """

    degree: int = 2
    h_contact: float = 0.05
    growth: float = 1.3
    levels: tuple[float, ...] = ()
    ci_level: float | None = None
    budget_levels: tuple[float, ...] = ()
    budget_widths: tuple[float, ...] = ()


@dataclass(frozen=True)
class Solver:
    """Contact formulation and kinematics: the ``[solver]`` fields of a case.

    Every field is the solver option of the same name, :class:`fem.options.ContactOptions` (its meaning, units and
    vocabulary are documented there, once), with the same default, except the case-level choices in
    :data:`CASE_LEVEL_DEFAULTS`: ``traction`` defaults to ``"halfplane"`` and ``formulation`` takes ``"auto"``
    (displacement below nu = NU_MIXED, Taylor-Hood mixed from there on; an explicit ``"displacement"`` is refused
    above nu = NU_DISPLACEMENT_MAX, ``"mixed"`` needs degree 2 and a scene with an analytic obstacle).
    ``kinematics = "finite"`` needs a hyperelastic material.model, traction = "obstacle", the displacement
    formulation and a scene that supports it (``docs/models.md``). The wiring passes every field through by name
    (:func:`workbench.scenes.wiring.solver_options`): a new option is one field here and one on ContactOptions.
    """

    method: str = "nitsche"
    kinematics: str = "small"
    traction: str = "halfplane"
    kappa0: float = 1.0e3
    gamma0: float = 10.0
    theta: int = 1
    formulation: str = "auto"
    linear_solver: str = "lu"


# Every [solver] field is the solver option (fem.options.ContactOptions) of the same name, with the same default,
# except these: case-level choices, each with its reason (tests/test_options_record.py checks the rest agree).
CASE_LEVEL_DEFAULTS = {
    "traction": "the case files compare with half-plane theory, which assumes a vertical gap and traction "
                "('halfplane'); a bare solve defaults to the obstacle's normal ('obstacle'), right for any geometry "
                "and the only traction finite kinematics supports",
    "formulation": "'auto' is a case-level choice resolved by nu (effective_formulation: the mixed formulation "
                   "from NU_MIXED on); the solver takes the resolved 'displacement' or 'mixed'",
}


@dataclass(frozen=True)
class Analytic:
    """Analytic predictions compared with the FEM (names of analytic/ predictions).

    Attributes:
        predictions: Names the scene computes for the run's indenter (:attr:`SceneSchema.predictions`); empty:
            the scene's own.
    """

    predictions: tuple[str, ...] = ()


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


@dataclass(frozen=True)
class Run:
    """One FEM run of a case: the base case with one variant's overrides applied."""

    label: str
    material: Material
    geometry: Geometry
    loading: Loading
    discretisation: Discretisation
    solver: Solver
    bodies: tuple[Body, ...] = ()


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
    scene = scene if isinstance(scene, str) and scene in _SCENE_SCHEMAS else None
    known = _geometry_specs(scene)
    values = _table_values(table, known, where, choices=lambda name: _geometry_choices(scene, name),
                           value_range=lambda name: _geometry_range(scene, name))
    cls = _SCENE_SCHEMAS[values["scene"]].geometry
    own = {f.name for f in fields(cls)}
    return cls(**{k: v for k, v in values.items() if k in own})


def _check_run(run: Run, where: str) -> None:
    """Cross-field checks of one run (after variant overrides)."""
    g, ld = run.geometry, run.loading
    sch = scene_schema(g.scene)
    if g.indenter not in sch.indenters:
        if len(sch.indenters) == 1:
            raise CaseError(f"{where}: geometry.indenter must be {next(iter(sch.indenters))!r} for geometry.scene = "
                            f"{g.scene!r}")
        owner = next(s.name for s in scene_schemas() if g.indenter in s.indenters)
        raise CaseError(f"{where}: geometry.indenter = {g.indenter!r} needs geometry.scene = {owner!r}")
    if sch.check_geometry is not None:
        sch.check_geometry(run, where)
    if ld.control == "force":
        if (ld.P is None) == (ld.half_width is None):
            raise CaseError(f"{where}: loading needs exactly one of P (N/mm) or half_width (mm) for force control")
        if ld.d:
            raise CaseError(f"{where}: loading.d is only allowed with control = 'displacement'")
    else:
        if not ld.d:
            raise CaseError(f"{where}: loading.d (list of displacements in mm) is required for displacement control")
        if list(ld.d) != sorted(ld.d):
            raise CaseError(f"{where}: loading.d = {_r(list(ld.d))} must be increasing")
        if ld.P is not None or ld.half_width is not None:
            raise CaseError(f"{where}: loading.P/half_width are only allowed with control = 'force'")
    if ld.control not in sch.controls:
        allowed = ", ".join(f"{c!r} ({CONTROL_NEEDS[c]})" for c in sch.controls)
        raise CaseError(f"{where}: loading.control = {_r(ld.control)} is not supported by the {g.scene} scene; "
                        f"allowed: {allowed}")
    if sch.check_load is not None:
        sch.check_load(run, where)
    _check_formulation(run, where)
    _check_model(run, where)
    _check_budget(run, where)


def _scenes_that(flag: str) -> list[str]:
    """The registered scenes whose schema has ``flag`` (``finite``, ``mixed``; ``budget_widths`` None)."""
    if flag == "budget_widths":
        return [s.name for s in scene_schemas() if s.budget_widths is None]
    return [s.name for s in scene_schemas() if getattr(s, flag)]


def _check_model(run: Run, where: str) -> None:
    """The model hierarchy's combinations (``docs/models.md``): a hyperelastic material goes with finite
    kinematics and finite kinematics with a hyperelastic material, the obstacle traction, the displacement
    formulation and a scene that supports it (the options :func:`fem.options.check_model` checks again)."""
    model, sol = run.material.model, run.solver
    bad = model_conflict(kinematics=sol.kinematics, material_model=model, traction=sol.traction,
                         formulation=effective_formulation(run))
    if bad is not None and bad.allowed == (LINEAR,):
        raise CaseError(f"{where}: material.model = {_r(model)} needs solver.kinematics = 'finite' (got "
                        f"{_r(sol.kinematics)}); allowed with small or convective kinematics: model = 'linear'")
    if bad is not None and bad.name == "material_model":
        raise CaseError(f"{where}: solver.kinematics = 'finite' needs a hyperelastic material.model (got "
                        f"{_r(model)}); allowed: {', '.join(map(repr, bad.allowed))}")
    if bad is not None and bad.name == "traction":
        raise CaseError(f"{where}: solver.kinematics = 'finite' needs solver.traction = 'obstacle' (got "
                        f"{_r(sol.traction)}); allowed: 'obstacle' (traction along the obstacle's current normal)")
    if bad is not None:
        raise CaseError(f"{where}: solver.kinematics = 'finite' supports the displacement formulation only (got "
                        f"{_r(effective_formulation(run))}); allowed: formulation = 'displacement' or 'auto' with "
                        f"nu < {NU_MIXED}")
    if sol.kinematics == FINITE and not scene_schema(run.geometry.scene).finite:
        raise CaseError(f"{where}: solver.kinematics = 'finite' is not supported by the {_r(run.geometry.scene)} "
                        f"scene; allowed: scene = {' or '.join(repr(n) for n in _scenes_that('finite'))}")


def _check_budget(run: Run, where: str) -> None:
    """The error budget needs three distinct levels, and three distinct body sizes on a scene whose budget takes
    them (:attr:`SceneSchema.budget_widths`)."""
    d = run.discretisation
    if not d.budget_levels and not d.budget_widths:
        return
    why_not = scene_schema(run.geometry.scene).budget_widths
    able = _scenes_that("budget_widths")
    if why_not is not None and d.budget_widths:
        raise CaseError(f"{where}: discretisation.budget_widths = {_r(list(d.budget_widths))} is not supported by "
                        f"the {_r(run.geometry.scene)} scene ({why_not}); allowed: scene = "
                        f"{' or '.join(repr(n) for n in able)}")
    takes = why_not is None
    for name, seq in (("budget_levels", d.budget_levels), ("budget_widths", d.budget_widths))[:2 if takes else 1]:
        if len(seq) != 3 or len(set(seq)) != 3:
            raise CaseError(f"{where}: discretisation.{name} = {_r(list(seq))} is not allowed; allowed: exactly "
                            f"three distinct values ({' or '.join(able)} scenes: with both budget_levels and "
                            "budget_widths)")
    if max(d.budget_levels) > BUDGET_SPAN * min(d.budget_levels):
        raise CaseError(f"{where}: discretisation.budget_levels = {_r(list(d.budget_levels))} spans more than a "
                        f"factor {BUDGET_SPAN:g}; allowed: max <= {BUDGET_SPAN:g} min (the grading is refined with "
                        "h_c, so a wider span meshes the finest level far too densely)")


def effective_formulation(run: Run) -> str:
    """The bulk formulation a run is solved with: ``solver.formulation``, ``"auto"`` resolved by nu
    (``"mixed"`` from NU_MIXED on, else ``"displacement"``)."""
    f = run.solver.formulation
    if f == "auto":
        return "mixed" if run.material.nu >= NU_MIXED else "displacement"
    return f


def _check_formulation(run: Run, where: str) -> None:
    """nu -> 1/2: the displacement formulation locks; the mixed one needs degree 2 and an analytic obstacle."""
    nu, sol = run.material.nu, run.solver
    form = effective_formulation(run)
    if form == "displacement" and nu > NU_DISPLACEMENT_MAX:
        raise CaseError(f"{where}: solver.formulation = 'displacement' at material.nu = {nu!r} locks (volumetric "
                        f"locking; it diverged at nu = 0.4999); allowed: nu <= {NU_DISPLACEMENT_MAX}, or "
                        "formulation = 'mixed' or 'auto' (Taylor-Hood, degree = 2)")
    if form == "mixed":
        why = (f"material.nu = {nu!r} >= {NU_MIXED} needs the mixed formulation (formulation = 'auto')"
               if sol.formulation == "auto" else "solver.formulation = 'mixed'")
        if run.discretisation.degree < 2:
            raise CaseError(f"{where}: {why}, which needs discretisation.degree = 2 (Taylor-Hood P2/P1); "
                            "allowed: degree = 2")
        if not scene_schema(run.geometry.scene).mixed:
            raise CaseError(f"{where}: {why}, which needs an analytic obstacle ({' or '.join(_scenes_that('mixed'))} "
                            f"scenes); allowed on the {run.geometry.scene} scene: nu < {NU_MIXED}")
        if sol.linear_solver == "gamg":
            raise CaseError(f"{where}: solver.linear_solver = 'gamg' with the mixed formulation ({why}): a saddle "
                            "point; allowed: linear_solver = 'lu' or 'lu_reuse'")


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
                        f"score, export and external under --out: {', '.join(p + '<case>' for p in COMMAND_PREFIXES)})"
                        "; allowed: any other name")
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


def _check_bands(case: Case, runs: tuple[Run, ...], where: str) -> None:
    """Band checks need the error budget (budget_levels) and name quantities the scene's budget has."""
    if not case.bands:
        return
    if not case.discretisation.budget_levels:
        raise CaseError(f"{where}: bands need the error budget; allowed: [bands] together with "
                        "discretisation.budget_levels (three levels)")
    notes = "; ".join(f"{s.name}: {s.band_note}" for s in scene_schemas() if s.band_note)
    for run in runs:
        allowed = scene_schema(run.geometry.scene).band_quantities
        for key, names in case.bands.items():
            for name in names:
                if re.sub(r"\[\d+\]$", "", name) not in allowed:
                    raise CaseError(f"{where}: bands.{key} = {_r(list(names))}: {_r(name)} is not a budget quantity "
                                    f"of the {run.geometry.scene} scene; allowed values: "
                                    f"{', '.join(repr(a) for a in allowed)}" + (f" ({notes})" if notes else ""))


def _check_used_geometry(run: Run, given: set, where: str) -> None:
    """A geometry key given but not read by the scene with this indenter is refused."""
    g = run.geometry
    used = scene_schema(g.scene).indenters.get(g.indenter, frozenset())
    for key in sorted(given - used - {"scene", "indenter"}):
        raise CaseError(f"{where}: geometry.{key} is not used by a {g.scene} scene with a {g.indenter} indenter; "
                        f"allowed keys: scene, indenter, {', '.join(sorted(used))}")


def _check_predictions(case: Case, runs: tuple[Run, ...], where: str) -> None:
    """Every listed prediction is one the scene computes for the indenter (an empty list: the scene's own); then
    each scene's case-level checks (:attr:`SceneSchema.check_case`)."""
    for run in runs:
        g = run.geometry
        allowed = scene_schema(g.scene).predictions.get(g.indenter, ())
        for name in case.analytic.predictions:
            if name not in allowed:
                raise CaseError(f"{where}: analytic.predictions = {_r(list(case.analytic.predictions))}: "
                                f"{_r(name)} is not computed for a {g.scene} scene with a {g.indenter} indenter; "
                                f"allowed values: {', '.join(repr(a) for a in allowed)}")
    for scene in dict.fromkeys(r.geometry.scene for r in runs):
        check = scene_schema(scene).check_case
        if check is not None:
            check(case, runs, where)


def case_names() -> list[str]:
    """Names of the case files in ``cases/``."""
    return sorted(p.stem for p in CASE_DIR.glob("*.toml"))
