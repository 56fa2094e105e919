"""The workbench deletes, replaces and overwrites only what it wrote (issue 23, "Critical"), through the real command
line.

Every refusal is checked the way a user meets it: ``python -m workbench ...`` in a subprocess exits 2 with exactly
one line on stderr that starts with ``error:`` and names the folder, file or field, and the user's files (and the
checkout) are byte-identical afterwards (paths and SHA-256 before and after). Refusals happen before any solve, so
these tests solve nothing, except :func:`test_a_run_marks_its_folders_and_replaces_only_its_own`, which solves the
smallest probe case twice at its CI level.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from fuzz_support import CHECKOUT, SKIP, tree
from probe_cases import PROBE_BLOCK

from cases.schema import RESERVED_NAMES, label_folder
from workbench.atomic import atomic_dir, write_json, write_root_text
from workbench.owned import MARKER, is_owned, make_dirs, read_marker, root_files
from workbench.paths import OutputPaths

ENV = os.environ | {"PYTHONPATH": str(CHECKOUT), "OMP_NUM_THREADS": "1"}


def wb(*args, cwd: Path, env: dict | None = None) -> subprocess.CompletedProcess:
    """``python -m workbench ARGS`` from ``cwd``."""
    return subprocess.run([sys.executable, "-m", "workbench", *map(str, args)], cwd=cwd, env=env or ENV,
                          capture_output=True, text=True, timeout=600)


def refused(proc: subprocess.CompletedProcess, *words: str) -> str:
    """Exit 2 and exactly one ``error:`` line on stderr that holds every one of ``words``; returns the line."""
    assert proc.returncode == 2, (proc.returncode, proc.stderr[-2000:])
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), proc.stderr
    for w in words:
        assert w in lines[0], (w, lines[0])
    return lines[0]


def case_file(path: Path, name: str, labels: tuple[str, ...] = ()) -> Path:
    """The smallest valid block case, named ``name``, with variants of ``labels``."""
    path.parent.mkdir(parents=True, exist_ok=True)
    text = PROBE_BLOCK.replace('name = "probe"', f'name = "{name}"')
    path.write_text(text + "".join(f'[[variant]]\nlabel = "{lb}"\n' for lb in labels))
    return path


def user_files(root: Path, rels) -> None:
    """A user's own files (no marker anywhere)."""
    for rel in rels:
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        (root / rel).write_text(f"the user's {rel}\n")


@pytest.fixture
def checkout_unchanged():
    """The checkout (tracked files, untracked ones and results/; not .git, the venv or caches): byte-identical."""
    skip = frozenset(SKIP)  # fuzz_support's: also a JIT cache the user put inside the checkout
    before = tree(CHECKOUT, skip=skip)
    yield
    assert tree(CHECKOUT, skip=skip) == before


# --- --out and WORKBENCH_RESULTS: never /, the home folder or the project's source ---------------------------------

def test_out_never_the_root_home_or_the_source_tree(tmp_path, checkout_unchanged):
    """Each real folder is given with a case file the schema refuses later (a reserved name): should this guard ever
    fail, the run still writes nothing there, and the test fails on the message."""
    home = tmp_path / "home"
    user_files(home, ["notes.txt", "cases/mine.toml"])
    refused_later = case_file(tmp_path / "c" / "logs.toml", "logs")
    case = case_file(tmp_path / "c" / "cases.toml", "cases")
    env = ENV | {"HOME": str(home)}
    before = tree(tmp_path)
    for out, why in ((CHECKOUT, "holds the project's source"), (CHECKOUT / "cases", "source folder"),
                     (CHECKOUT / "fem", "source folder"), (CHECKOUT.parent, "holds the project's source"),
                     ("/", "root of the file system"), (home, "home folder"), ("~", "home folder")):
        refused(wb("run", refused_later, "--out", out, cwd=tmp_path, env=env), "--out", why)
        refused(wb("run", refused_later, cwd=tmp_path, env=env | {"WORKBENCH_RESULTS": str(out)}),
                "WORKBENCH_RESULTS", why)
    # the issue: a case named "cases" run with --out at the checkout (its cases/ is the user's: refused again by the
    # ownership check if this guard ever fails)
    refused(wb("run", case, "--out", CHECKOUT, cwd=tmp_path, env=env), "--out", "holds the project's source")
    for out in (home, "~"):
        refused(wb("report", "--out", out, cwd=tmp_path, env=env), "--out", "home folder")
    refused(wb("convective-table", "--out", CHECKOUT / "analytic", cwd=tmp_path, env=env), "--out", "source folder")
    refused(wb("convergence", "--out", CHECKOUT, cwd=tmp_path, env=env), "--out", "project's source")
    assert tree(tmp_path) == before


# --- reserved names, two cases of one name, variant labels ------------------------------------------------------

def test_reserved_case_names_are_refused_and_the_users_folders_stay(tmp_path):
    out = tmp_path / "out"
    user_files(out, ["analytic/notes.txt", "logs/notes.txt", "mesh_cache/keep.msh"])
    before = tree(tmp_path)
    for name in ("analytic", "logs", "mesh_cache", "ci", "convergence", "Logs", "report"):
        case = case_file(tmp_path / f"{name}.toml", name)
        for cmd in (["validate", case], ["run", case, "--out", out]):
            refused(wb(*cmd, cwd=tmp_path), "[case] name", "is reserved", "mesh_cache, analytic, logs")
        case.unlink()
    assert tree(tmp_path) == before
    assert {"mesh_cache", "analytic", "logs", "ci", "convergence", "stability", "bench", "validity"} <= set(
        RESERVED_NAMES)
    paths = OutputPaths(tmp_path)
    assert {paths.mesh_cache.name, paths.logs.name, paths.ci.root.name, paths.analytic.name} <= set(
        RESERVED_NAMES)


def test_two_case_files_of_one_name_in_one_run_are_refused(tmp_path):
    a, b = case_file(tmp_path / "a.toml", "same"), case_file(tmp_path / "b.toml", "same")
    refused(wb("run", a, b, "--out", tmp_path / "out", cwd=tmp_path), "'same'", "given twice", "a.toml", "b.toml")
    assert not (tmp_path / "out").exists()


def test_variant_labels_map_to_distinct_folders_or_validate_refuses(tmp_path):
    clash = case_file(tmp_path / "clash.toml", "clash", ("a/b", "a_b"))
    refused(wb("validate", clash, cwd=tmp_path), "variant[1].label = 'a_b'", "variant[0].label = 'a/b'",
            "run folder 'a_b'")
    ok = case_file(tmp_path / "dots.toml", "dots", ("..", ".", "theta=pi/20"))
    proc = wb("validate", ok, cwd=tmp_path)
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr
    folders = [label_folder(lb) for lb in ("..", ".", "theta=pi/20", "a/../../b", ".hidden", "ü" * 64)]
    assert folders[:3] == ["_.", "_", "theta_pi_20"]
    assert all(f and not f.startswith(".") and "/" not in f and f.isascii() for f in folders)


# --- the folders and files of a run -----------------------------------------------------------------------------

def test_a_case_file_in_the_folder_its_results_would_replace_is_refused(tmp_path):
    # the issue: cf/proj/mycase.toml named proj, run with --out cf, deleted its own case file and the notes beside it
    cf = tmp_path / "cf"
    case = case_file(cf / "proj" / "mycase.toml", "proj")
    user_files(cf, ["proj/notes.txt"])
    before = tree(tmp_path)
    refused(wb("run", case, "--out", cf, cwd=tmp_path), str(cf / "proj"), "not written by the workbench")
    # the same when the folder is the workbench's own (a result folder the user saved a case file into)
    shutil.rmtree(cf)
    make_dirs(cf / "proj", kind="case")
    case = case_file(cf / "proj" / "mycase.toml", "proj")
    before = tree(tmp_path)
    refused(wb("run", case, "--out", cf, cwd=tmp_path), "mycase.toml", "lies inside", "would replace")
    assert tree(tmp_path) == before


def test_folders_without_the_marker_are_never_replaced_or_written_into(tmp_path):
    out = tmp_path / "out"
    case = case_file(tmp_path / "probe.toml", "probe")
    # results of an older workbench (no marker), a user's logs folder: refused, with how to proceed
    user_files(out, ["probe/metrics.json", "probe/notes.txt"])
    before = tree(tmp_path)
    line = refused(wb("run", case, "--out", out, cwd=tmp_path), str(out / "probe"), "not written by the workbench")
    assert "move it away" in line and MARKER in line
    shutil.rmtree(out / "probe")
    user_files(out, ["logs/notes.txt"])
    before = tree(tmp_path)
    refused(wb("run", case, "--out", out, cwd=tmp_path), str(out / "logs"))
    refused(wb("mesh", case, "--out", out, cwd=tmp_path), str(out / "logs"))
    assert tree(tmp_path) == before


def test_no_symlink_is_followed_out_of_out(tmp_path):
    out, elsewhere = tmp_path / "out", tmp_path / "elsewhere"
    user_files(elsewhere, ["keep.msh", "probe/notes.txt"])
    out.mkdir()
    (out / "mesh_cache").symlink_to(elsewhere)
    case = case_file(tmp_path / "probe.toml", "probe")
    before = tree(tmp_path)
    refused(wb("run", case, "--out", out, cwd=tmp_path), str(out / "mesh_cache"), "symlink")
    refused(wb("mesh", case, "--out", out, cwd=tmp_path), "symlink")
    refused(wb("convergence", "--mesh-cache", out / "mesh_cache", "--out", tmp_path / "conv", cwd=tmp_path),
            "symlink")
    (out / "mesh_cache").unlink()
    (out / "probe").symlink_to(elsewhere / "probe")  # a case folder that is a symlink
    before = tree(tmp_path)
    refused(wb("run", case, "--out", out, cwd=tmp_path), str(out / "probe"), "symlink")
    assert tree(tmp_path) == before


# --- report, ci and the studies ---------------------------------------------------------------------------------

def test_report_overwrites_only_the_files_it_wrote(tmp_path):
    folder = tmp_path / "mine"
    user_files(folder, ["report.md", "report.html"])
    before = tree(tmp_path)
    # the issue: WORKBENCH_RESULTS=<folder> workbench report overwrote a user's report.md and report.html
    refused(wb("report", cwd=tmp_path, env=ENV | {"WORKBENCH_RESULTS": str(folder)}), str(folder / "report.md"),
            "not written by the workbench")
    # with --out: the "HTML twins" of a user's analytic/convective.md and ci_report.md
    out = tmp_path / "out"
    user_files(out, ["analytic/convective.md", "analytic/convective.html"])
    refused(wb("report", "--out", out, cwd=tmp_path), str(out / "analytic"))
    shutil.rmtree(out / "analytic")
    user_files(out, ["ci_report.md", "ci_report.html"])
    refused(wb("report", "--out", out, cwd=tmp_path), str(out / "ci_report.html"))
    shutil.rmtree(out)
    assert tree(tmp_path) == before
    # its own files: written, listed in the output folder's marker, and overwritten by the next report
    clean = tmp_path / "clean"
    user_files(clean, ["notes.txt"])
    for _ in range(2):
        proc = wb("report", "--out", clean, cwd=tmp_path)
        assert proc.returncode == 0, proc.stderr
    assert {"report.md", "report.html"} <= root_files(clean)
    assert read_marker(clean)["adopted"] is True and not is_owned(clean)  # the user's folder stays the user's
    assert (clean / "notes.txt").read_text() == "the user's notes.txt\n"


def test_ci_refuses_a_users_files_before_running_anything(tmp_path):
    out = tmp_path / "out"
    user_files(out, ["ci/notes.txt"])
    before = tree(tmp_path)
    refused(wb("ci", "--out", out, cwd=tmp_path), str(out / "ci"), "not written by the workbench")
    assert tree(tmp_path) == before
    shutil.rmtree(out / "ci")
    user_files(out, ["ci_report.md"])
    before = tree(tmp_path)
    refused(wb("ci", "--out", out, cwd=tmp_path), str(out / "ci_report.md"))
    assert tree(tmp_path) == before


@pytest.mark.parametrize("study,folder", [("convergence", "convergence"), ("stability", "stability"),
                                          ("bench", "bench"), ("validity", "validity"),
                                          ("convective-table", "analytic")])
def test_every_study_refuses_a_users_folder(tmp_path, study, folder):
    out = tmp_path / "out"
    user_files(out, [f"{folder}/notes.txt", "given/notes.txt"])
    before = tree(tmp_path)
    env = ENV | {"WORKBENCH_RESULTS": str(out)}
    refused(wb(study, cwd=tmp_path, env=env), str(out / folder), "not written by the workbench")  # its default
    refused(wb(study, "--out", out / "given", cwd=tmp_path, env=env), str(out / "given"))
    assert tree(tmp_path) == before


# --- a real run: marks its folders, replaces only its own ---------------------------------------------------------

def test_a_run_marks_its_folders_and_replaces_only_its_own(tmp_path):
    out = tmp_path / "out"
    user_files(out, ["notes.txt", "mine/notes.txt"])
    case = case_file(tmp_path / "probe.toml", "probe")
    other = case_file(tmp_path / "other.toml", "other")
    mine = tree(out / "mine")
    # two concurrent runs into one --out: both make the mesh cache and logs checks at once, neither is refused
    procs = [subprocess.Popen([sys.executable, "-m", "workbench", "run", str(c), "--ci", "--out", str(out)],
                              cwd=tmp_path, env=ENV, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
             for c in (case, other)]
    for p in procs:
        err = p.communicate(timeout=600)[1]
        assert p.returncode in (0, 1) and err == "", (p.returncode, err[-2000:])
    proc = wb("run", case, "--ci", "--out", out, cwd=tmp_path)  # replaces the first run's folder (its own)
    assert proc.returncode in (0, 1) and proc.stderr == "", proc.stderr[-2000:]
    assert is_owned(out / "other", kinds=("case",))
    assert is_owned(out / "probe", kinds=("case",)) and is_owned(out / "mesh_cache", kinds=("mesh_cache",))
    assert is_owned(out / "probe" / "vtk" / "base", kinds=("vtk",))
    assert json.loads((out / "probe" / "metrics.json").read_text())["case"] == "probe"
    assert tree(out / "mine") == mine and (out / "notes.txt").read_text() == "the user's notes.txt\n"
    assert not is_owned(out) and not [p.name for p in out.iterdir() if p.name.startswith(".") and p.name != MARKER]


# --- the writers themselves ---------------------------------------------------------------------------------------

def test_atomic_dir_replaces_only_a_workbench_case_folder(tmp_path):
    from workbench.paths import OutputError

    user_files(tmp_path, ["user/notes.txt"])
    with pytest.raises(OutputError, match="not written by the workbench"), atomic_dir(tmp_path / "user"):
        pass
    make_dirs(tmp_path / "study", kind="convergence")  # the workbench's, but not a case folder
    with pytest.raises(OutputError, match="not one of: case"), atomic_dir(tmp_path / "study"):
        pass
    with atomic_dir(tmp_path / "case") as stage:
        write_json(stage / "metrics.json", {})
    with atomic_dir(tmp_path / "case") as stage:  # its own: replaced
        write_json(stage / "metrics.json", {"again": True})
    assert json.loads((tmp_path / "case" / "metrics.json").read_text()) == {"again": True}
    # a folder that only looks like a swap left behind (no marker) is never deleted or moved into place
    user_files(tmp_path, [".other.old.999999/notes.txt"])
    with atomic_dir(tmp_path / "other") as stage:
        write_json(stage / "metrics.json", {})
    assert (tmp_path / ".other.old.999999" / "notes.txt").is_file()
    assert tree(tmp_path / "user") == {"notes.txt": tree(tmp_path / "user")["notes.txt"]}


def test_a_top_level_file_is_overwritten_only_when_listed(tmp_path):
    from workbench.paths import OutputError

    write_root_text(tmp_path, "report.md", "one")
    write_root_text(tmp_path, "report.md", "two")
    assert (tmp_path / "report.md").read_text() == "two" and root_files(tmp_path) == {"report.md"}
    (tmp_path / "ci_report.md").write_text("the user's")
    with pytest.raises(OutputError, match="ci_report.md exists and was not written by the workbench"):
        write_root_text(tmp_path, "ci_report.md", "x")
    (tmp_path / "report.html").symlink_to(tmp_path / "ci_report.md")
    with pytest.raises(OutputError, match="symlink"):
        write_root_text(tmp_path, "report.html", "x")
    assert (tmp_path / "ci_report.md").read_text() == "the user's"


def test_a_study_elsewhere_writes_no_summary_above_its_folder(tmp_path, capsys):
    from workbench.reports.study_pages import publish_study

    user_files(tmp_path, ["report.md"])
    study = make_dirs(tmp_path / "conv", kind="convergence")  # `workbench convergence --out <user folder>/conv`
    (study / "report.md").write_text("# Convergence\n")
    before = tree(tmp_path)
    assert publish_study(study, []).is_file()
    assert "summary not rebuilt" in capsys.readouterr().out
    assert {k: v for k, v in tree(tmp_path).items() if not k.startswith("conv")} == {
        k: v for k, v in before.items() if not k.startswith("conv")}


def test_a_mesh_cache_made_by_the_mesh_layer_is_the_workbenchs(tmp_path):
    from meshes.cache import make_cache_dir
    from workbench.owned import TOOL

    make_cache_dir(tmp_path / "new" / "mesh_cache")
    assert is_owned(tmp_path / "new" / "mesh_cache", kinds=("mesh_cache",)) and TOOL == "contact-workbench"
    user_files(tmp_path, ["mine/keep.msh"])
    make_cache_dir(tmp_path / "mine")  # a folder that exists: left as it is
    assert not (tmp_path / "mine" / MARKER).exists()


def test_results_of_the_checkout_stay_the_default_and_allowed():
    from workbench.paths import DEFAULT_ROOT, OutputError, check_location

    check_location(DEFAULT_ROOT)
    check_location(DEFAULT_ROOT / "sub")
    for bad in (CHECKOUT / ".git", CHECKOUT / "tests", CHECKOUT / "workbench" / "x"):
        with pytest.raises(OutputError):
            check_location(bad)


# --- a read-only folder (a part that needs mount rights: skipped alone, with its reason) ---------------------------

def test_a_read_only_tmpfs_out_is_refused_in_a_private_mount_namespace(tmp_path):
    """A read-only tmpfs mounted in a private mount namespace (``unshare``), never on the host."""
    unshare = shutil.which("unshare")
    if unshare is None:
        pytest.skip("needs `unshare` (util-linux) to mount a read-only tmpfs in a private mount namespace")
    ro = tmp_path / "ro"
    ro.mkdir()
    case = case_file(tmp_path / "probe.toml", "probe")
    flags = ["--mount", "--propagation", "private"] + ([] if os.geteuid() == 0 else ["--map-root-user"])
    probe = subprocess.run([unshare, *flags, "mount", "-t", "tmpfs", "-o", "ro,size=64k", "tmpfs", str(ro)],
                           capture_output=True, text=True)
    if probe.returncode != 0:
        pytest.skip(f"no mount rights for a private mount namespace: {probe.stderr.strip()[:200]}")
    script = (f'mount -t tmpfs -o ro,size=64k tmpfs "{ro}" && '
              f'"{sys.executable}" -m workbench run "{case}" --out "{ro}"; echo "exit=$?" >&2; '
              f'"{sys.executable}" -m workbench run "{case}" --out "{ro}/new"; echo "exit=$?" >&2')
    proc = subprocess.run([unshare, *flags, "sh", "-c", script], capture_output=True, text=True, env=ENV,
                          cwd=tmp_path, timeout=300)
    lines = proc.stderr.splitlines()
    assert lines[1::2] == ["exit=2", "exit=2"], proc.stderr
    assert all(ln.startswith("error: --out ") and "read-only" in ln for ln in lines[0::2]), proc.stderr
    assert list(ro.iterdir()) == []  # the host never saw the mount
