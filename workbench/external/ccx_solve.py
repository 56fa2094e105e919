"""One benchmark level through CalculiX: the deck of each run, ccx, the load calibration, the result rows.

:func:`solve_run` writes the deck of one run (:func:`workbench.external.inp.inp_deck`) into a folder, runs ``ccx``
there and reads, for every reported step (the end of its hold step), the load the drive carries (the ``.dat``'s
``total force`` of the set ``DRIVE``: ``P = F . direction``, the drive's reaction along its direction, doubled
for a half model; N/mm) and the contact pressure along every pair's slave surface (the ``.frd``,
:func:`workbench.external.frd.chain_pressure`: CPRESS per reference length at the surface's nodes in order along
it, :func:`workbench.external.surface_chain.surface_chain`; positions: the nodes' reference coordinates).

* Displacement control (:attr:`Drive.control` ``"displacement"``): one ccx run, one ``*STEP`` per reported
  displacement (:attr:`Drive.report`, mm).
* Force control (``"force"``): the deck is displacement driven and the reported loads are reached by calibrating
  the approach of every step: ccx runs again while a step's load is more than :data:`LOAD_RTOL` off its target,
  at most :data:`MAX_RUNS` runs. The first approach is the caller's (the previous level's, which lands within a
  fraction of a percent), else ``P / (0.3 E*)`` (the workbench stepper's stiffness guess); the first correction
  is the secant through the origin (``d P_target / P``), later ones the secant through the last two runs.
  Every run's (d, P) and ccx wall time is kept (:attr:`RunResult.calibration`).

:func:`result_rows` turns the runs of a level into the result csv's rows
(:data:`workbench.external.benchmark.RESULT_COLUMNS`: ``x_mm, p_MPa, P_N_per_mm, h_mm, run, step, body``).
Units mm, N/mm, MPa; wall times s.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np

__all__ = ["CcxError", "StepResult", "RunResult", "ccx_executable", "run_ccx", "dat_forces", "solve_run",
           "result_rows", "write_result_csv", "LOAD_RTOL", "MAX_RUNS", "CCX_TIMEOUT_S"]

CCX_TIMEOUT_S = 1800
LOAD_RTOL = 0.005  # relative distance of a step's load from its target that ends the calibration
MAX_RUNS = 5  # ccx runs per run and level at most (the first one and four corrections)


class CcxError(RuntimeError):
    """CalculiX missing or failed (one line)."""


class StepResult(NamedTuple):
    """One reported step of one run: its index in :attr:`Drive.report`, the approach d (mm), the load P (N/mm,
    full body), and per slave surface (``body``) the reference positions X (n, 2) (mm) and pressures p (MPa, per
    reference length) at the surface's nodes in order along it."""

    step: int
    d: float
    P: float
    surfaces: tuple  # ((body, X, p), ...)


class RunResult(NamedTuple):
    """One run of a level: the label its result reports, what CalculiX solved (``model``, in words), the steps, every
    ccx run's ``{"d": [mm per step], "P": [N/mm per step], "wall_time_s": s}`` and the wall time of the scored one."""

    run: str
    model: str
    steps: tuple
    calibration: tuple
    wall_time_s: float


def ccx_executable() -> str:
    """The path of ``ccx``, or CcxError."""
    exe = shutil.which("ccx")
    if exe is None:
        raise CcxError("ccx (CalculiX) is not installed or not on PATH; install it with `make external` "
                       "(Debian package calculix-ccx)")
    return exe


def run_ccx(inp: Path, *, exe: str) -> float:
    """Run ``ccx -i <stem>`` in the deck's folder (one thread; log in ``<stem>.log``); the process wall time (s).
    CcxError if it fails (the first ``*ERROR`` line, else the exit code)."""
    log_path = inp.with_suffix(".log")
    start = time.perf_counter()
    with open(log_path, "w") as log:
        proc = subprocess.run([exe, "-i", inp.stem], cwd=inp.parent, stdout=log, stderr=subprocess.STDOUT,
                              timeout=CCX_TIMEOUT_S, env={"OMP_NUM_THREADS": "1", "PATH": "/usr/bin:/bin"})
    wall = time.perf_counter() - start
    text = log_path.read_text(errors="replace")
    if proc.returncode != 0 or "Job finished" not in text or "*ERROR" in text:
        first = next((ln.strip() for ln in text.splitlines() if "*ERROR" in ln), f"exit code {proc.returncode}")
        raise CcxError(f"ccx failed on {inp}: {first} (see {log_path})")
    return wall


_TOTAL = re.compile(r"total force \(fx,fy,fz\) for set (\S+) and time\s+(\S+)\s*\n\s*\n\s*(\S+)\s+(\S+)\s+(\S+)")


def dat_forces(dat: Path, *, nset: str = "DRIVE") -> list[tuple[float, np.ndarray]]:
    """Every ``total force`` of node set ``nset`` in a CalculiX ``.dat``: (total time, (fx, fy, fz)) in order."""
    text = dat.read_text(errors="replace")
    out = [(float(m.group(2)), np.array([float(m.group(k)) for k in (3, 4, 5)]))
           for m in _TOTAL.finditer(text) if m.group(1).upper() == nset.upper()]
    if not out:
        raise CcxError(f"{dat}: no 'total force' of set {nset} (*NODE PRINT, TOTALS=ONLY) in the .dat")
    return out


def _step_loads(dat: Path, *, drive, steps: list[int]) -> list[float]:
    """The load (N/mm, full body) at the end of each of the deck ``steps``: ``F . direction`` of the drive set's
    reaction, doubled for a half model."""
    forces = dat_forces(dat)
    half = 2.0 if drive.half_model else 1.0
    loads = []
    for k in steps:  # the deck steps that report (inp.report_steps): deck step k ends at total time k
        at = [f for t, f in forces if k - 1.0 + 1e-9 < t <= k + 1e-9]
        if not at:
            raise CcxError(f"{dat}: no total force of the drive at the end of step {k}")
        loads.append(half * float(np.dot(at[-1][:2], drive.direction)))
    return loads


def solve_run(benchmark, model, *, modelled, folder: Path, exe: str, d_guess: list[float] | None = None,
              log=print) -> RunResult:
    """Run ``modelled`` (:class:`workbench.external.inp.Modelled`: a run of ``benchmark`` and its contact type) on
    the 6-node ``model`` in ``folder`` (module docstring); CcxError on failure."""
    from workbench.external.frd import chain_pressure, read_frd
    from workbench.external.inp import first_approach, inp_deck, report_steps
    from workbench.external.surface_chain import surface_chain

    run = modelled.run
    drive = benchmark.drive
    targets = [float(v) for v in drive.report]
    force = drive.control == "force"
    d = list(d_guess) if (force and d_guess) else first_approach(benchmark)
    stem = re.sub(r"[^A-Za-z0-9_.-]", "_", run.label) or "run"
    inp = folder / f"{stem}.inp"
    history = []
    while True:
        inp.write_text(inp_deck(benchmark, model, run=run, d=d, contact=modelled.contact,
                                title=f"{benchmark.case} level {benchmark.level:g} run {run.label} (workbench)"))
        wall = run_ccx(inp, exe=exe)
        loads = _step_loads(inp.with_suffix(".dat"), drive=drive, steps=report_steps(run, len(d)))
        history.append({"d": list(d), "P": loads, "wall_time_s": wall})
        if not force:
            log(f"    {run.label}: P = {', '.join(f'{v:.6g}' for v in loads)} N/mm, ccx {wall:.1f} s")
            break
        off = [P / T - 1.0 for P, T in zip(loads, targets, strict=True)]
        log(f"    {run.label}: d = {', '.join(f'{v:.6g}' for v in d)} mm: P = {', '.join(f'{v:.6g}' for v in loads)} "
            f"N/mm ({', '.join(f'{v:+.2%}' for v in off)} from the target), ccx {wall:.1f} s")
        if all(abs(v) <= LOAD_RTOL for v in off) or len(history) >= MAX_RUNS:
            break
        d = _corrected(history, targets)
    frd = inp.with_suffix(".frd")
    data = read_frd(frd)
    chains = []
    for pair in benchmark.pairs:
        chain = surface_chain(model, pair.slave)
        chains.append((pair.slave_body, chain, model.nodes[chain]))
    steps = []
    for k, (dk, Pk) in enumerate(zip(d, history[-1]["P"], strict=True)):
        surfaces = []
        for body, chain, x in chains:
            p, _stretch = chain_pressure(data, step=report_steps(run, len(d))[k], chain=chain + 1, where=str(frd))
            surfaces.append((body, x, p))
        steps.append(StepResult(k, dk, Pk, tuple(surfaces)))
    return RunResult(modelled.label, modelled.model, tuple(steps), tuple(history), history[-1]["wall_time_s"])


def _corrected(history: list[dict], targets: list[float]) -> list[float]:
    """The next approaches: per step the secant through the origin (one run so far) or through the last two
    runs; a step without load (no contact) doubles its approach."""
    last = history[-1]
    out = []
    for k, T in enumerate(targets):
        d1, P1 = last["d"][k], last["P"][k]
        if not P1 > 0:
            out.append(2.0 * d1)
            continue
        if len(history) == 1:
            out.append(d1 * T / P1)
            continue
        d0, P0 = history[-2]["d"][k], history[-2]["P"][k]
        out.append(d1 + (T - P1) * (d1 - d0) / (P1 - P0) if P1 != P0 and d1 != d0 else d1 * T / P1)
    return out


def result_rows(runs: list[RunResult], *, h: float) -> list[dict]:
    """The rows of a level's result csv (module docstring): every run, step and slave surface; ``y_mm`` (the
    second reference coordinate) on every row when a slave surface is curved (the concave scenes' scorer projects
    (x, y) onto the concave curve), else none."""
    from workbench.external.surface_chain import is_horizontal

    curved = any(not is_horizontal(X) for r in runs for st in r.steps for _b, X, _p in st.surfaces)
    rows = []
    for r in runs:
        for st in r.steps:
            for body, X, p in st.surfaces:
                for (xi, yi), pi in zip(X, p, strict=True):
                    row = {"x_mm": float(xi), "p_MPa": max(float(pi), 0.0), "P_N_per_mm": st.P, "h_mm": h,
                           "run": r.run, "step": st.step, "body": body}
                    rows.append(row | ({"y_mm": float(yi)} if curved else {}))
    return rows


def write_result_csv(path: Path, rows: list[dict]) -> Path:
    """``rows`` as a csv with those columns of :data:`RESULT_COLUMNS` the rows have (in its order; floats as the
    shortest text that reads back to the same double)."""
    from workbench.external.benchmark import RESULT_COLUMNS

    cols = [c for c in RESULT_COLUMNS if rows and c in rows[0]]
    lines = [",".join(cols)]
    for row in rows:
        lines.append(",".join(repr(row[c]) if isinstance(row[c], float) else str(row[c]) for c in cols))
    path.write_text("\n".join(lines) + "\n")
    return path
