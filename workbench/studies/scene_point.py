"""A study point's scene, through the scene registry (:func:`workbench.scenes.scene_for`), not a scene's internals.

The studies size their own meshes (from the target half-width itself, so that a published sweep's meshes do not
move) and drive the solver with their own overrides; the obstacle and the comparison with theory are the scene's,
exactly as a case run gets them (:class:`workbench.scenes.base.Scene`).
"""

from __future__ import annotations

__all__ = ["run_failure", "run_scene_case", "scene_compare", "scene_obstacle"]


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


def run_failure(exc: BaseException) -> str:
    """The named error of a study run that raised, one line of at most 300 characters of its message:
    ``diverged: ...`` (the solver's :class:`fem.solver.ContactSolveError`), ``refused: ...`` (a ValueError or
    TypeError: the inputs), else ``failed: <type>: ...`` (e.g. a PETSc error, recorded by name: an exception object
    holding PETSc state could not be sent back from a worker)."""
    try:
        from fem.solver import ContactSolveError
    except Exception:  # noqa: BLE001  (the import itself failed: that is the error being named)
        ContactSolveError = ()  # noqa: N806
    text = " ".join(str(exc).split())[:300]
    if ContactSolveError and isinstance(exc, ContactSolveError):
        return f"diverged: {text}"
    if isinstance(exc, (ValueError, TypeError)):
        return f"refused: {text}"
    return f"failed: {type(exc).__name__}: {text}"


def run_scene_case(run, *, name: str, mesh_cache):
    """Mesh (cached under ``name``), solve and compare a case-level ``run`` through its registered scene in this
    process (:func:`workbench.pipeline.run_case.run_one` on MPI.COMM_SELF, silent): the scene's
    :class:`workbench.scenes.base.Outcome`, as a case file would get it."""
    import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

    from pathlib import Path

    from mpi4py import MPI

    from workbench.pipeline.run_case import run_one

    return run_one(run, name=name, mesh_cache=Path(mesh_cache), comm=MPI.COMM_SELF, progress=lambda _msg: None)
