"""One place for every output path of the workbench.

Everything the workbench writes lives under one output folder (``--out``; default ``results/`` beside the
``cases/`` folder of this checkout, or ``$WORKBENCH_RESULTS``), whatever the working directory is:

=====================  ============================================================
``<root>/<case>/``     a case's results (metrics.json, pressure.csv, plots, report, VTK)
``<root>/mesh_cache/`` meshes, keyed by a hash of their build parameters
``<root>/logs/``       the log of a failed case
``<root>/ci/``         ``workbench ci``: every case at its coarsest level
``<root>/<study>/``    a study (convergence, stability, bench) and ``analytic/`` (convective table)
=====================  ============================================================
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from cases.schema import CASE_DIR

__all__ = ["DEFAULT_ROOT", "OutputPaths", "default_paths"]

DEFAULT_ROOT = CASE_DIR.parent / "results"


@dataclass(frozen=True)
class OutputPaths:
    """The output folder and everything below it (absolute paths)."""

    root: Path

    def __post_init__(self) -> None:
        object.__setattr__(self, "root", Path(self.root).expanduser().resolve())

    @property
    def mesh_cache(self) -> Path:
        return self.root / "mesh_cache"

    @property
    def logs(self) -> Path:
        return self.root / "logs"

    @property
    def ci(self) -> OutputPaths:
        """The CI tree ``<root>/ci``."""
        return OutputPaths(self.root / "ci")

    def case(self, name: str) -> Path:
        return self.root / name

    def study(self, name: str) -> Path:
        return self.root / name

    @property
    def analytic(self) -> Path:
        return self.root / "analytic"


def default_paths(out: str | Path | None = None) -> OutputPaths:
    """``out`` if given, else ``$WORKBENCH_RESULTS``, else ``results/`` of this checkout."""
    if out is None:
        out = os.environ.get("WORKBENCH_RESULTS") or DEFAULT_ROOT
    return OutputPaths(Path(out))
