"""One level of ``workbench external workbench``: the workbench's own solver on a case, in a process of its own.

``python -m workbench.external.own_job CASE LEVEL FOLDER [MESH_CACHE [COARSER]]`` solves every run of ``CASE`` at the
mesh level ``LEVEL`` (the case's ``h_contact`` fraction; the mesh ``workbench run`` builds there, which is the mesh
``workbench export`` hands to another code: same node coordinates, tested against the CI key numbers) and writes,
per geometry (:func:`workbench.external.benchmarks.base.groups`: the wedge's two angles are two geometries, one
sub-folder each, named as ``workbench export`` names them):

* ``result.csv``: every run, step and the slave body in the result schema (:mod:`workbench.external.own_results`);
  where two runs of one problem are one benchmark run (the patch test's mortar and node-to-segment pairings), the
  first one's, and ``result_<label>.csv`` for each other (a variant, scored on its own);
* ``own_job.json``: per run the Newton iterations, the load carried (N/mm), the solver's wall time and the run's
  (meshing and post-processing included; s).

It is a separate process so that its wall time is measured as CalculiX's and Kratos's are: the interpreter, the
imports (dolfinx, PETSc), the FFCx compilation of any form not yet in the JIT cache, meshing and the solve. Serial
(``MPI.COMM_SELF``). Exit 0, or 1 with one line on stderr (``error: ...``).

Nested iteration (``COARSER``: the compare's coarser levels, comma-separated, coarsest first): a run of two meshed
bodies in force control (:func:`nests`) is solved the way ``make run``'s error budget solves its levels
(:mod:`fem.nested_start`): the coarsest level cold, each finer one from the last one's converged state, the level
itself last; only the level's answer is written, and the job's time includes the coarser solves (its record names
them per run: ``nested_from``). Each level converges to its own tolerances; only the iterations differ. Measured
on ``halfplanes_finite_parabola``'s three levels (h = 0.1, 0.05, 0.025; five runs each): every run cold along its
load path, 12 s, 90 s, and the finest level past the 900 s limit; nested, 11.0 s, 15.5 s and 24.3 s per level, the
coarser solves included. Other runs (a rigid obstacle, displacement control with its recorded steps) are solved
cold.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

__all__ = ["file_names", "nests", "solve_level", "main"]


def nests(run) -> bool:
    """Whether a level of ``run`` starts from the coarser levels' solution (module docstring): two meshed bodies
    (their problem interpolates the coarse state, :meth:`fem.two_body.problem.TwoBodyProblem.nested_guess`) in force
    control (one answer per run: no recorded steps for a nested start to skip)."""
    return len(run.bodies) == 2 and run.loading.control == "force"


def file_names(pairs) -> list[str]:
    """The result file of each (run label, benchmark run it is reported as) of one geometry, in order:
    ``result.csv``, or ``result_<run label>.csv`` for a run reported as a benchmark run ``result.csv`` already holds
    (a second run of one problem: the patch test's node-to-segment pairing beside its mortar one, the finite
    parabola's ``pairing`` convective run beside ``profile``), scored on its own. Checked by the benchmark run, not
    only against the file's first run: the parabola's ``pairing`` went into ``result.csv`` beside ``profile``, and the
    reader refused the file (two loads for one run)."""
    from cases.schema import label_folder

    held: set[str] = set()
    out = []
    for label, benchmark_run in pairs:
        out.append("result.csv" if benchmark_run not in held else f"result_{label_folder(label)}.csv")
        held.add(benchmark_run)
    return out


def solve_level(case_name: str, level: float, folder: Path, *, mesh_cache: Path,
                coarser: tuple[float, ...] = ()) -> dict:
    """Solve and write one level (module docstring), the runs that :func:`nests` through ``coarser`` (h_contact
    fractions, coarsest first); the job's record."""
    import dolfinx_solver  # noqa: F401  (MPI and PETSc first)

    from mpi4py import MPI

    import workbench.scenes  # noqa: F401
    from cases import load_case
    from cases.schema import label_folder
    from workbench.external.benchmarks.base import groups
    from workbench.external.own_results import groups_csv, outcome_groups
    from workbench.external.scorers import scorer_for
    from workbench.pipeline.run_case import run_one

    case = load_case(case_name)
    scorer = scorer_for(case)
    scored = scorer.runs(case)
    slave = scorer.bodies(case)[0].name
    parts = groups(case.runs(h_contact=level))
    coarse = {h: {r.label: r for r in case.runs(h_contact=h)} for h in coarser}
    record: dict = {"case": case.name, "level": level, "geometries": {}}
    for part in parts:
        key = "" if len(parts) == 1 else label_folder(part[0].label)
        sub = folder / key if key else folder
        sub.mkdir(parents=True, exist_ok=True)
        files: dict[str, list] = {}  # file name -> its groups
        reported = [next(s for s in scored if run.label in (s.label, *s.aliases)) for run in part]
        names = file_names([(run.label, srun.label) for run, srun in zip(part, reported, strict=True)])
        runs = []
        for run, srun, name in zip(part, reported, names, strict=True):
            t0 = time.perf_counter()
            start, chain = None, []
            for h in coarser if nests(run) else ():
                o = run_one(coarse[h][run.label], name=case.name, mesh_cache=mesh_cache, comm=MPI.COMM_SELF,
                            progress=lambda _m: None, **({} if start is None else {"nested_start": start}))
                start = o.result.nested_start
                chain.append({"h_contact": h, "iterations": int(sum(o.result.newton_iterations)),
                              "solve_s": float(o.result.wall_time_s)})
            outcome = run_one(run, name=case.name, mesh_cache=mesh_cache, comm=MPI.COMM_SELF,
                              progress=lambda _m: None, **({} if start is None else {"nested_start": start}))
            wall = time.perf_counter() - t0
            files.setdefault(name, []).extend(outcome_groups(outcome, label=srun.label, body=slave))
            res = outcome.result
            runs.append({"run": run.label, "reported_as": srun.label, "file": name, "P": float(res.P),
                         "iterations": int(sum(res.newton_iterations)), "solve_s": float(res.wall_time_s),
                         "wall_s": wall, "nested_from": chain})
        for name, grps in files.items():
            (sub / name).write_text(groups_csv(grps))
        record["geometries"][key or case.name] = {"runs": runs, "results": sorted(files)}
    return record


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    t0 = time.perf_counter()
    case, level, folder = argv[0], float(argv[1]), Path(argv[2])
    mesh_cache = Path(argv[3]) if len(argv) > 3 else folder / "mesh_cache"
    coarser = tuple(float(h) for h in argv[4].split(",") if h) if len(argv) > 4 else ()
    try:
        record = solve_level(case, level, folder, mesh_cache=mesh_cache, coarser=coarser)
    except Exception as exc:  # noqa: BLE001  (one line for the parent, which names the level)
        print(f"error: {type(exc).__name__}: {' '.join(str(exc).split())[:300]}", file=sys.stderr)
        return 1
    record["job_wall_s"] = time.perf_counter() - t0
    (folder / "own_job.json").write_text(json.dumps(record, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
