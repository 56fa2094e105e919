"""Issue 37 item 4: every study point is a case Run solved by ``run_one``; no study builds a mesh or names a failure by
hand, and no study module is over 600 lines. The mesh rule of the studies (:class:`TargetSized`) gives the meshes the
published sweeps were measured on (the same cache key as the sizing from the target itself)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

STUDY_DIR = Path(__file__).resolve().parents[1] / "workbench" / "studies"
HAND_MADE = re.compile(r"\bbuild_\w+_mesh\(|\bcreate_rectangle\(|\bread_mesh\(|\bsolve_run\(|\bsolve_contact\(|"
                       r"f\"(diverged|refused): \{")
# the exceptions, with their reasons: the bench's tutorial baseline is a uniform box of right triangles made by dolfinx
# (section 1 measures our graded meshes against it; it is solved through run_one too, scene_point.GivenMesh), and the
# bench reads its scene's cached mesh for what it measures on it besides the contact solve (a linear solve, the dofs)
EXEMPT = {"bench_measure.py": {"create_rectangle(", "read_mesh("}, "bench_two_body.py": {"read_mesh("}}


@pytest.mark.parametrize("path", sorted(STUDY_DIR.glob("*.py")), ids=lambda p: p.name)
def test_no_study_module_is_over_600_lines(path):
    assert len(path.read_text().splitlines()) <= 600


@pytest.mark.parametrize("path", sorted(p for p in STUDY_DIR.glob("*.py") if p.name != "scene_point.py"),
                         ids=lambda p: p.name)
def test_no_study_meshes_solves_or_names_a_failure_by_hand(path):
    """Meshes come from a scene (scene_point.TargetSized for the studies' rule), solves from run_one, names from
    run_failure: the code of a study calls none of the lower-level builders (docstrings may name them)."""
    code = re.sub(r'"""[\s\S]*?"""', "", path.read_text())
    code = re.sub(r'(?<![f\w])"[^"\n]*"', '""', code)  # plain strings (report text) out; f-strings kept
    found = {m.group(0) for m in HAND_MADE.finditer(code)} - EXEMPT.get(path.name, set())
    assert not found, found


def test_run_failure_names_each_kind():
    from fem.solver import ContactSolveError
    from workbench.studies.scene_point import run_failure

    assert run_failure(ContactSolveError("step 1\n  diverged")) == "diverged: step 1 diverged"
    assert run_failure(ValueError("nu = 0.5")) == "refused: nu = 0.5"
    assert run_failure(RuntimeError("x" * 400)).startswith("failed: RuntimeError: x") and \
        len(run_failure(RuntimeError("x" * 400))) == len("failed: RuntimeError: ") + 300


def test_target_sized_mesh_is_the_sweeps_mesh(tmp_path):
    """A stability spec's mesh through TargetSized has the cache key of the sweep's own rule (W = H = size a,
    h_c = a / h_ratio, from a itself): the same mesh reaches the solver."""
    from meshes.block import build_block_mesh
    from workbench.studies.scene_point import TargetSized
    from workbench.studies.stability_specs import Spec

    spec = Spec("t", "t", h_ratio=3.0, size_factor=10.0)
    run, a = spec.run(), spec.target_half_width
    mesh = TargetSized(h_ratio=spec.h_ratio).mesh(run, name="m", mesh_cache=tmp_path, comm=None)
    ref = build_block_mesh(width=spec.size_factor * a, height=spec.size_factor * a, contact_half_width=a,
                           h_contact=a / spec.h_ratio, half_model=True, out_dir=tmp_path, name="ref", comm=None)
    assert mesh.files.key == ref.key and mesh.estimate.half_width == pytest.approx(a, rel=1e-14)
