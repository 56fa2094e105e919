"""Bench section ``startup`` (issue 27, point 5): one CI-level case as a whole process against its mesh and solve.

What is timed (wall seconds, warm: the FFCx JIT cache and the mesh cache filled by a warm-up process first):

* ``process``: ``python -m workbench run <case> --ci --out <tmp>`` as a subprocess, start to exit, in two modes:
  ``full`` (the default: pressure plot and pyvista renders) and ``no_pictures`` (``--no-pictures``, the fast path
  for scripts). The modes alternate, ``repeats`` times each, so a change in the machine's load hits both.
* ``case_s``: the case's own ``wall_time_s`` that each of those processes wrote in its ``metrics.json`` (mesh from
  the cache, forms loaded from the disk cache, solve, comparison, VTK): the first run in a fresh process.
* ``mesh_solve_s``: the same CI-level run through :func:`workbench.pipeline.run_case.run_one` in this process,
  forms already loaded (mesh from the cache, solve, comparison; best of ``repeats`` after one warm-up call).
* ``import_floor_s``: ``python -c "import <the solve path's third-party packages>; os._exit(0)"``
  (:data:`FLOOR_IMPORTS`; no teardown, as ``workbench run`` ends: :mod:`workbench.fast_exit`): the interpreter and
  the libraries every run of the case needs, whatever the workbench does; no process that solves the case can be
  faster than this plus its case time.

* ``changed_material``: a copy of the case with every Young's modulus times :data:`CHANGED_E_FACTOR` and its name
  changed (:func:`changed_material_case`), as a whole ``--no-pictures`` process alternating with the original's:
  every number a case varies is a dolfinx Constant in the forms (:mod:`fem.coefficients`), so the copy compiles
  no new FFCx module (``new_modules``: files the copy's first process added to the JIT cache) and runs within
  :data:`CHANGED_TARGET` x the original's warm process time (issue 34: 14.4 s against 4.0 s before).

Ratios: ``process_s / case_s`` of each process (both measured in that process's own run, so a load that slows
the machine slows both: the issue's "5.6 s for a 0.8 s case"), median over the repeats, against the issue's
target :data:`TARGET_RATIO` (2); and, stricter, the best process against the best warm in-process
``mesh_solve_s``. The floor ratio ``(import_floor_s + case_s) / case_s`` says how close the target can come.
Best of the repeats is kept for every time (the median is kept too). The report is
:mod:`workbench.studies.bench_startup_report`.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

__all__ = ["CHANGED_E_FACTOR", "CHANGED_TARGET", "FLOOR_IMPORTS", "MODES", "TARGET_RATIO", "changed_material_case",
           "startup_cost"]

TARGET_RATIO = 2.0
"""Issue 27: the whole process of one CI-level case within this many times its mesh-and-solve time (warm)."""

CHANGED_E_FACTOR = 150000.0 / 210000.0
"""The changed copy's Young's moduli over the case's (issue 34 measured 210000 -> 150000 MPa)."""

CHANGED_TARGET = 1.5
"""Issue 34: the changed-material copy's warm process within this many times the original's."""

MODES = {"full": (), "no_pictures": ("--no-pictures",)}
"""Process modes: name -> extra ``workbench run`` options."""

FLOOR_IMPORTS = ("dolfinx_solver", "dolfinx.fem.petsc", "gmsh", "scipy.fft", "scipy.optimize", "scipy.special")
"""The third-party packages a Hertz run imports whatever the workbench does (dolfinx_solver first: it loads the
MPI library dolfinx links to)."""

_CHECKOUT = Path(__file__).resolve().parents[2]  # the subprocesses import this same checkout


def _env() -> dict:
    e = dict(os.environ)
    e["PYTHONPATH"] = str(_CHECKOUT) + os.pathsep + e.get("PYTHONPATH", "")
    return e


def _timed_process(cmd: list[str], *, timeout: float, cwd: Path) -> tuple[float, subprocess.CompletedProcess]:
    """``cmd`` run from ``cwd`` (a neutral folder: ``python -m``/``-c`` put the working directory first on the
    path, where another checkout would shadow this one)."""
    t0 = time.perf_counter()
    cp = subprocess.run(cmd, env=_env(), cwd=str(cwd), capture_output=True, text=True, timeout=timeout)
    dt = time.perf_counter() - t0
    if cp.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed (exit {cp.returncode}): {cp.stderr.strip()[-500:]}")
    return dt, cp


def _case_process(case: str, out: Path, extra: tuple[str, ...], *, timeout: float, name: str | None = None) -> dict:
    """One whole ``workbench run <case> --ci`` process (``case``: a name or a case file whose case is ``name``):
    its wall time and the case time it reported."""
    dt, _ = _timed_process([sys.executable, "-m", "workbench", "run", case, "--ci", "--out", str(out), *extra],
                           timeout=timeout, cwd=out.parent)
    m = json.loads((out / (name or case) / "metrics.json").read_text())
    return {"process_s": dt, "case_s": float(m["wall_time_s"]), "ndofs": m["ndofs"], "pass": bool(m["pass"]),
            "pngs": sorted(p.name for p in (out / case).glob("*.png"))}


def _in_process_mesh_solve(case: str, mesh_cache: Path, *, repeats: int) -> dict:
    """The CI-level run of ``case`` through ``run_one`` in this process: first call, then the best of ``repeats``."""
    from mpi4py import MPI

    import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
    from cases import load_case
    from workbench.pipeline.run_case import run_one

    c = load_case(case)
    level = c.discretisation.ci_level or c.discretisation.h_contact
    run = c.runs(h_contact=level)[0]
    times = []
    for _ in range(repeats + 1):
        t0 = time.perf_counter()
        run_one(run, name=case, mesh_cache=mesh_cache, comm=MPI.COMM_SELF, progress=lambda _m: None)
        times.append(time.perf_counter() - t0)
    return {"first_s": times[0], "best_s": min(times[1:]), "median_s": statistics.median(times[1:]),
            "h_contact": level}


def changed_material_case(case: str, folder: Path) -> tuple[str, Path]:
    """A copy of case ``case`` in ``folder`` with every ``E = ...`` line times :data:`CHANGED_E_FACTOR` and the
    name ``<case>_changed_material``: (its name, its file)."""
    import re

    from cases import load_case

    source = load_case(case).path.read_text(encoding="utf-8")
    name = f"{case}_changed_material"
    def scaled(m) -> str:
        return f"{m.group(1)}{float(m.group(2)) * CHANGED_E_FACTOR!r}"

    text, n_e = re.subn(r"(?m)^(\s*E\s*=\s*)([0-9.eE+]+)", scaled, source)
    text, n_name = re.subn(r'(?m)^(name\s*=\s*)"[^"]*"', f'\\g<1>"{name}"', text, count=1)
    if not (n_e and n_name):
        raise ValueError(f"case {case}: no 'E = ' line or no name to change")
    path = Path(folder) / f"{name}.toml"
    path.write_text(text, encoding="utf-8")
    return name, path


def _jit_modules() -> int:
    """Compiled FFCx modules in dolfinx's JIT cache folder (the ``.so`` files)."""
    import dolfinx.jit

    folder = Path(dolfinx.jit.DOLFINX_DEFAULT_JIT_OPTIONS["cache_dir"][0])
    return sum(1 for _ in folder.glob("*.so")) if folder.is_dir() else 0


def _summary(samples: list[dict], key: str) -> dict:
    v = [s[key] for s in samples]
    return {"best": min(v), "median": statistics.median(v), "all": v}


def _changed_material(case: str, out: Path, tmp: Path, *, repeats: int, timeout: float) -> dict:
    """The changed-material copy against the original, alternating ``--no-pictures`` processes (module docstring)."""
    name, path = changed_material_case(case, tmp)
    before = _jit_modules()
    first = _case_process(str(path), out, ("--no-pictures",), timeout=timeout, name=name)  # its mesh, its forms
    new_modules = _jit_modules() - before
    rows, originals = [], []
    for _ in range(repeats):
        originals.append(_case_process(case, out, ("--no-pictures",), timeout=timeout))
        rows.append(_case_process(str(path), out, ("--no-pictures",), timeout=timeout, name=name))
    ratio = statistics.median(r["process_s"] / o["process_s"] for r, o in zip(rows, originals, strict=True))
    return {"case": name, "E_factor": CHANGED_E_FACTOR, "new_modules": new_modules,
            "first_process_s": first["process_s"], "process_s": _summary(rows, "process_s"),
            "original_process_s": _summary(originals, "process_s"), "ratio": ratio, "target": CHANGED_TARGET,
            "target_met": bool(ratio <= CHANGED_TARGET and new_modules == 0), "pass": all(r["pass"] for r in rows)}


def startup_cost(case: str = "hertz_cylinder", *, repeats: int = 3, progress: Callable[[str], None] = print,
                 timeout: float = 600.0) -> dict:
    """The section's data (JSON-ready; see the module docstring). Writes only into a temporary folder.

    Args:
        case: The case (its ``ci_level``).
        repeats: Timed processes per mode and warm in-process calls, >= 1.
        progress: One line per finished measurement.
        timeout: Seconds allowed to each subprocess.
    """
    if isinstance(repeats, bool) or int(repeats) != repeats or repeats < 1:
        raise ValueError(f"repeats must be an integer >= 1, got {repeats!r}")
    with tempfile.TemporaryDirectory(prefix="bench_startup_") as tmp:
        out = Path(tmp) / "cli"
        _case_process(case, out, (), timeout=timeout)  # warm-up: mesh cache (and JIT if it was cold)
        samples: dict[str, list[dict]] = {m: [] for m in MODES}
        floor_cmd = [sys.executable, "-c", f"import {', '.join(FLOOR_IMPORTS)}; import os; os._exit(0)"]
        floor = []
        for _ in range(int(repeats)):  # the modes and the floor alternate: a change of load hits all three
            for mode, extra in MODES.items():
                samples[mode].append(_case_process(case, out, extra, timeout=timeout))
            floor.append(_timed_process(floor_cmd, timeout=timeout, cwd=Path(tmp))[0])
        inproc = _in_process_mesh_solve(case, out / "mesh_cache", repeats=int(repeats))
        changed = _changed_material(case, out, Path(tmp), repeats=int(repeats), timeout=timeout)
    best, orig = changed["process_s"]["best"], changed["original_process_s"]["best"]
    progress(f"startup changed E: {changed['new_modules']} new FFCx modules; process {best:.2f} s against the "
             f"original's {orig:.2f} s (x{changed['ratio']:.2f}; target x{CHANGED_TARGET:g} "
             f"{'met' if changed['target_met'] else 'NOT met'})")
    mesh_solve = inproc["best_s"]
    floor_s = min(floor)
    modes = {}
    for mode, rows in samples.items():
        proc, case_s = _summary(rows, "process_s"), _summary(rows, "case_s")
        ratio = statistics.median(r["process_s"] / r["case_s"] for r in rows)  # within each process
        modes[mode] = {"process_s": proc, "case_s": case_s, "ratio_to_case": ratio,
                       "ratio_to_mesh_solve": proc["best"] / mesh_solve, "target_met": bool(ratio <= TARGET_RATIO),
                       "pngs": rows[-1]["pngs"], "pass": all(r["pass"] for r in rows)}
        progress(f"startup {mode}: process {proc['best']:.2f} s, case {case_s['best']:.3f} s in that process "
                 f"(x{ratio:.1f}; target x{TARGET_RATIO:g} {'met' if ratio <= TARGET_RATIO else 'NOT met'}); "
                 f"warm mesh+solve in one process {mesh_solve:.3f} s (x{modes[mode]['ratio_to_mesh_solve']:.1f})")
    case_best = min(modes["no_pictures"]["case_s"]["best"], modes["full"]["case_s"]["best"])
    return {"case": case, "h_contact": inproc["h_contact"], "ndofs": samples["full"][-1]["ndofs"],
            "repeats": int(repeats), "target_ratio": TARGET_RATIO, "modes": modes,
            "mesh_solve_s": {"best": mesh_solve, "median": inproc["median_s"], "first_in_process": inproc["first_s"]},
            "import_floor_s": {"best": floor_s, "median": statistics.median(floor), "imports": list(FLOOR_IMPORTS)},
            "floor_ratio": (floor_s + case_best) / case_best, "bytecode_cache": not sys.dont_write_bytecode,
            "changed_material": changed,
            "load_avg": os.getloadavg()}
