"""Performance benchmark (issue "Performance and scale"): ``workbench bench [--quick] [--sections ...]``.

Writes ``<results>/bench/bench.json`` (the config and every number) and ``report.md`` atomically; the report
(:mod:`workbench.studies.bench_report`) and the plot (:mod:`workbench.studies.bench_plot`) read the JSON. A
benchmark to report, not a timed test: the targets are stated as met / not met. What is run is
:class:`BenchConfig`. Scene: ``cases/hertz_cylinder.toml`` (rigid circle R = 10 mm on a steel block, Hertz
load of a = 0.5 mm, half model). Error measure: ``rms = RMS(p - p_H)/p0`` at the measured load
(:func:`workbench.scenes.block_theory.rms_error`); target ``rms_target = 0.5 %``. Times are wall seconds;
"warm" means the FFCx JIT cache and the mesh cache are filled and the forms were loaded once in the process
(the best of up to ``repeats`` identical runs: the CPU may be shared). Every solve goes through the case
wiring (:func:`workbench.scenes.wiring.solve_run`, our runs through
:func:`workbench.pipeline.run_case.run_one`) with the section's overrides.

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

Internal worker modes (``workbench bench --worker scale|cold``, the config passed as JSON) run one
measurement in a subprocess and print one line ``BENCH_JSON {...}``.
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from workbench.atomic import write_json, write_text
from workbench.owned import ensure_dir
from workbench.studies.bench_config import BENCH_SECTIONS, SCALE_FAMILIES, BenchConfig
from workbench.studies.config import from_json, to_json
from workbench.studies.rates import fit_exponent

__all__ = ["BenchConfig", "LOG_EVENTS", "first_reaching", "main", "rel_diff", "run_bench", "scale_overrides",
           "uniform_box_mesh"]

LOG_EVENTS = ("MatLUFactorSym", "MatLUFactorNum", "MatSolve", "SNESJacobianEval", "SNESFunctionEval")
_DEFAULT = BenchConfig()
_CHECKOUT = Path(__file__).resolve().parents[2]  # the subprocesses import this same checkout
_ids = itertools.count()


# ----------------------------------------------------------------------------------------------- helpers


def first_reaching(rows: Sequence[dict], *, key: str = "rms", target: float = _DEFAULT.rms_target) -> dict | None:
    """The first row (ladder order: coarse to fine) with ``row[key] <= target``, or None."""
    for r in rows:
        v = r.get(key)
        if v is not None and math.isfinite(v) and v <= target:
            return r
    return None


def rel_diff(a: float, b: float) -> float:
    """|a - b| / max(|a|, |b|) (0 when both are 0)."""
    scale = max(abs(a), abs(b))
    return 0.0 if scale == 0 else abs(a - b) / scale


def _best_of(fn: Callable[[], Any], *, repeats: int, budget_s: float) -> tuple[float, Any]:
    """Run ``fn`` up to ``repeats`` times (stop once ``budget_s`` is spent); (min wall time, last output)."""
    best, out, spent = math.inf, None, 0.0
    for _ in range(max(1, repeats)):
        t0 = time.perf_counter()
        out = fn()
        dt = time.perf_counter() - t0
        best, spent = min(best, dt), spent + dt
        if spent > budget_s:
            break
    return best, out


def _log_counts() -> dict[str, dict]:
    """Cumulative PETSc log counts and times of :data:`LOG_EVENTS` (PETSc.Log.begin() must be on)."""
    from petsc4py import PETSc

    return {n: PETSc.Log.Event(n).getPerfInfo() for n in LOG_EVENTS}


def _log_delta(before: dict, after: dict) -> dict[str, dict]:
    return {
        n: {"count": int(after[n]["count"] - before[n]["count"]), "time_s": float(after[n]["time"] - before[n]["time"])}
        for n in LOG_EVENTS
    }


def _maxrss_mb() -> float:
    """``ru_maxrss`` of this process (MB; Linux reports KiB). Inherited across fork/exec on Linux."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _peak_rss_mb() -> float:
    """Peak resident memory of this process image (MB): VmHWM of /proc/self/status (new at exec, so a
    subprocess does not inherit its parent's peak); ``ru_maxrss`` where /proc is missing."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return float(line.split()[1]) / 1024.0
    except OSError:
        pass
    return _maxrss_mb()


# ------------------------------------------------------------------------------------------ the scenes


def _case_run(cfg: BenchConfig, h_contact: float | None = None):
    import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
    from cases import load_case

    return load_case(cfg.case).runs(h_contact=h_contact)[0]


def _configure(run, *, method: str, degree: int):
    return replace(
        run, solver=replace(run.solver, method=method), discretisation=replace(run.discretisation, degree=degree)
    )


def uniform_box_mesh(*, width: float, height: float, h: float, comm):
    """Half model x in [0, W/2], y in [-H, 0] of uniform right triangles (cell legs ~h, no grading).

    Physical groups as :mod:`meshes.block`: ``contact`` (top), ``clamped`` (bottom), ``symmetry`` (x = 0),
    ``sides`` (x = W/2).

    Args:
        width: W (mm), > 0.  height: H (mm), > 0.  h: target cell leg (mm), in (0, min(W/2, H)].
        comm: MPI communicator.

    Returns:
        dolfinx ``MeshData`` (cell_tags None).
    """
    import dolfinx_solver  # noqa: F401

    import dolfinx
    from dolfinx.io.gmsh import MeshData, PhysicalGroup

    for arg, val in (("width", width), ("height", height), ("h", h)):
        if not (val > 0 and math.isfinite(val)):
            raise ValueError(f"{arg} must be > 0 (mm), got {val}")
    if h > min(width / 2.0, height):
        raise ValueError(f"h must be <= min(W/2, H) = {min(width / 2.0, height)} mm, got {h}")
    nx, ny = math.ceil(width / 2.0 / h - 1e-9), math.ceil(height / h - 1e-9)
    mesh = dolfinx.mesh.create_rectangle(
        comm,
        [[0.0, -height], [width / 2.0, 0.0]],
        [nx, ny],
        cell_type=dolfinx.mesh.CellType.triangle,
        diagonal=dolfinx.mesh.DiagonalType.right,
    )
    fdim = 1
    mesh.topology.create_connectivity(fdim, 2)
    tol = 1e-9 * max(width, height)
    sides = {
        "contact": (1, lambda x: np.abs(x[1]) < tol),
        "clamped": (2, lambda x: np.abs(x[1] + height) < tol),
        "symmetry": (3, lambda x: np.abs(x[0]) < tol),
        "sides": (4, lambda x: np.abs(x[0] - width / 2.0) < tol),
    }
    idx, vals = [], []
    for tag, marker in sides.values():
        f = dolfinx.mesh.locate_entities_boundary(mesh, fdim, marker)
        idx.append(f)
        vals.append(np.full(f.size, tag, dtype=np.int32))
    idx, vals = np.concatenate(idx).astype(np.int32), np.concatenate(vals)
    order = np.argsort(idx, kind="stable")
    ft = dolfinx.mesh.meshtags(mesh, fdim, idx[order], vals[order])
    groups = {name: PhysicalGroup(1, tag) for name, (tag, _) in sides.items()}
    return MeshData(mesh=mesh, cell_tags=None, facet_tags=ft, ridge_tags=None, peak_tags=None, physical_groups=groups)


def _hertz_errors(result, run) -> dict:
    """Errors of a result against Hertz at the measured load, exactly as the case runner computes them."""
    from workbench.scenes.block import compare_result

    return compare_result(result, run).errors


def _solve_on(run, mesh_data, theory, *, case: str, **overrides):
    """Solve a block run on a given mesh through the case wiring: its scene's obstacle and load path (force
    control to ``theory.P``), :func:`workbench.scenes.wiring.solve_run` with the ``overrides``."""
    from workbench.scenes import SceneMesh, scene_for
    from workbench.scenes.wiring import solve_run

    scene = scene_for(run)
    mesh = SceneMesh(files=None, estimate=theory, summary="")  # the mesh is given: only the estimate is read
    return solve_run(run, mesh_data, scene.obstacle(run, mesh), scene.load_path(run, mesh), case=case, **overrides)


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
    res = _solve_on(_baseline_run(run, kappa0=kappa0), md, target, case="bench-baseline", predictor="extrapolate",
                    active_set_predictor=False, first_step_fraction=1.0, force_rtol=cfg.baseline_force_rtol)
    errors = _hertz_errors(res, run)
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


def _ours_once(run, cfg: BenchConfig, *, comm) -> dict:
    """One run of ours through the case pipeline (mesh from the cache, solve, comparison); times in s."""
    from workbench.pipeline.run_case import run_one

    t0 = time.perf_counter()
    o = run_one(run, name=f"bench_{cfg.case}", mesh_cache=cfg.cache_dir, comm=comm, progress=lambda s: None)
    m = o.metrics
    return {
        "config": f"{m['method']} P{m['degree']}",
        "method": m["method"],
        "degree": m["degree"],
        "box_over_a": run.geometry.width_factor,
        "h_over_a": run.discretisation.h_contact,
        "ndofs": m["ndofs"],
        "solve_s": m["wall_time_s"],
        "total_s": time.perf_counter() - t0,
        "newton_iterations": list(m["newton_iterations"]),
        "solves": m["load_steps"],
        **m["errors"],
    }


def _timed(fn: Callable[[], dict], *, repeats: int, budget_s: float) -> dict:
    """Warm timing of a row function: best total and best solver time over the repeats."""
    rows = []

    def once():
        rows.append(fn())
        return rows[-1]

    _best_of(once, repeats=repeats, budget_s=budget_s)
    row = dict(rows[-1])
    row["total_s"] = min(r["total_s"] for r in rows)
    row["solve_s"] = min(r["solve_s"] for r in rows)
    row["repeats"] = len(rows)
    row["rms_spread"] = max(rel_diff(r["rms"], rows[0]["rms"]) for r in rows)
    return row


def time_to_accuracy(cfg: BenchConfig, *, comm, progress) -> dict:
    """Section 1: the baseline ladder and the four configurations of ours, each until rms <= target.

    Besides the time to ``cfg.rms_target``, every baseline row is compared at ITS accuracy: the warm time of the
    first row of each configuration of ours with ``rms <=`` the baseline's rms (``same_accuracy``).
    """
    repeats, target = cfg.repeats, cfg.rms_target
    run = _case_run(cfg)
    out: dict[str, Any] = {"target_rms": target, "baseline": [], "ours": {}}
    # warm the JIT of the baseline forms on a tiny box (the JIT does not depend on the mesh)
    _baseline_once(run, cfg, box=10.0, h=0.5, comm=comm)
    for box, h in cfg.baseline_ladder:
        row = _timed(lambda box=box, h=h: _baseline_once(run, cfg, box=box, h=h, comm=comm), repeats=repeats,
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
                r = _configure(_case_run(cfg, level), method=method, degree=degree)
                _ours_once(r, cfg, comm=comm)  # warm-up: JIT and mesh cache
                row = _timed(lambda r=r: _ours_once(r, cfg, comm=comm), repeats=repeats, budget_s=2.0)
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


# ------------------------------------------------------------------------- linear solve, log events


def _block_mesh_data(run, cfg: BenchConfig, *, comm):
    """The cached graded mesh of a block run: its registered scene's mesh (as run_one builds it)."""
    from workbench.mesh_io import read_mesh
    from workbench.scenes import scene_for

    files = scene_for(run).mesh(run, name=f"bench_{cfg.case}", mesh_cache=cfg.cache_dir, comm=comm).files
    return read_mesh(files.msh, comm)


def linear_solve(mesh_data, run, *, repeats: int = 3, linear_solver: str = "lu",
                 petsc_options: dict | None = None) -> dict:
    """Warm time of one linear elastic solve (assembly of A and b, MUMPS LU, solve) on ``mesh_data``.

    ``linear_s``: a new problem each time (symbolic + numeric factorisation); ``linear_resolve_s``: the same
    problem solved again (PETSc keeps the symbolic factorisation: same nonzero pattern).

    Weak form: ``a(u, v) = -int_Gc p_H v_y ds`` with the Hertz pressure of the case load (MPa), clamped
    bottom, roller symmetry edge; options ``preonly`` / ``lu`` / ``mumps`` as the contact Newton iterations
    (``linear_solver="gamg"``: GMRES + GAMG with the rigid-body near-nullspace; ``"auto"``: the choice of
    :func:`fem.linear_solver.resolve` for this size, with its ordering, :mod:`fem.linear_solver`).
    ``petsc_options``: these options instead (GAMG when their ``pc_type`` is ``"gamg"``).
    """
    import dolfinx
    import dolfinx.fem.petsc
    import ufl

    from analytic.hertz import hertz, hertz_pressure
    from analytic.materials import plane_strain_modulus
    from fem.elasticity import lame, sigma
    from fem.linear_solver import linear_options, set_near_nullspace

    mesh = mesh_data.mesh
    lm = lame(E=run.material.E, nu=run.material.nu)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", run.discretisation.degree, (2,)))
    bcs = []
    for name, comps in (("clamped", (0, 1)), ("symmetry", (0,))):
        facets = mesh_data.facet_tags.find(mesh_data.physical_groups[name].tag)
        for c in comps:
            Vc, _ = V.sub(c).collapse()
            dofs = dolfinx.fem.locate_dofs_topological((V.sub(c), Vc), 1, facets)
            bcs.append(dolfinx.fem.dirichletbc(dolfinx.fem.Function(Vc), dofs, V.sub(c)))
    hz = hertz(
        run.loading.P if run.loading.P else _case_P(run),
        run.geometry.radius,
        plane_strain_modulus(run.material.E, run.material.nu),
    )
    X = ufl.SpatialCoordinate(mesh)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=mesh_data.facet_tags)
    p_h = hertz_pressure(X[0], a=hz.half_width, p0=hz.p0, xp=ufl)
    p_h = ufl.conditional(ufl.lt(abs(X[0]), hz.half_width), p_h, 0.0)
    v, du = ufl.TestFunction(V), ufl.TrialFunction(V)

    def fresh():
        """A new problem: assembly, symbolic + numeric LU, solve (what one linear solve costs)."""
        pb = dolfinx.fem.petsc.LinearProblem(
            a_form, L_form, bcs=bcs, petsc_options_prefix=f"bench_lin_{next(_ids)}_", petsc_options=opts
        )
        if opts.get("pc_type") == "gamg":
            set_near_nullspace(pb.A, V)
        pb.solve()
        return pb

    a_form = ufl.inner(sigma(du, lm), ufl.grad(v)) * ufl.dx
    L_form = -p_h * v[1] * ds(mesh_data.physical_groups["contact"].tag)
    ndofs = V.dofmap.index_map.size_global * 2
    opts = dict(petsc_options) if petsc_options is not None else linear_options(linear_solver, ndofs=ndofs)
    pb = fresh()  # warm-up: forms loaded
    best, pb = _best_of(fresh, repeats=repeats, budget_s=5.0)
    again, _ = _best_of(pb.solve, repeats=1, budget_s=0.0)
    return {"ndofs": ndofs, "linear_s": best, "linear_resolve_s": again}


def _case_P(run) -> float:
    from workbench.scenes.block_theory import block_theory

    return block_theory(run.geometry, run.material, P=run.loading.P, half_width=run.loading.half_width).P


def contact_vs_linear(run, cfg: BenchConfig, *, comm) -> dict:
    """Section 2 at one size: warm contact solve, warm linear solve, iterations and LU counts."""
    from petsc4py import PETSc

    repeats = cfg.repeats
    PETSc.Log.begin()
    _ours_once(run, cfg, comm=comm)  # warm-up
    before = _log_counts()
    row = _timed(lambda: _ours_once(run, cfg, comm=comm), repeats=1, budget_s=0.0)
    events = _log_delta(before, _log_counts())
    if repeats > 1:
        row2 = _timed(lambda: _ours_once(run, cfg, comm=comm), repeats=repeats - 1, budget_s=3.0)
        row["solve_s"] = min(row["solve_s"], row2["solve_s"])
        row["total_s"] = min(row["total_s"], row2["total_s"])
    lin = linear_solve(_block_mesh_data(run, cfg, comm=comm), run, repeats=repeats)
    its = row["newton_iterations"]
    return {
        **row,
        "linear_s": lin["linear_s"],
        "linear_resolve_s": lin["linear_resolve_s"],
        "linear_solves_equivalent": row["solve_s"] / lin["linear_s"],
        "newton_per_step": sum(its) / len(its),
        "events": events,
    }


# ------------------------------------------------------------------------------------ subprocess work


def _solve_case(run, mesh_data, *, petsc_options: dict | None = None, **overrides):
    """The run's case settings on ``mesh_data`` (force control to its classical load) through the wiring."""
    from workbench.scenes.block_theory import block_theory

    th = block_theory(run.geometry, run.material, P=run.loading.P, half_width=run.loading.half_width)
    return _solve_on(run, mesh_data, th, case="bench", petsc_options=petsc_options, **overrides)


def _family_mesh(family: str, level: float, cfg: BenchConfig, *, comm):
    """(run, mesh_data) of one size: ``graded`` = meshes.block at h_c = level a (the case's W = H = 40 a);
    ``uniform`` = :func:`uniform_box_mesh` W = H = scale_box a at h = level a (the case run at its h_c)."""
    if family == "graded":
        run = _case_run(cfg, level)
        return run, _block_mesh_data(run, cfg, comm=comm)
    run = _case_run(cfg)
    a0 = run.loading.half_width
    return run, uniform_box_mesh(width=cfg.scale_box * a0, height=cfg.scale_box * a0, h=level * a0, comm=comm)


def _ndofs(md, run) -> int:
    """Global displacement dofs of the run's element on ``md`` (decides the row's linear solver)."""
    import dolfinx

    V = dolfinx.fem.functionspace(md.mesh, ("Lagrange", run.discretisation.degree, (2,)))
    return V.dofmap.index_map.size_global * 2


def scale_overrides(cfg: BenchConfig, ndofs: int) -> dict:
    """Solver overrides of a cost-growth row of ``ndofs`` dofs: ``scale_predictor`` and ``scale_linear_solver``,
    ``"gamg"`` above ``krylov_threshold`` (``"auto"``: the solver decides at every size)."""
    auto = cfg.scale_linear_solver == "auto"
    kind = "gamg" if ndofs > cfg.krylov_threshold and not auto else cfg.scale_linear_solver
    return {"predictor": cfg.scale_predictor, "linear_solver": kind}


def _worker_scale(cfg: BenchConfig, family: str, level: float) -> dict:
    """One size of section 3, in its own process: mesh, contact solve(s) with the row's solver
    (:func:`scale_overrides`), the case solver as reference (below ``krylov_threshold``), one linear solve with
    the row's linear solver, peak memory."""
    import dolfinx_solver  # noqa: F401

    from mpi4py import MPI
    from petsc4py import PETSc

    comm = MPI.COMM_WORLD
    t0 = time.perf_counter()
    run, md = _family_mesh(family, level, cfg, comm=comm)
    mesh_s = time.perf_counter() - t0
    peak_mesh = _peak_rss_mb()
    over = scale_overrides(cfg, _ndofs(md, run))
    PETSc.Log.begin()
    before = _log_counts()
    res = _solve_case(run, md, **over)
    events = _log_delta(before, _log_counts())
    peak_first = _peak_rss_mb()  # mesh + one contact solve (every factor it made still alive)
    times = [res.wall_time_s]
    small = res.ndofs < cfg.small_ndofs
    times += [_solve_case(run, md, **over).wall_time_s for _ in range(2 if small else 1)]  # warm: forms loaded
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
        "events": events,
        "rms": _hertz_errors(res, run)["rms"],
        "P": res.P,
        "p_max": pt.p_max if pt else float("nan"),
        "half_width": pt.half_width if pt else float("nan"),
        "maxrss_mb": _maxrss_mb(),
        "peak_rss_mesh_mb": peak_mesh,
        "peak_rss_first_solve_mb": peak_first,
    }
    if res.ndofs <= cfg.krylov_threshold:  # the case solver on the same mesh: its time and the same answer
        ref = [_solve_case(run, md) for _ in range(2 if small else 1)]
        rpt = max(ref[-1].patches, key=lambda p: p.P)
        row["case"] = {"solve_s": min(r.wall_time_s for r in ref), "newton_iterations": list(ref[-1].newton_iterations),
                       "linear_solves_equivalent": min(r.wall_time_s for r in ref) / lin["linear_s"]}
        row["rel_diff_vs_case"] = {"P": rel_diff(res.P, ref[-1].P), "p_max": rel_diff(row["p_max"], rpt.p_max),
                                   "half_width": rel_diff(row["half_width"], rpt.half_width)}
    row["peak_rss_mb"] = _peak_rss_mb()
    return row


def _worker_cold(cfg: BenchConfig) -> dict:
    """Section 5: in this process, the first (cold or disk-warm) run of the case then a warm one."""
    t0 = time.perf_counter()
    import dolfinx_solver  # noqa: F401

    import dolfinx  # noqa: F401
    from mpi4py import MPI

    t_import = time.perf_counter() - t0
    comm = MPI.COMM_WORLD
    run = _case_run(cfg)
    t1 = time.perf_counter()
    _block_mesh_data(run, cfg, comm=comm)
    t_mesh = time.perf_counter() - t1
    first = _ours_once(run, cfg, comm=comm)
    second = _ours_once(run, cfg, comm=comm)
    return {
        "import_s": t_import,
        "mesh_s": t_mesh,
        "first_total_s": first["total_s"],
        "first_solve_s": first["solve_s"],
        "warm_total_s": second["total_s"],
        "warm_solve_s": second["solve_s"],
        "rms": second["rms"],
    }


def _env(extra: dict | None = None) -> dict:
    """The environment of a subprocess: this checkout first on PYTHONPATH (it imports this same code)."""
    e = dict(os.environ)
    e["PYTHONPATH"] = str(_CHECKOUT) + os.pathsep + e.get("PYTHONPATH", "")
    e.update(extra or {})
    return e


def _workbench(*args: str) -> list[str]:
    """The command line of ``workbench ARGS`` in this interpreter (``python -m workbench``)."""
    return [sys.executable, "-m", "workbench", *args]


def _mpiexec() -> str:
    """``mpiexec`` beside this interpreter (the venv's MPI), else the one on PATH."""
    local = Path(sys.executable).parent / "mpiexec"
    return str(local) if local.exists() else (shutil.which("mpiexec") or "mpiexec")


def _subprocess_json(args: list[str], cfg: BenchConfig, *, env: dict | None = None, cwd: Path | None = None,
                     timeout: float = 1200.0) -> dict:
    """Run ``workbench bench --worker ...`` with ``cfg`` and parse its ``BENCH_JSON`` line; adds ``process_s``."""
    cmd = _workbench("bench", "--worker-config", json.dumps(to_json(cfg)), *args)
    t0 = time.perf_counter()
    cp = subprocess.run(cmd, env=_env(env), cwd=None if cwd is None else str(cwd), capture_output=True, text=True,
                        timeout=timeout)
    dt = time.perf_counter() - t0
    if cp.returncode != 0:
        raise RuntimeError(f"bench worker {args} failed (exit {cp.returncode}): {cp.stderr.strip()[-500:]}")
    for line in cp.stdout.splitlines():
        if line.startswith("BENCH_JSON "):
            return {**json.loads(line[len("BENCH_JSON ") :]), "process_s": dt}
    raise RuntimeError(f"bench worker {args} printed no BENCH_JSON line")


def cost_growth(cfg: BenchConfig, *, progress) -> dict:
    """Section 3: one subprocess per size; exponents of warm solver time, linear solve and memory."""
    out = {}
    for family, levels in cfg.scale.items():
        rows = []
        for level in levels:
            row = _subprocess_json(["--worker", "scale", "--family", family, "--h-contact", repr(float(level))], cfg)
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


def _cli_metrics(out: Path, cfg: BenchConfig, *, np_: int, h_contact: float | None) -> dict:
    """``workbench run <case> --out out`` (under ``mpiexec -n np_`` when np_ > 1); the case's metrics."""
    cmd = _workbench("run", cfg.case, "--out", str(out))
    if h_contact is not None:
        cmd += ["--h-contact", repr(float(h_contact))]
    if np_ > 1:
        cmd = [_mpiexec(), "-n", str(np_), *cmd]
    t0 = time.perf_counter()
    cp = subprocess.run(cmd, env=_env(), capture_output=True, text=True, timeout=1200)
    dt = time.perf_counter() - t0
    if cp.returncode not in (0, 1):  # 1 = a tolerance violated at a non-default size: still comparable
        raise RuntimeError(f"{' '.join(cmd)} failed (exit {cp.returncode}): {cp.stderr.strip()[-500:]}")
    m = json.loads((out / cfg.case / "metrics.json").read_text())
    pt = max(m["patches"], key=lambda p: p["P"])
    return {
        "np": np_,
        "process_s": dt,
        "solve_s": m["wall_time_s"],
        "ndofs": m["ndofs"],
        "P": m["P"],
        "p0": pt["p_max"],
        "half_width": pt["half_width"],
        "rms": m["errors"]["rms"],
        "newton_iterations": m["newton_iterations"],
    }


def mpi_check(cfg: BenchConfig, *, progress) -> dict:
    """Section 4: serial against ``mpiexec -n 2`` through the CLI (warm: a serial warm-up run first).

    Every CLI run of one size writes to the same temporary output folder, so they share its mesh cache (the
    warm-up builds the mesh); each run's metrics are read right after it.
    """
    rows = []
    with tempfile.TemporaryDirectory(prefix="bench_mpi_") as tmp:
        out = Path(tmp) / "cli"
        for level in cfg.mpi_levels:
            _cli_metrics(out, cfg, np_=1, h_contact=level)  # mesh cache and JIT
            _cli_metrics(out, cfg, np_=2, h_contact=level)  # JIT of the parallel run (same forms)
            s = _cli_metrics(out, cfg, np_=1, h_contact=level)
            p = _cli_metrics(out, cfg, np_=2, h_contact=level)
            diff = {k: rel_diff(s[k], p[k]) for k in ("P", "p0", "half_width")}
            row = {
                "h_over_a": level,
                "serial": s,
                "np2": p,
                "rel_diff": diff,
                "reproduces_1e-8": all(v <= 1e-8 for v in diff.values()),
                "speedup_solve": s["solve_s"] / p["solve_s"],
                "speedup_process": s["process_s"] / p["process_s"],
            }
            rows.append(row)
            progress(
                f"mpi h_c={level}: ndofs {s['ndofs']}, max rel diff {max(diff.values()):.1e}, speed-up "
                f"solver {row['speedup_solve']:.2f}, process {row['speedup_process']:.2f}"
            )
    return {"rows": rows}


def cold_warm(cfg: BenchConfig, *, progress) -> dict:
    """Section 5a: fresh FFCx cache (XDG_CACHE_HOME) and mesh cache, then the same caches again; then the
    whole CLI with warm caches (a warm-up run of the CLI first fills its output folder's mesh cache)."""
    with tempfile.TemporaryDirectory(prefix="bench_cold_") as tmp:
        env = {"XDG_CACHE_HOME": str(Path(tmp) / "xdg")}
        fresh = replace(cfg, mesh_cache=Path(tmp) / "mesh_cache")
        cold = _subprocess_json(["--worker", "cold"], fresh, env=env, cwd=Path(tmp))
        disk_warm = _subprocess_json(["--worker", "cold"], fresh, env=env, cwd=Path(tmp))
    with tempfile.TemporaryDirectory(prefix="bench_cli_") as tmp:
        cmd = _workbench("run", cfg.case, "--out", str(Path(tmp) / "cli"))
        subprocess.run(cmd, env=_env(), capture_output=True, text=True, timeout=600)  # warm-up: mesh cache
        t0 = time.perf_counter()
        cp = subprocess.run(cmd, env=_env(), capture_output=True, text=True, timeout=600)
        cli_s = time.perf_counter() - t0
    out = {"cold_process": cold, "disk_warm_process": disk_warm, "cli_warm_process_s": cli_s, "cli_exit": cp.returncode}
    progress(
        f"cold: process {cold['process_s']:.1f} s (first run {cold['first_total_s']:.2f} s, mesh "
        f"{cold['mesh_s']:.2f} s); disk-warm process {disk_warm['process_s']:.1f} s (first run "
        f"{disk_warm['first_total_s']:.2f} s); in-process warm {disk_warm['warm_total_s']:.3f} s; "
        f"CLI warm {cli_s:.2f} s"
    )
    return out


def solver_variants(cfg: BenchConfig, *, comm, progress) -> dict:
    """Section 5b: warm solver time and factorisation counts per option set (one graded size,
    ``cfg.option_level``).

    PETSc options go through the wiring's ``petsc_options`` override (the SNES/KSP of the Newton solve; the
    Hertz predictor's own MUMPS solve keeps its defaults).
    """
    from petsc4py import PETSc

    level, repeats = cfg.option_level, cfg.repeats
    PETSc.Log.begin()
    run = _case_run(cfg, level)
    md = _block_mesh_data(run, cfg, comm=comm)
    _solve_case(run, md)  # warm-up: forms loaded once (the options do not change the forms)
    lin = linear_solve(md, run, repeats=repeats)
    rows = []
    for label, (opts, over) in cfg.solver_variants.items():
        before = _log_counts()
        res = _solve_case(run, md, petsc_options=opts, **over)
        events = _log_delta(before, _log_counts())
        times = [res.wall_time_s]
        while len(times) < repeats and sum(times) < 5.0:
            times.append(_solve_case(run, md, petsc_options=opts, **over).wall_time_s)
        row = {
            "variant": label,
            "options": opts,
            "overrides": over,
            "ndofs": res.ndofs,
            "solve_s": min(times),
            "linear_solves_equivalent": min(times) / lin["linear_s"],
            "newton_iterations": list(res.newton_iterations),
            "rms": _hertz_errors(res, run)["rms"],
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
        run, md = _family_mesh(family, level, cfg, comm=comm)
        _solve_case(run, md)  # warm-up
        row: dict[str, Any] = {"family": family, "h_over_a": level}
        for key, opts in (("case", {}), ("reuse", cfg.reuse_lu)):
            before = _log_counts()
            try:
                res = _solve_case(run, md, petsc_options=opts)
            except Exception as exc:  # noqa: BLE001  (a failed variant is a result, not a crash)
                row[key] = {"failed": str(exc).splitlines()[0]}
                continue
            ev = _log_delta(before, _log_counts())
            row["ndofs"] = res.ndofs
            row[key] = {
                "solve_s": res.wall_time_s,
                "P": res.P,
                "newton_iterations": list(res.newton_iterations),
                "lu_numeric": ev["MatLUFactorNum"]["count"],
                "triangular_solves": ev["MatSolve"]["count"],
                "rms": _hertz_errors(res, run)["rms"],
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
        row = contact_vs_linear(_case_run(cfg), cfg, comm=comm)
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
    p.add_argument("--repeats", type=int, default=_DEFAULT.repeats, help="warm repetitions per timing (best kept)")
    p.add_argument("--quick", action="store_true", help="small sizes only (development)")
    p.add_argument("--sections", nargs="+", default=list(BENCH_SECTIONS), help="sections (default: %(default)s)")
    p.add_argument("--out", type=Path, default=None, help="output folder (default: <results>/bench)")
    p.add_argument("--mesh-cache", type=Path, default=None, help="mesh cache (default: <results>/mesh_cache)")
    p.add_argument("--active-set-update", default=_DEFAULT.predictor_free_active_set_update,
                   help="active_set_update of the predictor-free section (default: %(default)s)")
    p.add_argument("--worker", choices=("scale", "cold"), help=argparse.SUPPRESS)
    p.add_argument("--worker-config", default=None, help=argparse.SUPPRESS)
    p.add_argument("--h-contact", type=float, default=None, help=argparse.SUPPRESS)
    p.add_argument("--family", choices=SCALE_FAMILIES, default="graded", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.worker:
        cfg = from_json(BenchConfig, json.loads(args.worker_config) if args.worker_config else None, strict=True)
        data = _worker_scale(cfg, args.family, args.h_contact) if args.worker == "scale" else _worker_cold(cfg)
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
