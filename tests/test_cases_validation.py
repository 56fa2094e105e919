"""Case files: every shipped case loads, and every bad value gives one clear line and exit code 2.

Requirement: a malformed or out-of-range case file (or CLI argument) is rejected before anything is
written, with one line naming the file, the field and the allowed range, and exit code 2.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from probe_cases import PROBE_BLOCK

from cases import case_names, load_case
from workbench.cli import main

ROOT = Path(__file__).resolve().parents[1]

GOOD = PROBE_BLOCK


def test_every_shipped_case_loads():
    names = case_names()
    assert {"hertz_cylinder", "wedge", "wedge_convective", "parabola_convective", "concave_symmetric",
            "close_to_conformal"} <= set(names)
    for name in names:
        case = load_case(name)
        assert case.runs(), name


def test_good_probe_loads(tmp_path):
    p = tmp_path / "probe.toml"
    p.write_text(GOOD)
    case = load_case(p)
    assert case.material.E == 210000.0
    assert case.runs()[0].solver.method == "nitsche"


# (replacement applied to GOOD, words the one-line message must contain)
BAD = {
    "unknown_key": (("nu = 0.3", "nu = 0.3\ncolour = 'red'"), ["material.colour", "unknown key"]),
    "unknown_section": (("[loading]", "[extra]\nx = 1\n[loading]"), ["extra", "unknown key"]),
    "wrong_type_E": (("E = 210000.0", 'E = "steel"'), ["material.E", "wrong type"]),
    "wrong_type_bool": (("radius = 10.0", "radius = 10.0\nhalf_model = 1"), ["geometry.half_model", "wrong type"]),
    "E_zero": (("E = 210000.0", "E = 0.0"), ["material.E", "E > 0"]),
    "E_negative": (("E = 210000.0", "E = -5.0"), ["material.E", "E > 0"]),
    "nu_half": (("nu = 0.3", "nu = 0.5"), ["material.nu", "-1 < nu < 0.5"]),
    "nu_above": (("nu = 0.3", "nu = 0.7"), ["material.nu", "-1 < nu < 0.5"]),
    "nu_minus_one": (("nu = 0.3", "nu = -1.0"), ["material.nu", "-1 < nu < 0.5"]),
    "wedge_angle_zero": (
        ('indenter = "circle"\nradius = 10.0', 'indenter = "wedge"\nwedge_angle = 0.0'),
        ["geometry.wedge_angle", "pi/2"],
    ),
    "wedge_angle_right": (
        ('indenter = "circle"\nradius = 10.0', 'indenter = "wedge"\nwedge_angle = 1.5708'),
        ["geometry.wedge_angle", "pi/2"],
    ),
    "wedge_angle_missing": (('indenter = "circle"\nradius = 10.0', 'indenter = "wedge"'), ["wedge_angle"]),
    "radius_negative": (("radius = 10.0", "radius = -1.0"), ["geometry.radius", "radius > 0"]),
    "P_negative": (("P = 100.0", "P = -100.0"), ["loading.P", "P > 0"]),
    "P_zero": (("P = 100.0", "P = 0"), ["loading.P", "P > 0"]),
    "half_width_zero": (("P = 100.0", "half_width = 0.0"), ["loading.half_width", "half_width > 0"]),
    "P_and_half_width": (("P = 100.0", "P = 100.0\nhalf_width = 0.5"), ["exactly one of P"]),
    "missing_E": (("E = 210000.0\n", ""), ["material.E", "required"]),
    "missing_section": (("[loading]\ncontrol = \"force\"\nP = 100.0", ""), ["[loading]", "required"]),
    "bad_choice": (('control = "force"', 'control = "torque"'), ["loading.control", "allowed values"]),
    "h_contact_above_one": (("P = 100.0", "P = 100.0\n[discretisation]\nh_contact = 2.0"),
                            ["discretisation.h_contact", "h_contact <= 1"]),
    "growth_too_small": (("P = 100.0", "P = 100.0\n[discretisation]\ngrowth = 1.0"),
                         ["discretisation.growth", "1.05 <= growth <= 2"]),
    "degree_three": (("P = 100.0", "P = 100.0\n[discretisation]\ndegree = 3"), ["discretisation.degree"]),
    "kappa_negative": (("P = 100.0", "P = 100.0\n[solver]\nkappa0 = -1.0"), ["solver.kappa0", "kappa0 > 0"]),
    "d_with_force": (("P = 100.0", "P = 100.0\nd = [0.1]"), ["loading.d"]),
    "d_negative": (('control = "force"\nP = 100.0', 'control = "displacement"\nd = [-0.1, 0.2]'),
                   ["loading.d", "d > 0"]),
    "d_not_increasing": (('control = "force"\nP = 100.0', 'control = "displacement"\nd = [0.3, 0.2]'),
                         ["loading.d", "increasing"]),
    "tolerance_negative": (("P = 100.0", "P = 100.0\n[tolerances]\nrms = -0.01"), ["tolerances.rms"]),
    "tolerance_unknown": (("P = 100.0", "P = 100.0\n[tolerances]\nwhatever = 0.01"), ["tolerances.whatever"]),
    "variant_bad_value": (("P = 100.0", "P = 100.0\n[[variant]]\nmaterial = { nu = 0.6 }"),
                          ["variant[0]", "material.nu", "-1 < nu < 0.5"]),
    "variant_unknown_key": (("P = 100.0", "P = 100.0\n[[variant]]\nmesh = { h = 1 }"), ["variant[0].mesh"]),
    "linear_solver_unknown": (("P = 100.0", 'P = 100.0\n[solver]\nlinear_solver = "cholesky"'),
                              ["solver.linear_solver", "allowed values"]),
    "linear_solver_gamg_mixed": (("P = 100.0", 'P = 100.0\n[solver]\nformulation = "mixed"\nlinear_solver = "gamg"'),
                                 ["solver.linear_solver", "gamg", "allowed"]),
    "malformed_toml": (("nu = 0.3", "nu = = 0.3"), ["malformed TOML"]),
    "load_unreachable_P": (("P = 100.0", "P = 1.0e7"), ["loading.P", "cannot be reached", "radius/2"]),
    "load_unreachable_half_width": (("P = 100.0", "half_width = 6.0"), ["loading.half_width", "cannot be reached"]),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_case_file_exit_2_one_line(name, tmp_path, capsys):
    (old, new), words = BAD[name]
    assert old in GOOD, name
    p = tmp_path / f"{name}.toml"
    p.write_text(GOOD.replace(old, new, 1))
    out = tmp_path / "results"
    code = main(["run", str(p), "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2, (name, err)
    assert len(err.splitlines()) == 1, err
    assert p.name in err or "variant" in err, err
    for w in words:
        assert w in err, (name, w, err)
    assert not out.exists(), "no partial results may be written"


def test_cli_bad_arguments_exit_2(tmp_path, capsys):
    p = tmp_path / "probe.toml"
    p.write_text(GOOD)
    assert main(["run", str(p), "--h-contact", "1.5", "--out", str(tmp_path / "r")]) == 2
    assert "--h-contact" in capsys.readouterr().err
    assert main(["run", "no_such_case", "--out", str(tmp_path / "r")]) == 2
    assert "no such case" in capsys.readouterr().err
    with pytest.raises(SystemExit) as exc:
        main(["frobnicate"])
    assert exc.value.code == 2
    assert not (tmp_path / "r").exists()


def test_cli_subprocess_exit_code(tmp_path):
    """The real process exits with 2 and prints exactly one line on stderr."""
    p = tmp_path / "bad.toml"
    p.write_text(GOOD.replace("nu = 0.3", "nu = 0.5"))
    proc = subprocess.run([sys.executable, "-m", "workbench", "run", str(p), "--out", str(tmp_path / "r")],
                          cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    assert proc.stderr.strip().count("\n") == 0 and "material.nu" in proc.stderr
    assert not (tmp_path / "r").exists()


def test_unreachable_concave_displacement_exit_2(tmp_path, capsys):
    """A displacement path that never reaches the concave body is bad input, rejected before any run."""
    p = tmp_path / "short.toml"
    text = (ROOT / "cases" / "concave_symmetric.toml").read_text()
    p.write_text(text.replace("d = [0.60, 0.80, 1.00]", "d = [0.05, 0.10]"))
    out = tmp_path / "r"
    assert main(["run", str(p), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "loading.d" in err and "never brings" in err, err
    assert not out.exists()
