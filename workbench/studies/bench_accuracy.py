"""Sections 1 and 2 of the benchmark (:mod:`workbench.studies.bench`): time to accuracy (the tutorial baseline
against our configurations) and one contact solve against one linear elastic solve on the same mesh.
"""

from __future__ import annotations

import math
import time
from dataclasses import replace
from typing import Any

from workbench.studies.bench_config import BenchConfig
from workbench.studies.bench_measure import (
    block_mesh_data,
    case_run,
    configure,
    first_reaching,
    hertz_errors,
    linear_solve,
    log_counts,
    log_delta,
    ours_once,
    solve_on,
    timed,
    uniform_box_mesh,
)

__all__ = ["contact_vs_linear", "time_to_accuracy"]


def _baseline_run(run, *, kappa0: float):
    """The baseline's settings as a case run: P2, penalty kappa0, small kinematics, one load step."""
    return replace(run, solver=replace(run.solver, method="penalty", kinematics="small", kappa0=kappa0),
                   discretisation=replace(run.discretisation, degree=2), loading=replace(run.loading, steps=1))


def _baseline_once(run, cfg: BenchConfig, *, box: float, h: float, comm) -> dict:
    """One baseline solve (see module docstring, section 1); times in s."""
    from workbench.scenes.block_theory import block_theory

    t0 = time.perf_counter()
    target = block_theory(run.geometry, run.material, P=run.loading.P, half_width=run.loading.half_width)
    a0 = target.half_width
    md = uniform_box_mesh(width=box * a0, height=box * a0, h=h * a0, comm=comm)
    t_mesh = time.perf_counter() - t0
    nx, ny = math.ceil(box / 2.0 / h - 1e-9), math.ceil(box / h - 1e-9)
    diam = math.hypot(box * a0 / 2.0 / nx, box * a0 / ny)  # ufl.CellDiameter of every right triangle (mm)
    kappa0 = cfg.baseline_kappa * diam  # kappa0 E / h = baseline_kappa E / (1 mm)
    res = solve_on(_baseline_run(run, kappa0=kappa0), md, target, case="bench-baseline", predictor="extrapolate",
                    active_set_predictor=False, first_step_fraction=1.0, force_rtol=cfg.baseline_force_rtol)
    errors = hertz_errors(res, run)
    return {
        "config": "baseline",
        "method": "penalty (fixed kappa)",
        "degree": 2,
        "box_over_a": box,
        "h_over_a": h,
        "ndofs": res.ndofs,
        "mesh_s": t_mesh,
        "solve_s": res.wall_time_s,
        "total_s": time.perf_counter() - t0,
        "newton_iterations": list(res.newton_iterations),
        "solves": len(res.load_steps),
        "kappa_N_per_mm3": cfg.baseline_kappa * run.material.E,
        **errors,
    }




def time_to_accuracy(cfg: BenchConfig, *, comm, progress) -> dict:
    """Section 1: the baseline ladder and the four configurations of ours, each until rms <= target.

    Besides the time to ``cfg.rms_target``, every baseline row is compared at ITS accuracy: the warm time of the
    first row of each configuration of ours with ``rms <=`` the baseline's rms (``same_accuracy``).
    """
    repeats, target = cfg.repeats, cfg.rms_target
    run = case_run(cfg)
    out: dict[str, Any] = {"target_rms": target, "baseline": [], "ours": {}}
    # warm the JIT of the baseline forms on a tiny box (the JIT does not depend on the mesh)
    _baseline_once(run, cfg, box=10.0, h=0.5, comm=comm)
    for box, h in cfg.baseline_ladder:
        row = timed(lambda box=box, h=h: _baseline_once(run, cfg, box=box, h=h, comm=comm), repeats=repeats,
                     budget_s=3.0)
        out["baseline"].append(row)
        progress(
            f"baseline W=H={box:g}a h=a*{h:g}: ndofs {row['ndofs']}, warm {row['total_s']:.2f} s "
            f"(solver {row['solve_s']:.2f} s, {len(row['newton_iterations'])} solves, its "
            f"{row['newton_iterations']}), rms {row['rms']:.3e}"
        )
        if row["rms"] <= target:
            break
    for method in cfg.our_methods:
        for degree in cfg.our_degrees:
            rows = []
            for level in cfg.our_levels:
                r = configure(case_run(cfg, level), method=method, degree=degree)
                ours_once(r, cfg, comm=comm)  # warm-up: JIT and mesh cache
                row = timed(lambda r=r: ours_once(r, cfg, comm=comm), repeats=repeats, budget_s=2.0)
                rows.append(row)
                progress(
                    f"{method} P{degree} h_c=a*{level:g}: ndofs {row['ndofs']}, warm {row['total_s']:.3f} s "
                    f"(solver {row['solve_s']:.3f} s), rms {row['rms']:.3e}"
                )
                if row["rms"] <= target:
                    break
            out["ours"][f"{method} P{degree}"] = rows
    out["case_steps"] = run.loading.steps
    base = first_reaching(out["baseline"], target=target)
    last = out["baseline"][-1]
    summary = {}
    for name, rows in out["ours"].items():
        best = first_reaching(rows, target=target)
        summary[name] = {
            "reached": best is not None,
            "h_over_a": best["h_over_a"] if best else None,
            "ndofs": best["ndofs"] if best else None,
            "total_s": best["total_s"] if best else None,
            "solve_s": best["solve_s"] if best else None,
            "rms": best["rms"] if best else None,
            "ratio_total": (base["total_s"] / best["total_s"]) if (base and best) else None,
            "ratio_solve": (base["solve_s"] / best["solve_s"]) if (base and best) else None,
            # baseline never reached the target: its finest (unconverged) rung is a lower bound of its time
            "ratio_total_lower_bound": (last["total_s"] / best["total_s"]) if (best and not base) else None,
        }
    out["baseline_reached"] = base
    out["summary"] = summary
    same = []
    for b in out["baseline"]:
        for name, rows in out["ours"].items():
            o = first_reaching(rows, target=b["rms"])
            if o is not None:
                same.append(
                    {
                        "baseline_h_over_a": b["h_over_a"],
                        "baseline_ndofs": b["ndofs"],
                        "rms": b["rms"],
                        "baseline_total_s": b["total_s"],
                        "ours": name,
                        "ours_h_over_a": o["h_over_a"],
                        "ours_ndofs": o["ndofs"],
                        "ours_total_s": o["total_s"],
                        "ratio_total": b["total_s"] / o["total_s"],
                        "ratio_solve": b["solve_s"] / o["solve_s"],
                    }
                )
    out["same_accuracy"] = same
    return out




def contact_vs_linear(run, cfg: BenchConfig, *, comm) -> dict:
    """Section 2 at one size: warm contact solve, warm linear solve, iterations and LU counts."""
    from petsc4py import PETSc

    repeats = cfg.repeats
    PETSc.Log.begin()
    ours_once(run, cfg, comm=comm)  # warm-up
    before = log_counts()
    row = timed(lambda: ours_once(run, cfg, comm=comm), repeats=1, budget_s=0.0)
    events = log_delta(before, log_counts())
    if repeats > 1:
        row2 = timed(lambda: ours_once(run, cfg, comm=comm), repeats=repeats - 1, budget_s=3.0)
        row["solve_s"] = min(row["solve_s"], row2["solve_s"])
        row["total_s"] = min(row["total_s"], row2["total_s"])
    lin = linear_solve(block_mesh_data(run, cfg, comm=comm), run, repeats=repeats)
    its = row["newton_iterations"]
    return {
        **row,
        "linear_s": lin["linear_s"],
        "linear_resolve_s": lin["linear_resolve_s"],
        "linear_solves_equivalent": row["solve_s"] / lin["linear_s"],
        "newton_per_step": sum(its) / len(its),
        "events": events,
    }
