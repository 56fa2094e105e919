"""The probes of issue 15, one test each: what a new user tried, and the behaviour now required.

Every refusal is exit code 2 with ONE stderr line naming the field (or option) and the allowed range, and
nothing written; folders and files honour the umask.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401

import json
import os
import subprocess
from pathlib import Path

import pytest
from test_cases_validation import GOOD

from cases import load_case
from cases.schema import MAX_ECHO, effective_formulation
from workbench.atomic import atomic_dir, write_json
from workbench.cli import main
from workbench.paths import OutputError, OutputPaths

ROOT = Path(__file__).resolve().parents[1]


def _refused(tmp_path, capsys, text: str, *words: str, name: str = "probe.toml") -> str:
    """Run ``text`` as a case file: exit 2, one line containing ``words``, nothing written anywhere."""
    p = tmp_path / name
    p.write_text(text)
    out = tmp_path / "results"
    before = sorted(os.listdir(tmp_path))
    code = main(["run", str(p), "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    assert len(err.splitlines()) == 1, err
    for w in words:
        assert w in err, (w, err)
    assert sorted(os.listdir(tmp_path)) == before and not out.exists()
    return err


@pytest.mark.parametrize("name", ["../../escaped", "sub/dir", "..", "a b", "x" * 65, "ü"])
def test_case_name_is_a_slug(name, tmp_path, capsys):
    text = GOOD.replace('name = "probe"', f"name = {json.dumps(name)}")
    _refused(tmp_path, capsys, text, "case.name", "letters, digits")
    assert not (tmp_path.parent / "escaped").exists()


def test_output_paths_never_leave_the_root(tmp_path):
    paths = OutputPaths(tmp_path / "out")
    assert paths.case("hertz_cylinder") == tmp_path / "out" / "hertz_cylinder"
    for bad in ("../x", "/etc", "..", "a/../../b"):
        with pytest.raises(OutputError, match="outside the output folder"):
            paths.case(bad)


@pytest.mark.parametrize("out, words", [("/dev/null/x", ["does not exist or is not a folder"]),
                                        ("FILE", ["is not a folder"]),
                                        ("FILE/x", ["does not exist or is not a folder"]),
                                        ("missing/parent/x", ["does not exist"])])
def test_unusable_out_is_one_line(out, words, tmp_path, capsys):
    (tmp_path / "FILE").write_text("a file\n")
    target = out if out.startswith("/") else str(tmp_path / out)
    assert main(["run", "hertz_cylinder", "--out", target]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--out" in err, err
    for w in words:
        assert w in err, err


def test_read_only_out_is_one_line(tmp_path, capsys):
    ro = tmp_path / "ro"
    ro.mkdir()
    if os.geteuid() == 0:
        if os.system(f"mount -t tmpfs -o ro,size=64k tmpfs {ro} 2>/dev/null") != 0:
            pytest.skip("root without permission to mount a read-only tmpfs: no read-only folder to test")
    else:
        ro.chmod(0o555)
    try:
        for target in (ro, ro / "new"):
            assert main(["run", "hertz_cylinder", "--out", str(target)]) == 2
            err = capsys.readouterr().err.strip()
            assert len(err.splitlines()) == 1 and "read-only" in err, err
    finally:
        if os.geteuid() == 0:
            os.system(f"umount {ro}")
        else:
            ro.chmod(0o755)


@pytest.mark.parametrize("preds, bad", [('["nonsense"]', "'nonsense'"), ('["wedge"]', "'wedge'"),
                                        ('["hertz", "convective"]', "convective")])
def test_predictions_are_checked_against_scene_and_indenter(preds, bad, tmp_path, capsys):
    _refused(tmp_path, capsys, GOOD + f"[analytic]\npredictions = {preds}\n", "analytic.predictions", bad)


def test_displacement_control_on_a_block_is_refused_by_validate(tmp_path, capsys):
    p = tmp_path / "disp.toml"
    p.write_text(GOOD.replace('control = "force"\nP = 100.0', 'control = "displacement"\nd = [0.01]'))
    assert main(["validate", str(p)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "loading.control" in err and "'force'" in err, err


@pytest.mark.parametrize("field, value", [("radius", "5.0"), ("wedge_angle", "0.3"), ("design", '"symmetric"')])
def test_a_geometry_field_the_scene_ignores_is_refused(field, value, tmp_path, capsys):
    text = GOOD.replace("radius = 10.0", "radius = 10.0" if field == "radius" else f"radius = 10.0\n{field} = {value}")
    if field == "radius":
        text = text.replace('indenter = "circle"\nradius = 10.0', 'indenter = "wedge"\nwedge_angle = 0.3\nradius = 5.0')
    _refused(tmp_path, capsys, text, f"geometry.{field}", "not used")


@pytest.mark.parametrize("np_value", ["abc", "0", "-1", "1.5", "01"])
def test_makefile_checks_np(np_value):
    proc = subprocess.run(["make", "-n", "hertz_cylinder", f"NP={np_value}"], cwd=ROOT, capture_output=True,
                          text=True, timeout=60)
    assert proc.returncode == 2, proc.stdout + proc.stderr
    err = proc.stderr.strip()
    assert len(err.splitlines()) == 1 and f"NP = '{np_value}'" in err and "whole number >= 1" in err, err


def test_makefile_accepts_np_2():
    proc = subprocess.run(["make", "-n", "hertz_cylinder", "NP=2"], cwd=ROOT, capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == 0 and "mpiexec -n 2" in proc.stdout, proc.stderr


def test_huge_E_gets_its_cause(tmp_path, capsys):
    _refused(tmp_path, capsys, GOOD.replace("E = 210000.0", "E = 1e300"), "material.E", "E <= 1e+12")


def test_tiny_load_is_round_off_not_resolution(tmp_path, capsys):
    """P = 1e-12: a/R = 2e-9; the pressure would be round-off noise (14 patches, p_max off 150 %), and the
    advice is about the load, not about refining h_contact."""
    err = _refused(tmp_path, capsys, GOOD.replace("P = 100.0", "P = 1e-12"), "loading.P", "a/R >= 1e-05",
                   "round-off")
    assert "h_contact" not in err


def test_huge_block_is_refused(tmp_path, capsys):
    """width_factor = 1e6 gave a 1.9 % load-balance error with no warning."""
    _refused(tmp_path, capsys, GOOD.replace("radius = 10.0", "radius = 10.0\nwidth_factor = 1e6"),
             "geometry.width_factor", "<= 10000")


def test_long_values_are_cut(tmp_path, capsys):
    huge = "x" * 200_000
    err = _refused(tmp_path, capsys, GOOD.replace('control = "force"', f'control = "{huge}"'), "loading.control")
    assert len(err) < 400 and "..." in err and "x" * (MAX_ECHO + 1) not in err, len(err)
    assert main(["validate", huge]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err) < 400 and len(err.splitlines()) == 1


def test_near_incompressible_displacement_is_refused_with_the_mixed_advice(tmp_path, capsys):
    text = GOOD.replace("nu = 0.3", "nu = 0.4999") + '[solver]\nformulation = "displacement"\n'
    _refused(tmp_path, capsys, text, "solver.formulation", "locks", "'mixed'")
    text = GOOD.replace("nu = 0.3", "nu = 0.4999") + "[discretisation]\ndegree = 1\n"
    _refused(tmp_path, capsys, text, "needs the mixed formulation", "degree = 2")


def test_auto_formulation_switches_to_mixed(tmp_path):
    p = tmp_path / "inc.toml"
    p.write_text(GOOD.replace("nu = 0.3", "nu = 0.4999"))
    assert effective_formulation(load_case(p).runs()[0]) == "mixed"
    p.write_text(GOOD)
    assert effective_formulation(load_case(p).runs()[0]) == "displacement"


def test_nu_0_4999_runs_with_the_mixed_formulation(tmp_path, capsys):
    """The locking case of the issue: the displacement formulation diverged at nu = 0.4999; now "auto" solves it
    with Taylor-Hood and meets the Hertz tolerances of the probe (p_max within 1 %)."""
    p = tmp_path / "inc.toml"
    p.write_text(GOOD.replace("nu = 0.3", "nu = 0.4999") + "[discretisation]\nh_contact = 0.1\n"
                 "[analytic]\npredictions = [\"hertz\"]\n[tolerances]\np_max = 0.01\n")
    out = tmp_path / "results"
    assert main(["run", str(p), "--out", str(out)]) == 0, capsys.readouterr().err
    m = json.loads((out / "probe" / "metrics.json").read_text())
    assert m["pass"] and m["errors"]["p_max"] <= 0.01, m["errors"]


def test_folders_and_files_honour_the_umask(tmp_path):
    old = os.umask(0o022)
    try:
        with atomic_dir(tmp_path / "case") as stage:
            write_json(stage / "metrics.json", {})
            (stage / "vtk").mkdir()
        assert (tmp_path / "case").stat().st_mode & 0o777 == 0o755
        assert (tmp_path / "case" / "vtk").stat().st_mode & 0o777 == 0o755
        assert (tmp_path / "case" / "metrics.json").stat().st_mode & 0o777 == 0o644
    finally:
        os.umask(old)


def test_an_interrupted_swap_is_repaired(tmp_path):
    """A kill between the two renames of atomic_dir leaves ``.case.old.<pid>`` and no ``case``: the next write
    puts the previous results back before staging (they are replaced only when the new ones are complete)."""
    old = tmp_path / ".case.old.12345"
    write_json(old / "metrics.json", {"previous": True})
    with pytest.raises(RuntimeError), atomic_dir(tmp_path / "case"):
        raise RuntimeError("the new run fails")
    assert json.loads((tmp_path / "case" / "metrics.json").read_text()) == {"previous": True}
    assert not old.exists()
