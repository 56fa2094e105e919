"""``workbench external workbench CASE [--levels N] [--out DIR] [--time-limit S]``: the workbench's own solver run
and scored exactly as an external code is.

The third code of ``workbench external compare``. Per level (the case's first ``N`` from its ``ci_level`` down,
default 3: :func:`workbench.external.code_runs.code_levels`, the levels ``workbench export --levels N`` writes), into
``<out>/external_workbench_<case>/h<H>/`` (staged: :func:`workbench.atomic.atomic_dir`, the same guard as every
command that writes), one process (:mod:`workbench.external.own_job`) solves every run of the case on the mesh
``workbench run`` builds at that level, the mesh ``workbench export`` hands the other codes (two meshed bodies in
force control: nested from the coarser levels, their solves in the level's time), and writes its ``result.csv`` in
the result schema. Then every geometry's levels are scored as ``workbench score`` scores any
code's (:func:`workbench.external.code_runs.score_geometry`) into ``<geometry>/score/`` (or ``score/``; a variant's
into ``score_<variant>/``).

``workbench.json`` (the summary, the same layout as ``ccx.json`` and ``kratos.json``): per geometry and level the
process wall time (``process_wall_s``: the interpreter, dolfinx's import, the FFCx compilation of forms not yet in
the JIT cache, meshing, the solve; serial), per run the Newton iterations, the load and the solver's own wall time.
A level whose job failed or ran out of time: one line naming it, exit 1, nothing written. Units mm, N/mm, s.
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

__all__ = ["main", "OwnError", "run_job", "CODE"]

CODE = "the workbench (dolfinx 0.11, Nitsche/penalty/mortar as the case sets, semismooth Newton, MUMPS, serial)"
TIME_LIMIT_S = 1800.0


class OwnError(RuntimeError):
    """A bad option (exit 2) or a level whose job failed (exit 1): one line."""

    def __init__(self, message: str, *, code: int = 1):
        super().__init__(message)
        self.code = code


def run_job(case: str, level: float, folder: Path, *, mesh_cache: Path, time_limit: float,
            coarser: tuple[float, ...] = ()) -> dict:
    """One level's job (:mod:`workbench.external.own_job`) in its own process, nested through the ``coarser``
    levels where the run allows (:func:`workbench.external.own_job.nests`); its record with the process wall time
    (``process_wall_s``). OwnError (one line) if it failed or ran out of time."""
    env = dict(os.environ) | {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
    from workbench.external.code_runs import timed_job

    return timed_job([sys.executable, "-m", "workbench.external.own_job", case, repr(level), str(folder),
                      str(mesh_cache), ",".join(repr(h) for h in coarser)], record=folder / "own_job.json", env=env,
                     error=OwnError,
                     what=f"the workbench on {case} h = {level:g}", time_limit=time_limit)


def main(argv: list[str] | None = None) -> int:
    """``workbench external workbench`` (exit 0 done, 1 a level failed, 2 bad input)."""
    from cases import CaseError
    from workbench import interrupt
    from workbench.atomic import atomic_dir
    from workbench.external.code_runs import code_parser, open_command, print_summary, score_all
    from workbench.owned import ensure_dir
    from workbench.paths import OutputError

    args = code_parser("workbench", __doc__, time_limit=TIME_LIMIT_S).parse_args(argv)
    try:
        paths, case, levels, folder = open_command("workbench", args, error=OwnError)
    except (OwnError, CaseError, OutputError) as exc:
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    interrupt.stage(f"running the workbench on {case.name} (writing {folder.name})")
    summary: dict = {"case": case.name, "code": CODE, "threads": 1, "geometries": {}}
    try:
        with atomic_dir(folder, kind="external") as stage:
            ensure_dir(paths.mesh_cache, kind="mesh_cache", kinds=("mesh_cache",))
            results: dict[tuple[str, str], list[Path]] = {}
            for i, lv in enumerate(levels):
                sub = stage / f"h{lv:g}"
                sub.mkdir()
                print(f"workbench {case.name} h = {lv:g}", flush=True)
                rec = run_job(case.name, lv, sub, mesh_cache=paths.mesh_cache, time_limit=args.time_limit,
                              coarser=tuple(levels[:i]))
                for key, geo in rec["geometries"].items():
                    folder_key = "" if key == case.name else key
                    entry = summary["geometries"].setdefault(key, {"levels": [], "score": None})
                    entry["levels"].append({"level": lv, "h_contact": lv, "process_wall_s": rec["process_wall_s"],
                                            "runs": geo["runs"]})
                    for name in geo["results"]:
                        variant = name.removeprefix("result").removesuffix(".csv").lstrip("_")
                        results.setdefault((folder_key, variant), []).append(sub / folder_key / name)
                    loads = ", ".join(f"{r['P']:.6g}" for r in geo["runs"])
                    print(f"  {key}: {rec['process_wall_s']:.2f} s, "
                          f"{sum(r['iterations'] for r in geo['runs'])} Newton iterations, P = {loads} N/mm",
                          flush=True)
            score_all(case.name, results, stage, summary)
            (stage / "workbench.json").write_text(json.dumps(summary, indent=1, default=str))
    except OwnError as exc:
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return exc.code
    except (CaseError, ValueError) as exc:  # OutputError among them: the folder changed meanwhile
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    print_summary("workbench", case.name, levels, folder, summary)
    return 0
