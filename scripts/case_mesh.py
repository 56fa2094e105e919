"""The mesh of every run of a case, built (or reused from the cache) without solving anything."""

from __future__ import annotations

from pathlib import Path

from cases import Case

__all__ = ["case_meshes"]


def case_meshes(case: Case, *, comm, h_contact: float | None = None, stats_dir: Path | None = None) -> dict:
    """Mesh files of each run of ``case`` by run label (``stats_dir``: also write ``mesh.json`` there)."""
    out = {}
    for run in case.runs(h_contact=h_contact):
        if run.geometry.scene == "block":
            from scripts.scene_block import block_mesh

            out[run.label] = block_mesh(run, name=case.name, comm=comm, stats_dir=stats_dir)[0]
        else:
            from scripts.scene_concave import concave_mesh

            out[run.label] = concave_mesh(run, name=case.name, comm=comm, stats_dir=stats_dir).files
    return out
