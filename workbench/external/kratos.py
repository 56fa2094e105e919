"""``workbench external kratos CASE [--levels N] [--out DIR] [--time-limit S]``: export, run Kratos, score.

Kratos Multiphysics 10.4.4 (its mortar augmented-Lagrangian frictionless contact) runs in a venv of its own,
``.venv-kratos/`` of this checkout (``make external`` creates it from ``requirements-kratos.txt``): its libraries
never meet dolfinx's MPI and PETSc. Without it: one line, exit 2, nothing written ("run make external").

Per level (the case's first ``N`` levels from its ``ci_level`` down, default 3, as ``workbench export --levels N``
writes them: :func:`workbench.external.code_runs.code_levels`), into
``<out>/external_kratos_<case>/h<H>/`` (staged: :func:`workbench.atomic.atomic_dir`, the same guard as every
command that writes):

1. the benchmark (:func:`workbench.external.benchmarks.base.build`: the case's mesh, a rigid indenter meshed as a
   band; a case with several geometries, the wedge's two angles, one folder per geometry);
2. the Kratos model of every run Kratos can model (:func:`workbench.external.mdpa.write_kratos`; the others are
   named with the reason in ``kratos_runs.json`` and the summary);
3. the job (:mod:`workbench.external.kratos_job`) in the Kratos venv, ``OMP_NUM_THREADS=1``, at most ``--time-limit``
   seconds (default 1800) per level; its log in ``kratos.log``. Force-controlled cases: the job drives the
   displacement and ramps, then corrects it by secant steps, until the drive's reaction is within 0.1 % of each
   target load (inside the one Kratos process: a frictionless elastic state does not depend on the path). A step
   that did not converge, a load not reached, the time limit: one line naming it, exit 1, nothing written.
4. the score of every geometry's levels (:mod:`workbench.external.score`), in ``<geometry>/score/`` (or ``score/``),
   where the scorer can judge the case; otherwise the results stay, and ``kratos.json`` says why it was not scored.

``kratos.json`` (the summary): per geometry and level, the process wall time (the job, Kratos's import included),
Newton iterations, steps, the load carried and its target, what Kratos modelled and what it could not (and why).
Units mm, N/mm, MPa, s.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

__all__ = ["main", "KratosError", "kratos_python", "run_job", "KRATOS_VENV", "JOB"]

PROJECT_ROOT = Path(__file__).resolve().parents[2]
KRATOS_VENV = PROJECT_ROOT / ".venv-kratos"
JOB = Path(__file__).with_name("kratos_job.py")
TIME_LIMIT_S = 1800.0


class KratosError(RuntimeError):
    """Kratos missing (exit 2) or a run that gave no result (exit 1): one line."""

    def __init__(self, message: str, *, code: int = 1):
        super().__init__(message)
        self.code = code


def kratos_python(venv: Path | None = None) -> Path:
    """The Kratos venv's interpreter; KratosError (exit 2) if the venv is missing or has no Kratos."""
    venv = KRATOS_VENV if venv is None else venv
    py = venv / "bin" / "python"
    if not py.is_file() or not any(venv.glob("lib/python3.*/site-packages/KratosMultiphysics/__init__.py")):
        raise KratosError(f"the Kratos venv {venv} is missing (or has no KratosMultiphysics); run make external "
                          "(it creates it from requirements-kratos.txt)", code=2)
    return py


def run_job(folder: Path, *, python: Path, time_limit: float) -> dict:
    """Run the Kratos job on ``folder`` (Kratos's log in ``kratos.log``); its ``kratos_job.json`` with the process
    wall time (``process_wall_s``). KratosError (one line) if it failed or ran out of time."""
    env = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "PATH": "/usr/bin:/bin",
           "HOME": str(folder), "PYTHONDONTWRITEBYTECODE": "1"}  # nothing written in the home folder
    from workbench.external.code_runs import timed_job

    return timed_job([str(python), str(JOB), str(folder)], record=folder / "kratos_job.json", cwd=folder, env=env,
                     log=folder / "kratos.log", what=f"Kratos job on {folder.name}", error=KratosError,
                     time_limit=time_limit)


def _level_summary(exp, record: dict, modelled, skipped: dict) -> dict:
    runs = []
    for r in record["runs"]:
        runs.append({"run": r["run"], "element": r["element"], "control": r["control"], "targets": r["targets"],
                     "reported": r.get("reported", []), "steps": len(r["steps"]), "iterations": r["iterations"],
                     "scale_factor": r.get("scale_factor"), "times_s": r["times_s"],
                     "load_balance": [s["P_supports"] / s["P"] - 1.0 if s["P"] else None
                                      for s in r["steps"] if any(s["step"] == q.get("at_step")
                                                                 for q in r.get("reported", []))]})
    return {"level": exp.benchmark.level, "h_contact": exp.benchmark.h_contact,
            "process_wall_s": record["process_wall_s"], "import_s": record["import_s"],
            "mesh": {k: exp.stats[k] for k in ("nodes", "cells") if k in exp.stats}, "runs": runs,
            "modelled": {m.run: {"kinematics": m.kinematics, "element": m.element, "meaning": m.meaning}
                         for m in modelled}, "not_modelled": skipped}


def main(argv: list[str] | None = None) -> int:
    """``workbench external kratos`` (exit 0 done, 1 a Kratos run failed, 2 bad input or no Kratos venv)."""
    from cases import CaseError
    from workbench import interrupt
    from workbench.atomic import atomic_dir
    from workbench.external.code_runs import code_parser, open_command, print_summary, score_all
    from workbench.owned import ensure_dir
    from workbench.paths import OutputError

    args = code_parser("kratos", __doc__, time_limit=TIME_LIMIT_S).parse_args(argv)
    try:
        paths, case, levels, folder = open_command("kratos", args, error=KratosError)
        python = kratos_python()  # after the arguments: a bad value is named even where Kratos is missing
    except (KratosError, CaseError, OutputError) as exc:
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    import workbench.external.benchmarks  # noqa: F401  (the scenes' benchmark builders register)
    from workbench.external.benchmarks.base import build
    from workbench.external.mdpa import NotModelled, kratos_runs, write_kratos

    interrupt.stage(f"running Kratos on {case.name} (writing {folder.name})")
    summary: dict = {"case": case.name, "code": "Kratos Multiphysics 10.4.4 (ALM mortar, frictionless)",
                     "threads": 1, "geometries": {}}
    try:
        with atomic_dir(folder, kind="external") as stage:
            ensure_dir(paths.mesh_cache, kind="mesh_cache", kinds=("mesh_cache",))
            results: dict[tuple[str, str], list[Path]] = {}
            for lv in levels:
                sub = stage / f"h{lv:g}"
                sub.mkdir()
                for exp in build(case, level=lv, mesh_cache=paths.mesh_cache, folder=sub):
                    key = str(exp.folder.relative_to(sub)) if exp.folder != sub else ""
                    modelled, skipped = kratos_runs(exp.benchmark)
                    write_kratos(exp.benchmark, exp.model, exp.folder)
                    print(f"kratos {case.name} {key + ' ' if key else ''}h = {lv:g}: "
                          f"{', '.join(m.run for m in modelled)}", flush=True)
                    record = run_job(exp.folder, python=python, time_limit=args.time_limit)
                    entry = summary["geometries"].setdefault(key or case.name, {"levels": [], "score": None})
                    entry["levels"].append(_level_summary(exp, record, modelled, skipped))
                    entry["not_modelled"] = skipped
                    results.setdefault((key, ""), []).append(exp.folder / "result.csv")
                    last = entry["levels"][-1]
                    loads = [f"{q['P']:.6g}" for r in last["runs"] for q in r["reported"]]
                    print(f"  {last['process_wall_s']:.2f} s, {sum(r['iterations'] for r in last['runs'])} "
                          f"Newton iterations, P = {', '.join(loads)} N/mm", flush=True)
            score_all(case.name, results, stage, summary)
            (stage / "kratos.json").write_text(json.dumps(summary, indent=1, default=str))
    except KratosError as exc:
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return exc.code
    except (NotModelled, CaseError, ValueError) as exc:  # OutputError among them: the folder changed meanwhile
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    print_summary("kratos", case.name, levels, folder, summary)
    return 0
