"""The two-body scene's case fields (issue 24): every bad value is refused with one line naming the field and
the allowed values or range, exit code 2, nothing written."""

from __future__ import annotations

from pathlib import Path

import pytest

from workbench.cli import main

ROOT = Path(__file__).resolve().parents[1]
CYL = (ROOT / "cases" / "elastic_cylinder.toml").read_text()
PATCH = (ROOT / "cases" / "patch_test.toml").read_text()

BAD = {
    "pairing": (CYL, 'pairing = "mortar"', 'pairing = "segment"', ["geometry.pairing", "mortar", "node_to_segment"]),
    "size_ratio": (CYL, "size_ratio = 0.77", "size_ratio = 9.0", ["geometry.size_ratio", "size_ratio < 5"]),
    "upper_E": (CYL, "upper_E = 210000.0", "upper_E = -1.0", ["geometry.upper_E", "upper_E"]),
    "upper_nu": (CYL, "upper_nu = 0.3", "upper_nu = 0.5", ["geometry.upper_nu", "upper_nu < 0.5"]),
    "missing_radius": (CYL, "radius = 40.0 ", "# radius = 10.0", ["geometry.radius", "required"]),
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
