"""Benchmark section ``nested`` (issue 38, item 1): the error budget's grid hierarchy solved cold and by nested
iteration, timed side by side in one process, with the Newton iterations of every level.

``workbench bench --sections nested`` runs it inside the benchmark (``bench.json["nested"]``, a section of
``report.md``).

What is compared (:class:`NestedBench`): one run of a two-body case (default ``halfplanes_beta_pos``'s ``small``
run) on its ``budget_levels`` at its largest ``budget_widths`` block, through the scene registry and
:func:`workbench.pipeline.run_case.run_one`, as the budget solves them (:func:`workbench.scenes.budget_rows.with_grid`):
*cold*, every level from the unloaded state along the case's load path; *nested*, the coarsest level cold and each
finer one from the last one's converged state (``nested_start``, :mod:`fem.nested_start`). Every level is solved
once first (JIT, mesh cache), then ``repeats`` times cold and nested in turn (so a load change on the shared machine
hits both); the best time of each level is kept. Time = the solver's ``wall_time_s`` (the mesh is read from the
cache either way). Both converge to the same tolerances: the values are reported beside the times (moment
half-width, relative difference).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from workbench.paths import default_paths

__all__ = ["NestedBench", "run_nested_bench"]


@dataclass(frozen=True)
class NestedBench:
    """The ``nested`` bench section.

    Attributes:
        case: A two-body case with ``budget_levels`` and ``budget_widths``.  run: The run (variant label) timed.
        repeats: Timed solves of each level and way (best kept), >= 1.
        mesh_cache: Mesh cache folder (default ``<results>/mesh_cache``).
    """

    case: str = "halfplanes_beta_pos"
    run: str = "small"
    repeats: int = 1
    mesh_cache: Path | None = None

    def __post_init__(self) -> None:
        if isinstance(self.repeats, bool) or int(self.repeats) != self.repeats or self.repeats < 1:
            raise ValueError(f"repeats must be an integer >= 1, got {self.repeats!r}")

    @property
    def cache_dir(self) -> Path:
        """The mesh cache: ``mesh_cache``, else ``<results>/mesh_cache``."""
        return Path(self.mesh_cache).resolve() if self.mesh_cache is not None else default_paths().mesh_cache


def run_nested_bench(cfg: NestedBench | None = None, *, comm=None, progress: Callable[[str], None] = print) -> dict:
    """Measure the section (module docstring); JSON-ready, no files written. ValueError: a case without budget
    levels or a run label it does not have."""
    import dolfinx_solver  # noqa: F401

    from mpi4py import MPI

    import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
    from cases import load_case
    from workbench.pipeline.run_case import run_one
    from workbench.scenes.budget_rows import with_grid
    from workbench.studies.config import to_json

    cfg = NestedBench() if cfg is None else cfg
    comm = MPI.COMM_SELF if comm is None else comm
    case = load_case(cfg.case)
    levels, widths = sorted(case.discretisation.budget_levels), sorted(case.discretisation.budget_widths)
    if not levels or not widths:
        raise ValueError(f"case {cfg.case!r} has no budget_levels / budget_widths: the nested section needs them")
    runs = {r.label: r for r in case.runs()}
    if cfg.run not in runs:
        raise ValueError(f"run must be one of {sorted(runs)} (case {cfg.case!r}), got {cfg.run!r}")
    W, coarse_first = widths[-1], sorted(levels, reverse=True)
    grid = {h: with_grid(runs[cfg.run], h=h, W=W, h_coarse=levels[-1]) for h in coarse_first}
    name = f"bench_nested_{cfg.case}"

    def solve(h, **kw):
        o = run_one(grid[h], name=name, mesh_cache=cfg.cache_dir, comm=comm, progress=lambda _m: None, **kw)
        r = o.result
        return o, {"h": h, "ndofs": int(r.ndofs), "solve_s": float(r.wall_time_s),
                   "newton_iterations": int(sum(r.newton_iterations)), "solves": len(r.newton_iterations),
                   "moment": float(o.comparison.moment)}

    for h in coarse_first:  # JIT, meshes
        solve(h)
    best: dict[str, dict] = {"cold": {}, "nested": {}}
    for _ in range(cfg.repeats):
        for h in coarse_first:
            _, row = solve(h)
            if h not in best["cold"] or row["solve_s"] < best["cold"][h]["solve_s"]:
                best["cold"][h] = row
        start = None
        for h in coarse_first:
            o, row = solve(h, **({} if start is None else {"nested_start": start}))
            start = o.result.nested_start
            if h not in best["nested"] or row["solve_s"] < best["nested"][h]["solve_s"]:
                best["nested"][h] = row
    rows = []
    for h in coarse_first:
        c, n = best["cold"][h], best["nested"][h]
        rows.append({"h": h, "ndofs": c["ndofs"], "cold": c, "nested": n,
                     "ratio": n["solve_s"] / c["solve_s"] if c["solve_s"] > 0 else float("nan"),
                     "moment_rel_diff": n["moment"] / c["moment"] - 1.0})
        progress(f"nested {cfg.case}[{cfg.run}] h_c = {h:g}, {c['ndofs']} dofs: cold {c['solve_s']:.2f} s "
                 f"({c['newton_iterations']} Newton its in {c['solves']} solves), nested {n['solve_s']:.2f} s "
                 f"({n['newton_iterations']} in {n['solves']}); moment differs {rows[-1]['moment_rel_diff']:.1e}")
    total_c = sum(r["cold"]["solve_s"] for r in rows)
    total_n = sum(r["nested"]["solve_s"] for r in rows)
    return {"config": to_json(cfg), "width": W, "rows": rows, "total_cold_s": total_c, "total_nested_s": total_n,
            "ratio": total_n / total_c if total_c > 0 else float("nan"), "load_avg": os.getloadavg()}
