"""Validity study: where the half-plane theories hold, model by model: ``workbench validity [--out DIR]``.

Writes ``<results>/validity/validity.json`` (the config, every run, every point with its theories and
uncertainties, the decomposition and the stress claim), then :mod:`workbench.studies.validity_report` writes
``report.md``/``report.html`` and :mod:`workbench.studies.validity_plot` the maps, both from the JSON alone.

Scenes (:class:`workbench.studies.validity_config.ValidityConfig`): a rigid exact circle (a/R from 1e-3 to 0.4) and a
rigid wedge (face angle theta from pi/40 to pi/4, slope tan theta) on a clamped block, beta = -(1 - 2 nu)/(2 (1 - nu))
from -1/2 (nu = 0) to ~0 (nu = 0.499), each with every model (traction x kinematics). The target half-width is
a = 1 mm in every point, so one mesh serves a scene and a level; the load is the classical load of a.
Two ELASTIC half-planes with a parabolic gap (issue 25, :mod:`workbench.studies.validity_halfplanes`): Dundurs beta
of both signs (``halfplanes_beta``, through the E ratio at nu = 0) x b0/R, small and convective (Ciavarella-Hills's
model) through the ``halfplanes`` scene; their moment ratio convective over small against Ciavarella-Hills
converged and first order (:func:`assemble_halfplanes`). An ELASTIC wedge on a block of the same material
(:mod:`workbench.studies.validity_elastic_wedge`): the paper's theta < pi/5 internal-stress claim as it states it.

Measures (dimensionless, each over the classical value at the run's MEASURED load P): ``moment`` =
2 sqrt(M2/M0) of the contact pressure over the classical one (Hertz: a; wedge: 2 b / sqrt 6), ``p_max`` (circle)
over Hertz's p0, and ``half_width`` (the zero crossing) over the classical half-width. The theories give the
same ratios (:mod:`analytic.halfplane`): Hertz (1), the exact circle, Ciavarella-Hills converged on the circle and
on the parabola, the classical wedge (1), Ciavarella-Hills converged on the wedge, and the first-order closed
forms (half-width only: they give no pressure).

Uncertainty of a model's value (relative): three levels a/h_c give a GCI (:func:`workbench.error_budget.grid_study`)
and the Richardson value; one more run on the middle level with the block 4x wider
(``width_factor_far``) corrects the truncation (f_far - f_W on the middle level: the truncation error is a property
of the block, not of h_c), assumed of order 1 in a/W (the convective ratio's measured order, docs/error_budget.md;
contact quantities converge like (a/W)^2): correction (4/3) (f_far - f_W), its uncertainty |f_far - f_W| / 3
(covers any order between 1 and 2). U = GCI + truncation uncertainty.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from workbench.atomic import write_json
from workbench.owned import ensure_dir
from workbench.studies.config import to_json
from workbench.studies.executor import (
    ExecutorChoice,
    add_executor_options,
    executor_from_args,
    run_points,
    worker_summary,
)
from workbench.studies.scene_point import TargetSized, run_failure, run_point
from workbench.studies.validity_assemble import CLAIM_X, CLAIM_Z, assemble, claim_points
from workbench.studies.validity_config import ValidityConfig
from workbench.studies.validity_elastic_wedge import ElasticWedgeTask, claim_elastic_wedge, elastic_wedge_tasks
from workbench.studies.validity_halfplanes import HalfplanesTask, halfplanes_tasks

__all__ = ["Point", "Task", "finite_settings", "main", "run_study", "run_validity_point", "solve_task", "tasks"]

# Finite-strain runs only (measured on the wedge, neo-Hookean, a/h = 4, 8, 16, W/a = 160 and 640, theta = pi/40 ..
# pi/4, nu = 0 and 0.3: 38 of 40 runs converge with these, none of the nu = 0.3 ones did before):
# * FINITE_STEPS load steps (3 steps: the first level follows the short first step with a 10-40 times larger
#   increment; fem.stepping also caps the finite increments' growth and uses a backtracking line search);
# * FINITE_THETA: the incomplete Nitsche variant (theta = 0). With the symmetric one (theta = 1) the semismooth
#   Newton iterates of the steep wedges cycle between two active sets (theta = pi/4, nu = 0.3, a/h = 8: the
#   residual stalls at 0.60 N/mm, det F alternating 0.8085 / 0.8188 at the apex, 30 iterations): 6 of 6 test points
#   failed with theta = 1, 0 of 6 with theta = 0. Both variants are consistent (the same limit as h -> 0; the
#   levels' extrapolation removes their O(h) difference);
# * FINITE_CUTBACKS step halvings per step and FINITE_MAX_IT Newton iterations per solve.
FINITE_STEPS = 24
FINITE_THETA = 0
FINITE_CUTBACKS = 4
FINITE_MAX_IT = 30
# St Venant-Kirchhoff loses ellipticity in compression: in plane-strain uniaxial compression (lateral stretch 1)
# its nominal stress lambda_1 (lambda + 2 mu) (lambda_1^2 - 1) / 2 peaks at the stretch 1/sqrt(3) = 0.577 and
# falls beyond it. Measured (a/h = 8, W/a = 160, the FINITE_* settings): SVK converges at theta = pi/40 and
# pi/20 (smallest principal stretch 0.84-0.89 and 0.77), and diverges from pi/10 on (nu = 0.3: at the load level
# 3/24, the last iterate's smallest stretch 0.38; nu = 0: 4/24, 0.39; pi/5, nu = 0: 1/24, 0.10 and inverted
# cells). The neo-Hookean solutions there reach 0.53-0.62 (pi/10), 0.21-0.24 (pi/5), 0.05-0.08 (pi/4). So SVK
# wedges above SVK_WEDGE_THETA_MAX are skipped with that reason.
SVK_WEDGE_THETA_MAX = math.pi / 20
SVK_WEDGE_SKIP = ("St Venant-Kirchhoff loses ellipticity below the stretch 1/sqrt(3) = 0.577 (plane-strain "
                  "uniaxial compression); wedges steeper than pi/20 reach smaller apex stretches (neo-Hookean, "
                  "a/h = 8: 0.53-0.62 at pi/10, 0.21-0.24 at pi/5, 0.05-0.08 at pi/4) and SVK diverged there "
                  "(pi/10, nu = 0.3: at the load level 3/24, smallest stretch 0.38)")


@dataclass(frozen=True)
class Task:
    """One FEM run of the study (a = 1 mm; units mm, N/mm, MPa).

    Attributes:
        scene: ``cylinder`` (exact circle, R = 1/param) or ``wedge`` (theta = param).
        param: a/R or theta (rad).  nu: Poisson ratio.  traction, kinematics: the model.
        level: ``h0``, ``h1``, ``h2`` (coarse to fine) or ``far`` (fine, wide block).
        h_ratio, width_factor, growth: a/h_c, W/a and the grading of the mesh.
        E, n_steps, mixed_from_nu, material_model: material and solver.
        stresses: also sample the stresses of the claim grid.
    """

    scene: str
    param: float
    nu: float
    traction: str
    kinematics: str
    level: str
    h_ratio: float
    width_factor: float
    growth: float
    E: float
    n_steps: int
    mixed_from_nu: float
    material_model: str = "linear"
    stresses: bool = False

    @property
    def mesh_name(self) -> str:
        return f"validity_{self.scene}_h{self.h_ratio:g}_W{self.width_factor:g}"

    @property
    def model(self) -> str:
        return f"{self.traction}/{self.kinematics}"


def tasks(cfg: ValidityConfig) -> tuple[list[Task], list[dict]]:
    """Every run of the study, and every (point, model) skipped before running, with its reason."""
    out, skipped = [], []
    if not cfg.rigid:
        return out, skipped
    levels = [(f"h{i}", h, cfg.width_factor) for i, h in enumerate(cfg.h_ratios)]
    levels.append(("far", cfg.h_ratios[1], cfg.width_factor_far))
    scenes = [("cylinder", v) for v in cfg.cylinder_a_over_R] + [("wedge", v) for v in cfg.wedge_theta]
    for scene, param in scenes:
        for nu in cfg.nu:
            for traction, kin in cfg.models:
                if kin == "finite" and nu >= cfg.mixed_from_nu:
                    skipped.append({"scene": scene, "param": param, "nu": nu, "model": f"{traction}/{kin}",
                                    "reason": f"finite strain has no mixed formulation; nu = {nu:g} >= "
                                              f"{cfg.mixed_from_nu:g} locks the displacement formulation"})
                    continue
                if (kin == "finite" and scene == "wedge" and cfg.finite_material == "saint_venant_kirchhoff"
                        and param > SVK_WEDGE_THETA_MAX * (1.0 + 1e-9)):
                    skipped.append({"scene": scene, "param": param, "nu": nu, "model": f"{traction}/{kin}",
                                    "reason": SVK_WEDGE_SKIP})
                    continue
                for level, h, W in levels:
                    growth = 1.0 + (cfg.growth - 1.0) * cfg.h_ratios[0] / h
                    stresses = scene == "wedge" and nu == cfg.claim_nu and kin == "small" and level in ("h2", "far")
                    out.append(Task(scene, float(param), float(nu), traction, kin, level, float(h), float(W),
                                    growth, cfg.E, FINITE_STEPS if kin == "finite" else cfg.n_steps,
                                    cfg.mixed_from_nu,
                                    cfg.finite_material if kin == "finite" else "linear", stresses))
    return out, skipped


def _run(task: Task):
    from cases.schema import Discretisation, Loading, Material, Run, Solver
    from workbench.scenes.block_schema import BlockGeometry

    if task.scene == "cylinder":
        geo = BlockGeometry(scene="block", indenter="circle", radius=1.0 / task.param, width_factor=task.width_factor,
                            height_factor=task.width_factor, half_model=True)
    else:
        geo = BlockGeometry(scene="block", indenter="wedge", wedge_angle=task.param, wedge_slope="exact",
                            width_factor=task.width_factor, height_factor=task.width_factor, half_model=True)
    form = "mixed" if task.nu >= task.mixed_from_nu else "displacement"
    return Run(label=task.scene, material=Material(E=task.E, nu=task.nu, model=task.material_model), geometry=geo,
               loading=Loading(control="force", half_width=1.0, steps=task.n_steps),
               discretisation=Discretisation(degree=2, h_contact=1.0 / task.h_ratio, growth=task.growth),
               solver=Solver(method="nitsche", kinematics=task.kinematics, traction=task.traction,
                             formulation=form, theta=FINITE_THETA if task.kinematics == "finite" else 1))


def build_mesh(task: Task, mesh_cache: str) -> dict:
    """Build (or reuse) the mesh of ``task`` in the cache through its point's scene; returns its statistics."""
    run = _run(task)
    mesh = _scene(task).mesh(run, name=task.mesh_name, mesh_cache=Path(mesh_cache), comm=None)
    return {"mesh": task.mesh_name, "cells": mesh.files.stats.get("cells")}


def _scene(task: Task):
    """The point's scene: the block scene with the mesh sized from a = 1 mm itself (W = width_factor a, h_c = a /
    h_ratio: :class:`workbench.studies.scene_point.TargetSized`)."""
    return TargetSized(h_ratio=task.h_ratio)


_MESHES: dict = {}  # the meshes this worker has read, by cache key (run_one's ``meshes``)


def solve_task(task: Task, mesh_cache: str) -> dict:
    """Run one task in this process (MPI.COMM_SELF); returns its record. Never raises: any failure becomes the
    record's named ``error`` (an exception object holding PETSc state could not even be sent back)."""
    try:
        return _solve_task(task, mesh_cache)
    except Exception as exc:  # noqa: BLE001  (named: diverged, refused or failed)
        return {"task": asdict(task), "model": task.model, "converged": False, "error": run_failure(exc)}


@dataclass(frozen=True)
class Point:
    """One point of the study for the shared runner (:func:`workbench.studies.executor.run_points`): build the
    mesh of ``task`` (``mesh``) or solve it (``solve``), with the mesh cache folder."""

    kind: str
    task: Task | HalfplanesTask
    mesh_cache: str


def run_validity_point(point: Point) -> dict:
    """The study's point function (module level: sent to the workers by name); a two-half-planes task goes to
    :mod:`workbench.studies.validity_halfplanes`."""
    if isinstance(point.task, HalfplanesTask):
        from workbench.studies import validity_halfplanes as hp

        return (hp.build_mesh if point.kind == "mesh" else hp.solve_task)(point.task, point.mesh_cache)
    if isinstance(point.task, ElasticWedgeTask):
        from workbench.studies import validity_elastic_wedge as ew

        return (ew.build_mesh if point.kind == "mesh" else ew.solve_task)(point.task, point.mesh_cache)
    if point.kind == "mesh":
        return build_mesh(point.task, point.mesh_cache)
    return solve_task(point.task, point.mesh_cache)


def _solve_task(task: Task, mesh_cache: str) -> dict:
    from workbench.scenes.budget_theory import moment_half_width

    rec = {"task": asdict(task), "model": task.model, "converged": False, "error": None}
    # finite strain: FINITE_* (above); a run that cannot converge fails in seconds, with its SNES reason
    extra = ({"max_cutbacks": FINITE_CUTBACKS, "max_it": FINITE_MAX_IT} if task.kinematics == "finite" else {})
    t0 = time.perf_counter()
    try:
        o = run_point(_run(task), name=task.mesh_name, mesh_cache=mesh_cache, scene=_scene(task), meshes=_MESHES,
                      case=f"validity {task.model}", **extra)
    except Exception as exc:  # noqa: BLE001  (named: diverged, refused or failed)
        return rec | {"error": run_failure(exc), "time_s": time.perf_counter() - t0}
    res, cmp = o.result, o.comparison
    cells = o.metrics["mesh"].get("cells")
    th = cmp.theory
    s = res.samples
    moment = 2.0 * moment_half_width(s.s, s.p, s.weight, center=0.0)
    classical_moment = th.half_width * (1.0 if task.scene == "cylinder" else 2.0 / math.sqrt(6.0))
    rec |= {"converged": True, "time_s": time.perf_counter() - t0, "cells": cells, "P": res.P,
            "iterations": int(sum(res.newton_iterations)), "warnings": list(res.warnings),
            "b_classical": th.half_width, "p0_classical": th.p_ref if task.scene == "cylinder" else None,
            "moment": moment / classical_moment, "half_width": cmp.half_width / th.half_width,
            "p_max": cmp.p_max / th.p_ref if task.scene == "cylinder" else None}
    if task.stresses:
        from fem.probe import stress_at_points

        b = th.half_width
        pts = np.array([(x * b, -z * b) for z in CLAIM_Z for x in CLAIM_X])
        st = stress_at_points(res, pts)
        rec["stresses"] = {"x": pts[:, 0].tolist(), "z": (-pts[:, 1]).tolist(), "sxx": st.sxx.tolist(),
                           "szz": st.syy.tolist(), "sxz": st.sxy.tolist()}  # FEM sxy = McEwen's s_xz (measured)
    return rec


def finite_settings() -> dict:
    """The solver settings of the finite-strain runs (the FINITE_* constants) and the SVK wedge limit, for the
    JSON and the report."""
    return {"load_steps": FINITE_STEPS, "nitsche_theta": FINITE_THETA, "max_cutbacks": FINITE_CUTBACKS,
            "max_it": FINITE_MAX_IT, "svk_wedge_theta_max": SVK_WEDGE_THETA_MAX}


# the records saved while the study runs (every SAVE_EVERY runs and at the end of the solves), read by --resume
PARTIAL = "validity_runs.partial.json"
SAVE_EVERY = 10


def remaining(todo: list, saved: list[dict]) -> list:
    """The tasks of ``todo`` that no saved record solved (a saved record's ``task`` is its task as a dict; a failed
    run's record counts as done: its failure is a measured outcome)."""
    done = {json.dumps(r["task"], sort_keys=True) for r in saved}
    return [t for t in todo if json.dumps(asdict(t), sort_keys=True) not in done]


def run_study(cfg: ValidityConfig, *, executor: ExecutorChoice | None = None, progress=print,
              saved: list[dict] = (), on_records=None) -> tuple[list[dict], list[dict], dict]:
    """Run every task on ``executor`` (default: ``cfg.workers`` local processes): the meshes first, one point
    each, then the solves. Returns the records (each with its ``worker``), the skipped entries and the timing
    (with where the runs ran and the JIT compiles and retries: :func:`workbench.studies.executor.worker_summary`).
    ``saved``: records of an interrupted run of the same config; their tasks are not run again (:func:`remaining`).
    ``on_records(records)``: called with every record so far (``saved`` first) every :data:`SAVE_EVERY` runs and
    after the last one."""
    executor = ExecutorChoice("local", cfg.workers) if executor is None else executor
    todo, skipped = tasks(cfg)
    # the two-half-planes part and the elastic wedge of the paper's claim (issue 25): after the rigid runs
    todo = remaining([*todo, *halfplanes_tasks(cfg), *elastic_wedge_tasks(cfg)], list(saved))
    if saved:
        progress(f"validity: {len(saved)} runs saved by an interrupted run, {len(todo)} to run")
    cache = str(cfg.cache_dir)
    ensure_dir(cache, kind="mesh_cache", kinds=("mesh_cache",))  # the workbench's own, or refused
    meshes = {t.mesh_name: t for t in todo}
    timing = {}
    t0 = time.perf_counter()
    mesh_stats = run_points(run_validity_point, [Point("mesh", t, cache) for t in meshes.values()],
                            executor=executor)
    timing["meshes_s"] = time.perf_counter() - t0
    progress(f"validity: {len(meshes)} meshes in {timing['meshes_s']:.0f} s; {len(todo)} runs on "
             f"{executor.workers} {executor.kind} worker(s)")

    new: list[dict] = []

    def said(i, n, rec):
        new.append(rec)
        if on_records is not None and (i % SAVE_EVERY == 0 or i == n):
            on_records([*saved, *new])
        if i % 50 == 0 or i == n:
            progress(f"validity: {i}/{n} runs, {time.perf_counter() - t0:.0f} s")

    # chunks of 4: the levels h0, h1, h2, far of one (point, model) share their forms (tasks() lists them together),
    # so one worker compiles them once. validity --tiny on 2 cold workers: 72 forms compiled (one process: 69);
    # with chunks of 2, 138
    records = [*saved, *run_points(run_validity_point, [Point("solve", t, cache) for t in todo], executor=executor,
                                   chunksize=4, progress=said)]
    timing["runs_s"] = time.perf_counter() - t0 - timing["meshes_s"]
    for m in mesh_stats:
        m.pop("worker", None)
    return records, skipped, {"meshes": mesh_stats, **timing, "where": worker_summary(records)}


def _saved_runs(path: Path, cfg: ValidityConfig) -> list[dict]:
    """The records an interrupted run of ``cfg`` saved in ``path``; ValueError (one line) when there is none, it is
    not such a file, or it was written with another config."""
    if not path.is_file():
        raise ValueError(f"no saved runs at {path}; allowed: --resume after an interrupted run into the same --out")
    try:
        data = json.loads(path.read_text())
        runs, config = data["runs"], data["config"]
        if not isinstance(runs, list) or not all(isinstance(r, dict) and isinstance(r.get("task"), dict)
                                                 for r in runs):
            raise TypeError("runs")
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise ValueError(f"{path} is not a file of saved validity runs ({type(exc).__name__})") from None
    if config != json.loads(json.dumps(to_json(cfg))):
        raise ValueError(f"{path} was written with other options; allowed: the options of the interrupted run")
    return runs


class _Parser(argparse.ArgumentParser):
    """argparse whose errors are one stderr line and exit code 2."""

    def error(self, message: str):  # type: ignore[override]
        print(f"{self.prog}: error: {' '.join(message.split())}", file=sys.stderr)
        raise SystemExit(2)


def main(argv: list[str] | None = None) -> int:
    """CLI ``workbench validity [--out DIR] [--mesh-cache DIR] [--executor local|mpi] [--workers N] [--quick]
    [--tiny] [--halfplanes-only] [--elastic-wedge-only] [--resume]``;
    bad options or config values: one line, exit 2, nothing run or written."""
    ap = _Parser(prog="workbench validity", description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=None, help="output folder (default: <results>/validity)")
    ap.add_argument("--mesh-cache", type=Path, default=None, help="mesh cache (default: <results>/mesh_cache)")
    add_executor_options(ap, workers=ValidityConfig.workers)
    ap.add_argument("--quick", action="store_true", help="two points per scene, nu = 0 and 0.499; two half-planes "
                    "at beta = -0.3 and +0.3, b0/R = 0.1; the elastic wedge at pi/10 and pi/5 (a smoke run)")
    ap.add_argument("--tiny", action="store_true", help="one point per scene, nu = 0, two half-planes at beta = "
                    "-0.3 and +0.3, the elastic wedge at pi/5, coarse levels on small blocks (the end-to-end test: "
                    "every layer in seconds, no meaningful numbers)")
    ap.add_argument("--halfplanes-only", action="store_true", help="the two-elastic-half-planes part alone (no rigid "
                    "circle or wedge, no elastic wedge)")
    ap.add_argument("--elastic-wedge-only", action="store_true", help="the elastic-wedge part alone (the paper's "
                    "theta < pi/5 claim and its finite-strain rows; no rigid indenter, no two half-planes)")
    ap.add_argument("--resume", action="store_true", help=f"continue an interrupted run: the runs saved in "
                    f"<out>/{PARTIAL} (written every {SAVE_EVERY} runs while the study runs) are not run again; "
                    "the other options must be those of the interrupted run")
    args = ap.parse_args(argv)
    if args.halfplanes_only and args.elastic_wedge_only:
        print("workbench validity: error: --halfplanes-only and --elastic-wedge-only exclude each other; allowed: "
              "one of them", file=sys.stderr)
        return 2
    kw = {}
    if args.quick:
        kw = {"cylinder_a_over_R": (0.01, 0.2), "wedge_theta": (math.pi / 10, math.pi / 5), "nu": (0.0, 0.499),
              "halfplanes_beta": (-0.3, 0.3), "halfplanes_b0_over_R": (0.1,),
              "elastic_wedge_theta": (math.pi / 10, math.pi / 5)}
    if args.tiny:
        kw = {"cylinder_a_over_R": (0.1,), "wedge_theta": (math.pi / 10,), "nu": (0.0,), "h_ratios": (2.0, 3.0, 4.0),
              "width_factor": 20.0, "width_factor_far": 40.0, "halfplanes_beta": (-0.3, 0.3),
              "halfplanes_b0_over_R": (0.1,), "halfplanes_h_ratios": (2.0, 3.0, 4.0),
              "halfplanes_finite_h_ratios": (3.0, 4.0, 5.0),
              "elastic_wedge_theta": (math.pi / 5,), "elastic_wedge_h_ratios": (2.0, 3.0, 4.5),
              "elastic_wedge_width": 12.0, "elastic_wedge_width_far": 24.0,
              # the finite wedge's four runs took 110 s of the tiny run's 294 s (1 worker, a loaded machine):
              # left out; its rows are tested on synthetic records (tests/test_elastic_wedge_claim.py)
              "elastic_wedge_finite_laws": (), "elastic_wedge_finite_theta": ()}
    if args.halfplanes_only:
        kw |= {"rigid": False, "elastic_wedge_theta": ()}
    if args.elastic_wedge_only:
        kw |= {"rigid": False, "halfplanes_beta": ()}
    try:
        executor = executor_from_args(args)
        cfg = ValidityConfig(out=args.out, mesh_cache=args.mesh_cache, workers=executor.workers, **kw)
    except ValueError as exc:
        print(f"workbench validity: error: {exc}", file=sys.stderr)
        return 2
    out = cfg.out_dir
    saved: list[dict] = []
    if args.resume:
        try:
            saved = _saved_runs(out / PARTIAL, cfg)
        except ValueError as exc:
            print(f"workbench validity: error: --resume: {exc}", file=sys.stderr)
            return 2
    t0 = time.perf_counter()
    import resource

    def save(recs: list[dict]) -> None:
        write_json(out / PARTIAL, {"config": to_json(cfg), "runs": recs})

    records, skipped, timing = run_study(cfg, executor=executor, saved=saved, on_records=save)
    if executor.kind == "local":  # MPI workers are no children of this process: their time is in "where"
        timing["cpu_s_workers"] = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime + \
            resource.getrusage(resource.RUSAGE_CHILDREN).ru_stime
    points, dropped = assemble(cfg, records, skipped)
    claim = claim_points(cfg, records)
    claim_elastic = claim_elastic_wedge(cfg, records)
    dropped += [d | {"nu": cfg.elastic_wedge_nu} for d in claim_elastic.pop("dropped")]
    wall = time.perf_counter() - t0
    from workbench.studies.reference import measure_reference

    reference = measure_reference(executor=executor, mesh_cache=cfg.cache_dir)
    summary = {"runs": len(records), "converged": sum(r["converged"] for r in records),
               "failed": sum(not r["converged"] for r in records), "points": len(points), "dropped": len(dropped),
               "wall_time_s": wall, "executor": executor.kind, "workers": executor.workers,
               "cpu_count": os.cpu_count(), "jit_retries": timing["where"]["jit_retries"],
               "jit_compiles_on_workers": timing["where"]["jit_compiles"], "reference": reference, **timing}
    write_json(out / "validity.json", {"config": to_json(cfg), "summary": summary, "points": points,
                                       "dropped": dropped, "claim": claim, "claim_elastic_wedge": claim_elastic,
                                       "runs": records,
                                       "finite_settings": finite_settings()})
    (out / PARTIAL).unlink(missing_ok=True)  # every run is in validity.json now
    from workbench.studies.validity_plot import main as plot_main
    from workbench.studies.validity_report import write_report

    write_report(out)
    plot_main(["--dir", str(out)])
    print(f"validity: {summary['runs']} runs ({summary['failed']} failed), {summary['points']} points, "
          f"{summary['dropped']} dropped entries, {wall:.0f} s on {executor.workers} {executor.kind} worker(s), "
          f"{summary['jit_retries']} JIT retries -> {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
