"""Sections 4 and 5a of the benchmark (:mod:`workbench.studies.bench`): whole processes: serial against
``mpiexec -n 2`` through the command line, and cold against warm caches (:func:`worker_cold` runs in a subprocess).
"""

from __future__ import annotations

import json
import subprocess
import tempfile
import time
from dataclasses import replace
from pathlib import Path

from workbench.studies.bench_config import BenchConfig
from workbench.studies.bench_measure import (
    block_mesh_data,
    case_run,
    mpiexec,
    ours_once,
    rel_diff,
    subprocess_env,
    subprocess_json,
    workbench_cmd,
)

__all__ = ["cold_warm", "mpi_check", "worker_cold"]


def worker_cold(cfg: BenchConfig) -> dict:
    """Section 5: in this process, the first (cold or disk-warm) run of the case then a warm one."""
    t0 = time.perf_counter()
    import dolfinx_solver  # noqa: F401

    import dolfinx  # noqa: F401
    from mpi4py import MPI

    t_import = time.perf_counter() - t0
    comm = MPI.COMM_WORLD
    run = case_run(cfg)
    t1 = time.perf_counter()
    block_mesh_data(run, cfg, comm=comm)
    t_mesh = time.perf_counter() - t1
    first = ours_once(run, cfg, comm=comm)
    second = ours_once(run, cfg, comm=comm)
    return {
        "import_s": t_import,
        "mesh_s": t_mesh,
        "first_total_s": first["total_s"],
        "first_solve_s": first["solve_s"],
        "warm_total_s": second["total_s"],
        "warm_solve_s": second["solve_s"],
        "rms": second["rms"],
    }




def _cli_metrics(out: Path, cfg: BenchConfig, *, np_: int, h_contact: float | None) -> dict:
    """``workbench run <case> --out out`` (under ``mpiexec -n np_`` when np_ > 1); the case's metrics."""
    cmd = workbench_cmd("run", cfg.case, "--out", str(out))
    if h_contact is not None:
        cmd += ["--h-contact", repr(float(h_contact))]
    if np_ > 1:
        cmd = [mpiexec(), "-n", str(np_), *cmd]
    t0 = time.perf_counter()
    cp = subprocess.run(cmd, env=subprocess_env(), capture_output=True, text=True, timeout=1200)
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
        cold = subprocess_json(["--worker", "cold"], fresh, env=env, cwd=Path(tmp))
        disk_warm = subprocess_json(["--worker", "cold"], fresh, env=env, cwd=Path(tmp))
    with tempfile.TemporaryDirectory(prefix="bench_cli_") as tmp:
        cmd = workbench_cmd("run", cfg.case, "--out", str(Path(tmp) / "cli"))
        subprocess.run(cmd, env=subprocess_env(), capture_output=True, text=True, timeout=600)  # warm-up: mesh cache
        t0 = time.perf_counter()
        cp = subprocess.run(cmd, env=subprocess_env(), capture_output=True, text=True, timeout=600)
        cli_s = time.perf_counter() - t0
    out = {"cold_process": cold, "disk_warm_process": disk_warm, "cli_warm_process_s": cli_s, "cli_exit": cp.returncode}
    progress(
        f"cold: process {cold['process_s']:.1f} s (first run {cold['first_total_s']:.2f} s, mesh "
        f"{cold['mesh_s']:.2f} s); disk-warm process {disk_warm['process_s']:.1f} s (first run "
        f"{disk_warm['first_total_s']:.2f} s); in-process warm {disk_warm['warm_total_s']:.3f} s; "
        f"CLI warm {cli_s:.2f} s"
    )
    return out
