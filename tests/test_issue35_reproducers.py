"""Issue 35: every reproducer of the hostile new user, through the real command line (``python -m workbench``).

Each refusal: exit 2, exactly one line on stderr starting with ``error:`` and naming the file, folder or option,
nothing written (paths and SHA-256 of the sandbox before and after). Each signal: exit 130 (SIGINT) or 143
(SIGTERM) with one ``interrupted:`` line that says what is on disk. Each verdict that must not be given: exit 0
with "No verdict" and its reason. The process sends itself the signal at a named moment
(``WORKBENCH_TEST_SIGNAL_AT``, :mod:`workbench.interrupt`), so the late moments (the swap, the exit, an import of
VTK) are reached every time, not by chance. ``HOME`` points at a sandbox folder, checked after the commands that
start gmsh. ``tests/test_output_guard_matrix.py`` holds the guard's matrix over every command (in-process).
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from external_files import FRD, VTP, hertz_levels, with_disp, zlib_vtp
from fuzz_support import CHECKOUT, tree
from probe_cases import PROBE_BLOCK

ENV = os.environ | {"PYTHONPATH": str(CHECKOUT), "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
CASE = "hertz_cylinder"


def wb(*args, cwd: Path, env: dict | None = None, timeout: float = 300) -> subprocess.CompletedProcess:
    """``python -m workbench ARGS`` from ``cwd`` (``HOME`` in the sandbox)."""
    env = ENV | {"HOME": str(cwd / "home")} | (env or {})
    return subprocess.run([sys.executable, "-m", "workbench", *map(str, args)], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=timeout)


def refused(proc: subprocess.CompletedProcess, *words: str) -> str:
    """Exit 2 and exactly one ``error:`` line on stderr holding every one of ``words``; returns the line."""
    assert proc.returncode == 2, (proc.returncode, proc.stderr[-3000:])
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), proc.stderr[-3000:]
    for w in words:
        assert w in lines[0], (w, lines[0])
    return lines[0]


def interrupted(proc: subprocess.CompletedProcess, sig: int, *words: str) -> str:
    """Exit 128 + sig and exactly one ``interrupted:`` line holding every one of ``words``."""
    lines = proc.stderr.splitlines()
    assert proc.returncode == 128 + sig, (proc.returncode, proc.stderr[-3000:])
    assert len(lines) == 1 and lines[0].startswith(f"interrupted: {signal.Signals(sig).name} during "), \
        proc.stderr[-3000:]
    for w in words:
        assert w in lines[0], (w, lines[0])
    return lines[0]


def leftovers(out: Path) -> list[str]:
    return [str(p) for p in out.rglob(".*") if any(k in p.name for k in (".staging.", ".old.", ".new."))]


@pytest.fixture
def box(tmp_path):
    """The sandbox: a home folder, three Hertz levels and one csv of a single level."""
    (tmp_path / "home").mkdir()
    hertz_levels(tmp_path)
    return tmp_path


# --- data loss and writes outside the output folder -----------------------------------------------------------

def test_export_refuses_a_users_mesh_cache_and_a_symlink_out_of_out_as_run_does(box):
    o = box / "o"
    mine = o / "mesh_cache" / "export_hertz_cylinder_base-7b6bf480fef259fa.msh"
    mine.parent.mkdir(parents=True)
    mine.write_text("mine\n")
    before = tree(box)
    refused(wb("export", CASE, "--format", "msh", "--out", o, cwd=box), str(o / "mesh_cache"),
            "not written by the workbench")
    refused(wb("run", CASE, "--dry-run", "--out", o, cwd=box), str(o / "mesh_cache"), "not written by the workbench")
    assert tree(box) == before and mine.read_text() == "mine\n"
    (box / "elsewhere").mkdir()
    (o / "mesh_cache" / mine.name).unlink()
    (o / "mesh_cache").rmdir()
    (o / "mesh_cache").symlink_to(box / "elsewhere")
    before = tree(box)
    refused(wb("export", CASE, "--format", "msh", "--out", o, cwd=box), str(o / "mesh_cache"), "symlink")
    assert tree(box) == before


def test_a_users_folder_named_like_a_staging_folder_is_kept(box):
    """Only staging folders with the workbench's marker are cleared (pid 4194999 is never alive here)."""
    from workbench.owned import make_dirs

    o = box / "o"
    mine = o / ".score_hertz_cylinder.staging.4194999.mine"
    mine.mkdir(parents=True)
    stale = make_dirs(o / ".score_hertz_cylinder.staging.4194999.abc123", kind="score")  # a killed score's own
    proc = wb("score", CASE, box / "level_0.01.csv", "--out", o, cwd=box)
    assert proc.returncode == 0, proc.stderr
    assert mine.is_dir() and not stale.exists()
    assert (o / "score_hertz_cylinder" / "score.json").is_file()


def test_score_and_export_check_workbench_results_as_run_does(box):
    """WORKBENCH_RESULTS = the home folder, a folder with missing parents, a file, the checkout's cases/: refused
    under that name. The level file given to score is malformed, and export asks for a level too fine to fit, so
    a guard that failed would still write nothing (the checkout is checked byte for byte all the same)."""
    (box / "afile").write_text("a file\n")
    (box / "bad.csv").write_text("x_mm,p_MPa\n")
    checkout = tree(CHECKOUT, skip=frozenset({".git", ".venv", "__pycache__", ".pytest_cache", ".ruff_cache",
                                              ".hypothesis", ".xdg"}))
    before = tree(box)
    for results, why in ((box / "home", "is the home folder"), (box / "a" / "b" / "c", "does not exist"),
                         (box / "afile", "is not a folder"), (CHECKOUT / "cases", "source folder")):
        env = {"WORKBENCH_RESULTS": str(results)}
        refused(wb("score", CASE, box / "bad.csv", cwd=box, env=env), "WORKBENCH_RESULTS", why)
        refused(wb("export", CASE, "--format", "json", "--h-contact", "1e-6", cwd=box, env=env), "WORKBENCH_RESULTS",
                why)
    assert tree(box) == before
    assert tree(CHECKOUT, skip=frozenset({".git", ".venv", "__pycache__", ".pytest_cache", ".ruff_cache",
                                          ".hypothesis", ".xdg"})) == checkout


def test_case_names_of_the_score_export_and_external_folders_are_reserved(box):
    for name in ("score_hertz_cylinder", "export_hertz_cylinder", "external_ccx_hertz_cylinder", "Score_x"):
        case = box / f"{name}.toml"
        case.write_text(PROBE_BLOCK.replace('name = "probe"', f'name = "{name}"'))
        refused(wb("validate", case, cwd=box), "[case] name", "reserved prefix", "score_<case>")
        case.unlink()


# --- signals: the swap, the exit, an import -----------------------------------------------------------------------

def test_sigterm_during_the_swap_says_the_new_results_are_in_place(box):
    out = box / "out"
    proc = wb("score", CASE, box / "level_0.01.csv", "--out", out, cwd=box,
              env={"WORKBENCH_TEST_SIGNAL_AT": "swap:SIGTERM"})
    line = interrupted(proc, signal.SIGTERM, "score_hertz_cylinder were already complete and in place")
    assert "previous results kept" not in line
    assert json.loads((out / "score_hertz_cylinder" / "score.json").read_text())["case"] == CASE
    assert not leftovers(out), leftovers(out)
    proc = wb("run", "wedge", "--ci", "--no-pictures", "--out", out, cwd=box,
              env={"WORKBENCH_TEST_SIGNAL_AT": "swap:SIGINT"})
    interrupted(proc, signal.SIGINT, "replacing the results folder of wedge", "wedge were already complete")
    assert json.loads((out / "wedge" / "metrics.json").read_text())["case"] == "wedge"
    assert not leftovers(out), leftovers(out)


@pytest.mark.parametrize("point", ["work-done", "exit", "atexit", "os-exit"])
def test_sigint_and_sigterm_during_the_exit_of_score(box, point):
    """score ends through the fast exit: a signal at each moment of it is one line, 130 / 143."""
    out = box / "out"
    for sig in (signal.SIGINT, signal.SIGTERM):
        proc = wb("score", CASE, box / "level_0.01.csv", "--out", out, cwd=box,
                  env={"WORKBENCH_TEST_SIGNAL_AT": f"{point}:{signal.Signals(sig).name}"})
        interrupted(proc, sig, "score_hertz_cylinder were already complete and in place")
        assert (out / "score_hertz_cylinder" / "score.json").is_file() and not leftovers(out)


def test_sigint_and_sigterm_during_the_exit_of_run_and_the_interpreters_teardown(box):
    """run's fast exit; the full teardown (WORKBENCH_FULL_EXIT=1, the last atexit handler reports); a command that
    does not end through the fast exit (validate)."""
    out = box / "out"
    proc = wb("run", CASE, "--ci", "--no-pictures", "--out", out, cwd=box,
              env={"WORKBENCH_TEST_SIGNAL_AT": "os-exit:SIGINT"})
    interrupted(proc, signal.SIGINT, "during the exit", "hertz_cylinder were already complete")
    assert json.loads((out / CASE / "metrics.json").read_text())["case"] == CASE
    for point, sig in (("teardown", signal.SIGTERM), ("exit", signal.SIGINT)):
        proc = wb("score", CASE, box / "level_0.01.csv", "--out", out, cwd=box,
                  env={"WORKBENCH_TEST_SIGNAL_AT": f"{point}:{signal.Signals(sig).name}",
                       "WORKBENCH_FULL_EXIT": "1"})
        interrupted(proc, sig, "during the exit")
    proc = wb("validate", CASE, cwd=box, env={"WORKBENCH_TEST_SIGNAL_AT": "exit:SIGTERM"})
    interrupted(proc, signal.SIGTERM, "during the exit", "previous results kept")
    assert not leftovers(out)


def test_a_signal_at_the_start_of_a_nested_vtk_import_is_one_line(box):
    """The late SIGINT of make faults (a segmentation fault, no line) landed in the case report's import of
    pyvista: an exception inside VTK's module initialisation. A signal when vtkRenderingContextOpenGL2 imports
    vtkRenderingContext2D gave a second line ('pyvista render failed: ImportError') every time; now the signal
    waits for the import to finish."""
    out = box / "out"
    first = wb("run", CASE, "--ci", "--no-pictures", "--out", out, cwd=box)
    assert first.returncode == 0, first.stderr[-2000:]
    before = tree(out / CASE)
    proc = wb("run", CASE, "--ci", "--out", out, cwd=box,
              env={"WORKBENCH_TEST_SIGNAL_AT": "import:vtkmodules.vtkRenderingContext2D:SIGTERM"})
    interrupted(proc, signal.SIGTERM, "writing the results of hertz_cylinder", "previous results kept")
    assert tree(out / CASE) == before and not leftovers(out)


# --- malformed result files: one line, exit 2 ---------------------------------------------------------------------

def _csv_variants(box: Path) -> dict[str, tuple[Path, list[str]]]:
    rows = (box / "level_0.01.csv").read_text().splitlines()
    body = [r.split(",")[:2] for r in rows[1:]]
    files = {}

    def write(name, text, *words):
        (box / name).write_text(text)
        files[name] = (box / name, list(words))

    write("long_field.csv", rows[0] + "\n" + "\n".join(rows[1:3]) + "\n" + "1" * 200_000 + ",1,1\n",
          "line 4 is not csv", "field larger than field limit")
    write("weights_0.csv", "x_mm,p_MPa,weight_mm\n" + "".join(f"{x},{p},0\n" for x, p in body),
          "integrates to P = 0")
    write("load_1e300.csv", "x_mm,p_MPa,P_N_per_mm\n" + "".join(f"{x},{p},1e300\n" for x, p in body),
          "P = 1e+300", "outside what the case's theory evaluates")
    write("p_1e300.csv", "x_mm,p_MPa\n" + "".join(f"{x},{float(p) * 1e300!r}\n" for x, p in body),
          "outside what the case's theory evaluates")
    write("p_1e-320.csv", "x_mm,p_MPa\n" + "".join(f"{x},{float(p) * 1e-320!r}\n" for x, p in body),
          "outside what the case's theory evaluates")
    return files


def test_malformed_csv_results_are_one_line(box):
    out = box / "out"
    for name, (f, words) in _csv_variants(box).items():
        before = tree(box)
        refused(wb("score", CASE, f, "--out", out, cwd=box), name, *words)
        assert tree(box) == before, name
    refused(wb("score", CASE, box / "level_0.01.csv", "--samples-per-element", "9" * 400, "--out", out, cwd=box),
            "--samples-per-element = a number of 400 digits", "allowed: 1 to 1000")
    assert not out.exists()


def test_malformed_frd_results_are_one_line(box):
    out = box / "out"
    contact = " -1         1 0.00000E+00 0.00000E+00 0.00000E+00 5.00000E+03 0.00000E+00 0.00000E+00"
    cases = {
        "short_contact.frd": (FRD.replace(contact, contact[:-24]), ["CONTACT", "a record with 4 values", "allowed: 6"]),
        "one_coordinate.frd": (FRD.replace(" -1         2 1.00000E-01 0.00000E+00 0.00000E+00",
                                           " -1         2 1.00000E-01"), ["node 2", "allowed: 3"]),
        "cpress_nan.frd": (FRD.replace("5.00000E+03", "        NaN"), ["CONTACT", "NaN or infinite", "node 1"]),
        "empty_disp.frd": (with_disp().replace(" -1         1 0.00000E+00-1.00000E-03 0.00000E+00\n", "")
                           .replace(" -1         2 1.00000E-05-9.00000E-04 0.00000E+00\n", "")
                           .replace(" -1         3 2.00000E-05-5.00000E-04 0.00000E+00\n", ""),
                           ["the DISP block has no node records"]),
        "inf_coordinate.frd": (FRD.replace(" -1         3 2.00000E-01", " -1         3         inf"),
                               ["node 3 has a non-finite coordinate"]),
    }
    for name, (text, words) in cases.items():
        (box / name).write_text(text)
        refused(wb("score", CASE, box / name, "--format", "frd", "--out", out, cwd=box), name, *words)
    (box / "with_disp.frd").write_text(with_disp())  # the DISP block as CalculiX writes it (ALL: no value) is read
    proc = wb("score", CASE, box / "with_disp.frd", "--format", "frd", "--out", out, cwd=box)
    assert proc.returncode == 0, proc.stderr
    assert json.loads((out / "score_hertz_cylinder" / "score.json").read_text())["levels"][0]["samples"] == 5


def test_malformed_vtk_results_are_one_line(box):
    out = box / "out"
    (box / "r.vtp").write_text(VTP)
    (box / "no_file.pvd").write_text('<VTKFile type="Collection"><Collection><DataSet timestep="1"/></Collection>'
                                     "</VTKFile>\n")
    refused(wb("score", CASE, box / "no_file.pvd", "--format", "vtu", "--out", out, cwd=box), "no_file.pvd",
            "no file attribute")
    (box / "elsewhere").mkdir()
    (box / "elsewhere" / "r.vtp").write_text(VTP)
    (box / "pvds").mkdir()
    (box / "pvds" / "up.pvd").write_text('<VTKFile type="Collection"><Collection><DataSet file="../elsewhere/r.vtp"/>'
                                         "</Collection></VTKFile>\n")
    refused(wb("score", CASE, box / "pvds" / "up.pvd", "--format", "vtu", "--out", out, cwd=box), "up.pvd",
            "outside the folder")
    (box / "one_d.vtp").write_text(VTP.replace('Name="Points" NumberOfComponents="3" format="ascii">0 0 0 0.1 0 0 0.2 '
                                               '0 0', 'Name="Points" NumberOfComponents="1" format="ascii">0 0.1 0.2'))
    refused(wb("score", CASE, box / "one_d.vtp", "--format", "vtu", "--out", out, cwd=box), "one_d.vtp",
            "1 component(s); allowed: 2 or 3")
    (box / "bomb.vtp").write_text(zlib_vtp(points=3, zeros=64 * 2**20))  # 64 MB of zeros declared, 3 points
    assert (box / "bomb.vtp").stat().st_size < 100_000
    refused(wb("score", CASE, box / "bomb.vtp", "--format", "vtu", "--out", out, cwd=box), "bomb.vtp",
            "declares 67108936 bytes uncompressed", "refused before inflating")
    assert not out.exists()


def test_fifos_and_a_symlink_out_of_the_folder_are_never_read(box):
    """A FIFO as RESULT or as a .pvd's dataset hung score until killed; a symlink to /etc/passwd put its first line
    in the error; a FIFO case file was called 'no such case file'."""
    out = box / "out"
    os.mkfifo(box / "fifo.csv")
    refused(wb("score", CASE, box / "fifo.csv", "--out", out, cwd=box, timeout=60), "fifo.csv", "is a FIFO")
    os.mkfifo(box / "fifo.vtp")
    (box / "fifo.pvd").write_text('<VTKFile type="Collection"><Collection><DataSet file="fifo.vtp"/></Collection>'
                                  "</VTKFile>\n")
    refused(wb("score", CASE, box / "fifo.pvd", "--format", "vtu", "--out", out, cwd=box, timeout=60), "fifo.pvd",
            "is a FIFO")
    (box / "pw.csv").symlink_to("/etc/passwd")
    line = refused(wb("score", CASE, box / "pw.csv", "--out", out, cwd=box), "pw.csv", "outside the folder")
    first = Path("/etc/passwd").read_text().splitlines()[0]
    assert first not in line and "root:" not in line
    (box / "passwd_copy.csv").write_text(Path("/etc/passwd").read_text())  # a copy in the folder: never echoed
    line = refused(wb("score", CASE, box / "passwd_copy.csv", "--out", out, cwd=box), "missing column")
    assert first not in line and "root:" not in line
    os.mkfifo(box / "case.toml")
    refused(wb("validate", box / "case.toml", cwd=box, timeout=60), "case.toml", "not a regular file", "FIFO")
    # a device or a file without .toml was called "no such case file" too (both exist)
    refused(wb("run", "/dev/zero", "--ci", "--out", out, cwd=box, timeout=60), "/dev/zero", "not a regular file")
    (box / "notes.txt").write_text("[case]\n")
    refused(wb("run", box / "notes.txt", "--ci", "--out", out, cwd=box, timeout=60), "notes.txt", "is not a .toml file")
    assert not out.exists()


def test_score_refuses_a_case_it_cannot_judge_before_reading(box):
    """The wedge's own pressure.csv gave a TypeError; since issue 36 every case of the 14 is scored, and a case score
    cannot judge is refused first (the file does not even exist): a run with finite kinematics, which the case
    compares in the current configuration while a result gives reference positions."""
    text = (CHECKOUT / "cases" / "hertz_cylinder.toml").read_text()
    probe = box / "finite_probe.toml"
    probe.write_text(text.replace('name = "hertz_cylinder"', 'name = "finite_probe"')
                     .replace('kinematics = "small"', 'kinematics = "finite"')
                     .replace('traction = "halfplane"', 'traction = "obstacle"')
                     .replace("\nnu = 0.3\n", '\nnu = 0.3\nmodel = "neo_hookean"\n'))
    refused(wb("score", probe, box / "missing.csv", "--out", box / "out", cwd=box), "case finite_probe",
            "finite kinematics", "allowed: a case whose runs are small or convective")
    assert not (box / "out").exists()


def test_export_refuses_a_level_too_fine_with_runs_size_estimate_and_writes_nothing_in_home(box):
    refused(wb("export", CASE, "--format", "msh", "--h-contact", "1e-6", "--out", box / "out", cwd=box),
            "--h-contact = 1e-06 needs about", "triangles", "allowed: --h-contact >=")
    home = tree(box / "home")
    proc = wb("export", CASE, "--format", "inp", "--out", box / "out", cwd=box)
    assert proc.returncode == 0, proc.stderr
    assert tree(box / "home") == home == {}, tree(box / "home")  # gmsh's FLTK wrote ~/.fltk/fltk.org/fltk.prefs


def test_pictures_write_nothing_in_home(box):
    """matplotlib created an empty ``~/.config/matplotlib`` (its config folder) for every picture: ``run`` with its
    pictures and ``score`` (its pressure.png) leave the home folder as it was (the caches stay where
    ``XDG_CACHE_HOME`` says)."""
    cache = {"XDG_CACHE_HOME": os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")}
    run = wb("run", CASE, "--ci", "--out", box / "out", cwd=box, env=cache)
    assert run.returncode == 0 and (box / "out" / CASE / "pressure.png").is_file(), run.stderr[-2000:]
    score = wb("score", CASE, *sorted(box.glob("level_*.csv")), "--out", box / "out", cwd=box, env=cache)
    assert score.returncode == 0, score.stderr[-2000:]
    assert tree(box / "home") == {}, tree(box / "home")


def test_python_m_analytic_errors_start_with_error(box):
    for args, words in ((["hertz", "--P", "-1", "--R", "1", "--E", "1", "--nu", "0.3"], ["--P = -1.0"]),
                        (["lcp"], ["required: --config"]), (["bogus"], ["invalid choice"])):
        proc = subprocess.run([sys.executable, "-m", "analytic", *args], cwd=box, env=ENV, capture_output=True,
                              text=True, timeout=120)
        refused(proc, "python -m analytic", *words)


# --- verdicts that must not be given ------------------------------------------------------------------------------

def _verdict(proc) -> dict:
    assert proc.returncode == 0, proc.stderr
    out = Path(proc.stdout.splitlines()[0].split(" -> ")[1].split(" (")[0])
    return json.loads((out / "score.json").read_text())


def test_no_verdict_for_mixed_units_reversed_sizes_or_different_loads(box):
    out = box / "out"
    metres = hertz_levels(box, hs=(0.01,), scale_x=1e-3, scale_p=1e6, names=["level_0.01_m.csv"])
    score = _verdict(wb("score", CASE, box / "level_0.04.csv", box / "level_0.02.csv", *metres, "--out", out,
                        cwd=box))
    assert score["verdict"].startswith("No verdict:") and "consistent" not in score["verdict"].lower()
    assert score["models"] is None
    assert "positions in mm and pressures in MPa?" in score["verdict"] and "loads differ" in score["verdict"]
    assert "not finite or not narrower than the quantity" in score["verdict"]
    files = [box / f"level_{h}.csv" for h in (0.04, 0.02, 0.01)]
    score = _verdict(wb("score", CASE, *files, "--h", "0.01", "0.02", "0.04", "--out", out, cwd=box))
    assert score["verdict"].startswith("No verdict:") and "h does not decrease" in score["verdict"]
    assert "diverge" in score["verdict"] and score["grid_study"]["p_max"]["status"] == "diverging"
    other = hertz_levels(box, hs=(0.01,), scale_p=1.05, names=["level_0.01_heavier.csv"])  # 5 % more load
    score = _verdict(wb("score", CASE, *files[:2], *other, "--out", out, cwd=box))
    assert score["verdict"].startswith("No verdict:") and "loads differ by 5.000%" in score["verdict"]
    score = _verdict(wb("score", CASE, *files, "--out", out, cwd=box))  # the control: a verdict
    assert not score["plausibility"] and "-0.500% from Hertz" in score["verdict"]


def test_duplicated_positions_are_merged_like_the_frd_and_vtu_readers_do(box):
    rows = (box / "level_0.01.csv").read_text().splitlines()
    x, p, load = rows[41].split(",")
    (box / "dup.csv").write_text("\n".join(rows + [f"{x},{float(p) * 0.5!r},{load}"]) + "\n")  # a lower twin
    out = box / "out"
    proc = wb("score", CASE, box / "dup.csv", "--out", out, cwd=box)
    assert "1 sample(s) at a repeated position merged, the largest pressure kept" in proc.stdout
    dup = _verdict(proc)["levels"][0]
    assert "dup.csv: 1" in (out / "score_hertz_cylinder" / "report.md").read_text()  # the report says so too
    one = _verdict(wb("score", CASE, box / "level_0.01.csv", "--out", out, cwd=box))["levels"][0]
    assert dup["merged_samples"] == 1 and one["merged_samples"] == 0
    for key in ("P_integral", "p_max", "half_width", "half_width_moment", "samples"):
        assert dup[key] == one[key], key
    assert "merged" not in (out / "score_hertz_cylinder" / "report.md").read_text()


def test_a_gmsh_failure_in_export_is_one_line_and_nothing_written(box, monkeypatch, capsys):
    """Under a memory limit gmsh raised an Exception with a traceback (exit 1, 'tolerance FAIL'); the meshing now
    fails in one line (in-process: a limit that lets the size estimate pass but not gmsh depends on the machine)."""
    import workbench.scenes.block as block
    from workbench.external.export import main as export_main

    def failing_mesh(*args, **kwargs):
        raise Exception("gmsh: Could not allocate memory")  # what gmsh raises: a bare Exception

    monkeypatch.setattr(block, "block_mesh", failing_mesh)
    out = box / "out"
    assert export_main(["hertz_cylinder", "--format", "msh", "--out", str(out)]) == 1
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: export hertz_cylinder failed: Exception: gmsh: Could not "
                                                   "allocate memory; nothing written"), lines
    assert not (out / "export_hertz_cylinder").exists() and not leftovers(out)
