"""Section 3 of the benchmark (:mod:`workbench.studies.bench`): cost growth, one subprocess per size
(:func:`worker_scale` runs in it).
"""

from __future__ import annotations

import time

from workbench.studies.bench_config import BenchConfig
from workbench.studies.bench_measure import (
    count_dofs,
    family_mesh,
    hertz_errors,
    linear_solve,
    log_counts,
    log_delta,
    malloc_env,
    maxrss_mb,
    peak_rss_mb,
    rel_diff,
    scale_overrides,
    solve_case,
    subprocess_json,
)
from workbench.studies.rates import fit_exponent

__all__ = ["cost_growth", "worker_scale"]


def worker_scale(cfg: BenchConfig, family: str, level: float) -> dict:
    """One size of section 3, in its own process: mesh, contact solve(s) with the row's solver
    (:func:`scale_overrides`), the case solver as reference (below ``krylov_threshold``), one linear solve with
    the row's linear solver, peak memory. For a family of ``scale_nested`` (where ``h_c * factor`` is at most
    ``scale_nested_coarsest``), each contact solve is two: a coarse mesh of the same family at ``h_c * factor``
    (the row's options), then the row's mesh started from it
    (``nested_start``: its active set and d, :mod:`fem.nested_start`); the row's time is the sum of both
    solvers' times (the coarse mesh is read before the clock, as the row's own mesh is)."""
    import dolfinx_solver  # noqa: F401

    from mpi4py import MPI
    from petsc4py import PETSc

    comm = MPI.COMM_WORLD
    t0 = time.perf_counter()
    run, md = family_mesh(family, level, cfg, comm=comm)
    mesh_s = time.perf_counter() - t0
    peak_mesh = peak_rss_mb()
    over = scale_overrides(cfg, count_dofs(md, run))
    coarse, factor = None, cfg.scale_nested.get(family)
    if factor and level * factor > cfg.scale_nested_coarsest:  # too coarse to resolve the contact: the Hertz zone
        factor = None
    if factor:  # nested iteration: a coarse mesh of the same geometry, built for this row
        coarse_run, coarse_md = family_mesh(family, level * factor, cfg, comm=comm)
        coarse_over = scale_overrides(cfg, count_dofs(coarse_md, coarse_run))

    def contact_solve():
        """The row's contact solve: (result, its time), the coarse solve's time included when nested."""
        nonlocal coarse
        if factor:
            coarse = solve_case(coarse_run, coarse_md, **coarse_over)
            fine = solve_case(run, md, nested_start=coarse.nested_start, **over)
            return fine, fine.wall_time_s + coarse.wall_time_s
        fine = solve_case(run, md, **over)
        return fine, fine.wall_time_s

    PETSc.Log.begin()
    before = log_counts()
    res, first_s = contact_solve()
    events = log_delta(before, log_counts())
    peak_first = peak_rss_mb()  # mesh + one contact solve (every factor it made still alive)
    times = [first_s]
    small = res.ndofs < cfg.small_ndofs
    times += [contact_solve()[1] for _ in range(2 if small else 1)]  # warm: forms loaded
    from fem.linear_solver import linear_options, resolve

    kind = "gamg" if resolve(over["linear_solver"], ndofs=res.ndofs) == "gamg" else "lu"
    # the same linear solver as the row's Newton iterations (auto: its choice and ordering at this size)
    lin = linear_solve(md, run, repeats=3 if small else 1,
                       linear_solver="auto" if over["linear_solver"] == "auto" else kind)
    by_kind = {}
    if res.ndofs <= cfg.crossover_max_ndofs:  # the LU/GAMG crossover: one linear solve of each kind
        for label, popts in (("lu", linear_options("auto", ndofs=0)), ("gamg", linear_options("gamg"))):
            same = (label == kind) and over["linear_solver"] == "auto"
            by_kind[label] = lin["linear_s"] if same else linear_solve(md, run, repeats=2 if small else 1,
                                                                      petsc_options=popts)["linear_s"]
    its = list(res.newton_iterations)
    pt = max(res.patches, key=lambda p: p.P) if res.patches else None
    row = {
        "family": family,
        "h_over_a": level,
        "ndofs": res.ndofs,
        "overrides": over,
        "linear_kind": kind,
        "linear_by_kind_s": by_kind,
        "mesh_read_s": mesh_s,
        "solve_s": min(times),
        "solve_first_s": times[0],
        "linear_s": lin["linear_s"],
        "linear_resolve_s": lin["linear_resolve_s"],
        "linear_solves_equivalent": min(times) / lin["linear_s"],
        "newton_iterations": its,
        "newton_per_step": sum(its) / len(its),
        "nested": None if coarse is None else {"factor": factor, "ndofs": coarse.ndofs,
                                                 "solve_s": coarse.wall_time_s,
                                                 "newton_iterations": list(coarse.newton_iterations)},
        "events": events,
        "rms": hertz_errors(res, run)["rms"],
        "P": res.P,
        "p_max": pt.p_max if pt else float("nan"),
        "half_width": pt.half_width if pt else float("nan"),
        "maxrss_mb": maxrss_mb(),
        "peak_rss_mesh_mb": peak_mesh,
        "peak_rss_first_solve_mb": peak_first,
    }
    if res.ndofs <= cfg.krylov_threshold:  # the case solver on the same mesh: its time and the same answer
        ref = [solve_case(run, md) for _ in range(2 if small else 1)]
        rpt = max(ref[-1].patches, key=lambda p: p.P)
        row["case"] = {"solve_s": min(r.wall_time_s for r in ref), "newton_iterations": list(ref[-1].newton_iterations),
                       "linear_solves_equivalent": min(r.wall_time_s for r in ref) / lin["linear_s"]}
        row["rel_diff_vs_case"] = {"P": rel_diff(res.P, ref[-1].P), "p_max": rel_diff(row["p_max"], rpt.p_max),
                                   "half_width": rel_diff(row["half_width"], rpt.half_width)}
    row["peak_rss_mb"] = peak_rss_mb()
    return row




def cost_growth(cfg: BenchConfig, *, progress) -> dict:
    """Section 3: one subprocess per size; exponents of warm solver time, linear solve and memory."""
    out = {}
    for family, levels in cfg.scale.items():
        rows = []
        for level in levels:
            row = subprocess_json(["--worker", "scale", "--family", family, "--h-contact", repr(float(level))], cfg,
                                  env=malloc_env(cfg))
            rows.append(row)
            progress(
                f"scale {family} h=a*{level:.4g}: ndofs {row['ndofs']}, solver {row['solve_s']:.2f} s, "
                f"linear {row['linear_s']:.3f} s ({row['linear_solves_equivalent']:.1f} linear solves), "
                f"its {row['newton_iterations']}, peak {row['peak_rss_mb']:.0f} MB"
            )
        n = [r["ndofs"] for r in rows]
        fits = {}
        for key in ("solve_s", "linear_s", "peak_rss_mb", "peak_rss_first_solve_mb"):
            if any(key not in r for r in rows):
                continue
            t = [r[key] for r in rows]
            fits[key] = {
                "all": fit_exponent(n, t)._asdict(),
                "largest3": fit_exponent(n, t, n_last=3)._asdict() if len(n) >= 3 else None,
            }
        out[family] = {"rows": rows, "fits": fits}
    return out
