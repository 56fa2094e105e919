"""Sections 5b, 5c and 6 of the benchmark (:mod:`workbench.studies.bench`): solver option sets, reuse of the
first LU, and Newton iterations without an analytic predictor.
"""

from __future__ import annotations

from typing import Any

from workbench.studies.bench_config import BenchConfig
from workbench.studies.bench_log_events import factor_solves
from workbench.studies.bench_measure import (
    block_mesh_data,
    case_run,
    family_mesh,
    hertz_errors,
    linear_solve,
    log_counts,
    log_delta,
    rel_diff,
    solve_case,
)
from workbench.studies.scene_point import run_failure

__all__ = ["lu_reuse", "predictor_free", "solver_variants"]


def solver_variants(cfg: BenchConfig, *, comm, progress) -> dict:
    """Section 5b: warm solver time and factorisation counts per option set (one graded size,
    ``cfg.option_level``).

    PETSc options go through the wiring's ``petsc_options`` override (the SNES/KSP of the Newton solve; the
    Hertz predictor's own MUMPS solve keeps its defaults).
    """
    from petsc4py import PETSc

    level, repeats = cfg.option_level, cfg.repeats
    PETSc.Log.begin()
    run = case_run(cfg, level)
    md = block_mesh_data(run, cfg, comm=comm)
    solve_case(run, md)  # warm-up: forms loaded once (the options do not change the forms)
    lin = linear_solve(md, run, repeats=repeats)
    rows = []
    for label, (opts, over) in cfg.solver_variants.items():
        before = log_counts()
        res = solve_case(run, md, petsc_options=opts, **over)
        events = log_delta(before, log_counts())
        times = [res.wall_time_s]
        while len(times) < repeats and sum(times) < 5.0:
            times.append(solve_case(run, md, petsc_options=opts, **over).wall_time_s)
        row = {
            "variant": label,
            "options": opts,
            "overrides": over,
            "ndofs": res.ndofs,
            "solve_s": min(times),
            "linear_solves_equivalent": min(times) / lin["linear_s"],
            "newton_iterations": list(res.newton_iterations),
            "rms": hertz_errors(res, run)["rms"],
            "P": res.P,
            "events": events,
        }
        rows.append(row)
        progress(
            f"variant [{label}]: solver {row['solve_s']:.3f} s, its {row['newton_iterations']}, LU sym/num "
            f"{events['MatLUFactorSym']['count']}/{events['MatLUFactorNum']['count']} "
            f"({events['MatLUFactorSym']['time_s']:.3f}/{events['MatLUFactorNum']['time_s']:.3f} s)"
        )
    return {"h_over_a": level, "linear": lin, "rows": rows}


def lu_reuse(cfg: BenchConfig, *, comm, progress) -> dict:
    """Section 5c: the case solver against ``cfg.reuse_lu`` (GMRES + LU of the first Jacobian) per mesh."""
    from petsc4py import PETSc

    PETSc.Log.begin()
    rows = []
    for family, level in cfg.reuse_meshes:
        run, md = family_mesh(family, level, cfg, comm=comm)
        solve_case(run, md)  # warm-up
        row: dict[str, Any] = {"family": family, "h_over_a": level}
        for key, opts in (("case", {}), ("reuse", cfg.reuse_lu)):
            before = log_counts()
            try:
                res = solve_case(run, md, petsc_options=opts)
            except Exception as exc:  # noqa: BLE001  (a failed variant is a result, not a crash)
                row[key] = {"failed": run_failure(exc)}
                continue
            ev = log_delta(before, log_counts())
            row["ndofs"] = res.ndofs
            row[key] = {
                "solve_s": res.wall_time_s,
                "P": res.P,
                "newton_iterations": list(res.newton_iterations),
                "lu_numeric": ev["MatLUFactorNum"]["count"],
                "triangular_solves": factor_solves(ev),
                "rms": hertz_errors(res, run)["rms"],
            }
        if "P" in row.get("reuse", {}) and "P" in row.get("case", {}):
            row["rel_diff_P"] = rel_diff(row["case"]["P"], row["reuse"]["P"])
        rows.append(row)
        brief = {
            k: (
                f"{row[k]['solve_s']:.3f} s, LU {row[k]['lu_numeric']}, MatSolve {row[k]['triangular_solves']}"
                if "solve_s" in row.get(k, {})
                else row.get(k)
            )
            for k in ("case", "reuse")
        }
        progress(f"LU reuse {family} h=a*{level:g}: {brief}")
    return {"options": cfg.reuse_lu, "rows": rows}


def _newton_rows(cfg: BenchConfig, *, comm, progress, **overrides) -> dict:
    """Every run of the predictor-free cases through the case pipeline with ``overrides``: per scene the Newton
    iterations of each solve, the mean per solve, P and the solver time of each run."""
    import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
    from cases import load_case
    from workbench.pipeline.run_case import run_one

    scenes = {}
    for name in cfg.predictor_free_cases:
        runs, its_all = {}, []
        for run in load_case(name).runs():
            o = run_one(run, name=name, mesh_cache=cfg.cache_dir, comm=comm, progress=lambda s: None, **overrides)
            m = o.metrics
            its = [int(i) for i in m["newton_iterations"]]
            its_all += its
            runs[run.label] = {"ndofs": m["ndofs"], "newton_iterations": its, "P": m["P"],
                               "solve_s": m["wall_time_s"], "newton_per_step": sum(its) / len(its)}
        scenes[name] = {"runs": runs, "newton_per_step": sum(its_all) / len(its_all), "solves": len(its_all),
                        "newton_max": max(its_all)}
        progress(f"predictor-free {overrides}: {name} {sum(its_all) / len(its_all):.2f} per solve "
                 f"({ {k: r['newton_iterations'] for k, r in runs.items()} })")
    return scenes


def predictor_free(cfg: BenchConfig, *, comm, progress) -> dict:
    """Section 6: Newton iterations per solve without an analytic predictor (module docstring)."""
    update = cfg.predictor_free_active_set_update
    ours = _newton_rows(cfg, comm=comm, progress=progress, predictor="extrapolate",
                        active_set=cfg.predictor_free_active_set, active_set_update=update)
    plain = (None if update == "newton" else
             _newton_rows(cfg, comm=comm, progress=progress, predictor="extrapolate",
                          active_set=cfg.predictor_free_active_set, active_set_update="newton"))
    ref = _newton_rows(cfg, comm=comm, progress=progress, predictor="extrapolate", active_set="extrapolate")
    default = _newton_rows(cfg, comm=comm, progress=progress)
    target = cfg.predictor_free_target
    for name, row in ours.items():
        row["met"] = row["newton_per_step"] <= target
        row["max_rel_diff_P_vs_default"] = max(
            rel_diff(r["P"], default[name]["runs"][label]["P"]) for label, r in row["runs"].items())
    total = {k: sum(sum(sum(r["newton_iterations"]) for r in s["runs"].values()) for s in rows.values())
             for k, rows in (("ours", ours), ("active_set_update_newton", plain), ("reference", ref),
                             ("case_default", default)) if rows is not None}
    return {"active_set": cfg.predictor_free_active_set, "active_set_update": update, "target": target,
            "scenes": ours, "reference_active_set_extrapolate": ref, "case_default": default,
            "active_set_update_newton": plain, "total_newton_iterations": total,
            "all_met": all(r["met"] for r in ours.values())}
