"""The convective table's configuration (:mod:`workbench.studies.convective_table`); shared helpers in
:mod:`workbench.studies.config`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from workbench.paths import default_paths
from workbench.studies.config import folder

__all__ = ["ConvectiveTableConfig"]


@dataclass(frozen=True)
class ConvectiveTableConfig:
    """Convective-effect table (:mod:`workbench.studies.convective_table`): b/b0 of Ciavarella & Hills.

    Attributes:
        thetas: Wedge angles (rad) by name.  wedge_betas: Dundurs beta of the wedge rows.
        parabola_b0_over_R, parabola_betas: The parabola rows.
        n_nodes: Gauss-Chebyshev nodes of the table.  self_convergence_nodes: Nodes of the self-convergence.
        out: Output folder (default ``<results>/analytic``).
    """

    thetas: dict = field(default_factory=lambda: {"pi/20": math.pi / 20, "pi/10": math.pi / 10,
                                                  "pi/5": math.pi / 5})
    wedge_betas: tuple[float, ...] = (-0.5, -0.25, -0.1)
    parabola_b0_over_R: tuple[float, ...] = (0.05, 0.1, 0.25, 0.4)
    parabola_betas: tuple[float, ...] = (-0.5, -0.25)
    n_nodes: int = 65536
    self_convergence_nodes: tuple[int, ...] = (1024, 4096, 16384, 65536, 262144)
    out: Path | None = None

    @property
    def out_dir(self) -> Path:
        """The output folder: ``out``, else ``<results>/analytic``."""
        return folder(self.out, default_paths().analytic)
