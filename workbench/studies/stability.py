"""Numerical-stability sweep on stiff and extreme cases: ``workbench stability [--study NAME ...] [--out DIR]``.

Writes ``<results>/stability/stability.json`` (the config and one record per run) and ``report.md``, then
:mod:`workbench.studies.stability_plot` draws ``method.png`` and ``incompressible.png`` from the JSON.
Every run either converges within its accuracy band or carries a NAMED reason: a solver failure
(``diverged: ... SNES reason -5 (DIVERGED_MAX_IT)``), a warning of the solver's own checks
(``contact unresolved``, ``penetration``, ``no contact``, ``contact truncated``; :mod:`fem.postprocess`), or a
model limit stated with the run (e.g. the exact circle is not Hertz's parabola at a/R = 0.4). A converged run
outside its band with none of these is counted ``SILENT`` -- the sweep's failure mode; the report lists them.

Scene (unless a study says otherwise): rigid exact circle R = 10 mm on a block (half model, W = H = 40 a,
clamped bottom), plane strain, E = 200 GPa, nu = 0.3, a/R = 0.05, force control to the Hertz load of a, P2,
h_contact = a/10, Nitsche gamma0 = 10, theta = 1, ``small`` kinematics, ``halfplane`` traction. Each run is a
:class:`Spec` (:mod:`workbench.studies.stability_specs`), which becomes a case run (:meth:`Spec.run`, a
:class:`cases.schema.Run`) solved by :func:`workbench.pipeline.run_case.run_one` like any case run, with the study's
solver overrides (formulation, iterations, cut-backs, predictor) and the block scene sized from the target
half-width (:class:`workbench.studies.scene_point.TargetSized`): its errors are the block scene's comparison against
Hertz (or the wedge) at the MEASURED load; a failure is named by :func:`workbench.studies.scene_point.run_failure`.
The report is :mod:`workbench.studies.stability_report`.

Every spec (and the ``conformal`` design) is one point of :func:`workbench.studies.executor.run_points`, run on
``MPI.COMM_SELF`` in this process (``--workers 1``, the default: the published times), in local processes
(``--workers N``) or on MPI ranks (``mpiexec -n N python -m mpi4py.futures -m workbench stability``).

What is swept, and the accuracy bands, are :class:`StabilityConfig` (band 2 %: see there).

Studies: ``method`` (penalty kappa0, Nitsche gamma0 x theta, with a 1-norm condition estimate of the
Jacobian, :mod:`fem.conditioning`), ``augmented_lagrangian`` (kappa0 over five decades: every run must
converge, :func:`classify_augmented_lagrangian`), ``incompressible`` (nu -> 1/2, P1/P2 displacement vs
Taylor-Hood mixed), ``convective`` (wedge b/b0, small vs convective kinematics, as beta -> 0), ``loads`` (a/R
over 2.6 decades, mesh scaled with a), ``resolution`` (h_c from 2a to a/8: the "contact unresolved" warning),
``scale`` (E over nine decades: non-dimensional results), ``conformal`` (close-to-conformal design, first
Table 1 steps: the 0.00043 mm indentation and relative radius ~228 mm), ``faults`` (Newton cut-back, an
unrecoverable step), ``two_body`` (two elastic bodies, E ratios 1e-3 ... 1e3 and nu = 0.499 on either side:
:class:`TwoBodySpec`, the elastic cylinder case through the scene registry and the case pipeline,
:func:`classify_two_body`). Select studies with ``--study NAME`` (repeatable), e.g. ``--study two_body``.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

import argparse
import dataclasses
import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from analytic import convective, materials, wedge
from workbench.atomic import write_json, write_text
from workbench.owned import ensure_dir
from workbench.paths import default_paths
from workbench.studies.config import to_json
from workbench.studies.executor import (
    ExecutorChoice,
    add_executor_options,
    executor_from_args,
    run_points,
    worker_summary,
)
from workbench.studies.scene_point import TargetSized, run_failure
from workbench.studies.stability_config import AL, STABILITY_STUDIES, StabilityConfig
from workbench.studies.stability_report import penalty_sweep, report_markdown
from workbench.studies.stability_specs import Spec, TwoBodySpec, specs, two_body_specs

__all__ = ["STUDIES", "Spec", "StabilityConfig", "TwoBodySpec", "classify", "classify_augmented_lagrangian",
           "classify_two_body", "convective_ratios", "main", "penalty_sweep", "report_markdown", "run_block_spec",
           "run_conformal", "run_sweep", "run_two_body_spec", "scale_invariance", "specs", "two_body_specs"]

STUDIES = STABILITY_STUDIES


def run_block_spec(spec: Spec, *, comm, mesh_cache: Path | None = None) -> dict:
    """Run one block spec through the case pipeline (:func:`workbench.pipeline.run_case.run_one`: the block scene
    with the mesh sized from the target, :class:`workbench.studies.scene_point.TargetSized`); returns its record
    (parameters, converged, iterations, time, errors, warnings).

    Args:
        spec: The run.
        comm: MPI communicator.
        mesh_cache: Mesh cache folder (default ``<results>/mesh_cache``).
    """
    from fem.solver import ContactSolveError
    from workbench.pipeline.run_case import run_one

    run = spec.run()
    a = spec.target_half_width
    scene = TargetSized(h_ratio=spec.h_ratio)
    meshes: dict = {}
    rec = {"study": spec.study, "label": spec.label, "params": spec.params()}
    t0 = time.perf_counter()
    try:
        o = run_one(run, name=f"stability_{spec.indenter}",
                    mesh_cache=mesh_cache if mesh_cache is not None else default_paths().mesh_cache, comm=comm,
                    progress=lambda _msg: None, scene=scene, meshes=meshes, case=spec.label,
                    **spec.solver_overrides())
    except (ContactSolveError, ValueError) as exc:  # named: diverged, or refused (e.g. displacement at nu = 0.4999)
        return _head(rec, scene, a) | {"converged": False, "error": run_failure(exc),
                                       "time_s": time.perf_counter() - t0, "warnings": [], "errors": {},
                                       "iterations": None}
    res, cmp = o.result, o.comparison
    rec = _head(rec, scene, a) | {
        "converged": True, "error": None, "time_s": time.perf_counter() - t0, "ndofs": res.ndofs,
        "iterations": int(sum(res.newton_iterations)), "max_iterations": int(max(res.newton_iterations)),
        "solves": len(res.newton_iterations), "cutbacks": sum(1 for r in res.load_steps if r["kind"] == "cutback"),
        "warnings": list(res.warnings), "P": res.P, "d": res.d}
    if spec.option("method") == AL or any("uzawa" in r for r in res.load_steps):
        rec["uzawa"] = _uzawa(res)
    hw, pmax, th = cmp.half_width, cmp.p_max, cmp.theory
    rec |= {"errors": cmp.errors, "half_width": hw, "p_max": pmax, "n_patches": len(res.patches),
            "half_width_theory": th.half_width, "p_ref_theory": th.p_ref,
            "nondim": {"p_max/E*": pmax / th.E_star, "a/R": hw / spec.R, "P/(E* R)": res.P / (th.E_star * spec.R)}}
    if spec.condition:
        from fem.conditioning import jacobian_condition

        c = jacobian_condition(res, meshes[scene.built.files.key])  # the mesh the result was solved on
        rec["condition"] = c._asdict()
    return rec


def _head(rec: dict, scene: TargetSized, a: float) -> dict:
    """The record's mesh and target (known once the point's scene has meshed it): cells, a and its load."""
    mesh = scene.built
    return rec | {"cells": mesh.files.stats.get("cells") if mesh else None, "target_half_width": a,
                  "P_target": mesh.estimate.P if mesh else None}


def _uzawa(res) -> dict:
    """The augmented Lagrangian's own loop from its load-step records: Newton solves per load level (``uzawa``),
    their total, and the largest final gap violation over max|u| (``uzawa_gap``); empty if not recorded."""
    steps = [r for r in res.load_steps if "uzawa" in r]
    if not steps:
        return {}
    gaps = [r["uzawa_gap"] for r in steps if r.get("uzawa_gap") is not None]
    return {"solves": [int(r["uzawa"]) for r in steps], "total": int(sum(r["uzawa"] for r in steps)),
            "gap_max": max(gaps) if gaps else None}


def classify(rec: dict) -> str:
    """``ok`` | ``named: <reason>`` | ``SILENT`` (converged, out of band, nothing named) for one record."""
    spec = rec["params"]
    if not rec["converged"]:
        tag = "expected failure" if spec.get("expect_failure") else "failure"
        return f"named ({tag}): {rec['error'].splitlines()[0]}"
    if spec.get("expect_failure"):
        return "SILENT"  # meant to fail but converged: nothing told the user it was not the run asked for
    worst = max((v for k, v in rec["errors"].items() if k in ("p_max", "half_width", "rms") and v == v),
                default=math.nan)
    rec["worst_error"] = worst
    within = spec.get("band") is None or (worst == worst and worst <= spec["band"])
    if rec["warnings"]:
        names = list(dict.fromkeys(w.split(":")[0] for w in rec["warnings"]))
        return "named (warning): " + "; ".join(names) + ("" if within else " [out of band]")
    if within:
        return "ok"
    if spec.get("model_limit"):
        return f"named ({spec['model_limit'].split(':')[0]}): {spec['model_limit']}"
    return "SILENT"


def classify_augmented_lagrangian(rec: dict) -> str:
    """The augmented-Lagrangian sweep's own classification: every stiffness must converge.

    A run that does not converge is ``FAILED (must converge): <reason>``, an expectation violated (counted
    with the SILENT runs: the sweep exits 1), not a named pass as a diverged penalty run is. A converged run
    is classified as any other (:func:`classify`: ``ok``, ``named (warning)`` or ``SILENT``).
    """
    if not rec["converged"]:
        return f"FAILED (must converge): {rec['error'].splitlines()[0]}"
    return classify(rec)


def augmented_lagrangian_summary(records: list[dict]) -> dict:
    """The AL sweep in one record: per kappa0 its Newton and Uzawa iterations and its errors; how far the
    errors move over the converged runs; and the largest relative deviation of d, p_max and the half-width
    from the middle kappa0's run (an augmented Lagrangian enforces the constraint at convergence whatever
    kappa0, so its answer should not depend on kappa0; the penalty's does)."""
    recs = [r for r in records if r["study"] == AL]
    rows = []
    for r in recs:
        e = r.get("errors", {})
        rows.append({"kappa0": r["params"]["kappa0"], "converged": r["converged"],
                     "iterations": r.get("iterations"), "max_iterations": r.get("max_iterations"),
                     "solves": r.get("solves"), "uzawa": r.get("uzawa", {}).get("total"),
                     "uzawa_gap": r.get("uzawa", {}).get("gap_max"), "p_max": e.get("p_max"),
                     "half_width": e.get("half_width"), "rms": e.get("rms"), "load_balance": e.get("load_balance"),
                     "time_s": r.get("time_s"), "status": r.get("status")})
    ok = [x for x in rows if x["converged"]]
    spread = {k: (max(x[k] for x in ok) - min(x[k] for x in ok)) if ok else None
              for k in ("p_max", "half_width", "rms")}
    conv = [r for r in recs if r["converged"]]
    deviation = None
    if conv:
        ref = conv[len(conv) // 2]
        deviation = max(abs(r[k] / ref[k] - 1.0) for r in conv for k in ("d", "p_max", "half_width"))
    return {"runs": len(rows), "converged": len(ok), "all_converged": bool(rows) and len(ok) == len(rows),
            "error_spread": spread, "max_rel_deviation": deviation,
            "reference_kappa0": conv[len(conv) // 2]["params"]["kappa0"] if conv else None, "rows": rows}


def convective_ratios(records: list[dict], *, main_block: float = 160.0) -> list[dict]:
    """FEM b/b0 at the same load (each half-width over its classical value at its own load) vs theory; the
    ``main_block`` rows first."""
    rows = []
    by = {(r["params"]["nu"], r["params"]["size_factor"], r["params"]["kinematics"]): r
          for r in records if r["study"] == "convective"}
    for nu, size in sorted({k[:2] for k in by}, key=lambda k: (k[1] != main_block, k)):
        s, c = by.get((nu, size, "small")), by.get((nu, size, "convective"))
        if not (s and c and s["converged"] and c["converged"]):
            continue
        fem_ratio = (c["half_width"] / c["half_width_theory"]) / (s["half_width"] / s["half_width_theory"])
        beta = materials.beta_rigid_indenter(nu)
        m = wedge.wedge_slope(s["params"]["wedge_angle"], convention="paper")
        sol = convective.solve(convective.wedge_profile(m), beta=beta)
        rows.append({"nu": nu, "block": size, "beta": beta, "fem": fem_ratio,
                     "converged_theory": sol.b_over_b0_converged,
                     "first_order": sol.b_over_b0_first_order,
                     "rel_error": abs(fem_ratio - sol.b_over_b0_converged) / sol.b_over_b0_converged})
    return rows


def scale_invariance(records: list[dict], *, reference_E: float = 1e3) -> list[dict]:
    """Non-dimensional results of the E sweep relative to the ``reference_E`` (MPa) run (round-off expected)."""
    runs = [r for r in records if r["study"] == "scale" and r["converged"]]
    ref = next((r for r in runs if r["params"]["E"] == reference_E), None)
    if ref is None:
        return []
    return [{"E": r["params"]["E"], **{k: abs(v / ref["nondim"][k] - 1.0) for k, v in r["nondim"].items()},
             "iterations": r["iterations"]} for r in runs]


def run_conformal(cfg: StabilityConfig | None = None, *, comm, progress) -> list[dict]:
    """Close-to-conformal design through its first Table 1 steps d = 0.46, 0.47, 0.48 mm at the defaults
    (``cfg.conformal_d``), through the case pipeline's :func:`workbench.pipeline.run_case.run_one`.

    d = 0.46 is the paper's first row (indentation 0.00043 mm); the primary pair's relative radius is ~228 mm,
    hundreds of times the contact half-width. One record per step (P, peak, patches, Newton iterations).
    """
    from cases.schema import load_case
    from fem.solver import ContactSolveError
    from workbench.pipeline.run_case import run_one

    cfg = StabilityConfig() if cfg is None else cfg
    case = load_case("close_to_conformal")
    run = case.runs(h_contact=case.discretisation.ci_level)[0]
    run = dataclasses.replace(run, loading=dataclasses.replace(run.loading, d=tuple(cfg.conformal_d)))
    t0 = time.perf_counter()
    base = {"study": "conformal", "params": {"design": "close_to_conformal", "h_contact": run.discretisation.h_contact,
                                             "method": run.solver.method, "band": None}}
    try:
        out = run_one(run, name="stability_close_to_conformal", mesh_cache=cfg.cache_dir, comm=comm,
                      progress=progress)
    except ContactSolveError as exc:
        return [base | {"label": "close_to_conformal d=0.46..0.48", "converged": False,
                        "error": run_failure(exc), "warnings": [], "errors": {}, "iterations": None,
                        "time_s": time.perf_counter() - t0}]
    from analytic.hertz import TABLE1

    paper = {row.d: {"P": row.P, "p0": row.p0, "delta": row.delta} for row in TABLE1
             if row.config == "close_to_conformal"}
    recs = []
    for s, snap in zip(out.metrics["steps"], out.result.snapshots, strict=True):
        hw = [e["half_width"] for e in s["patches"]]
        recs.append(base | {"label": f"close_to_conformal d={s['d']:.2f}", "converged": True, "error": None,
                            "iterations": s["iterations"],
                            "time_s": out.metrics["wall_time_s"] / len(out.metrics["steps"]),
                            "warnings": list(snap.warnings),
                            "errors": {"load_balance": abs(s["P"] - s["P_pressure"]) / abs(s["P"])},
                            "d": s["d"], "delta_lcp": s["delta_lcp"], "P": s["P"], "p_max": s["p_max"],
                            "patch_half_widths": hw, "n_patches": s["n_patches"],
                            "width_eq5": [e["width_eq5"][0] if e["width_eq5"] else math.nan for e in s["patches"]],
                            "paper": paper.get(round(s["d"], 2)),
                            "relative_radius": [r for e in s["patches"] for r in e["R_pairs"]]})
    return recs


def _two_body_run(spec: TwoBodySpec, cfg: StabilityConfig):
    """The case's first run with the spec's bodies and mesh level (displacement formulation: the two-body scene has
    no mixed one, so nu = 0.499 locks, and says so)."""
    from cases.schema import load_case

    run = load_case(cfg.two_body_case).runs(h_contact=1.0 / spec.h_ratio)[0]
    lower, upper = run.bodies  # the case's [[body]] tables: the lower body first
    bodies = (dataclasses.replace(lower, nu=spec.nu_lower),
              dataclasses.replace(upper, E=spec.ratio * lower.E, nu=spec.nu_upper))
    return dataclasses.replace(run, bodies=bodies, material=bodies[0].material,
                               solver=dataclasses.replace(run.solver, formulation="displacement"))


def run_two_body_spec(spec: TwoBodySpec, cfg: StabilityConfig, *, comm) -> dict:
    """Run one two-body point through the case pipeline (its scene from the registry: mesh, load path, comparison
    with the exact circle); its record: converged, Newton iterations per step, load balance, errors, warnings."""
    from fem.solver import ContactSolveError
    from workbench.pipeline.run_case import run_one

    run = _two_body_run(spec, cfg)
    rec = {"study": "two_body", "label": spec.label, "params": spec.params()}
    t0 = time.perf_counter()
    try:
        m = run_one(run, name="stability_two_body", mesh_cache=cfg.cache_dir, comm=comm,
                    progress=lambda _: None).metrics
    except (ContactSolveError, ValueError) as exc:  # named: diverged or refused
        return rec | {"converged": False, "error": run_failure(exc), "time_s": time.perf_counter() - t0,
                      "warnings": [], "errors": {}, "iterations": None}
    its = [int(i) for i in m["newton_iterations"]]
    e = m["errors"]
    return rec | {"converged": True, "error": None, "time_s": time.perf_counter() - t0, "ndofs": m["ndofs"],
                  "newton_iterations": its, "iterations": sum(its), "max_iterations": max(its, default=0),
                  "solves": len(its), "warnings": list(m["warnings"]), "P": m["P"], "p_max": m.get("p_max"),
                  "E_star": m["E_star"],
                  "errors": {k: e[k] for k in ("p_max", "half_width", "half_width_moment", "rms", "load_balance")
                             if k in e}}


def classify_two_body(rec: dict) -> str:
    """A two-body point: ``ok`` (converged, p_max and the moment half-width within the band, Newton iterations per
    step within the limit, no warning), ``named: <reason>`` (a failure, a solver warning, e.g. near-incompressible),
    or ``SILENT`` (out of band or over the iterations with nothing named)."""
    par = rec["params"]
    if not rec["converged"]:
        return f"named (failure): {rec['error'].splitlines()[0]}"
    worst = max((rec["errors"].get(k, math.nan) for k in ("p_max", "half_width_moment")), default=math.nan)
    rec["worst_error"] = worst
    slow = rec["max_iterations"] > par["newton"]
    within = worst == worst and worst <= par["band"] and not slow
    its = f", {rec['max_iterations']} Newton its in a step" if slow else ""
    note = "" if within else f" [out of band{its}]"
    if rec["warnings"]:
        return "named (warning): " + "; ".join(dict.fromkeys(w.split(":")[0] for w in rec["warnings"])) + note
    return "ok" if within else "SILENT" + note


@dataclass(frozen=True)
class Point:
    """One point of the sweep for the shared runner: a block ``spec``, a two-body point, or the ``conformal``
    design (spec None)."""

    spec: Spec | TwoBodySpec | None
    cfg: StabilityConfig


def run_stability_point(point: Point) -> dict:
    """The sweep's point function (module level: sent to the workers by name); on ``MPI.COMM_SELF``. A block
    spec returns its record with its ``status``; the conformal design ``{"records": [...]}``."""
    from mpi4py import MPI

    comm = MPI.COMM_SELF
    if point.spec is None:
        recs = run_conformal(point.cfg, comm=comm, progress=lambda _: None)
        for rec in recs:
            rec["status"] = classify(rec)
        return {"records": recs}
    if isinstance(point.spec, TwoBodySpec):
        rec = run_two_body_spec(point.spec, point.cfg, comm=comm)
        rec["status"] = classify_two_body(rec)
        return rec
    rec = run_block_spec(point.spec, comm=comm, mesh_cache=point.cfg.cache_dir)
    rec["status"] = (classify_augmented_lagrangian if point.spec.study == AL else classify)(rec)
    return rec


def run_sweep(cfg: StabilityConfig | None = None, *, executor: ExecutorChoice | None = None,
              progress=print) -> list[dict]:
    """Run the studies of ``cfg`` (default: all) on ``executor`` (default: in this process); returns one record
    per run, each with its ``status`` and where it ran (``worker``)."""
    cfg = StabilityConfig() if cfg is None else cfg
    executor = ExecutorChoice() if executor is None else executor
    ensure_dir(cfg.cache_dir, kind="mesh_cache", kinds=("mesh_cache",))  # the workbench's own, or refused
    todo = [Point(s, cfg) for s in specs(cfg) if s.study in cfg.studies]
    if "conformal" in cfg.studies:
        todo.append(Point(None, cfg))
    if "two_body" in cfg.studies:
        todo += [Point(s, cfg) for s in two_body_specs(cfg)]

    def said(i: int, n: int, rec: dict) -> None:
        for r in rec.get("records", [rec]):
            progress(f"[{i:3d}/{n}] {r['study']:14s} {r['label']:38s} {r['status'][:60]:60s} {r['time_s']:.2f} s")

    records = []
    for rec in run_points(run_stability_point, todo, executor=executor, progress=said):
        for r in rec.get("records", [rec]):
            records.append(r | {"worker": rec["worker"]})
    return records


def main(argv: list[str] | None = None) -> int:
    """CLI ``workbench stability [--study NAME ...] [--out DIR] [--mesh-cache DIR] [--executor local|mpi]
    [--workers N]``; exit 1 if any run is SILENT or an augmented-Lagrangian run FAILED, 2 on a bad option."""
    ap = argparse.ArgumentParser(prog="workbench stability", description=__doc__.splitlines()[0])
    ap.add_argument("--study", action="append", choices=STUDIES, help="run only these studies (repeatable)")
    ap.add_argument("--out", type=Path, default=None, help="output folder (default: <results>/stability)")
    ap.add_argument("--mesh-cache", type=Path, default=None, help="mesh cache (default: <results>/mesh_cache)")
    add_executor_options(ap, workers=1)
    args = ap.parse_args(argv)
    try:
        executor = executor_from_args(args)
    except ValueError as exc:
        print(f"workbench stability: error: {exc}", file=sys.stderr)
        return 2
    cfg = StabilityConfig(studies=tuple(args.study or STUDIES), out=args.out, mesh_cache=args.mesh_cache)
    t0 = time.perf_counter()
    records = run_sweep(cfg, executor=executor)
    where = worker_summary(records)
    wall = time.perf_counter() - t0
    from workbench.studies.reference import measure_reference

    reference = measure_reference(executor=executor, mesh_cache=cfg.cache_dir)
    summary = {
        "runs": len(records),
        "ok": sum(r["status"] == "ok" for r in records),
        "named": sum(r["status"].startswith("named") for r in records),
        "silent": sum(r["status"] == "SILENT" for r in records),
        "failed": sum(r["status"].startswith("FAILED") for r in records),
        "wall_time_s": wall, "reference": reference,
        "executor": executor.kind, "workers": executor.workers, "jit_retries": where["jit_retries"],
        "jit_compiles_on_workers": where["jit_compiles"], "where": where,
        "band": cfg.band,
        "convective": convective_ratios(records, main_block=max((b for _, b in cfg.convective_runs), default=0.0)),
        "scale": scale_invariance(records, reference_E=cfg.scale_reference_E),
        AL: augmented_lagrangian_summary(records) if AL in cfg.studies else None,
    }
    out = cfg.out_dir
    write_json(out / "stability.json", {"config": to_json(cfg), "summary": summary, "records": records})
    write_text(out / "report.md", report_markdown(summary, records))
    from workbench.studies.stability_plot import main as plot_main  # plotting is separate; it reads the JSON back

    plot_main(["--dir", str(out)])
    print(f"stability: {summary['runs']} runs, {summary['ok']} ok, {summary['named']} named, "
          f"{summary['silent']} SILENT, {summary['failed']} FAILED in {summary['wall_time_s']:.0f} s -> {out}")
    return 1 if summary["silent"] or summary["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())
