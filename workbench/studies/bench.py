"""Performance benchmark (issue "Performance and scale"): ``workbench bench [--quick] [--sections ...]``.

Writes ``<results>/bench/bench.json`` (the config and every number) and ``report.md`` atomically; the report
(:mod:`workbench.studies.bench_report`) and the plot (:mod:`workbench.studies.bench_plot`) read the JSON. A
benchmark to report, not a timed test: the targets are stated as met / not met. What is run is
:class:`BenchConfig`. Scene: ``cases/hertz_cylinder.toml`` (rigid circle R = 10 mm on a steel block, Hertz
load of a = 0.5 mm, half model). Error measure: ``rms = RMS(p - p_H)/p0`` at the measured load
(:func:`workbench.scenes.block_theory.rms_error`); target ``rms_target = 0.5 %``. Times are wall seconds;
"warm" means the FFCx JIT cache and the mesh cache are filled and the forms were loaded once in the process
(the best of up to ``repeats`` identical runs: the CPU may be shared). Every solve goes through the case
pipeline (:func:`workbench.pipeline.run_case.run_one`) with the section's overrides: our runs on their scene's
cached mesh, the solves timed on one mesh in memory and the baseline on its uniform box through
:func:`workbench.studies.scene_point.run_on_mesh`. Modules: sections 1-2 :mod:`workbench.studies.bench_accuracy`,
3 :mod:`workbench.studies.bench_scale`, 4-5a :mod:`workbench.studies.bench_process`, 5b-6
:mod:`workbench.studies.bench_options`, 7 :mod:`workbench.studies.bench_two_body`, 8
:mod:`workbench.studies.bench_startup`; the measuring tools :mod:`workbench.studies.bench_measure`.

Sections:

1. Time to accuracy. Baseline = the common tutorial set-up: a uniform mesh of right triangles over the whole
   box (half model, W = H = ``box`` a, no grading), P2, penalty with a FIXED stiffness
   ``kappa = baseline_kappa E / (1 mm)`` (not scaled by E/h), force control from zero to
   ``baseline_force_rtol`` (``predictor="extrapolate"``, no active-set predictor, one full load step,
   ``first_step_fraction=1``; the solver's force corrections: tangent of the last state, else secant).
   Ours = the case (Nitsche or penalty ``kappa0 E/h``, P1 or P2, graded mesh of :mod:`meshes.block`, Hertz
   predictor). Each ladder is run coarse to fine until ``rms <= rms_target``; the time to accuracy is the
   warm time of the first configuration that reaches it (mesh + solve + comparison; solver only also kept).
2. Contact solve against one linear elastic solve on the same mesh (same LU/MUMPS, assembly included),
   Newton iterations per load step, and the PETSc factorisation counts (PETSc log events).
3. Cost growth: P2, the case's Nitsche scene, on graded meshes of decreasing h_c and on uniform meshes up
   to ~1e6 dofs, one subprocess per size. Each size is solved with the row's options
   (:func:`scale_overrides`: ``scale_predictor``, ``scale_linear_solver``, and ``linear_solver="gamg"`` above
   ``krylov_threshold`` dofs; with ``scale_linear_solver="auto"``, the default, the solver's own choice by size
   at every row: one configuration) and compared with one linear elastic solve on the same mesh with the same
   linear solver (``"auto"``: the same choice and MUMPS ordering), in "linear solves per contact solve"; up to
   ``crossover_max_ndofs`` one LU and one GAMG linear solve are timed too (the crossover of ``"auto"``); below
   the threshold the case solver runs too (its cost in linear solves and the relative
   differences of P, p_max and the half-width). Peak memory = the high-water mark VmHWM of that process after
   the mesh, after the first contact solve, and at the end (``ru_maxrss`` is inherited from the parent across
   fork/exec on Linux, so after a big section it only shows the parent's peak; both are kept). Fitted exponent
   of time against ndofs (:func:`workbench.studies.rates.fit_exponent`).
4. MPI: ``mpiexec -n 2 workbench run hertz_cylinder`` against the serial run (P, p0, half-width to
   1e-8 relative) and the speed-up (default size and a larger one).
5. Repeated work: cold (fresh FFCx cache via ``XDG_CACHE_HOME`` and a fresh mesh cache, in a subprocess)
   against warm; symbolic against numeric factorisations (PETSc log events); MUMPS ordering, PETSc LU and
   three load steps (``solver_variants``); reuse of the first LU through GMRES and a lagged
   preconditioner (``reuse_lu``), all through the wiring's ``petsc_options`` override.

6. Predictor-free Newton (issue 16): every run of ``predictor_free_cases`` at its default level with
   ``predictor="extrapolate"`` (no analytic predictor) and the solver option ``active_set`` =
   ``predictor_free_active_set`` (and ``active_set_update`` = ``predictor_free_active_set_update``, with
   ``"newton"`` as a second reference row when it differs), and with today's ``active_set="extrapolate"`` as
   the reference: Newton
   iterations per solve (the prescribed-active-set iteration included; force corrections and steps without
   contact, 0 iterations, are solves too), the mean per scene, and the loads against the case default.

7. Two elastic bodies (issue 24): each two-body case against the rigid case with the same number of dofs, timed
   side by side, and its Newton iterations per load step (:mod:`workbench.studies.bench_two_body`).
8. Start-up and output (issue 27): one CI-level case as a whole process (default and ``--no-pictures``) against
   its mesh and solve in one process, and the interpreter-and-imports floor
   (:mod:`workbench.studies.bench_startup`; alone: ``workbench bench --sections startup``).
9. Nested iteration (issue 38): the error budget's levels of a two-body case solved cold and each from the
   coarser one, side by side, with their Newton iterations (:mod:`workbench.studies.bench_nested`).

Internal worker modes (``workbench bench --worker scale|cold``, the config passed as JSON) run one
measurement in a subprocess and print one line ``BENCH_JSON {...}``.
"""


from __future__ import annotations

import argparse
import json
import os
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from workbench.atomic import write_json, write_text
from workbench.owned import ensure_dir
from workbench.studies.bench_accuracy import contact_vs_linear, time_to_accuracy
from workbench.studies.bench_config import BENCH_SECTIONS, SCALE_FAMILIES, BenchConfig
from workbench.studies.bench_measure import DEFAULT, case_run
from workbench.studies.bench_options import lu_reuse, predictor_free, solver_variants
from workbench.studies.bench_process import cold_warm, mpi_check, worker_cold
from workbench.studies.bench_scale import cost_growth, worker_scale
from workbench.studies.config import from_json, to_json

__all__ = ["BenchConfig", "main", "run_bench"]


# ------------------------------------------------------------------------------------------ the study


def run_bench(cfg: BenchConfig | None = None, *, progress: Callable[[str], None] = print) -> dict:
    """Run the benchmark sections of ``cfg`` (default :class:`BenchConfig`) and return the JSON-ready data (no
    files written)."""
    import dolfinx_solver  # noqa: F401

    from mpi4py import MPI

    cfg = BenchConfig() if cfg is None else cfg
    ensure_dir(cfg.cache_dir, kind="mesh_cache", kinds=("mesh_cache",))  # the workbench's own, or refused
    sections = cfg.sections
    comm = MPI.COMM_WORLD
    t0 = time.perf_counter()
    out: dict[str, Any] = {
        "config": to_json(cfg),
        "case": cfg.case,
        "rms_target": cfg.rms_target,
        "targets": cfg.targets,
        "repeats": cfg.repeats,
        "baseline": {
            "kappa": f"{cfg.baseline_kappa:g} E / mm",
            "ladder": cfg.baseline_ladder,
            "force_rtol": cfg.baseline_force_rtol,
        },
        "cpu_count": os.cpu_count(),
        "load_avg_start": os.getloadavg(),
    }
    if "accuracy" in sections:
        out["accuracy"] = time_to_accuracy(cfg, comm=comm, progress=progress)
    if "linear" in sections:
        row = contact_vs_linear(case_run(cfg), cfg, comm=comm)
        out["linear"] = row
        progress(
            f"default: solver {row['solve_s']:.3f} s = {row['linear_solves_equivalent']:.1f} linear solves "
            f"({row['linear_s']:.4f} s); Newton its {row['newton_iterations']}"
        )
    if "scale" in sections:
        out["scale"] = cost_growth(cfg, progress=progress)
    if "mpi" in sections:
        out["mpi"] = mpi_check(cfg, progress=progress)
    if "cache" in sections:
        out["cache"] = cold_warm(cfg, progress=progress)
    if "options" in sections:
        out["options"] = solver_variants(cfg, comm=comm, progress=progress)
        out["lu_reuse"] = lu_reuse(cfg, comm=comm, progress=progress)
    if "predictor_free" in sections:
        out["predictor_free"] = predictor_free(cfg, comm=comm, progress=progress)
    if "two_body" in sections:  # issue 24: two bodies against a rigid case with the same dofs
        from workbench.studies.bench_two_body import TwoBodyBench, run_two_body_bench

        out["two_body"] = run_two_body_bench(TwoBodyBench(repeats=cfg.repeats, mesh_cache=cfg.cache_dir),
                                             comm=comm, progress=progress)
    if "startup" in sections:  # issue 27 point 5: the whole CI-level process against its mesh and solve
        from workbench.studies.bench_startup import startup_cost

        out["startup"] = startup_cost(cfg.case, repeats=cfg.repeats, progress=progress)
    if "nested" in sections:  # issue 38 item 1: the budget's levels cold against nested iteration
        from workbench.studies.bench_nested import NestedBench, run_nested_bench

        out["nested"] = run_nested_bench(NestedBench(repeats=cfg.repeats, mesh_cache=cfg.cache_dir), comm=comm,
                                         progress=progress)
    if "techniques" in sections:  # issue 38 items 3 and 4: condensation and solver variants, measured
        from workbench.studies.bench_techniques import techniques

        out["techniques"] = techniques(cfg, progress=progress)
    out["load_avg_end"] = os.getloadavg()
    out["bench_wall_time_s"] = time.perf_counter() - t0
    from workbench.studies.executor import ExecutorChoice
    from workbench.studies.reference import measure_reference

    out["reference"] = measure_reference(executor=ExecutorChoice(), mesh_cache=cfg.cache_dir)  # issue 27: ratio
    return out


# --------------------------------------------------------------------------------------------- CLI


def main(argv: list[str] | None = None) -> int:
    """CLI ``workbench bench [--repeats N] [--quick] [--sections ...] [--out DIR]``; writes ``<results>/bench/``."""
    p = argparse.ArgumentParser(prog="workbench bench", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--repeats", type=int, default=DEFAULT.repeats, help="warm repetitions per timing (best kept)")
    p.add_argument("--quick", action="store_true", help="small sizes only (development)")
    p.add_argument("--sections", nargs="+", default=list(BENCH_SECTIONS), help="sections (default: %(default)s)")
    p.add_argument("--out", type=Path, default=None, help="output folder (default: <results>/bench)")
    p.add_argument("--mesh-cache", type=Path, default=None, help="mesh cache (default: <results>/mesh_cache)")
    p.add_argument("--active-set-update", default=DEFAULT.predictor_free_active_set_update,
                   help="active_set_update of the predictor-free section (default: %(default)s)")
    p.add_argument("--worker", choices=("scale", "cold", "techniques"), help=argparse.SUPPRESS)
    p.add_argument("--worker-config", default=None, help=argparse.SUPPRESS)
    p.add_argument("--h-contact", type=float, default=None, help=argparse.SUPPRESS)
    p.add_argument("--family", choices=SCALE_FAMILIES, default="graded", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.worker:
        cfg = from_json(BenchConfig, json.loads(args.worker_config) if args.worker_config else None, strict=True)
        if args.worker == "techniques":
            from workbench.studies.bench_techniques import worker_techniques

            data = worker_techniques(cfg, args.family, args.h_contact)
        else:
            data = worker_scale(cfg, args.family, args.h_contact) if args.worker == "scale" else worker_cold(cfg)
        print("BENCH_JSON " + json.dumps(data, default=float), flush=True)
        return 0
    try:
        cfg = BenchConfig(repeats=args.repeats, sections=tuple(args.sections), out=args.out,
                          mesh_cache=args.mesh_cache, predictor_free_active_set_update=args.active_set_update)
        if args.quick:
            cfg = cfg.quick()
        from workbench.pipeline.size_estimate import check_levels_fit

        check_levels_fit([cfg.case], (*cfg.our_levels, *cfg.mpi_levels), study="bench",
                         field="our_levels / mpi_levels")  # before any mesh
        data = run_bench(cfg, progress=lambda s: print(f"[bench] {s}", flush=True))
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    from workbench.studies.bench_report import to_markdown

    out = cfg.out_dir
    write_json(out / "bench.json", data)
    write_text(out / "report.md", to_markdown(data))
    try:
        from workbench.studies.bench_plot import plot_bench

        plot_bench(data, out)
    except ImportError:
        pass
    print(f"[bench] wrote {out / 'report.md'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
