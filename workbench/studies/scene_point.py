"""A study point is a case run solved by :func:`workbench.pipeline.run_case.run_one`; this module holds what the
studies share around it: two adapters of the block scene (sized from the target itself, or on a mesh in memory),
the silent point runner and the name of a failure.

:class:`TargetSized` is the registered block scene (:class:`workbench.scenes.block.BlockScene`: its obstacle and its
comparison with theory, exactly as a case run gets them) with the studies' mesh rule: W = H = width_factor a and
h_c = a / h_ratio from the TARGET half-width a itself (the scene recomputes the half-width from the load, which
differs from a in the last bit and would move the published sweeps' meshes), the mesh named by the point, and a
displacement-controlled load path where the point asks for one (the stability sweep's faults).
:class:`GivenMesh` is the same block scene on a mesh the study already holds in memory (the benchmark's solves on one
mesh, timed; its tutorial baseline's uniform box): :func:`run_on_mesh` solves a run on it through ``run_one``.
:func:`run_point` runs one point silently on ``MPI.COMM_SELF``; :func:`run_failure` names what a run raised.
"""

from __future__ import annotations

from pathlib import Path

from workbench.scenes.block import BlockScene

__all__ = ["GivenMesh", "TargetSized", "run_failure", "run_on_mesh", "run_point"]


class TargetSized(BlockScene):
    """The block scene of one study point, its mesh sized from the target half-width ``run.loading.half_width``.

    Args:
        h_ratio: a / h_c (the contact element size is a / h_ratio, mm, as the study states it).

    Attributes:
        built: The :class:`workbench.scenes.base.SceneMesh` of the last :meth:`mesh` (the point's record reads its
            cells even when the solve fails), else None.
    """

    def __init__(self, *, h_ratio: float):
        self.h_ratio = h_ratio
        self.built = None

    def estimate(self, run):
        """The classical theory at the target half-width (force target; the mesh's size for any control)."""
        from workbench.scenes.block_theory import block_theory

        return block_theory(run.geometry, run.material, half_width=run.loading.half_width)

    def mesh(self, run, *, name: str, mesh_cache: Path, comm, stats_dir: Path | None = None):
        """The (cached) block mesh named ``name``: W = width_factor a, H = height_factor a, h_c = a / h_ratio,
        the run's growth and half model, the apex refined under a wedge."""
        from meshes.block import build_block_mesh
        from workbench.scenes import SceneMesh

        g, a = run.geometry, run.loading.half_width
        files = build_block_mesh(width=g.width_factor * a, height=g.height_factor * a, contact_half_width=a,
                                 h_contact=a / self.h_ratio, growth=run.discretisation.growth,
                                 half_model=g.half_model, apex_refinement=g.indenter == "wedge",
                                 out_dir=Path(mesh_cache), name=name, stats_dir=stats_dir, comm=comm)
        target = self.estimate(run)
        self.built = SceneMesh(files, target, f"mesh {files.stats.get('cells', '?')} cells, a = {a:.4g} mm "
                                              f"(target), P target = {target.P:.6g} N/mm")
        return self.built

    def load_path(self, run, mesh):
        """Force control to the classical load of a, or displacement control to the run's last ``d``."""
        from workbench.scenes.base import LoadPath

        ld = run.loading
        if ld.control == "displacement":
            return LoadPath("displacement", ld.d[-1], ld.steps, symmetric_half=run.geometry.half_model,
                            record_at=tuple(ld.d) if len(ld.d) > 1 else None)
        return super().load_path(run, mesh)


class GivenMesh(BlockScene):
    """The block scene of a run on a mesh already in memory (``mesh_data``, a dolfinx ``MeshData``), driven to the
    load of ``estimate`` (its :class:`workbench.scenes.block_theory.BlockTheory`): :func:`run_on_mesh` hands the
    mesh to ``run_one`` through its ``meshes`` dict under :attr:`key`; nothing is meshed or read."""

    def __init__(self, mesh_data, estimate):
        self.mesh_data, self.estimate = mesh_data, estimate
        self.key = f"given-{id(mesh_data):x}"

    def mesh(self, run, *, name: str, mesh_cache: Path, comm, stats_dir: Path | None = None):
        """The given mesh (no files: ``stats`` holds its cell count)."""
        from meshes.cache import MeshFiles
        from workbench.scenes import SceneMesh

        cells = self.mesh_data.mesh.topology.index_map(self.mesh_data.mesh.topology.dim).size_global
        files = MeshFiles(msh=None, xdmf=None, stats={"cells": int(cells)}, key=self.key, cached=True)
        return SceneMesh(files, self.estimate, f"given mesh, {cells} cells")


def run_on_mesh(run, mesh_data, estimate, *, case: str, **solver_overrides):
    """Solve and compare ``run`` on ``mesh_data`` (:class:`GivenMesh`) through
    :func:`workbench.pipeline.run_case.run_one` (silent, on the mesh's communicator): the scene's Outcome."""
    from workbench.pipeline.run_case import run_one

    scene = GivenMesh(mesh_data, estimate)
    return run_one(run, name=case, mesh_cache=Path("."), comm=mesh_data.mesh.comm, progress=lambda _msg: None,
                   scene=scene, meshes={scene.key: mesh_data}, case=case, **solver_overrides)


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


def run_point(run, *, name: str, mesh_cache, scene=None, meshes: dict | None = None, case: str | None = None,
              **solver_overrides):
    """Mesh (cached under ``name``), solve and compare one study point in this process
    (:func:`workbench.pipeline.run_case.run_one` on MPI.COMM_SELF, silent): the scene's
    :class:`workbench.scenes.base.Outcome`. ``scene``: the point's scene (default: the run's registered one);
    ``meshes``: the worker's read meshes by cache key; ``case``: the name in the solver's messages;
    ``solver_overrides``: the study's solver options."""
    import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

    from mpi4py import MPI

    from workbench.pipeline.run_case import run_one

    return run_one(run, name=name, mesh_cache=Path(mesh_cache), comm=MPI.COMM_SELF, progress=lambda _msg: None,
                   scene=scene, meshes=meshes, case=case, **solver_overrides)
