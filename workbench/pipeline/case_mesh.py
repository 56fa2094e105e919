"""The mesh of every run of a case, built (or reused from the cache) without solving anything."""

from __future__ import annotations

from pathlib import Path

from cases import Case
from workbench.scenes import scene_for

__all__ = ["case_meshes"]


def case_meshes(case: Case, *, mesh_cache: Path, comm, h_contact: float | None = None,
                stats_dir: Path | None = None) -> dict:
    """Mesh files of each run of ``case`` by run label (``stats_dir``: also write ``mesh.json`` there)."""
    return {run.label: scene_for(run).mesh(run, name=case.name, mesh_cache=mesh_cache, comm=comm,
                                           stats_dir=stats_dir).files
            for run in case.runs(h_contact=h_contact)}
