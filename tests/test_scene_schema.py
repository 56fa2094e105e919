"""The case schema names no scene (issue 24): each scene registers its own fields, choices, checks, tolerance keys,
predictions and (scene, indenter) pairs as a :class:`cases.schema.SceneSchema`, and a new scene loads a case
without touching ``cases/schema.py``.

Requirements: ``cases/schema.py`` contains no registered scene or indenter name (as a word, in code or prose); a
toy scene registered here (not in the schema, not in workbench) loads, validates and refuses its own case files
with the schema's one-line messages; a case loaded with no scene registered says what to import.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import pytest

import workbench.scenes  # noqa: F401  (the shipped scenes register their schemas)
from cases import schema
from cases.schema import CaseError, Geometry, SceneSchema, load_case

SCHEMA_FILE = Path(schema.__file__)


def test_schema_names_no_scene():
    text = SCHEMA_FILE.read_text()
    names = set()
    for sch in schema.scene_schemas():
        names |= {sch.name, *sch.indenters, *sch.geometry_fields()}
    names -= {"scene", "indenter"}
    assert {"block", "concave", "circle", "wedge", "particle", "radius", "design"} <= names
    found = sorted(n for n in names if re.search(rf"\b{re.escape(n)}\b", text, re.IGNORECASE))
    assert not found, f"cases/schema.py names scene-specific words: {found}"


@dataclass(frozen=True)
class ToyGeometry(Geometry):
    """A strip pressed by a punch (test only)."""

    punch_width: float | None = None
    strip_height: float = 5.0
    finish: str = "smooth"


def _toy_check(run, where):
    if run.geometry.punch_width is None:
        raise CaseError(f"{where}: geometry.punch_width is required for a toy scene; allowed: punch_width > 0 (mm)")


TOY = SceneSchema(
    name="toy_strip", geometry=ToyGeometry,
    indenters={"flat_punch": frozenset({"punch_width", "strip_height", "finish"}),
               "pin": frozenset({"strip_height"})},
    predictions={"flat_punch": ("sadowsky",), "pin": ()}, controls=("displacement",),
    choices={"finish": ("smooth", "rough")},
    ranges={"punch_width": (0.0, 100.0, False, True, "0 < punch_width <= 100")},
    tolerances={"sadowsky_rms": "RMS against Sadowsky"}, band_quantities=("punch_load",),
    budget_widths="the strip is the real geometry", check_geometry=_toy_check)

CASE = """
[material]
E = 1000.0
nu = 0.3
[geometry]
scene = "toy_strip"
indenter = "flat_punch"
GEOM
[loading]
control = "displacement"
d = [0.01, 0.02]
[analytic]
predictions = ["sadowsky"]
[tolerances]
sadowsky_rms = 0.05
"""


@pytest.fixture
def toy(monkeypatch):
    monkeypatch.setitem(schema._SCENE_SCHEMAS, TOY.name, TOY)  # removed again after the test
    return TOY


def _load(tmp_path, geom="punch_width = 2.0", extra=""):
    p = tmp_path / "toy.toml"
    p.write_text(CASE.replace("GEOM", geom) + extra)
    return load_case(p)


def test_a_toy_scene_loads_without_touching_the_schema(toy, tmp_path):
    case = _load(tmp_path, 'punch_width = 2.0\nfinish = "rough"')
    (run,) = case.runs()
    assert isinstance(run.geometry, ToyGeometry)
    assert (run.geometry.punch_width, run.geometry.strip_height, run.geometry.finish) == (2.0, 5.0, "rough")
    assert case.tolerances == {"sadowsky_rms": 0.05} and case.analytic.predictions == ("sadowsky",)


@pytest.mark.parametrize(("geom", "extra", "message"), [
    ("", "", "toy.toml: variant[0]: geometry.punch_width is required for a toy scene"),
    ('punch_width = 2.0\nfinish = "matte"', "", "geometry.finish = 'matte' is not allowed; allowed values: 'smooth', "
                                                "'rough'"),
    ("punch_width = 200.0", "", "geometry.punch_width = 200.0 is out of range; allowed: 0 < punch_width <= 100"),
    ("punch_width = 2.0\nradius = 1.0", "", "geometry.radius is not used by a toy_strip scene with a flat_punch "
                                            "indenter; allowed keys: scene, indenter, finish, punch_width, "
                                            "strip_height"),
    ("punch_width = 2.0\nbogus = 1.0", "", "geometry.bogus is an unknown key; allowed keys: scene, indenter, "),
    ("punch_width = 2.0", '[solver]\nkinematics = "finite"\n[material.x]\n', "material.x is an unknown key"),
    ("punch_width = 2.0", "[bands]\ncontain_theory = ['p_max']\n", "bands need the error budget"),
])
def test_a_toy_scene_is_refused_in_one_line(toy, tmp_path, geom, extra, message):
    with pytest.raises(CaseError) as exc:
        _load(tmp_path, geom, extra)
    assert message in str(exc.value) and "\n" not in str(exc.value), str(exc.value)


def test_the_toy_scene_capabilities_are_its_own(toy, tmp_path):
    p = tmp_path / "toy.toml"
    text = CASE.replace("GEOM", "punch_width = 2.0")
    p.write_text(text.replace('control = "displacement"\nd = [0.01, 0.02]', 'control = "force"\nP = 1.0'))
    with pytest.raises(CaseError, match=r"loading.control = 'force' is not supported by the toy_strip scene; "
                                        r"allowed: 'displacement' \(with d\)"):
        load_case(p)
    p.write_text(text.replace("[analytic]", "[discretisation]\nbudget_levels = [0.1, 0.07, 0.05]\n"
                              "budget_widths = [10.0, 20.0, 40.0]\n[analytic]"))
    with pytest.raises(CaseError, match=r"not supported by the 'toy_strip' scene \(the strip is the real geometry\); "
                                        r"allowed: scene = 'block'"):
        load_case(p)
    p.write_text(text.replace("predictions = [\"sadowsky\"]", "predictions = [\"hertz\"]"))
    with pytest.raises(CaseError, match="'hertz' is not computed for a toy_strip scene with a flat_punch indenter; "
                                        "allowed values: 'sadowsky'"):
        load_case(p)


def test_the_shipped_scenes_are_registered_in_order():
    assert [s.name for s in schema.scene_schemas()][:2] == ["block", "concave"]
    assert schema.scene_schema("block").geometry.__name__ == "BlockGeometry"


def test_no_registered_scene_is_a_clear_error(monkeypatch):
    import cases.scene_schema  # the registry's module (cases.schema re-exports it)

    monkeypatch.setattr(cases.scene_schema, "_SCENE_SCHEMAS", {})
    with pytest.raises(RuntimeError, match="import workbench.scenes"):
        load_case("hertz_cylinder")


def test_a_bad_scene_schema_is_refused_at_registration():
    @dataclass(frozen=True)
    class NoDefault(Geometry):
        width: float

    with pytest.raises(TypeError, match="needs a default"):
        schema.register_scene_schema(SceneSchema(name="bad", geometry=NoDefault, indenters={}, predictions={},
                                                 controls=("force",)))
    with pytest.raises(TypeError, match="not fields of ToyGeometry"):
        schema.register_scene_schema(SceneSchema(name="bad", geometry=ToyGeometry, indenters={"pin": {"radius"}},
                                                 predictions={}, controls=("force",)))
    assert "bad" not in schema._SCENE_SCHEMAS
