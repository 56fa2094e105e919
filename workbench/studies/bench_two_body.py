"""Benchmark section ``two_body`` (issue 24 acceptance): a two-body case against a rigid case with the same number of
dofs, timed side by side in one process, and the Newton iterations per load step of every two-body run.

``workbench bench --sections two_body`` runs it inside the benchmark (``bench.json["two_body"]``, a section of
``report.md``); ``python -m workbench.studies.bench_two_body [--out DIR] [--repeats N] [--quick]`` runs it alone and
writes ``two_body.json`` and ``two_body.md`` (default folder ``<results>/bench``).

What is compared (:class:`TwoBodyBench`): each run of each two-body case (its case file and variants, at the level
given, through the scene registry and :func:`workbench.pipeline.run_case.run_one`: the two-body scene's own load
path, no analytic predictor) against the rigid case (``hertz_cylinder``: rigid exact circle, Nitsche P2, as the case
file sets it, its Hertz predictor included) on the rigid scene's own mesh, refined until its dofs match the two-body
run's within ``match_rtol`` (:func:`match_rigid`: a secant on log ndofs against log h_c, meshes counted before any
solve). Both are solved once (JIT and mesh cache), then ``repeats`` times alternately (so a load change on the shared
machine hits both); the best time of each is kept. Cost = warm wall time of ``run_one`` (mesh read from the cache,
solve, comparison with theory), s; the solver time alone (``wall_time_s``) is kept beside it. Targets: cost ratio
two-body / rigid <= ``cost_target`` (2) and at most ``newton_target`` (4) Newton iterations in every load step.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

from workbench.paths import default_paths

__all__ = ["TwoBodyBench", "main", "match_rigid", "mesh_ndofs", "run_two_body_bench"]


@dataclass(frozen=True)
class TwoBodyBench:
    """The ``two_body`` bench section.

    Attributes:
        cases: (two-body case, h_contact or None for the case's default level) pairs; every run (variant) is timed.
            The patch test's default level has ~2k dofs, where fixed costs dominate: it is timed at h_c = W/50.
        rigid_case: The rigid case whose mesh is refined to the same dofs.
        match_rtol: |ndofs_rigid / ndofs_two_body - 1| allowed.
        cost_target: The acceptance's cost ratio (two-body / rigid).
        newton_target: Newton iterations per load step allowed (every step).
        rigid_free: Solver overrides of a second rigid timing without its analytic predictor (the bench's
            predictor-free settings, as the two-body load path): it separates the cost of the two-body coupling from
            that of the predictor. The target is judged against the rigid case as its file sets it.
        repeats: Timed warm solves of each side (best kept), >= 1.
        mesh_cache: Mesh cache folder (default ``<results>/mesh_cache``).
    """

    cases: tuple[tuple[str, float | None], ...] = (("elastic_cylinder", None), ("patch_test", 0.02))
    rigid_case: str = "hertz_cylinder"
    match_rtol: float = 0.03
    cost_target: float = 2.0
    newton_target: int = 4
    rigid_free: dict = field(default_factory=lambda: {"predictor": "extrapolate", "active_set": "geometry",
                                                      "active_set_update": "edge_fit"})
    repeats: int = 3
    mesh_cache: Path | None = None

    def __post_init__(self) -> None:
        if isinstance(self.repeats, bool) or int(self.repeats) != self.repeats or self.repeats < 1:
            raise ValueError(f"repeats must be an integer >= 1, got {self.repeats!r}")
        if not 0 < self.match_rtol < 0.5:
            raise ValueError(f"match_rtol must be in (0, 0.5), got {self.match_rtol!r}")
        if not self.cases:
            raise ValueError("cases must name at least one two-body case")

    @property
    def cache_dir(self) -> Path:
        """The mesh cache: ``mesh_cache``, else ``<results>/mesh_cache``."""
        return Path(self.mesh_cache).resolve() if self.mesh_cache is not None else default_paths().mesh_cache


def mesh_ndofs(mesh_data, degree: int) -> int:
    """Displacement dofs of a 2D vector Lagrange space of ``degree`` (1 or 2) on a triangle mesh (both bodies of a
    two-body mesh): 2 (vertices + edges) for P2, 2 vertices for P1."""
    topo = mesh_data.mesh.topology
    topo.create_entities(1)
    n = topo.index_map(0).size_global + (topo.index_map(1).size_global if degree == 2 else 0)
    return 2 * int(n)


def _at(run, h_contact: float):
    return replace(run, discretisation=replace(run.discretisation, h_contact=float(h_contact)))


def match_rigid(run, target: int, *, name: str, mesh_cache: Path, comm, rtol: float, max_iter: int = 12):
    """The rigid ``run`` at the h_contact whose mesh has ``target`` dofs within ``rtol``: a secant on log ndofs
    against log h_c from the run's own level (meshes only, through its registered scene).

    Returns:
        (run at the matched level, its ndofs, [(h_c, ndofs) tried]).

    Raises:
        ValueError: no level within ``rtol`` after ``max_iter`` meshes (or the level leaves (0, 1]).
    """
    from workbench.mesh_io import read_mesh
    from workbench.scenes import scene_for

    scene = scene_for(run)
    tried: list[tuple[float, int]] = []

    def count(h):
        r = _at(run, h)
        md = read_mesh(scene.mesh(r, name=name, mesh_cache=mesh_cache, comm=comm).files.msh, comm)
        tried.append((h, mesh_ndofs(md, r.discretisation.degree)))
        return tried[-1][1]

    h, slope = run.discretisation.h_contact, -1.0  # graded meshes: ndofs ~ 1/h_c to start with
    n = count(h)
    for _ in range(max_iter):
        if abs(n / target - 1.0) <= rtol:
            return _at(run, h), n, tried
        h_new = h * (target / n) ** (1.0 / slope)
        h_new = min(max(h_new, h / 4.0), min(4.0 * h, 1.0))
        if h_new == h:  # at the coarsest level h_c = 1
            break
        n_new = count(h_new)
        if n_new != n and h_new != h:
            slope = min(max(math.log(n_new / n) / math.log(h_new / h), -3.0), -0.3)
        h, n = h_new, n_new
    if abs(n / target - 1.0) <= rtol:
        return _at(run, h), n, tried
    raise ValueError(f"no h_contact in (0, 1] of {name} gives {target} dofs within {rtol:g}; tried (h_c, dofs) "
                     f"{[(round(h, 6), k) for h, k in tried]}")


def _lu_numeric() -> tuple[int, float]:
    """Cumulative count and time (s) of PETSc's numeric LU factorisations (the log must be on)."""
    from petsc4py import PETSc

    info = PETSc.Log.Event("MatLUFactorNum").getPerfInfo()
    return int(info["count"]), float(info["time"])


def _timed(run, *, name: str, mesh_cache: Path, comm, **overrides) -> dict:
    """One warm run through the pipeline: wall time of run_one (s), the solver's time, Newton iterations, and the
    numeric LU factorisations of the run (count, s: where a Newton iteration's cost goes)."""
    from workbench.pipeline.run_case import run_one

    n0, t_lu = _lu_numeric()
    t0 = time.perf_counter()
    m = run_one(run, name=name, mesh_cache=mesh_cache, comm=comm, progress=lambda _: None, **overrides).metrics
    total = time.perf_counter() - t0
    n1, t_lu1 = _lu_numeric()
    return {"total_s": total, "solve_s": m["wall_time_s"], "ndofs": m["ndofs"],
            "newton_iterations": [int(i) for i in m["newton_iterations"]], "h_contact": run.discretisation.h_contact,
            "method": m["method"], "lu_numeric": n1 - n0, "lu_numeric_s": t_lu1 - t_lu}


def _best(rows: list[dict]) -> dict:
    out = dict(rows[-1])
    for key in ("total_s", "solve_s", "lu_numeric_s"):
        out[key] = min(r[key] for r in rows)
    out["repeats"] = len(rows)
    return out


def run_two_body_bench(cfg: TwoBodyBench | None = None, *, comm=None,
                       progress: Callable[[str], None] = print) -> dict:
    """Measure the section (module docstring); JSON-ready, no files written."""
    import dolfinx_solver  # noqa: F401

    from mpi4py import MPI
    from petsc4py import PETSc

    import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
    from cases import load_case
    from workbench.studies.config import to_json

    cfg = TwoBodyBench() if cfg is None else cfg
    comm = MPI.COMM_SELF if comm is None else comm
    PETSc.Log.begin()
    cache = cfg.cache_dir
    rigid_base = load_case(cfg.rigid_case).runs()[0]
    rigid_name = f"bench_two_body_{cfg.rigid_case}"
    matched: dict[int, tuple] = {}
    rows = []
    for case_name, level in cfg.cases:
        for run in load_case(case_name).runs(h_contact=level):
            name = f"bench_two_body_{case_name}"
            warm = _timed(run, name=name, mesh_cache=cache, comm=comm)  # JIT, mesh
            target = warm["ndofs"]
            if target not in matched:
                matched[target] = match_rigid(rigid_base, target, name=rigid_name, mesh_cache=cache, comm=comm,
                                              rtol=cfg.match_rtol)
            rigid_run, _, tried = matched[target]
            _timed(rigid_run, name=rigid_name, mesh_cache=cache, comm=comm)  # JIT, mesh
            two, rigid, free = [], [], []
            for _ in range(cfg.repeats):
                two.append(_timed(run, name=name, mesh_cache=cache, comm=comm))
                rigid.append(_timed(rigid_run, name=rigid_name, mesh_cache=cache, comm=comm))
                free.append(_timed(rigid_run, name=rigid_name, mesh_cache=cache, comm=comm, **cfg.rigid_free))
            tb, rg, fr = _best(two), _best(rigid), _best(free)
            its = tb["newton_iterations"]
            row = {"case": case_name, "run": run.label, "two_body": tb, "rigid": rg, "rigid_predictor_free": fr,
                   "ndofs_rel_diff": rg["ndofs"] / tb["ndofs"] - 1.0, "rigid_levels_tried": tried,
                   "ratio_total": tb["total_s"] / rg["total_s"], "ratio_solve": tb["solve_s"] / rg["solve_s"],
                   "ratio_total_predictor_free": tb["total_s"] / fr["total_s"],
                   "newton_max": max(its, default=0), "newton_per_step": sum(its) / max(len(its), 1)}
            row["cost_met"] = row["ratio_total"] <= cfg.cost_target
            row["newton_met"] = row["newton_max"] <= cfg.newton_target
            rows.append(row)
            progress(f"two_body {case_name}[{run.label}] {tb['ndofs']} dofs: {tb['total_s']:.3f} s (solver "
                     f"{tb['solve_s']:.3f} s) vs rigid {cfg.rigid_case} h_c={rg['h_contact']:.4g} {rg['ndofs']} dofs: "
                     f"{rg['total_s']:.3f} s (solver {rg['solve_s']:.3f} s): ratio {row['ratio_total']:.2f} "
                     f"(solver {row['ratio_solve']:.2f}); rigid predictor-free {fr['total_s']:.3f} s, its "
                     f"{fr['newton_iterations']}: ratio {row['ratio_total_predictor_free']:.2f}; Newton its {its}")
    return {"config": to_json(cfg), "rows": rows, "cost_target": cfg.cost_target,
            "newton_target": cfg.newton_target, "all_met": all(r["cost_met"] and r["newton_met"] for r in rows),
            "load_avg": os.getloadavg()}


def main(argv: list[str] | None = None) -> int:
    """``python -m workbench.studies.bench_two_body [--out DIR] [--repeats N] [--quick]``."""
    p = argparse.ArgumentParser(prog="python -m workbench.studies.bench_two_body", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", type=Path, default=None, help="output folder (default: <results>/bench)")
    p.add_argument("--mesh-cache", type=Path, default=None, help="mesh cache (default: <results>/mesh_cache)")
    p.add_argument("--repeats", type=int, default=TwoBodyBench.repeats, help="timed warm solves (best kept)")
    p.add_argument("--quick", action="store_true", help="the elastic cylinder at its CI level only")
    args = p.parse_args(argv)
    from workbench.atomic import write_json, write_text
    from workbench.owned import ensure_dir
    from workbench.studies.bench_report import two_body_markdown

    out = Path(args.out).resolve() if args.out is not None else default_paths().study("bench")
    try:
        cfg = TwoBodyBench(repeats=args.repeats, mesh_cache=args.mesh_cache)
        if args.quick:
            cfg = replace(cfg, cases=(("elastic_cylinder", 0.1),))
        ensure_dir(out, kind="bench", kinds=("bench",))
        ensure_dir(cfg.cache_dir, kind="mesh_cache", kinds=("mesh_cache",))
        data = run_two_body_bench(cfg, progress=lambda s: print(f"[bench] {s}", flush=True))
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    write_json(out / "two_body.json", data)
    write_text(out / "two_body.md", "\n".join(two_body_markdown(data, [])) + "\n")
    print(f"[bench] wrote {out / 'two_body.md'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
