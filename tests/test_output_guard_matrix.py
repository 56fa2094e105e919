"""One output-folder guard for every command that writes (issue 35): the same hostile folders for each command.

Requirement: ``run``, ``mesh``, ``report``, ``ci``, the five studies, ``score``, ``export`` and ``external``
(``ccx``, ``kratos``, ``workbench``, ``compare``) and ``forcelaw`` refuse each hostile folder below with exit 2 and
one ``error:`` line naming it, whether the output folder comes from ``--out`` or from ``WORKBENCH_RESULTS``, and
nothing in the sandbox changes (paths and SHA-256 before and after). The folders: a file; a folder whose parents are
missing; the home folder; a source folder of the checkout (a copy of its layout, the guard pointed at it); the
command's own folder made by the user (no marker); and, for the commands that write the mesh cache, a ``mesh_cache``
that is a symlink out of the output folder or a user's unmarked folder. A good folder passes the guard for every
command (the control: the matrix would pass trivially if everything were refused).

In-process (``workbench.cli.main(argv)``): the step after each command's guard is replaced by a recorder that
raises :class:`Reached`, so a guard that lets a hostile folder through fails the test without computing anything.
The real command line runs the reproducers of the issue: ``tests/test_issue35_reproducers.py``.
"""

from __future__ import annotations

import pytest
from fuzz_support import tree

import workbench.paths as paths_module
from workbench.cli import main

CASE = "hertz_cylinder"
STUDIES = {"convergence": "convergence", "stability": "stability", "bench": "bench", "validity": "validity",
           "convective-table": "analytic", "concave-map": "concave_map"}
EXTERNAL = ("external", "external_kratos", "external_workbench", "external_compare")  # ccx, kratos, own, compare
MESH_WRITERS = {"run", "mesh", "convergence", "stability", "bench", "validity", "concave-map", "export", *EXTERNAL}
COMMANDS = ["run", "mesh", "report", "ci", *STUDIES, "score", "export", *EXTERNAL, "forcelaw"]
ROWS = ["file", "missing_parents", "home", "source", "user_target", "mesh_link", "mesh_user"]
WORDS = {"file": ["is not a folder"], "missing_parents": ["does not exist"], "home": ["home folder"],
         "source": ["source folder"], "user_target": ["not written by the workbench"], "mesh_link": ["symlink"],
         "mesh_user": ["mesh_cache", "not written by the workbench"]}


class Reached(BaseException):
    """The command got past its guard."""


def _reached(*args, **kwargs):
    raise Reached


@pytest.fixture
def recorders(monkeypatch):
    """The step after each command's guard raises Reached."""
    import importlib

    import analytic.force_law as force_law
    import workbench.external.ccx as ccx
    import workbench.external.compare as compare
    import workbench.external.export as export
    import workbench.external.kratos as kratos
    import workbench.external.own_code as own_code
    import workbench.external.score as score
    import workbench.pipeline.case_mesh as case_mesh
    import workbench.pipeline.ci as ci
    import workbench.pipeline.run_case as run_case
    import workbench.reports.summary as summary
    from workbench.cli import STUDIES as MODULES

    monkeypatch.setattr(run_case, "run_case", _reached)
    monkeypatch.setattr(case_mesh, "case_meshes", _reached)
    monkeypatch.setattr(summary, "write_summary", _reached)
    monkeypatch.setattr(ci, "run_ci", _reached)
    monkeypatch.setattr(score, "read_results", _reached)
    monkeypatch.setattr(export, "export_case", _reached)
    monkeypatch.setattr(ccx, "ccx_executable", _reached)
    monkeypatch.setattr(kratos, "kratos_python", _reached)
    monkeypatch.setattr(own_code, "run_job", _reached)
    monkeypatch.setattr(compare, "_check_codes", _reached)
    monkeypatch.setattr(force_law, "force_law", _reached)
    for module in MODULES.values():
        monkeypatch.setattr(importlib.import_module(module), "main", _reached)


def _target(command: str, root) -> tuple[str, bool]:
    """The folder (or file) the command writes under the output folder ``root``, and whether it is a file."""
    if command in STUDIES:
        return STUDIES[command], False
    return {"run": (CASE, False), "mesh": (CASE, False), "report": ("report.md", True), "ci": ("ci", False),
            "score": (f"score_{CASE}", False), "export": (f"export_{CASE}", False),
            "external": (f"external_ccx_{CASE}", False), "external_kratos": (f"external_kratos_{CASE}", False),
            "external_workbench": (f"external_workbench_{CASE}", False),
            "external_compare": ("external_compare", False),
            "forcelaw": ("forcelaw_close_to_conformal", False)}[command]


def _argv(command: str, sandbox, out: str | None, *, mesh_cache: str | None = None) -> list[str]:
    """The command line; ``out`` is the output folder (for a study: its own folder, with ``--mesh-cache``)."""
    extra = [] if out is None else ["--out", out]
    if command in STUDIES and mesh_cache is not None and command != "convective-table":
        extra += ["--mesh-cache", mesh_cache]
    head = {"run": ["run", CASE], "mesh": ["mesh", CASE], "report": ["report"], "ci": ["ci"],
            "score": ["score", CASE, str(sandbox / "level.csv")], "export": ["export", CASE, "--format", "json"],
            "external": ["external", "ccx", CASE], "external_kratos": ["external", "kratos", CASE],
            "external_workbench": ["external", "workbench", CASE],
            "external_compare": ["external", "compare", CASE],
            "forcelaw": ["forcelaw", "close_to_conformal"]}.get(command, [command])
    return head + extra


def _plant(sandbox, row: str, command: str):
    """The hostile folder of ``row`` for ``command``; returns the output folder (the root)."""
    (sandbox / "home").mkdir()
    (sandbox / "home" / "notes.txt").write_text("home\n")
    (sandbox / "level.csv").write_text("x_mm,p_MPa\n0,1\n0.1,0\n")
    for name in ("cases", "fem", "workbench", ".git"):
        (sandbox / "checkout" / name).mkdir(parents=True)
        (sandbox / "checkout" / name / "source.py").write_text(f"# {name}\n")
    (sandbox / "elsewhere").mkdir()
    (sandbox / "elsewhere" / "keep.msh").write_text("a mesh outside the output folder\n")
    root = sandbox / "out"
    if row == "file":
        (sandbox / "a file").write_text("not a folder\n")
        return sandbox / "a file"
    if row == "missing_parents":
        return sandbox / "a" / "b" / "c"
    if row == "home":
        return sandbox / "home"
    if row == "source":
        return sandbox / "checkout" / "cases"
    root.mkdir()
    (root / "notes.txt").write_text("the user's notes\n")
    if row == "user_target":
        name, is_file = _target(command, root)
        if is_file:
            (root / name).write_text("the user's own report\n")
        else:
            (root / name).mkdir()
            (root / name / "notes.txt").write_text("the user's\n")
    elif row == "mesh_link":
        (root / "mesh_cache").symlink_to(sandbox / "elsewhere")
    elif row == "mesh_user":
        (root / "mesh_cache").mkdir()
        (root / "mesh_cache" / f"export_{CASE}_base-7b6bf480fef259fa.msh").write_text("the user's mesh\n")
    return root


def _call(argv, capsys):
    try:
        code = main(argv)
    except Reached:
        return "reached", capsys.readouterr().err
    except SystemExit as exc:
        code = exc.code
    return code, capsys.readouterr().err


@pytest.fixture
def sandbox(tmp_path, monkeypatch):
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    monkeypatch.setattr(paths_module, "PROJECT_ROOT", tmp_path / "checkout")
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.mark.parametrize("via", ["--out", "WORKBENCH_RESULTS"])
@pytest.mark.parametrize("command", COMMANDS)
def test_every_command_refuses_every_hostile_folder(command, via, sandbox, recorders, capsys, monkeypatch):
    rows = [r for r in ROWS if not r.startswith("mesh_") or command in MESH_WRITERS]
    refused = []
    for row in rows:
        box = sandbox / row
        box.mkdir()
        monkeypatch.setenv("HOME", str(box / "home"))
        root = _plant(box, row, command)
        if via == "WORKBENCH_RESULTS":
            monkeypatch.setenv("WORKBENCH_RESULTS", str(root))
            argv = _argv(command, box, None)
        else:
            monkeypatch.setenv("WORKBENCH_RESULTS", str(box / "unused_root"))  # a study's default root: valid
            if command in STUDIES:
                study_dir = root / STUDIES[command] if row in ("user_target", "mesh_link", "mesh_user") else root
                argv = _argv(command, box, str(study_dir), mesh_cache=str(root / "mesh_cache"))
            else:
                argv = _argv(command, box, str(root))
        monkeypatch.setattr(paths_module, "PROJECT_ROOT", box / "checkout")
        before = tree(box)
        code, err = _call(argv, capsys)
        lines = err.splitlines()
        assert code == 2, (command, via, row, code, err[-2000:])
        assert len(lines) == 1 and lines[0].startswith("error: "), (command, via, row, err)
        for word in WORDS[row]:
            assert word in lines[0], (command, via, row, word, lines[0])
        if row in ("file", "missing_parents", "home", "source"):
            named = "--out" if via == "--out" else "WORKBENCH_RESULTS"
            assert named in lines[0], (command, via, row, lines[0])
        assert tree(box) == before, (command, via, row)
        refused.append(row)
    assert refused == rows


@pytest.mark.parametrize("command", COMMANDS)
def test_a_good_output_folder_passes_every_guard(command, sandbox, recorders, capsys, monkeypatch):
    """The control: a new folder (and, for a study, a new study folder and mesh cache) gets past the guard."""
    _plant(sandbox, "good", command)
    monkeypatch.setenv("WORKBENCH_RESULTS", str(sandbox / "results"))
    for argv in (_argv(command, sandbox, None),
                 _argv(command, sandbox, str(sandbox / "given"), mesh_cache=str(sandbox / "given_cache"))):
        code, err = _call(argv, capsys)
        assert code == "reached", (argv, code, err[-2000:])
