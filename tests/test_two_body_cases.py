"""The two-body scene's case fields (issue 24): every bad value is refused with one line naming the field and
the allowed values or range, exit code 2, nothing written."""

from __future__ import annotations

from pathlib import Path

import pytest

from cases.schema import CaseError, load_case
from workbench.cli import main

ROOT = Path(__file__).resolve().parents[1]
CYL = (ROOT / "cases" / "elastic_cylinder.toml").read_text()
PATCH = (ROOT / "cases" / "patch_test.toml").read_text()

BAD = {
    "pairing": (CYL, 'pairing = "mortar"', 'pairing = "segment"', ["geometry.pairing", "mortar", "node_to_segment"]),
    "size_ratio": (CYL, "size_ratio = 0.77", "size_ratio = 9.0", ["geometry.size_ratio", "size_ratio < 5"]),
    "body_E": (CYL, 'name = "cylinder"\nE = 210000.0', 'name = "cylinder"\nE = -1.0', ["body[1].E", "E > 0"]),
    "body_nu": (CYL, 'name = "cylinder"\nE = 210000.0\nnu = 0.3', 'name = "cylinder"\nE = 210000.0\nnu = 0.5',
                ["body[1].nu", "nu < 0.5"]),
    "body_model": (CYL, 'name = "cylinder"', 'name = "cylinder"\nmodel = "neo_hookean"',
                   ["body[1].model", "'linear'"]),
    "body_model_unknown": (CYL, 'name = "cylinder"', 'name = "cylinder"\nmodel = "rubber"',
                           ["body[1].model", "linear"]),
    "body_name": (CYL, 'name = "block"', 'name = "the block"', ["body[0].name", "letters"]),
    "body_name_twice": (CYL, 'name = "cylinder"', 'name = "block"', ["body names", "distinct"]),
    "body_unknown_key": (CYL, 'name = "cylinder"', 'name = "cylinder"\ncolour = "grey"', ["body[1].colour", "unknown"]),
    "body_missing_E": (CYL, 'name = "cylinder"\nE = 210000.0', 'name = "cylinder"', ["body[1].E", "required"]),
    "one_body": (CYL, '[[body]]             # the cylinder: the same steel (beta = 0)\nname = "cylinder"\n'
                 'E = 210000.0\nnu = 0.3\n', "", ["2 [[body]] tables", "lower body", "got 1"]),
    "material_and_body": (CYL, "[geometry]", "[material]\nE = 1.0\nnu = 0.3\n\n[geometry]",
                          ["[material] and [[body]]"]),
    "upper_E_legacy": (CYL, "size_ratio = 0.77", "size_ratio = 0.77\nupper_E = 1.0", ["geometry.upper_E", "[[body]]"]),
    "variant_material": (PATCH, 'geometry = { pairing = "mortar" }',
                         'geometry = { pairing = "mortar" }\nmaterial = { E = 1.0 }', ["variant[0].material", "body"]),
    "variant_bodies_length": (PATCH, 'geometry = { pairing = "mortar" }',
                              'geometry = { pairing = "mortar" }\nbody = [{ E = 1.0 }]', ["body", "a list of 2"]),
    "variant_body_nu": (PATCH, 'geometry = { pairing = "mortar" }',
                        'geometry = { pairing = "mortar" }\nbody = [{}, { nu = 0.6 }]', ["body[1].nu", "nu < 0.5"]),
    "missing_radius": (CYL, "radius = 40.0 ", "# radius = 40.0", ["geometry.radius", "required"]),
    "convective": (CYL, 'kinematics = "small"', 'kinematics = "convective"', ["solver.kinematics", "'small'"]),
    "nitsche": (CYL, 'method = "penalty"', 'method = "nitsche"', ["solver.method", "penalty"]),
    "patch_force": (PATCH, 'control = "displacement"\nd = [0.001]', 'control = "force"\nP = 10.0',
                    ["loading.control", "displacement"]),
    "patch_radius": (PATCH, "block_width = 1.0", "block_width = 1.0\nradius = 3.0", ["radius"]),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_two_body_case_exit_2_one_line(name, tmp_path, capsys):
    text, old, new, words = BAD[name]
    assert old in text, name
    p = tmp_path / f"{name}.toml"
    p.write_text(text.replace(old, new, 1))
    out = tmp_path / "results"
    code = main(["run", str(p), "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2, (name, err)
    assert len(err.splitlines()) == 1, err
    for w in words:
        assert w in err, (name, w, err)
    assert not out.exists()


def test_only_in_two_body_files():
    """A single-body case refuses [[body]]; a two-body case refuses [material] alone."""
    hertz = (ROOT / "cases" / "hertz_cylinder.toml").read_text()
    body = '\n[[body]]\nname = "b"\nE = 1.0\nnu = 0.3\n'
    with pytest.raises(CaseError, match=r"\[material\] and \[\[body\]\] are both given; allowed: \[material\]"):
        _load(hertz + body)
    with pytest.raises(CaseError, match=r"\[\[body\]\] is not allowed for the block scene"):
        _load(hertz.replace("[material]\nE = 210000.0        # MPa (steel)\nnu = 0.3\n", body))
    no_bodies = CYL.split("[[body]]")[0] + "[material]\nE = 1.0\nnu = 0.3\n\n[geometry]" + CYL.split("[geometry]")[1]
    with pytest.raises(CaseError, match=r"needs 2 \[\[body\]\] tables .* got \[material\]"):
        _load(no_bodies)


def test_a_variant_overrides_a_body():
    """``body = [{}, {E = ...}]`` in a variant changes the upper body only; run.material is the lower body's."""
    text = PATCH.replace('geometry = { pairing = "node_to_segment" }',
                         'geometry = { pairing = "node_to_segment" }\nbody = [{}, { E = 1000.0, name = "soft" }]')
    mortar, nts = _load(text).runs()
    assert [b.name for b in mortar.bodies] == ["lower_block", "upper_block"] and mortar.bodies[1].E == 70000.0
    assert [b.name for b in nts.bodies] == ["lower_block", "soft"] and nts.bodies[1].E == 1000.0
    assert nts.bodies[0] == mortar.bodies[0] and nts.material == mortar.material == mortar.bodies[0].material


_TMP = []


def _load(text):
    import tempfile

    d = Path(tempfile.mkdtemp())
    _TMP.append(d)
    p = d / "t.toml"
    p.write_text(text)
    return load_case(p)


def test_both_bodies_in_the_vtk_with_their_names_and_materials(tmp_path):
    """The patch test's VTK: one grid holding both bodies, each cell carrying its body's index, E and nu, and
    frames.json naming the bodies as the case does (the view script's title lists them)."""
    import json
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-m", "workbench", "run", "patch_test", "--ci", "--no-pictures",
                          "--out", str(tmp_path)], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    run = tmp_path / "patch_test" / "vtk" / "mortar"
    bodies = json.loads((run / "frames.json").read_text())["bodies"]
    assert [(b["index"], b["name"], b["E_MPa"], b["nu"]) for b in bodies] == [
        (0, "lower_block", 200000.0, 0.3), (1, "upper_block", 70000.0, 0.25)]
    import meshio

    data = meshio.read(sorted(run.glob("body_*.vtu"))[-1]).point_data
    body, E, nu = (data[k].ravel().tolist() for k in ("body", "E_MPa", "nu"))
    assert set(body) == {0.0, 1.0}
    assert {(b, e, n) for b, e, n in zip(body, E, nu, strict=True)} == {(0.0, 200000.0, 0.3), (1.0, 70000.0, 0.25)}
