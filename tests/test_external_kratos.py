"""Kratos (workbench/external/kratos_job.py in .venv-kratos) on the contact patch test, and the command line's
refusals. The job tests skip with the reason where the Kratos venv is missing (``make external`` or
``make kratos-venv`` creates it; ``make kratos-check`` runs this file).

Measured (patch_test at h/W = 0.143, lower block 7 segments, upper 5, non-matching): the load is the exact
uniaxial one, P = d / (H1 (1 - nu1^2)/E1 + H2 (1 - nu2^2)/E2) W. With the contact in the current configuration
(Kratos moves the mesh: the deck's ``move_mesh_flag`` true, the default and the workbench's choice) the nodal
pressure per reference length is uniform to 3.6e-4 inside and 1.9e-3 at the free end node x = W (1.3e-4 at the
roller end x = 0); per deformed length (Kratos's own multiplier) to 5.3e-4 and 1.75e-3. Both scale with d: the
lateral strains of the two blocks differ (nu 0.3 and 0.25, E 200 and 70 GPa), the upper block's end slides past
the lower one's by 2.2e-4 W, and the mortar integrals on the deformed, slid segments are not those of the
reference. With ``move_mesh_flag`` false (the contact in the reference configuration) the same deck is uniform
to round-off (3e-14), and so is the current-configuration deck at d / 1000 (the deviations go with d). So the
deviation is what the deck controls (the configuration of the contact integrals), not the end nodes' mortar
treatment as such.
"""

from __future__ import annotations

import csv
import json
import subprocess

import pytest
from kratos_benchmarks import two_body_benchmark

from workbench.external import kratos
from workbench.external.mdpa import write_kratos

try:
    PYTHON = kratos.kratos_python()
    MISSING = ""
except kratos.KratosError as exc:
    PYTHON, MISSING = None, str(exc)
needs_kratos = pytest.mark.skipif(PYTHON is None, reason=f"no Kratos venv: {MISSING}")


def _exact(bench) -> float:
    """The patch test's uniform pressure (MPa): uniaxial plane strain, sides free, the interface slipping."""
    import workbench.scenes  # noqa: F401
    from cases import load_case

    run = load_case(bench.case).runs()[0]
    g, (lo, up) = run.geometry, run.bodies
    d = bench.drive.report[0]
    return d / (g.height_lower * (1 - lo.nu**2) / lo.E + g.height_upper * (1 - up.nu**2) / up.E)


def _run(folder, *, move_mesh: bool = True) -> tuple[list[dict], dict]:
    if not move_mesh:
        p = folder / "ProjectParameters_small.json"
        params = json.loads(p.read_text())
        params["solver_settings"]["move_mesh_flag"] = False
        p.write_text(json.dumps(params))
    record = kratos.run_job(folder, python=PYTHON, time_limit=120)
    with open(folder / "result.csv") as fh:
        return list(csv.DictReader(fh)), record


@pytest.fixture(scope="module")
def patch(tmp_path_factory):
    cache = tmp_path_factory.mktemp("mesh_cache")
    return two_body_benchmark("patch_test", level=0.143, mesh_cache=cache)


@needs_kratos
@pytest.mark.parametrize("move_mesh", [True, False], ids=["current", "reference"])
def test_patch_test_uniformity(patch, tmp_path, move_mesh):
    """The load is exact to 1e-9 either way; the pressure is uniform to round-off with the contact in the reference
    configuration, and to the lateral strain's order in the current one (module docstring)."""
    bench, mesh = patch
    write_kratos(bench, mesh, tmp_path)
    rows, record = _run(tmp_path, move_mesh=move_mesh)
    p_exact = _exact(bench)
    W = 1.0  # patch_test's block width (mm)
    run = record["runs"][0]
    assert record["failure"] is None and all(s["converged"] for s in run["steps"]) and run["iterations"] <= 4
    P = float(rows[0]["P_N_per_mm"])
    scale = 1.0 if move_mesh else 1e-9
    assert abs(P / (p_exact * W) - 1) < 1e-9 + 1e-5 * move_mesh  # the current configuration: 3e-7 measured
    assert abs(run["steps"][-1]["P_supports"] / P - 1) < 1e-7  # load balance: Newton stops at 1e-6 relative
    dev = sorted((float(r["x_mm"]), float(r["p_MPa"]) / (P / W) - 1) for r in rows)
    assert len(dev) == 8 and {r["body"] for r in rows} == {"lower_block"} and {r["run"] for r in rows} == {"small"}
    inside = [abs(e) for x, e in dev if 0 < x < W]
    ends = [abs(e) for x, e in dev if x in (0.0, W)]
    assert max(inside) < 5e-4 * scale + 1e-12 and max(ends) < 2.5e-3 * scale + 1e-12, dev
    if move_mesh:
        assert max(ends) > 1e-3  # the free end node x = W: the slid, stretched segments (1.9e-3 measured)


def test_missing_venv_one_line_exit_2(tmp_path, capsys, monkeypatch):
    """Without the Kratos venv: one line naming make external, exit 2, nothing written."""
    monkeypatch.setattr(kratos, "KRATOS_VENV", tmp_path / "no-venv")
    out = tmp_path / "out"
    code = kratos.main(["kratos", "patch_test", "--levels", "1", "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and err[0].startswith("error:") and "make external" in err[0]
    assert not (out / "external_kratos_patch_test").exists()


@pytest.mark.parametrize("argv, words", [
    (["kratos", "patch_test", "--levels", "9"], "--levels 9; allowed: 1 to"),
    (["kratos", "patch_test", "--time-limit", "nan"], "--time-limit"),
    (["kratos", "no_such_case"], "no_such_case"),
])
def test_bad_input_one_line_exit_2(tmp_path, capsys, argv, words):
    code = kratos.main([*argv, "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and err[0].startswith("error:") and words in err[0]
    assert not any((tmp_path / "out").glob("external_kratos_*"))


def test_unknown_code_through_the_command_line(tmp_path):
    """``workbench external <code>``: an unknown code is one line naming the codes, exit 2."""
    import sys

    proc = subprocess.run([sys.executable, "-m", "workbench", "external", "abaqus", "patch_test", "--out",
                           str(tmp_path)], capture_output=True, text=True, timeout=120)
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 2 and len(lines) == 1 and "allowed: ccx, kratos" in lines[0]
    assert not any(tmp_path.iterdir())
