"""Faults: Newton cut-back, unrecoverable solves, interrupted and crashed runs, bad CLI input.

Requirement: a diverging Newton step is cut back automatically; if recovery is impossible the run stops with an
error naming the cause (SNES reason), writes ``results/logs/<case>.log`` and leaves no corrupt results; SIGINT
leaves the previous results intact; a rerun after a crash works. The CLI runs are subprocesses in ``tmp_path``
(their mesh cache too) on the coarse ci_level mesh (``--h-contact 0.1``): the file takes ~10 s warm.
"""

import dolfinx_solver  # noqa: F401

import os
import re
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from mpi4py import MPI

from analytic.hertz import hertz
from fem.elasticity import plane_strain_modulus
from fem.obstacles import CircleObstacle
from fem.solver import ContactSolveError, solve_contact
from meshes.block import build_block_mesh
from workbench.mesh_io import read_mesh

ROOT = Path(__file__).resolve().parents[1]
R, E, NU, A = 10.0, 2.0e5, 0.3, 0.5
E_STAR = plane_strain_modulus(E=E, nu=NU)


@pytest.fixture(scope="module")
def mesh10(tmp_path_factory):
    mf = build_block_mesh(width=40 * A, height=40 * A, contact_half_width=A, h_contact=A / 10, half_model=True,
                          out_dir=tmp_path_factory.mktemp("faults_mesh"), name="faults")
    return read_mesh(mf.msh, MPI.COMM_WORLD)


def _cli(args, cwd, **kw):
    env = dict(os.environ, PYTHONPATH=str(ROOT), OMP_NUM_THREADS="1")
    return subprocess.Popen([sys.executable, "-m", "workbench", *args], cwd=cwd, env=env, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, **kw)


def _run(args, cwd):
    proc = _cli(args, cwd)
    out, err = proc.communicate(timeout=120)
    return proc.returncode, out, err


def _snapshot(folder: Path) -> dict:
    return {p.relative_to(folder): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def _interrupt_at_first_step(out: Path, cwd: Path):
    """Start ``run hertz_cylinder`` on a fine mesh (still solving when its first load step is printed), send
    SIGINT at that line, and return the finished process and its stderr."""
    proc = _cli(["run", "hertz_cylinder", "--h-contact", "0.025", "--out", str(out)], cwd)
    for line in proc.stdout:
        if "step:" in line:
            proc.send_signal(signal.SIGINT)
            break
    _, err = proc.communicate(timeout=120)
    return proc, err


def _no_staging(root: Path) -> bool:
    return not [p for p in root.iterdir() if ".staging." in p.name or ".old." in p.name]


def test_cutback_recovers_a_huge_single_step(mesh10):
    """One displacement step to d = 0.06 mm (a ~ 0.5 mm), no active-set predictor, 4 Newton iterations allowed:
    the full step diverges, the solver halves it (cut-backs) and reaches the target; the result still meets
    Hertz within the 2 % band of the stability sweep (P2, h = a/10) at the measured load."""
    res = solve_contact(mesh10, CircleObstacle(center=(0.0, R), radius=R), E=E, nu=NU, traction="halfplane",
                        control="displacement", target=0.06, n_steps=1, symmetric_half=True, max_it=4,
                        active_set_predictor=False, first_step_fraction=1.0)
    kinds = [r["kind"] for r in res.load_steps]
    assert kinds.count("cutback") >= 1, kinds
    # each failed solve is recorded with its cost (its iterations are not in newton_iterations): the full step
    # ran to its 4 iterations and failed, before the first cut-back's record
    assert res.failed_solves and res.failed_solves[0]["kind"] == "step" and res.failed_solves[0]["reason"] < 0
    assert res.failed_solves[0]["iterations"] == 4 and res.failed_solves[0]["d"] == pytest.approx(0.06)
    assert res.d == pytest.approx(0.06, rel=1e-14)
    h = hertz(res.P, R, E_STAR)
    assert abs(res.patches[0].half_width / h.half_width - 1.0) <= 0.02
    assert abs(res.patches[0].p_max / h.p0 - 1.0) <= 0.02
    assert res.warnings == []


def test_unrecoverable_step_names_the_snes_reason(mesh10):
    """One Newton iteration and one cut-back cannot reach the target: ContactSolveError with the PETSc name."""
    with pytest.raises(ContactSolveError, match=r"faulty: load step 1 .*SNES reason -5 \(DIVERGED_MAX_IT\)"):
        solve_contact(mesh10, CircleObstacle(center=(0.0, R), radius=R), E=E, nu=NU, traction="halfplane",
                      control="displacement", target=0.06, n_steps=1, symmetric_half=True, max_it=1,
                      active_set_predictor=False, first_step_fraction=1.0, max_cutbacks=1, case="faulty")


GOOD = (ROOT / "cases" / "hertz_cylinder.toml").read_text().replace('name = "hertz_cylinder"', 'name = "fault_probe"')
# A run that cannot converge. It was the penalty with kappa0 = 1e12 until issue 15 made stiff penalties converge
# (fem.methods.penalty: nodal law, relaxed Uzawa). Now: symmetric Nitsche with gamma0 = 1e-6, far below its
# stability bound (the -theta/gamma int sigma_n(u) sigma_n(v) term makes the Jacobian indefinite); here (h = a/10)
# it ends in SNES DIVERGED_DTOL after its cut-backs (measured).
BAD = GOOD.replace('method = "nitsche"', 'method = "nitsche"\ngamma0 = 1e-6')


def test_cli_failed_run_keeps_previous_results_and_rerun_works(tmp_path):
    case = tmp_path / "fault_probe.toml"
    out = tmp_path / "results"
    case.write_text(GOOD)
    code, _, err = _run(["run", str(case), "--h-contact", "0.1", "--out", str(out)], tmp_path)
    assert code == 0, err
    before = _snapshot(out / "fault_probe")
    assert (out / "fault_probe" / "metrics.json").is_file()

    case.write_text(BAD)  # same case name: a failure must not touch the previous results
    code, _, err = _run(["run", str(case), "--h-contact", "0.1", "--out", str(out)], tmp_path)
    assert code == 1, err
    assert re.search(r"SNES reason -\d+ \(DIVERGED_[A-Z_]+\)", err) and "previous results left intact" in err, err
    log = out / "logs" / "fault_probe.log"
    assert log.is_file() and "ContactSolveError" in log.read_text()
    assert _snapshot(out / "fault_probe") == before
    assert _no_staging(out)

    case.write_text(GOOD)  # rerun after the crash
    code, _, err = _run(["run", str(case), "--h-contact", "0.1", "--out", str(out)], tmp_path)
    assert code == 0, err
    assert (out / "fault_probe" / "metrics.json").is_file() and _no_staging(out)


def test_sigint_leaves_previous_results_intact(tmp_path):
    out = tmp_path / "results"
    code, _, err = _run(["run", "hertz_cylinder", "--h-contact", "0.1", "--out", str(out)], tmp_path)
    assert code == 0, err
    before = _snapshot(out / "hertz_cylinder")
    proc, err = _interrupt_at_first_step(out, tmp_path)
    assert proc.returncode != 0, err
    assert _snapshot(out / "hertz_cylinder") == before
    code, _, err = _run(["run", "hertz_cylinder", "--h-contact", "0.1", "--out", str(out)], tmp_path)
    assert code == 0, err


def test_sigint_exits_130_and_cleans_its_staging_folder(tmp_path):
    """Ctrl-C must reach Python as KeyboardInterrupt: run_case then prints "interrupted: ..." and exits 130,
    and atomic_dir removes its staging folder. Fails while ``workbench.mesh_io.read_mesh`` leaves SIGINT at
    SIG_DFL (dolfinx's ``read_from_msh`` calls ``gmsh.initialize()``, whose ``interruptible=True`` default
    resets the handler): the process is then killed by the signal (-2) and ``.<case>.staging.*`` stays behind."""
    out = tmp_path / "results"
    proc, err = _interrupt_at_first_step(out, tmp_path)
    assert proc.returncode == 130 and "interrupted" in err, (proc.returncode, err)
    assert not (out / "hertz_cylinder").exists() and _no_staging(out)


@pytest.mark.parametrize("args, word", [(["run"], "CASE"), (["run", "hertz_cylinder", "--h-contact", "abc"],
                                                               "--h-contact")])
def test_cli_bad_arguments_exit_2(tmp_path, args, word):
    """No case, or a non-numeric --h-contact: exit 2, one line on stderr naming the argument, nothing written."""
    code, _, err = _run([*args, "--out", str(tmp_path / "r")], tmp_path)
    assert code == 2 and len(err.strip().splitlines()) == 1 and word in err, err
    assert not (tmp_path / "r").exists()
