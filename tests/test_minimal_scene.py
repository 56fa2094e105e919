"""A new scene from files of its own, registered the documented way, runs end to end (issue 37).

Requirement: ``docs/architecture.md`` ("How to add ... a scene") promises a scene in three things, in new files
only. The minimal scene ``flat_block`` (``tests/minimal_scene/``: ``schema.py``, its case schema; ``scene.py``, the
eight methods of :class:`workbench.scenes.base.Scene`; ``theory.py``, its exact solution; ``flat_block.toml``, a
case file) is registered with :func:`workbench.scenes.base.register_scene` (the one line a shipped scene adds to
``workbench/scenes/__init__.py``) and its case runs through ``workbench run`` (:func:`workbench.cli.main`, in this
process, where the scene is registered) into a temporary folder: ``metrics.json`` holds the results contract and
the exact uniform pressure to round-off, and every key number has a class. No file outside ``tests/`` is touched.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from cases import scene_schema
from workbench.pipeline.key_numbers import key_numbers
from workbench.pipeline.number_classes import classify, explicit_class
from workbench.scenes import base

HERE = Path(__file__).resolve().parent
CASE = HERE / "minimal_scene" / "flat_block.toml"


@pytest.fixture
def flat_block(monkeypatch):
    """The scene registered for one test (both registries restored afterwards)."""
    from minimal_scene.scene import FlatBlockScene

    monkeypatch.setattr(base, "SCENES", dict(base.SCENES))
    monkeypatch.setattr(scene_schema, "_SCENE_SCHEMAS", dict(scene_schema._SCENE_SCHEMAS))
    return base.register_scene(FlatBlockScene())


def test_the_minimal_scene_runs_end_to_end(flat_block, tmp_path):
    from workbench.cli import main

    assert main(["run", str(CASE), "--ci", "--no-pictures", "--out", str(tmp_path)]) == 0
    out = tmp_path / "minimal_flat_block"
    m = json.loads((out / "metrics.json").read_text())
    assert m["pass"] is True, m["checks"]
    (run,) = m["runs"]
    assert run["scene"] == "flat_block" and run["method"] == "nitsche"
    assert set(run) >= set(base.SolveMetrics._fields) | {"label", "kinematics", "degree", "h_contact", "errors"}
    # the exact solution: p = E d / ((1 - nu^2) H) uniform over the top, P = p W (minimal_scene/theory.py)
    p_exact = 1000.0 * 0.002 / (1.0 - 0.3**2) / 1.0
    assert run["analytic"]["p"] == pytest.approx(p_exact, rel=1e-14)
    assert run["P"] == pytest.approx(2.0 * p_exact, rel=1e-8)
    assert m["errors"]["uniformity"] <= 1e-8 and m["errors"]["load_balance"] <= 1e-9
    for f in ("pressure.csv", "report.md", "run.log"):
        assert (out / f).is_file(), f
    numbers = key_numbers(tmp_path)
    assert "minimal_flat_block/runs/base/P" in numbers
    # every key number of the new scene has a class without a line outside its files: SolveMetrics's are declared
    # in workbench/scenes/base.py, an error is an error, the mesh fingerprint and the verdict are the pipeline's
    assert {k: explicit_class(k) for k in numbers if explicit_class(k) is None} == {}
    assert classify("minimal_flat_block/errors/uniformity") == ("error", "error")
    assert classify("minimal_flat_block/runs/base/patches/0/center") == ("physics", "position")


def test_registration_is_undone_after_a_test():
    assert "flat_block" not in base.SCENES and "flat_block" not in scene_schema._SCENE_SCHEMAS
