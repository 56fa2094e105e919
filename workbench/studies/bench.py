"""Performance benchmark (issue "Performance and scale"): ``python -m workbench.studies.bench`` (``make bench``).

Writes ``results/bench/bench.json`` (every number) and ``results/bench/report.md`` atomically; the plot
(``workbench.studies.bench_plot``) reads the JSON. A benchmark to report, not a timed test: the targets are stated as
met / not met. Scene: ``cases/hertz_cylinder.toml`` (rigid circle R = 10 mm on a steel block, Hertz load of
a = 0.5 mm, half model). Error measure: ``rms = RMS(p - p_H)/p0`` at the measured load
(:func:`workbench.scenes.block_theory.rms_error`); target ``RMS_TARGET = 0.5 %``. Times are wall seconds; "warm" means
the FFCx JIT cache and the mesh cache are filled and the forms were loaded once in the process (the best of
up to ``repeats`` identical runs: the CPU may be shared).

Sections:

1. Time to accuracy. Baseline = the common tutorial set-up: a uniform mesh of right triangles over the whole
   box (half model, W = H = ``box`` a, no grading), P2, penalty with a FIXED stiffness
   ``kappa = BASELINE_KAPPA E / (1 mm)`` (not scaled by E/h), force control from zero to
   ``BASELINE_FORCE_RTOL`` (``predictor="extrapolate"``, no active-set predictor, one full load step,
   ``first_step_fraction=1``; the solver's force corrections: tangent of the last state, else secant).
   Ours = the case (Nitsche or penalty ``kappa0 E/h``, P1 or P2, graded mesh of :mod:`meshes.block`, Hertz
   predictor). Each ladder is run coarse to fine until ``rms <= RMS_TARGET``; the time to accuracy is the
   warm time of the first configuration that reaches it (mesh + solve + comparison; solver only also kept).
2. Contact solve against one linear elastic solve on the same mesh (same LU/MUMPS, assembly included),
   Newton iterations per load step, and the PETSc factorisation counts (PETSc log events).
3. Cost growth: P2, the case's Nitsche solver, on graded meshes of decreasing h_c and on uniform meshes up
   to ~1e6 dofs, one subprocess per size. Peak memory = the high-water mark VmHWM of that process
   (``ru_maxrss`` is inherited from the parent across fork/exec on Linux, so after a big section it only
   shows the parent's peak; both are kept). Fitted exponent of time against ndofs (:func:`fit_exponent`).
4. MPI: ``mpiexec -n 2 workbench run hertz_cylinder`` against the serial run (P, p0, half-width to
   1e-8 relative) and the speed-up (default size and a larger one).
5. Repeated work: cold (fresh FFCx cache via ``XDG_CACHE_HOME`` and a fresh mesh cache, in a subprocess)
   against warm; symbolic against numeric factorisations (PETSc log events); MUMPS ordering, PETSc LU and
   three load steps (:data:`SOLVER_VARIANTS`); reuse of the first LU through GMRES and a lagged
   preconditioner (:data:`REUSE_LU`), all through ``solve_contact(..., petsc_options=...)``.

Internal worker modes (``--worker scale|cold``) run one measurement in a subprocess and print one line
``BENCH_JSON {...}``.
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from workbench.atomic import write_json, write_text

__all__ = [
    "BASELINE_KAPPA",
    "BASELINE_LADDER",
    "ExponentFit",
    "RMS_TARGET",
    "fit_exponent",
    "first_reaching",
    "main",
    "rel_diff",
    "run_bench",
    "uniform_box_mesh",
]

OUT_DIR = Path("results") / "bench"
ROOT = Path(__file__).resolve().parent.parent
CASE = "hertz_cylinder"
RMS_TARGET = 0.005
BASELINE_KAPPA = 1e3  # kappa = 1e3 E / mm (N/mm^3): fixed, not scaled by 1/h
BASELINE_FORCE_RTOL = 1e-3  # force to 0.1 % of the load (ours: the case default 1e-10)
# (W = H in units of a, uniform h in units of a), ordered by ndofs (half model, P2: 41k, 161k, 642k dofs).
# W = H = 20 a is the smallest box whose size error alone stays below the target (graded Nitsche P2 at
# W = H = 5, 10, 20, 40 a: rms 3.7 %, 1.1 %, 0.45 %, 0.23 %); 40 a at h = a/20 would be 2.6M dofs.
BASELINE_LADDER = ((20.0, 0.2), (20.0, 0.1), (20.0, 0.05))
OUR_LEVELS = (0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625, 0.003125, 0.0015625)
# Cost growth, two mesh families (P2, the case's Nitsche solver):
#   graded: meshes.block at h_c / a (ndofs ~ 1/h_c: the grading keeps the fine zone one layer thick);
#   uniform: the baseline's uniform W = H = 20 a half box at h / a (ndofs ~ 1/h^2), up to ~1e6 dofs.
SCALE = {"graded": (0.05, 0.0125, 0.003125, 0.00078125, 0.000390625), "uniform": (0.2, 0.1, 1.0 / 15.0, 0.05, 0.04)}
SCALE_BOX = 20.0
SMALL_NDOFS = 50_000  # below this a size is timed 3 times in its process (best kept)
MPI_LEVELS = (None, 0.00078125)  # None: the case default h_c
OPTION_LEVEL = 0.00078125  # size of the solver-options comparison (graded, ~9e4 dofs)
# Reuse of the LU between Newton solves: GMRES preconditioned by the LU of the FIRST Jacobian, kept for the
# whole run (snes_lag_preconditioner -2: rebuild at the next chance then never; persists across solves).
# The later Jacobians differ from it only in the rows of the contact dofs whose state changed, so GMRES needs
# about as many triangular solves as there are such dofs: a win when the contact zone holds few dofs, a loss
# when it holds thousands (a graded a/1280 mesh did not finish in 3 min: GMRES ran into its iteration cap).
# Section 5c measures it on two small meshes only. (SNES lag 2 with preonly was measured 10x slower: the
# stale LU is then the exact inverse and Newton needs many more iterations; lag -1 is refused from options.)
REUSE_LU = {
    "ksp_type": "gmres",
    "ksp_rtol": 1e-12,
    "ksp_atol": 0.0,
    "ksp_gmres_restart": 300,
    "ksp_max_it": 300,
    "snes_lag_preconditioner": -2,
    "snes_lag_preconditioner_persists": True,
}
REUSE_MESHES = (("uniform", 0.2), ("graded", 0.003125))  # (family, h/a) of section 5c
# label -> (petsc_options, solve_contact overrides)
SOLVER_VARIANTS = {
    "case (MUMPS LU per Newton iteration)": ({}, {}),
    "MUMPS ICNTL(7)=5 (METIS ordering)": ({"mat_mumps_icntl_7": 5}, {}),
    "PETSc LU, nd ordering, reuse_ordering": (
        {"pc_factor_mat_solver_type": "petsc", "pc_factor_mat_ordering_type": "nd", "pc_factor_reuse_ordering": True},
        {},
    ),
    "3 load steps (n_steps=3, the previous case default)": ({}, {"n_steps": 3}),
}
TARGETS = {"speedup_vs_baseline": 10.0, "default_warm_s": 3.0, "linear_solves": 4.0, "exponent": 1.3}
LOG_EVENTS = ("MatLUFactorSym", "MatLUFactorNum", "MatSolve", "SNESJacobianEval", "SNESFunctionEval")
PY = str(ROOT / ".venv" / "bin" / "python")
_ids = itertools.count()
MPIEXEC = str(ROOT / ".venv" / "bin" / "mpiexec")


# ----------------------------------------------------------------------------------------------- helpers


class ExponentFit(NamedTuple):
    """Power law ``t = c ndofs^exponent`` fitted by least squares in log-log.

    Attributes:
        exponent: fitted exponent (1 = linear cost).
        prefactor: c (s).
        n_points: number of sizes fitted.
        max_residual: largest |log t - fit| over the fitted sizes.
    """

    exponent: float
    prefactor: float
    n_points: int
    max_residual: float


def fit_exponent(ndofs: Sequence[float], times: Sequence[float], *, n_last: int | None = None) -> ExponentFit:
    """Fit ``t = c ndofs^k`` over the ``n_last`` largest sizes (all by default).

    Uses :func:`workbench.studies.convergence.fit_rate` (one log-log fit in one place).

    Args:
        ndofs: sizes, strictly increasing, > 0.
        times: times (s), > 0.
        n_last: number of largest sizes fitted, >= 2 (default: all).

    Raises:
        ValueError: fewer than two sizes, non-increasing sizes or a non-positive value.
    """
    from workbench.studies.convergence import fit_rate

    n = np.asarray(ndofs, dtype=float)
    if n.ndim != 1 or n.size < 2:
        raise ValueError(f"ndofs must hold >= 2 sizes, got {n.size}")
    if not np.all(np.diff(n) > 0):
        raise ValueError(f"ndofs must be strictly increasing, got {n.tolist()}")
    f = fit_rate(n, times, n_finest=n.size if n_last is None else n_last)
    return ExponentFit(f.slope, float(math.exp(f.intercept)), f.n_points, f.max_residual)


def first_reaching(rows: Sequence[dict], *, key: str = "rms", target: float = RMS_TARGET) -> dict | None:
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


def _case_run(h_contact: float | None = None):
    from cases import load_case

    return load_case(CASE).runs(h_contact=h_contact)[0]


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


def _baseline_once(run, *, box: float, h: float, comm) -> dict:
    """One baseline solve (see module docstring, section 1); times in s."""
    from fem.solver import solve_contact
    from workbench.scenes.block_theory import block_theory
    from workbench.scenes.block import obstacle_for

    t0 = time.perf_counter()
    target = block_theory(run.geometry, run.material, P=run.loading.P, half_width=run.loading.half_width)
    a0 = target.half_width
    md = uniform_box_mesh(width=box * a0, height=box * a0, h=h * a0, comm=comm)
    t_mesh = time.perf_counter() - t0
    nx, ny = math.ceil(box / 2.0 / h - 1e-9), math.ceil(box / h - 1e-9)
    diam = math.hypot(box * a0 / 2.0 / nx, box * a0 / ny)  # ufl.CellDiameter of every right triangle (mm)
    kappa0 = BASELINE_KAPPA * diam  # kappa0 E / h = BASELINE_KAPPA E / (1 mm)
    res = solve_contact(
        md,
        obstacle_for(run, target),
        E=run.material.E,
        nu=run.material.nu,
        degree=2,
        method="penalty",
        kinematics="small",
        traction=run.solver.traction,
        kappa0=kappa0,
        control="force",
        target=target.P,
        n_steps=1,
        symmetric_half=True,
        predictor="extrapolate",
        active_set_predictor=False,
        first_step_fraction=1.0,
        force_rtol=BASELINE_FORCE_RTOL,
        case="bench-baseline",
    )
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
        "kappa_N_per_mm3": BASELINE_KAPPA * run.material.E,
        **errors,
    }


def _ours_once(run, *, comm) -> dict:
    from workbench.scenes.block import run_block

    t0 = time.perf_counter()
    o = run_block(run, name=f"bench_{CASE}", stage=None, comm=comm, progress=lambda s: None)
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


def time_to_accuracy(*, repeats: int, comm, progress, ladder: Sequence = BASELINE_LADDER) -> dict:
    """Section 1: the baseline ladder and the four configurations of ours, each until rms <= target.

    Besides the time to ``RMS_TARGET``, every baseline row is compared at ITS accuracy: the warm time of the
    first row of each configuration of ours with ``rms <=`` the baseline's rms (``same_accuracy``).
    """
    run = _case_run()
    out: dict[str, Any] = {"target_rms": RMS_TARGET, "baseline": [], "ours": {}}
    # warm the JIT of the baseline forms on a tiny box (the JIT does not depend on the mesh)
    _baseline_once(run, box=10.0, h=0.5, comm=comm)
    for box, h in ladder:
        row = _timed(lambda box=box, h=h: _baseline_once(run, box=box, h=h, comm=comm), repeats=repeats, budget_s=3.0)
        out["baseline"].append(row)
        progress(
            f"baseline W=H={box:g}a h=a*{h:g}: ndofs {row['ndofs']}, warm {row['total_s']:.2f} s "
            f"(solver {row['solve_s']:.2f} s, {len(row['newton_iterations'])} solves, its "
            f"{row['newton_iterations']}), rms {row['rms']:.3e}"
        )
        if row["rms"] <= RMS_TARGET:
            break
    for method in ("nitsche", "penalty"):
        for degree in (1, 2):
            rows = []
            for level in OUR_LEVELS:
                r = _configure(_case_run(level), method=method, degree=degree)
                _ours_once(r, comm=comm)  # warm-up: JIT and mesh cache
                row = _timed(lambda r=r: _ours_once(r, comm=comm), repeats=repeats, budget_s=2.0)
                rows.append(row)
                progress(
                    f"{method} P{degree} h_c=a*{level:g}: ndofs {row['ndofs']}, warm {row['total_s']:.3f} s "
                    f"(solver {row['solve_s']:.3f} s), rms {row['rms']:.3e}"
                )
                if row["rms"] <= RMS_TARGET:
                    break
            out["ours"][f"{method} P{degree}"] = rows
    out["case_steps"] = run.loading.steps
    base = first_reaching(out["baseline"])
    last = out["baseline"][-1]
    summary = {}
    for name, rows in out["ours"].items():
        best = first_reaching(rows)
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


def _block_mesh_data(run, *, comm):
    """The cached graded mesh of a block run: :func:`workbench.scenes.block.block_mesh` (as run_block builds it)."""
    from workbench.mesh_io import read_mesh
    from workbench.scenes.block import block_mesh

    files, _ = block_mesh(run, name=f"bench_{CASE}", comm=comm)
    return read_mesh(files.msh, comm)


def linear_solve(mesh_data, run, *, repeats: int = 3) -> dict:
    """Warm time of one linear elastic solve (assembly of A and b, MUMPS LU, solve) on ``mesh_data``.

    ``linear_s``: a new problem each time (symbolic + numeric factorisation); ``linear_resolve_s``: the same
    problem solved again (PETSc keeps the symbolic factorisation: same nonzero pattern).

    Weak form: ``a(u, v) = -int_Gc p_H v_y ds`` with the Hertz pressure of the case load (MPa), clamped
    bottom, roller symmetry edge; options ``preonly`` / ``lu`` / ``mumps`` as the contact Newton iterations.
    """
    import dolfinx
    import dolfinx.fem.petsc
    import ufl

    from analytic.hertz import hertz, hertz_pressure
    from analytic.materials import plane_strain_modulus
    from fem.elasticity import lame, sigma

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
        pb.solve()
        return pb

    a_form = ufl.inner(sigma(du, lm), ufl.grad(v)) * ufl.dx
    L_form = -p_h * v[1] * ds(mesh_data.physical_groups["contact"].tag)
    opts = {"ksp_type": "preonly", "pc_type": "lu", "pc_factor_mat_solver_type": "mumps"}
    pb = fresh()  # warm-up: forms loaded
    best, pb = _best_of(fresh, repeats=repeats, budget_s=5.0)
    again, _ = _best_of(pb.solve, repeats=1, budget_s=0.0)
    return {"ndofs": V.dofmap.index_map.size_global * 2, "linear_s": best, "linear_resolve_s": again}


def _case_P(run) -> float:
    from workbench.scenes.block_theory import block_theory

    return block_theory(run.geometry, run.material, P=run.loading.P, half_width=run.loading.half_width).P


def contact_vs_linear(run, *, comm, repeats: int) -> dict:
    """Section 2 at one size: warm contact solve, warm linear solve, iterations and LU counts."""
    from petsc4py import PETSc

    PETSc.Log.begin()
    _ours_once(run, comm=comm)  # warm-up
    before = _log_counts()
    row = _timed(lambda: _ours_once(run, comm=comm), repeats=1, budget_s=0.0)
    events = _log_delta(before, _log_counts())
    if repeats > 1:
        row2 = _timed(lambda: _ours_once(run, comm=comm), repeats=repeats - 1, budget_s=3.0)
        row["solve_s"] = min(row["solve_s"], row2["solve_s"])
        row["total_s"] = min(row["total_s"], row2["total_s"])
    lin = linear_solve(_block_mesh_data(run, comm=comm), run, repeats=repeats)
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
    """``fem.solver.solve_contact`` with the run's settings (as workbench.scenes.block) on ``mesh_data``."""
    from fem.solver import solve_contact
    from workbench.scenes.block_theory import block_theory
    from workbench.scenes.block import obstacle_for

    th = block_theory(run.geometry, run.material, P=run.loading.P, half_width=run.loading.half_width)
    s = run.solver
    kw = dict(
        E=run.material.E,
        nu=run.material.nu,
        degree=run.discretisation.degree,
        method=s.method,
        kinematics=s.kinematics,
        traction=s.traction,
        kappa0=s.kappa0,
        gamma0=s.gamma0,
        theta=s.theta,
        control="force",
        target=th.P,
        n_steps=run.loading.steps,
        symmetric_half=run.geometry.half_model,
        petsc_options=petsc_options,
        case="bench",
    )
    kw.update(overrides)
    return solve_contact(mesh_data, obstacle_for(run, th), **kw)


def _family_mesh(family: str, level: float, *, comm):
    """(run, mesh_data) of one size: ``graded`` = meshes.block at h_c = level a (the case's W = H = 40 a);
    ``uniform`` = :func:`uniform_box_mesh` W = H = SCALE_BOX a at h = level a (the case run at its h_c)."""
    if family == "graded":
        run = _case_run(level)
        return run, _block_mesh_data(run, comm=comm)
    run = _case_run()
    a0 = run.loading.half_width
    return run, uniform_box_mesh(width=SCALE_BOX * a0, height=SCALE_BOX * a0, h=level * a0, comm=comm)


def _worker_scale(family: str, level: float) -> dict:
    """One size of section 3, in its own process: mesh, contact solve(s), linear solve, peak memory."""
    import dolfinx_solver  # noqa: F401

    from mpi4py import MPI
    from petsc4py import PETSc

    comm = MPI.COMM_WORLD
    t0 = time.perf_counter()
    run, md = _family_mesh(family, level, comm=comm)
    mesh_s = time.perf_counter() - t0
    PETSc.Log.begin()
    before = _log_counts()
    res = _solve_case(run, md)
    events = _log_delta(before, _log_counts())
    peak_first = _peak_rss_mb()  # mesh + one contact solve (its two MUMPS factors alive)
    times = [res.wall_time_s]
    small = res.ndofs < SMALL_NDOFS
    times += [_solve_case(run, md).wall_time_s for _ in range(2 if small else 1)]  # warm: forms loaded
    lin = linear_solve(md, run, repeats=3 if small else 1)
    its = list(res.newton_iterations)
    return {
        "family": family,
        "h_over_a": level,
        "ndofs": res.ndofs,
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
        "maxrss_mb": _maxrss_mb(),
        "peak_rss_mb": _peak_rss_mb(),
        "peak_rss_first_solve_mb": peak_first,
    }


def _worker_cold() -> dict:
    """Section 5: in this process, the first (cold or disk-warm) run of the case then a warm one."""
    t0 = time.perf_counter()
    import dolfinx_solver  # noqa: F401

    import dolfinx  # noqa: F401
    from mpi4py import MPI

    t_import = time.perf_counter() - t0
    comm = MPI.COMM_WORLD
    run = _case_run()
    t1 = time.perf_counter()
    _block_mesh_data(run, comm=comm)
    t_mesh = time.perf_counter() - t1
    first = _ours_once(run, comm=comm)
    second = _ours_once(run, comm=comm)
    return {
        "import_s": t_import,
        "mesh_s": t_mesh,
        "first_total_s": first["total_s"],
        "first_solve_s": first["solve_s"],
        "warm_total_s": second["total_s"],
        "warm_solve_s": second["solve_s"],
        "rms": second["rms"],
    }


def _subprocess_json(
    args: list[str], *, env: dict | None = None, cwd: Path | None = None, timeout: float = 1200.0
) -> dict:
    """Run ``python -m workbench.studies.bench --worker ...`` and parse its ``BENCH_JSON`` line; adds ``process_s``."""
    e = dict(os.environ)
    e["PYTHONPATH"] = str(ROOT) + os.pathsep + e.get("PYTHONPATH", "")
    e.update(env or {})
    t0 = time.perf_counter()
    cp = subprocess.run(
        [PY, "-m", "workbench.studies.bench", *args], env=e, cwd=str(cwd or ROOT), capture_output=True, text=True, timeout=timeout
    )
    dt = time.perf_counter() - t0
    if cp.returncode != 0:
        raise RuntimeError(f"bench worker {args} failed (exit {cp.returncode}): {cp.stderr.strip()[-500:]}")
    for line in cp.stdout.splitlines():
        if line.startswith("BENCH_JSON "):
            return {**json.loads(line[len("BENCH_JSON ") :]), "process_s": dt}
    raise RuntimeError(f"bench worker {args} printed no BENCH_JSON line")


def cost_growth(*, families: dict[str, Sequence[float]], progress) -> dict:
    """Section 3: one subprocess per size; exponents of warm solver time, linear solve and memory."""
    out = {}
    for family, levels in families.items():
        rows = []
        for level in levels:
            row = _subprocess_json(["--worker", "scale", "--family", family, "--h-contact", repr(float(level))])
            rows.append(row)
            progress(
                f"scale {family} h=a*{level:.4g}: ndofs {row['ndofs']}, solver {row['solve_s']:.2f} s, "
                f"linear {row['linear_s']:.3f} s ({row['linear_solves_equivalent']:.1f} linear solves), "
                f"its {row['newton_iterations']}, peak {row['peak_rss_mb']:.0f} MB"
            )
        n = [r["ndofs"] for r in rows]
        fits = {}
        for key in ("solve_s", "linear_s", "peak_rss_mb", "peak_rss_first_solve_mb"):
            t = [r[key] for r in rows]
            fits[key] = {
                "all": fit_exponent(n, t)._asdict(),
                "largest3": fit_exponent(n, t, n_last=3)._asdict() if len(n) >= 3 else None,
            }
        out[family] = {"rows": rows, "fits": fits}
    return out


def _cli_metrics(out: Path, *, np_: int, h_contact: float | None) -> dict:
    cmd = [PY, "-m", "workbench", "run", CASE, "--out", str(out)]
    if h_contact is not None:
        cmd += ["--h-contact", repr(float(h_contact))]
    if np_ > 1:
        cmd = [MPIEXEC, "-n", str(np_), *cmd]
    t0 = time.perf_counter()
    cp = subprocess.run(cmd, cwd=str(ROOT), capture_output=True, text=True, timeout=1200)
    dt = time.perf_counter() - t0
    if cp.returncode not in (0, 1):  # 1 = a tolerance violated at a non-default size: still comparable
        raise RuntimeError(f"{' '.join(cmd)} failed (exit {cp.returncode}): {cp.stderr.strip()[-500:]}")
    m = json.loads((out / CASE / "metrics.json").read_text())
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


def mpi_check(*, levels: Sequence[float | None], progress) -> dict:
    """Section 4: serial against ``mpiexec -n 2`` through the CLI (warm: a serial warm-up run first)."""
    rows = []
    with tempfile.TemporaryDirectory(prefix="bench_mpi_") as tmp:
        for level in levels:
            _cli_metrics(Path(tmp) / "warm", np_=1, h_contact=level)  # mesh cache and JIT
            _cli_metrics(Path(tmp) / "warm2", np_=2, h_contact=level)  # JIT of the parallel run (same forms)
            s = _cli_metrics(Path(tmp) / "s", np_=1, h_contact=level)
            p = _cli_metrics(Path(tmp) / "p", np_=2, h_contact=level)
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


def cold_warm(*, progress) -> dict:
    """Section 5a: fresh FFCx cache (XDG_CACHE_HOME) and mesh cache (cwd), then the same caches again."""
    with tempfile.TemporaryDirectory(prefix="bench_cold_") as tmp:
        env = {"XDG_CACHE_HOME": str(Path(tmp) / "xdg")}
        cold = _subprocess_json(["--worker", "cold"], env=env, cwd=Path(tmp))
        disk_warm = _subprocess_json(["--worker", "cold"], env=env, cwd=Path(tmp))
    t0 = time.perf_counter()
    cp = subprocess.run(
        [PY, "-m", "workbench", "run", CASE, "--out", str(Path(tempfile.gettempdir()) / "bench_cli")],
        cwd=str(ROOT),
        capture_output=True,
        text=True,
        timeout=600,
    )
    cli_s = time.perf_counter() - t0
    out = {"cold_process": cold, "disk_warm_process": disk_warm, "cli_warm_process_s": cli_s, "cli_exit": cp.returncode}
    progress(
        f"cold: process {cold['process_s']:.1f} s (first run {cold['first_total_s']:.2f} s, mesh "
        f"{cold['mesh_s']:.2f} s); disk-warm process {disk_warm['process_s']:.1f} s (first run "
        f"{disk_warm['first_total_s']:.2f} s); in-process warm {disk_warm['warm_total_s']:.3f} s; "
        f"CLI warm {cli_s:.2f} s"
    )
    return out


def solver_variants(*, level: float, comm, repeats: int, progress) -> dict:
    """Section 5b: warm solver time and factorisation counts per option set (one graded size).

    PETSc options go through ``solve_contact(..., petsc_options=...)`` (the SNES/KSP of the Newton solve; the
    Hertz predictor's own MUMPS solve keeps its defaults).
    """
    from petsc4py import PETSc

    PETSc.Log.begin()
    run = _case_run(level)
    md = _block_mesh_data(run, comm=comm)
    _solve_case(run, md)  # warm-up: forms loaded once (the options do not change the forms)
    lin = linear_solve(md, run, repeats=repeats)
    rows = []
    for label, (opts, over) in SOLVER_VARIANTS.items():
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


def lu_reuse(*, comm, progress) -> dict:
    """Section 5c: the case solver against :data:`REUSE_LU` (GMRES + LU of the first Jacobian) per mesh."""
    from petsc4py import PETSc

    PETSc.Log.begin()
    rows = []
    for family, level in REUSE_MESHES:
        run, md = _family_mesh(family, level, comm=comm)
        _solve_case(run, md)  # warm-up
        row: dict[str, Any] = {"family": family, "h_over_a": level}
        for key, opts in (("case", {}), ("reuse", REUSE_LU)):
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
    return {"options": REUSE_LU, "rows": rows}


# ------------------------------------------------------------------------------------------ the study


def run_bench(
    *,
    repeats: int = 3,
    scale: dict[str, Sequence[float]] | None = None,
    mpi_levels: Sequence[float | None] = MPI_LEVELS,
    option_level: float = OPTION_LEVEL,
    ladder: Sequence = BASELINE_LADDER,
    sections: Sequence[str] = ("accuracy", "linear", "scale", "mpi", "cache", "options"),
    progress: Callable[[str], None] = print,
) -> dict:
    """Run the benchmark sections and return the JSON-ready data (no files written).

    Args:
        repeats: warm repetitions per timing (best kept), >= 1.
        scale: family (graded, uniform) -> h / a of the cost-growth sizes, strictly decreasing, in (0, 1]
            (default :data:`SCALE`).
        mpi_levels: h_c / a of the MPI comparisons (None: the case default).
        option_level: h_c / a of the PETSc-options comparison.
        ladder: baseline (box/a, h/a) rungs, cheapest first.
        sections: subset of accuracy, linear, scale, mpi, cache, options.
        progress: one-line status output.
    """
    import dolfinx_solver  # noqa: F401

    from mpi4py import MPI

    if int(repeats) != repeats or repeats < 1:
        raise ValueError(f"repeats must be an integer >= 1, got {repeats!r}")
    scale = SCALE if scale is None else scale
    for family, levels in scale.items():
        if family not in SCALE:
            raise ValueError(f"scale family must be one of {sorted(SCALE)}, got {family!r}")
        if any(not 0 < v <= 1 for v in levels) or np.any(np.diff(levels) >= 0):
            raise ValueError(f"scale[{family!r}] must be strictly decreasing values in (0, 1], got {list(levels)}")
    known = {"accuracy", "linear", "scale", "mpi", "cache", "options"}
    if not set(sections) <= known:
        raise ValueError(f"sections must be a subset of {sorted(known)}, got {list(sections)}")
    comm = MPI.COMM_WORLD
    t0 = time.perf_counter()
    out: dict[str, Any] = {
        "case": CASE,
        "rms_target": RMS_TARGET,
        "targets": TARGETS,
        "repeats": repeats,
        "baseline": {
            "kappa": f"{BASELINE_KAPPA:g} E / mm",
            "ladder": BASELINE_LADDER,
            "force_rtol": BASELINE_FORCE_RTOL,
        },
        "cpu_count": os.cpu_count(),
        "load_avg_start": os.getloadavg(),
    }
    if "accuracy" in sections:
        out["accuracy"] = time_to_accuracy(repeats=repeats, comm=comm, progress=progress, ladder=ladder)
    if "linear" in sections:
        row = contact_vs_linear(_case_run(), comm=comm, repeats=repeats)
        out["linear"] = row
        progress(
            f"default: solver {row['solve_s']:.3f} s = {row['linear_solves_equivalent']:.1f} linear solves "
            f"({row['linear_s']:.4f} s); Newton its {row['newton_iterations']}"
        )
    if "scale" in sections:
        out["scale"] = cost_growth(families=scale, progress=progress)
    if "mpi" in sections:
        out["mpi"] = mpi_check(levels=mpi_levels, progress=progress)
    if "cache" in sections:
        out["cache"] = cold_warm(progress=progress)
    if "options" in sections:
        out["options"] = solver_variants(level=option_level, comm=comm, repeats=repeats, progress=progress)
        out["lu_reuse"] = lu_reuse(comm=comm, progress=progress)
    out["load_avg_end"] = os.getloadavg()
    out["bench_wall_time_s"] = time.perf_counter() - t0
    return out


# --------------------------------------------------------------------------------------------- CLI


def main(argv: list[str] | None = None) -> int:
    """``python -m workbench.studies.bench [--repeats N] [--quick] [--sections ...]``; writes results/bench/."""
    p = argparse.ArgumentParser(
        prog="python -m workbench.studies.bench", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument("--repeats", type=int, default=3, help="warm repetitions per timing (best kept)")
    p.add_argument("--quick", action="store_true", help="small sizes only (development)")
    p.add_argument("--sections", nargs="+", default=["accuracy", "linear", "scale", "mpi", "cache", "options"])
    p.add_argument("--out", type=Path, default=OUT_DIR)
    p.add_argument("--worker", choices=("scale", "cold"), help=argparse.SUPPRESS)
    p.add_argument("--h-contact", type=float, default=None, help=argparse.SUPPRESS)
    p.add_argument("--family", choices=tuple(SCALE), default="graded", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.worker == "scale":
        print("BENCH_JSON " + json.dumps(_worker_scale(args.family, args.h_contact), default=float), flush=True)
        return 0
    if args.worker == "cold":
        print("BENCH_JSON " + json.dumps(_worker_cold(), default=float), flush=True)
        return 0
    kw: dict[str, Any] = {}
    if args.quick:
        kw = {
            "scale": {"graded": SCALE["graded"][:3], "uniform": (0.4, 0.2)},
            "mpi_levels": (None,),
            "option_level": 0.0125,
            "ladder": BASELINE_LADDER[:1],
        }
    try:
        data = run_bench(
            repeats=args.repeats, sections=args.sections, progress=lambda s: print(f"[bench] {s}", flush=True), **kw
        )
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    from workbench.studies.bench_report import to_markdown

    write_json(args.out / "bench.json", data)
    write_text(args.out / "report.md", to_markdown(data))
    try:
        from workbench.studies.bench_plot import plot_bench

        plot_bench(data, args.out)
    except ImportError:
        pass
    print(f"[bench] wrote {args.out / 'report.md'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
