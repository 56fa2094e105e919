"""Checks that need the geometry, run before anything is written (bad input -> CaseError -> exit 2)."""

from __future__ import annotations

from cases import Case, CaseError
from workbench.scenes import scene_for

__all__ = ["preflight"]


def preflight(case: Case) -> None:
    """Every run has a registered scene, and the scene accepts it (e.g. a load that can be reached)."""
    for run in case.runs():
        try:
            scene = scene_for(run)
        except ValueError as exc:
            raise CaseError(f"{case.path.name}: {exc}") from None
        scene.preflight(run, where=case.path.name)
