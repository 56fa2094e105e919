"""A study point's scene, through the scene registry (:func:`workbench.scenes.scene_for`), not a scene's internals.

The studies size their own meshes (from the target half-width itself, so that a published sweep's meshes do not
move) and drive the solver with their own overrides; the obstacle and the comparison with theory are the scene's,
exactly as a case run gets them (:class:`workbench.scenes.base.Scene`).
"""

from __future__ import annotations

__all__ = ["scene_compare", "scene_obstacle"]


def _mesh(files, estimate):
    from workbench.scenes import SceneMesh

    return SceneMesh(files, estimate, "")


def scene_obstacle(run, *, files, estimate):
    """The rigid obstacle of ``run`` from its registered scene (``estimate``: the scene's contact estimate the
    mesh was sized from, e.g. the block's classical theory at the target load)."""
    from workbench.scenes import scene_for

    return scene_for(run).obstacle(run, _mesh(files, estimate))


def scene_compare(run, result, *, files, estimate):
    """The registered scene's comparison of ``result`` with theory (block: the classical theory at the measured
    load, :class:`workbench.scenes.block.BlockComparison`)."""
    from workbench.scenes import scene_for

    return scene_for(run).compare(run, result, _mesh(files, estimate), progress=lambda _: None).comparison
