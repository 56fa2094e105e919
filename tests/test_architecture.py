"""The package's shape: an installed console command, a layer contract that holds, no import cycles,
registries that take new entries, and no dependence on the working directory."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import grimp
import pytest

from workbench.cli import EXTERNAL, STUDIES
from workbench.paths import DEFAULT_ROOT, default_paths
from workbench.scenes import SCENES, register_scene

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent
PACKAGES = ("vocabulary", "analytic", "measures", "cases", "meshes", "fem", "workbench")
SUBCOMMANDS = ("list", "validate", "run", "mesh", "report", "ci", *STUDIES, *EXTERNAL)


def test_layer_contract_holds():
    """`lint-imports` (import-linter, pinned): workbench > fem | meshes | cases > analytic, and inside
    workbench cli > studies > pipeline > scenes > reports (pyproject.toml)."""
    proc = subprocess.run([str(BIN / "lint-imports")], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stdout[-4000:]
    assert "0 broken" in proc.stdout


def _cycles(graph: grimp.ImportGraph) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan, iterative)."""
    index, low, on_stack, stack, out = {}, {}, set(), [], []
    counter = [0]
    for root in sorted(graph.modules):
        if root in index:
            continue
        work = [(root, iter(sorted(graph.find_modules_directly_imported_by(root))))]
        index[root] = low[root] = counter[0]
        counter[0] += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            for child in children:
                if child not in index:
                    index[child] = low[child] = counter[0]
                    counter[0] += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph.find_modules_directly_imported_by(child)))))
                    break
                if child in on_stack:
                    low[node] = min(low[node], index[child])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    comp = []
                    while True:
                        m = stack.pop()
                        on_stack.discard(m)
                        comp.append(m)
                        if m == node:
                            break
                    if len(comp) > 1:
                        out.append(sorted(comp))
    return out


def test_no_import_cycles():
    graph = grimp.build_graph(*PACKAGES)
    assert _cycles(graph) == []


def test_cycle_finder_finds_a_cycle():
    """The check above can fail: a two-module cycle is found."""
    graph = grimp.ImportGraph()
    for m in ("a", "b", "c"):
        graph.add_module(m)
    graph.add_import(importer="a", imported="b")
    graph.add_import(importer="b", imported="a")
    graph.add_import(importer="b", imported="c")
    assert _cycles(graph) == [["a", "b"]]


def test_console_command_lists_every_subcommand(tmp_path):
    exe = BIN / "workbench"
    assert exe.is_file(), "`make setup` installs the package (pip install -e .) with its console command"
    proc = subprocess.run([str(exe), "--help"], cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    for name in SUBCOMMANDS:
        assert name in proc.stdout, name
    for name in (*STUDIES, *EXTERNAL):  # each study's own options are reachable through the one command
        proc = subprocess.run([str(exe), name, "--help"], cwd=tmp_path, capture_output=True, text=True,
                              timeout=120)
        assert proc.returncode == 0, (name, proc.stderr[-2000:])
    assert not any(tmp_path.iterdir()), "--help writes nothing"


def test_commands_do_not_depend_on_the_working_directory(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "workbench", "validate", "hertz_cylinder"], cwd=tmp_path,
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    assert not any(tmp_path.iterdir())
    assert DEFAULT_ROOT == ROOT / "results" and DEFAULT_ROOT.is_absolute()
    assert default_paths(tmp_path / "x").mesh_cache == (tmp_path / "x" / "mesh_cache").resolve()


def test_bad_subcommand_is_one_line_and_exit_2(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "workbench", "frobnicate"], cwd=tmp_path, capture_output=True,
                          text=True, timeout=60)
    assert proc.returncode == 2
    assert len(proc.stderr.strip().splitlines()) == 1, proc.stderr


def test_scene_registry_takes_a_new_scene_and_refuses_a_non_scene():
    assert {"block", "concave"} <= set(SCENES)

    from dataclasses import dataclass

    from cases import schema as case_schema

    @dataclass(frozen=True)
    class RingGeometry(case_schema.Geometry):
        inner_radius: float = 1.0

    class Ring:
        name = "ring_test"
        schema = case_schema.SceneSchema(name="ring_test", geometry=RingGeometry,
                                         indenters={"pin": frozenset({"inner_radius"})}, predictions={"pin": ()},
                                         controls=("displacement",))

        def preflight(self, run, *, where): ...
        def estimate_cells(self, run): ...
        def mesh(self, run, *, name, mesh_cache, comm, stats_dir=None): ...
        def obstacle(self, run, mesh): ...
        def load_path(self, run, mesh): ...
        def compare(self, run, result, mesh, *, progress): ...
        def judge(self, case, outcomes): ...
        def error_budget(self, case, *, solve, progress): ...

    try:
        register_scene(Ring())
        assert "ring_test" in SCENES and case_schema.scene_schema("ring_test").geometry is RingGeometry
    finally:
        SCENES.pop("ring_test", None)
        case_schema._SCENE_SCHEMAS.pop("ring_test", None)

    class NotAScene:
        name = "broken"

    with pytest.raises(TypeError):
        register_scene(NotAScene())
