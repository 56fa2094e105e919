"""Scenes: how a case run is meshed, what its rigid obstacle is, how it is loaded, compared and judged.

The registry :data:`SCENES` maps the ``[geometry] scene`` value of a case file to a :class:`Scene`. Adding a
scene: its case schema, its theory and a class implementing :class:`workbench.scenes.base.Scene`, each in a new
module, and one line below (``docs/architecture.md``, "How to add ... a scene"; ``tests/test_minimal_scene.py``
adds one from files of its own).
"""

from workbench.scenes.base import (
    SCENES,
    CaseComparison,
    LoadPath,
    Outcome,
    Scene,
    SceneMesh,
    Series,
    register_scene,
    scene_for,
)
from workbench.scenes.block import BlockScene
from workbench.scenes.concave import ConcaveScene
from workbench.scenes.halfplanes import HalfplanesScene
from workbench.scenes.two_body import TwoBodyScene

__all__ = ["SCENES", "CaseComparison", "LoadPath", "Outcome", "Scene", "SceneMesh", "Series", "register_scene",
           "scene_for"]

register_scene(BlockScene())
register_scene(ConcaveScene())
register_scene(TwoBodyScene())
register_scene(HalfplanesScene())
