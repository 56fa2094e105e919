"""Scenes: how a case run is meshed, what its rigid obstacle is, how it is loaded, compared and judged.

The registry :data:`SCENES` maps the ``[geometry] scene`` value of a case file to a :class:`Scene`. Adding a
scene: write one module with a class implementing :class:`workbench.scenes.base.Scene` and add one line
below.
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
