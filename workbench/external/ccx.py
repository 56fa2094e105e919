"""``workbench external ccx CASE [--levels N] [--out DIR]``: export, run CalculiX on every run it models, score.

CalculiX (``ccx``, Debian's ``calculix-ccx`` 2.20, which ``make external`` installs) runs the decks of
:mod:`workbench.external.inp`. Without ``ccx`` on the PATH: one line, exit 2, nothing written. The output folder
``external_ccx_<case>/`` and the mesh cache pass the guard of every command that writes
(:func:`workbench.paths.checked_paths`, :func:`workbench.owned.check_dir`) before ccx is looked for, and the whole
folder is staged (:func:`workbench.atomic.atomic_dir`): it replaces the previous one only when the command ends.

Levels: the case's first ``N`` (default 3) from its ``ci_level`` down (:func:`workbench.external.export.level_sequence`,
the levels ``workbench export --levels N`` writes). Per level, into ``<out>/external_ccx_<case>/h<H>/``:

1. the benchmark (:func:`workbench.external.benchmarks.build`: the case's mesh, a rigid indenter meshed as a band;
   the wedge's two angles one folder each, ``h<H>/<geometry>/``);
2. per run CalculiX models (:func:`workbench.external.inp.ccx_runs`): its deck ``<run>.inp`` and ccx's files
   (``.frd``, ``.dat``, ``.sta``, ``.log``), the load calibration of a force-controlled case and the pressure along
   the slave surface at every reported step (:func:`workbench.external.ccx_solve.solve_run`); the approach found
   on one level starts the next (one ccx run per finer level where it lands within 0.5 %);
3. ``result.csv``: every run, step and slave body in the result schema (``x_mm, p_MPa, P_N_per_mm, h_mm, run, step,
   body``, and ``y_mm`` on a curved slave surface; :data:`workbench.external.benchmark.RESULT_COLUMNS`); a convective
   run, which CalculiX solves at finite strain, is reported as ``finite`` (the score's added finite run, held against
   the convective theory); the patch test's node-to-surface run (CalculiX's other contact discretisation of the same
   problem) goes to ``result_node_to_surface.csv``.

Then every geometry's levels are scored as ``workbench score`` scores them (:mod:`workbench.external.score`) into
``<geometry>/score/`` (or ``score/``; a variant's into ``score_<variant>/``), and ``ccx.json`` sums it up: per
geometry and level the mesh, every ccx process's wall time (``process_wall_s``: all of them, calibration included;
``scored_wall_s``: the run whose result is scored), each run's loads against the targets, what CalculiX modelled and
how, and what it could not (and why). A run that ccx could not finish (no convergence, the time limit) is named there
with ccx's first ``*ERROR`` line; the others are written and scored, and the command exits 1. Exit 0: every modelled
run finished. Units mm, N/mm, MPa, s.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from workbench.external.ccx_solve import CcxError, ccx_executable, run_ccx

__all__ = ["main", "CcxError", "ccx_executable", "run_ccx", "ccx_levels", "CODE"]

CODE = "CalculiX 2.20 (ccx; CPE6, frictionless penalty contact, SPOOLES, one thread)"


def ccx_levels(case, n: int) -> list[float]:
    """The case's first ``n`` mesh levels from its ``ci_level`` down."""
    from workbench.external.code_runs import code_levels

    return code_levels(case, n, error=CcxError)


def _level(exp, *, exe: str, guesses: dict, key: str, log) -> dict:
    """Every run CalculiX models of one exported benchmark level: solved, written as ``result.csv`` (and
    ``result_<variant>.csv`` for another contact discretisation); the summary."""
    from workbench.external.ccx_solve import result_rows, solve_run, write_result_csv
    from workbench.external.inp import ccx_runs, quadratic_model

    bench = exp.benchmark
    model = quadratic_model(bench, exp.model)
    modelled, skipped = ccx_runs(bench)
    done: dict[str, list] = {}
    runs, failed = [], {}
    for m in modelled:
        try:
            r = solve_run(bench, model, modelled=m, folder=exp.folder, exe=exe,
                          d_guess=guesses.get((key, m.run.label)), log=log)
        except (CcxError, subprocess.TimeoutExpired) as exc:
            failed[m.run.label] = " ".join(str(exc).split())[:400]
            log(f"    {m.run.label}: FAILED: {failed[m.run.label]}")
            continue
        guesses[(key, m.run.label)] = [st.d for st in r.steps]
        done.setdefault(m.variant, []).append(r)
        runs.append({"run": m.run.label, "reported_as": r.run, "variant": m.variant, "contact": m.contact,
                     "model": r.model, "scored_wall_s": r.wall_time_s, "ccx_runs": len(r.calibration),
                     "calibration": list(r.calibration),
                     "steps": [{"step": st.step, "d": st.d, "P": st.P, "target": bench.drive.report[st.step]}
                               for st in r.steps]})
    results = {}
    for variant, rs in done.items():
        name = f"result_{variant}.csv" if variant else "result.csv"
        write_result_csv(exp.folder / name, result_rows(rs, h=bench.h_contact))
        results[variant] = name
    wall = sum(c["wall_time_s"] for r in runs for c in r["calibration"])
    return {"level": bench.level, "h_contact": bench.h_contact, "control": bench.drive.control,
            "mesh": {k: exp.stats[k] for k in ("nodes", "cells") if k in exp.stats},
            "quadratic_nodes": int(len(model.nodes)), "process_wall_s": wall, "runs": runs, "failed": failed,
            "modelled": {m.run.label: {"kinematics": m.run.kinematics, "contact": m.contact, "model": m.model,
                                       "reported_as": m.label, "variant": m.variant} for m in modelled},
            "not_modelled": skipped, "results": results}


def main(argv: list[str] | None = None) -> int:
    """``workbench external ccx`` (exit 0 every modelled run done and scored, 1 a run failed (the rest written),
    2 bad input or ccx missing)."""
    from cases import CaseError
    from workbench import interrupt
    from workbench.atomic import atomic_dir
    from workbench.external.code_runs import code_parser, open_command, print_summary, score_all
    from workbench.owned import ensure_dir
    from workbench.paths import OutputError

    args = code_parser("ccx", __doc__).parse_args(argv)
    try:
        paths, case, levels, folder = open_command("ccx", args, error=CcxError)
        exe = ccx_executable()  # after the arguments: a bad value is named even where ccx is missing
    except (CcxError, CaseError, OutputError) as exc:
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    import workbench.external.benchmarks  # noqa: F401  (the scenes' benchmark builders register)
    from workbench.external.benchmarks import build

    interrupt.stage(f"running CalculiX on {case.name} (writing {folder.name})")
    summary: dict = {"case": case.name, "code": CODE, "threads": 1, "geometries": {}}
    failed = 0
    try:
        with atomic_dir(folder, kind="external") as stage:
            ensure_dir(paths.mesh_cache, kind="mesh_cache", kinds=("mesh_cache",))
            results: dict[str, list[Path]] = {}
            guesses: dict = {}
            for lv in levels:
                sub = stage / f"h{lv:g}"
                sub.mkdir()
                for exp in build(case, level=lv, mesh_cache=paths.mesh_cache, folder=sub):
                    key = str(exp.folder.relative_to(sub)) if exp.folder != sub else ""
                    print(f"ccx {case.name} {key + ' ' if key else ''}h = {lv:g} "
                          f"({exp.stats.get('nodes', '?')} nodes)", flush=True)
                    rec = _level(exp, exe=exe, guesses=guesses, key=key, log=lambda s: print(s, flush=True))
                    entry = summary["geometries"].setdefault(key or case.name, {"levels": [], "score": None})
                    entry["levels"].append(rec)
                    entry["not_modelled"] = rec["not_modelled"]
                    failed += len(rec["failed"])
                    for variant, name in rec["results"].items():
                        results.setdefault((key, variant), []).append(exp.folder / name)
            score_all(case.name, results, stage, summary)
            (stage / "ccx.json").write_text(json.dumps(summary, indent=1, default=str))
    except (CaseError, ValueError) as exc:  # OutputError among them: the folder changed meanwhile
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    print_summary("ccx", case.name, levels, folder, summary)
    if failed:
        print(f"{failed} run(s) failed: see {folder / 'ccx.json'}")
    return 1 if failed else 0
