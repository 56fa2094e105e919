"""Block scene: an elastic block under a rigid circle, parabola or wedge, compared with half-plane theory.

Reads top to bottom: classical estimate -> mesh sized from it -> rigid obstacle -> force-controlled FEM
-> comparison at the measured load. Units: mm, N, MPa.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import NamedTuple

import numpy as np

from cases.schema import Run
from scripts.compare import BlockTheory, block_theory, compare_block
from scripts.outcome import Outcome, Series, step_printer

__all__ = ["BlockComparison", "block_mesh", "compare_result", "obstacle_for", "run_block"]

MESH_CACHE = Path("results/mesh_cache")


def obstacle_for(run: Run, theory: BlockTheory):
    """The rigid obstacle of a block run (an analytic curve, never a mesh)."""
    from fem.obstacles import CircleObstacle, ParabolaObstacle, WedgeObstacle

    g = run.geometry
    if g.indenter == "circle":
        return CircleObstacle(center=(0.0, g.radius), radius=g.radius)
    if g.indenter == "parabola":
        return ParabolaObstacle(radius=g.radius)
    return WedgeObstacle(slope=theory.m)


class BlockComparison(NamedTuple):
    """A block result against its classical theory at the measured load (samples mirrored to the full body)."""

    x: np.ndarray
    p: np.ndarray
    sigma_nn: np.ndarray
    half_width: float
    p_max: float
    theory: BlockTheory
    errors: dict


def compare_result(result, run: Run) -> BlockComparison:
    """Compare a :class:`fem.solver.ContactResult` of a block run with half-plane theory at its measured load.

    A half model's samples (x >= 0) are mirrored to the full body; the main patch is the one carrying the
    largest load.
    """
    smp = result.samples
    x, p, snn = smp.s, smp.p, smp.sigma_nn
    if result.half:  # mirror the half model (x >= 0) to the full body for plots and errors
        keep = x > 0
        x = np.concatenate([-x[keep][::-1], x])
        p = np.concatenate([p[keep][::-1], p])
        snn = np.concatenate([snn[keep][::-1], snn])
    main = max(result.patches, key=lambda pt: pt.P) if result.patches else None
    half_width = main.half_width if main else math.nan
    p_max = main.p_max if main else math.nan
    theory, errors = compare_block(x=x, p=p, P=result.P, P_pressure=result.P_pressure,
                                   half_width_fem=half_width, p_max_fem=p_max, geometry=run.geometry,
                                   material=run.material)
    return BlockComparison(x, p, snn, half_width, p_max, theory, errors)


def block_mesh(run: Run, *, name: str, comm, stats_dir: Path | None = None):
    """The (cached) mesh of a block run, sized from the classical estimate of its contact half-width.

    Returns:
        ``(MeshFiles, BlockTheory)``: the mesh files and the classical prediction at the target load.
    """
    from meshes.block import build_block_mesh

    g, ld, disc = run.geometry, run.loading, run.discretisation
    target = block_theory(g, run.material, P=ld.P, half_width=ld.half_width)
    a0 = target.half_width
    files = build_block_mesh(
        width=g.width_factor * a0, height=g.height_factor * a0, contact_half_width=a0,
        h_contact=disc.h_contact * a0, growth=disc.growth, half_model=g.half_model,
        apex_refinement=g.indenter == "wedge",
        out_dir=MESH_CACHE, name=f"{name}_{run.label}".replace("/", "_").replace("=", "_"),
        stats_dir=stats_dir, comm=comm,
    )
    return files, target


def run_block(run: Run, *, name: str, stage: Path | None, comm, progress) -> Outcome:
    """Run one block scene and compare it with its classical prediction.

    Args:
        run: The run record (case with one variant applied).
        name: Case name (for mesh file names and error messages).
        stage: Staging folder of the case results (rank 0), or None on other ranks.
        comm: MPI communicator.
        progress: ``progress(str)`` for one-line status output.
    """
    from fem.solver import solve_contact
    from scripts.mesh_io import read_mesh

    g, ld, disc, sol = run.geometry, run.loading, run.discretisation, run.solver
    files, target = block_mesh(run, name=name, comm=comm)
    a0 = target.half_width
    progress(f"[{run.label}] mesh {files.stats.get('cells', '?')} cells ({'cached' if files.cached else 'built'}), "
             f"a0 = {a0:.4g} mm, P target = {target.P:.6g} N/mm")
    mesh_data = read_mesh(files.msh, comm)

    result = solve_contact(
        mesh_data, obstacle_for(run, target), E=run.material.E, nu=run.material.nu, degree=disc.degree,
        method=sol.method, kinematics=sol.kinematics, traction=sol.traction, kappa0=sol.kappa0,
        gamma0=sol.gamma0, theta=sol.theta, control="force", target=target.P, n_steps=ld.steps,
        symmetric_half=g.half_model, on_step=step_printer(progress, run.label), case=f"{name}[{run.label}]",
    )
    for w in result.warnings:
        progress(f"[{run.label}] WARNING: {w}")
    cmp = compare_result(result, run)
    x, p, snn, theory, errors = cmp.x, cmp.p, cmp.sigma_nn, cmp.theory, cmp.errors
    half_width, p_max = cmp.half_width, cmp.p_max
    if sol.kinematics == "convective":
        # The classical theory ignores the convective effect this run measures: its errors are kept for
        # information only (the convective comparison is made at case level, scripts/case_checks.py).
        errors = {(k if k == "load_balance" else f"{k}_vs_classical"): v for k, v in errors.items()}
    metrics = {
        "label": run.label,
        "scene": "block",
        "nu": run.material.nu,
        "method": sol.method,
        "kinematics": sol.kinematics,
        "traction": sol.traction,
        "degree": disc.degree,
        "h_contact": disc.h_contact,
        "ndofs": result.ndofs,
        "wall_time_s": result.wall_time_s,
        "newton_iterations": list(result.newton_iterations),
        "load_steps": result.load_steps,
        "d": result.d,
        "P": result.P,
        "P_pressure": result.P_pressure,
        "patches": [pt._asdict() for pt in result.patches],
        "warnings": list(result.warnings),
        "patch_half_width": half_width,
        "p_max": p_max,
        "mesh": files.stats,
        "analytic": {
            "kind": theory.kind, "P": theory.P, "E_star": theory.E_star, "half_width": theory.half_width,
            "p_ref": theory.p_ref, "R": theory.R, "m": theory.m,
        },
        "errors": errors,
    }
    order = np.argsort(x, kind="stable")
    x, p, snn = x[order], p[order], snn[order]
    predictions = {f"{theory.kind} (at measured P)": theory.pressure(x)}
    lim = 1.6 * max(half_width if math.isfinite(half_width) else 0.0, theory.half_width)
    series = Series(run.label, x, p, snn, predictions, "x (mm, material)", (-lim, lim))
    return Outcome(run.label, metrics, [series], theory, result)
