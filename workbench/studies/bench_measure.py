"""How the benchmark measures (:mod:`workbench.studies.bench`): warm timing (best of repeats), PETSc log
events, peak memory, the case run and one run of ours through the case pipeline, the benchmark's own uniform box
(the tutorial baseline's mesh), one linear elastic solve on a mesh, and the subprocesses a section runs. Times in
s, memory in MB.
"""

from __future__ import annotations

import itertools
import json
import math
import os
import resource
import shutil
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from workbench.studies.bench_config import BenchConfig
from workbench.studies.bench_log_events import LOG_EVENTS
from workbench.studies.config import to_json

__all__ = ["DEFAULT", "LOG_EVENTS", "best_of", "block_mesh_data", "case_P", "case_run", "configure", "count_dofs",
           "family_mesh", "first_reaching", "hertz_errors", "linear_solve", "log_counts", "log_delta", "maxrss_mb",
           "mpiexec", "ours_once", "peak_rss_mb", "rel_diff", "scale_overrides", "solve_case", "solve_on",
           "subprocess_env", "subprocess_json", "timed", "uniform_box_mesh", "workbench_cmd"]


DEFAULT = BenchConfig()
CHECKOUT = Path(__file__).resolve().parents[2]  # the subprocesses import this same checkout
_ids = itertools.count()


def first_reaching(rows: Sequence[dict], *, key: str = "rms", target: float = DEFAULT.rms_target) -> dict | None:
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


def best_of(fn: Callable[[], Any], *, repeats: int, budget_s: float) -> tuple[float, Any]:
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


def log_counts() -> dict[str, dict]:
    """Cumulative PETSc log counts and times of :data:`LOG_EVENTS` (PETSc.Log.begin() must be on)."""
    from petsc4py import PETSc

    return {n: PETSc.Log.Event(n).getPerfInfo() for n in LOG_EVENTS}


def log_delta(before: dict, after: dict) -> dict[str, dict]:
    return {
        n: {"count": int(after[n]["count"] - before[n]["count"]), "time_s": float(after[n]["time"] - before[n]["time"])}
        for n in LOG_EVENTS
    }


def maxrss_mb() -> float:
    """``ru_maxrss`` of this process (MB; Linux reports KiB). Inherited across fork/exec on Linux."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def peak_rss_mb() -> float:
    """Peak resident memory of this process image (MB): VmHWM of /proc/self/status (new at exec, so a
    subprocess does not inherit its parent's peak); ``ru_maxrss`` where /proc is missing."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return float(line.split()[1]) / 1024.0
    except OSError:
        pass
    return maxrss_mb()



def case_run(cfg: BenchConfig, h_contact: float | None = None):
    import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
    from cases import load_case

    return load_case(cfg.case).runs(h_contact=h_contact)[0]


def configure(run, *, method: str, degree: int):
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


def hertz_errors(result, run) -> dict:
    """Errors of a result against Hertz at the measured load, exactly as the case runner computes them."""
    from workbench.scenes.block import compare_result

    return compare_result(result, run).errors


def solve_on(run, mesh_data, theory, *, case: str, **overrides):
    """Solve a block run on a given mesh through the case pipeline (:func:`workbench.studies.scene_point.run_on_mesh`:
    its scene's obstacle, force control to ``theory.P``, ``run_one`` with the ``overrides``); the ContactResult."""
    from workbench.studies.scene_point import run_on_mesh

    return run_on_mesh(run, mesh_data, theory, case=case, **overrides).result


def ours_once(run, cfg: BenchConfig, *, comm) -> dict:
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




def timed(fn: Callable[[], dict], *, repeats: int, budget_s: float) -> dict:
    """Warm timing of a row function: best total and best solver time over the repeats."""
    rows = []

    def once():
        rows.append(fn())
        return rows[-1]

    best_of(once, repeats=repeats, budget_s=budget_s)
    row = dict(rows[-1])
    row["total_s"] = min(r["total_s"] for r in rows)
    row["solve_s"] = min(r["solve_s"] for r in rows)
    row["repeats"] = len(rows)
    row["rms_spread"] = max(rel_diff(r["rms"], rows[0]["rms"]) for r in rows)
    return row




def block_mesh_data(run, cfg: BenchConfig, *, comm):
    """The cached graded mesh of a block run: its registered scene's mesh (as run_one builds it)."""
    from workbench.mesh_io import read_mesh
    from workbench.scenes import scene_for

    files = scene_for(run).mesh(run, name=f"bench_{cfg.case}", mesh_cache=cfg.cache_dir, comm=comm).files
    return read_mesh(files.msh, comm)


def block_space(mesh_data, run):
    """(V, bcs) of the bench's block: the run's vector P_k space on ``mesh_data`` and its supports (clamped base,
    roller symmetry edge: u_x = 0), as the case solves it."""
    import dolfinx

    V = dolfinx.fem.functionspace(mesh_data.mesh, ("Lagrange", run.discretisation.degree, (2,)))
    bcs = []
    for name, comps in (("clamped", (0, 1)), ("symmetry", (0,))):
        facets = mesh_data.facet_tags.find(mesh_data.physical_groups[name].tag)
        for c in comps:
            Vc, _ = V.sub(c).collapse()
            dofs = dolfinx.fem.locate_dofs_topological((V.sub(c), Vc), 1, facets)
            bcs.append(dolfinx.fem.dirichletbc(dolfinx.fem.Function(Vc), dofs, V.sub(c)))
    return V, bcs


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
    V, bcs = block_space(mesh_data, run)
    hz = hertz(
        run.loading.P if run.loading.P else case_P(run),
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
    best, pb = best_of(fresh, repeats=repeats, budget_s=5.0)
    again, _ = best_of(pb.solve, repeats=1, budget_s=0.0)
    return {"ndofs": ndofs, "linear_s": best, "linear_resolve_s": again}


def case_P(run) -> float:
    from workbench.scenes.block_theory import block_theory

    return block_theory(run.geometry, run.material, P=run.loading.P, half_width=run.loading.half_width).P




def solve_case(run, mesh_data, *, petsc_options: dict | None = None, **overrides):
    """The run's case settings on ``mesh_data`` (force control to its classical load) through the wiring."""
    from workbench.scenes.block_theory import block_theory

    th = block_theory(run.geometry, run.material, P=run.loading.P, half_width=run.loading.half_width)
    return solve_on(run, mesh_data, th, case="bench", petsc_options=petsc_options, **overrides)


def family_mesh(family: str, level: float, cfg: BenchConfig, *, comm):
    """(run, mesh_data) of one size: ``graded`` = meshes.block at h_c = level a (the case's W = H = 40 a);
    ``uniform`` = :func:`uniform_box_mesh` W = H = scale_box a at h = level a (the case run at its h_c)."""
    if family == "graded":
        run = case_run(cfg, level)
        return run, block_mesh_data(run, cfg, comm=comm)
    run = case_run(cfg)
    a0 = run.loading.half_width
    return run, uniform_box_mesh(width=cfg.scale_box * a0, height=cfg.scale_box * a0, h=level * a0, comm=comm)


def count_dofs(md, run) -> int:
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




def malloc_env(cfg: BenchConfig) -> dict:
    """The environment a cost-growth or techniques worker adds: glibc's malloc tunables ``cfg.worker_malloc`` (empty:
    none; an already set ``GLIBC_TUNABLES`` wins)."""
    if not cfg.worker_malloc or "GLIBC_TUNABLES" in os.environ:
        return {}
    return {"GLIBC_TUNABLES": cfg.worker_malloc}


def subprocess_env(extra: dict | None = None) -> dict:
    """The environment of a subprocess: this checkout first on PYTHONPATH (it imports this same code)."""
    e = dict(os.environ)
    e["PYTHONPATH"] = str(CHECKOUT) + os.pathsep + e.get("PYTHONPATH", "")
    e.update(extra or {})
    return e


def workbench_cmd(*args: str) -> list[str]:
    """The command line of ``workbench ARGS`` in this interpreter (``python -m workbench``)."""
    return [sys.executable, "-m", "workbench", *args]


def mpiexec() -> str:
    """``mpiexec`` beside this interpreter (the venv's MPI), else the one on PATH."""
    local = Path(sys.executable).parent / "mpiexec"
    return str(local) if local.exists() else (shutil.which("mpiexec") or "mpiexec")


def subprocess_json(args: list[str], cfg: BenchConfig, *, env: dict | None = None, cwd: Path | None = None,
                     timeout: float = 1200.0) -> dict:
    """Run ``workbench bench --worker ...`` with ``cfg`` and parse its ``BENCH_JSON`` line; adds ``process_s``."""
    cmd = workbench_cmd("bench", "--worker-config", json.dumps(to_json(cfg)), *args)
    t0 = time.perf_counter()
    cp = subprocess.run(cmd, env=subprocess_env(env), cwd=None if cwd is None else str(cwd), capture_output=True,
                        text=True, timeout=timeout)
    dt = time.perf_counter() - t0
    if cp.returncode != 0:
        raise RuntimeError(f"bench worker {args} failed (exit {cp.returncode}): {cp.stderr.strip()[-500:]}")
    for line in cp.stdout.splitlines():
        if line.startswith("BENCH_JSON "):
            return {**json.loads(line[len("BENCH_JSON ") :]), "process_s": dt}
    raise RuntimeError(f"bench worker {args} printed no BENCH_JSON line")
