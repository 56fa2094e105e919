"""The minimal scene ``flat_block``: an elastic half block on rollers, pressed by a rigid flat plane
(displacement control), against the exact uniform compression of :mod:`theory`. Units mm, N, MPa.

It implements the eight methods of :class:`workbench.scenes.base.Scene` with the shared pieces of the scenes'
base: :class:`workbench.scenes.base.SolveMetrics` and :func:`workbench.scenes.base.run_keys` for the keys every
scene writes.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from cases.schema import Case, Run
from workbench.scenes.base import CaseComparison, LoadPath, Outcome, SceneMesh, Series, SolveMetrics, run_keys

from .schema import FLAT_BLOCK_SCHEMA
from .theory import uniform_compression

__all__ = ["FlatBlockScene"]


class FlatBlockScene:
    """A half block (x >= 0) under a rigid plane; bottom ``roller_y``, symmetry edge ``roller_x``, side free."""

    name = "flat_block"
    schema = FLAT_BLOCK_SCHEMA

    def preflight(self, run: Run, *, where: str) -> None:
        """Nothing beyond the case schema's checks."""

    def estimate_cells(self, run: Run) -> float:
        """Triangles of the half block at the contact size everywhere (an upper bound of the graded mesh)."""
        g = run.geometry
        h = run.discretisation.h_contact * g.width
        return 2.0 * (g.width / 2) * g.height / h**2

    def mesh(self, run: Run, *, name: str, mesh_cache: Path, comm, stats_dir: Path | None = None) -> SceneMesh:
        from meshes.block import build_block_mesh

        g, disc = run.geometry, run.discretisation
        files = build_block_mesh(width=g.width, height=g.height, contact_half_width=g.width / 4,
                                 h_contact=disc.h_contact * g.width, growth=disc.growth, half_model=True,
                                 out_dir=mesh_cache, name=f"{name}_{run.label}", stats_dir=stats_dir, comm=comm)
        return SceneMesh(files, None, f"mesh {files.stats.get('cells', '?')} cells")

    def obstacle(self, run: Run, mesh: SceneMesh):
        from fem.obstacles import PlaneObstacle

        return PlaneObstacle(height=0.0)

    def load_path(self, run: Run, mesh: SceneMesh) -> LoadPath:
        d = tuple(run.loading.d)
        return LoadPath("displacement", d[-1], run.loading.steps, symmetric_half=True, record_at=d,
                        supports={"clamped": "roller_y", "symmetry": "roller_x"})

    def compare(self, run: Run, result, mesh: SceneMesh, *, progress) -> Outcome:
        g, smp = run.geometry, result.samples
        th = uniform_compression(E=run.material.E, nu=run.material.nu, width=g.width, height=g.height,
                                 d=result.d)
        solved = SolveMetrics.of(result)
        errors = solved.solve_errors() | {
            "uniformity": float(np.max(np.abs(smp.p / th.p - 1.0))) if smp.p.size else float("nan"),
            "load": abs(result.P / th.P - 1.0)}
        metrics = run_keys(run, self.name) | solved.as_dict() | {
            "p_max": float(np.max(smp.p)) if smp.p.size else float("nan"), "mesh": mesh.files.stats,
            "analytic": {"kind": "uniform", "p": th.p, "P": th.P}, "errors": errors}
        series = Series(run.label, smp.s, smp.p, smp.sigma_nn, {"uniform compression": np.full(smp.s.size, th.p)},
                        "x (mm, material)", (0.0, g.width / 2), weight=smp.weight, q=smp.q)
        return Outcome(run.label, run, metrics, [series], th, None, result)

    def judge(self, case: Case, outcomes: list[Outcome]) -> CaseComparison:
        return CaseComparison({}, {}, "Uniform compression under a rigid plane.", {})

    def error_budget(self, case: Case, *, solve, progress):
        return None
