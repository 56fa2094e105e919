"""Run one case end to end and write ``<out>/<case>/`` atomically: the one path from case file to outputs.

For every run of the case: its scene (:mod:`workbench.scenes`) meshes it, names the rigid obstacle and the
load path; the solver (:func:`workbench.scenes.wiring.solve_run`) solves it; the scene compares the result
with theory. Then the scene judges the whole case, the case-level ``metrics.json`` is assembled here
(:func:`case_metrics`) and the reports are written from the saved files (:mod:`workbench.reports`).

Outputs (the results contract): ``metrics.json``, ``pressure.csv``, ``pressure.png``, ``report.md`` /
``report.html``, ``run.log`` and ``vtk/<run>/`` (ParaView); with ``pictures=False`` (``--no-pictures``) no
PNG. Everything is written into a staging folder that replaces ``results/<case>/`` only when the case has
finished, so an interrupted or failed run leaves the previous results intact. A failed run writes
``results/logs/<case>.log`` and exits 1.

Works under ``mpiexec -n N``: every rank takes part in the solve and the VTK output; rank 0 writes the
rest.
"""

from __future__ import annotations

import math
import sys
import time
import traceback
from pathlib import Path

from cases.schema import Case, CaseError, Run, label_folder
from workbench import interrupt
from workbench.atomic import atomic_dir, write_json, write_text
from workbench.owned import ensure_dir, mark
from workbench.paths import OutputError, OutputPaths
from workbench.scenes import Outcome, scene_for
from workbench.scenes.numbers import EXCLUDED, LOAD, MESH, VERDICT, declare
from workbench.scenes.wiring import solve_run, step_printer

__all__ = ["run_case", "run_one", "case_metrics"]

# The number classes of what case_metrics writes (workbench.scenes.numbers): the case's load (its first run's), its
# verdict, and each run's mesh fingerprint (its identity: counts and hashes; the perturbation amplitude is the
# emulation's own setting, make emulate sets it, not a result). The errors are the runs' and the judge's, declared
# where those are written.
declare("case", __name__, P=LOAD, P_pressure=LOAD, **{"pass": VERDICT})
declare("fingerprint", __name__, perturb=EXCLUDED, **{"*": MESH})


def _progress_printer(comm, log: list[str]):
    t0 = time.perf_counter()

    def progress(msg: str) -> None:
        interrupt.check()  # a signal whose exception native code swallowed stops the run here
        line = f"[{time.perf_counter() - t0:7.1f} s] {msg}"
        log.append(line)
        if comm.rank == 0:
            print(line, flush=True)

    return progress


def case_metrics(case: Case, outcomes: list, *, h_contact: float | None, wall_time_s: float) -> dict:
    """The case-level ``metrics.json`` from its runs' metrics (the results contract).

    Top-level fields describe the case as a whole: ``ndofs`` is the largest run, times and iterations are
    summed, ``P``/``P_pressure``/``patches`` are those of the first run, ``errors`` holds the worst value of
    each error over the runs plus case-level comparisons (e.g. ``b_over_b0``), and ``runs`` lists every run.
    An error that is NaN or missing in any run is NaN for the case (its check fails), and
    ``errors_undefined`` names the runs where it was. Every run carries ``mesh_fingerprint``
    (:class:`meshes.fingerprint.MeshFingerprint` as a dict). ``checked_errors`` names the error each tolerance reads
    (its own key, or the scene's choice of the theory that applies, :class:`workbench.scenes.base.CaseComparison`).
    """
    runs = [o.metrics for o in outcomes]
    for r in runs:  # the mesh's identity next to its numbers: a later comparison can say "mesh differs"
        r["mesh_fingerprint"] = (r.get("mesh") or {}).get("fingerprint")
    first = runs[0]
    errors: dict[str, float] = {}
    undefined: dict[str, list[str]] = {}  # error -> runs where it could not be computed (never dropped silently)
    for r in runs:
        for k, v in r.get("errors", {}).items():
            if v is None or (isinstance(v, float) and math.isnan(v)):
                undefined.setdefault(k, []).append(r["label"])
            else:
                errors[k] = max(errors.get(k, 0.0), v)
    for k in undefined:  # an error undefined in one run is undefined for the case: its check fails
        errors[k] = math.nan
    extra = scene_for(outcomes[0].run).judge(case, outcomes)
    errors.update(extra.errors)
    tol = dict(case.tolerances)
    checked = {k: extra.checked.get(k, k) for k in tol}  # the error each check reads (the theory that applies)
    checks = {k: bool(errors.get(checked[k]) is not None and errors[checked[k]] <= t) for k, t in tol.items()}
    kin = sorted({r["kinematics"] for r in runs})
    return extra.top | {
        "case": case.name,
        "description": case.description,
        "method": "+".join(sorted({r["method"] for r in runs})),
        "kinematics": "+".join(kin),
        "h_contact": h_contact if h_contact is not None else case.discretisation.h_contact,
        "ndofs": max(r["ndofs"] for r in runs),
        "wall_time_s": wall_time_s,
        "newton_iterations": int(sum(sum(r["newton_iterations"]) for r in runs)),
        "load_steps": int(sum(len(r["load_steps"]) for r in runs)),
        "failed_solves": int(sum(r.get("failed_solves", 0) for r in runs)),  # cut back and retried
        "failed_iterations": int(sum(r.get("failed_iterations", 0) for r in runs)),
        "P": first["P"],
        "P_pressure": first["P_pressure"],
        "patches": first["patches"],
        "analytic": {"runs": {r["label"]: r.get("analytic") for r in runs}, **extra.analytic},
        "errors": errors,
        "errors_undefined": undefined,
        "tolerances": tol,
        "checks": checks,
        "checked_errors": checked,
        "pass": bool(all(checks.values())),
        "headline": extra.headline,
        "case_tables": extra.tables,
        "runs": runs,
    }


def run_one(run: Run, *, name: str, mesh_cache: Path, comm, progress=print, stats_dir: Path | None = None,
            frames: list | None = None, scene=None, meshes: dict | None = None, case: str | None = None,
            **solver_overrides) -> Outcome:
    """Mesh, solve and compare one run through its scene: the one way a case run and every study point is solved.

    Args:
        run: The run record.  name: The case (or study point) name; the scene names its mesh from it.
        mesh_cache: The mesh cache folder.  comm: The MPI communicator.  progress: One-line progress printer.
        stats_dir: Where the scene writes mesh statistics (None: nowhere).
        frames: A list that receives every converged step for the VTK time series.
        scene: The scene that meshes, drives and compares the run (default: its registered scene,
            :func:`workbench.scenes.scene_for`); a study passes its adapter of that scene
            (:mod:`workbench.studies.scene_point`: ``TargetSized``, the mesh sized from the target itself;
            ``GivenMesh``, a mesh already in memory, handed in through ``meshes``).
        meshes: A dict that keeps the read meshes by their cache key (``MeshFiles.key``): a study's worker reads
            each mesh once for all its runs, and the caller finds the ``MeshData`` a result was solved on.
        case: The name the solver's messages carry (default ``name[label]``; a study point: its own label).
        solver_overrides: Extra solver keywords (:func:`workbench.scenes.wiring.solve_run`).
    """
    from workbench.mesh_io import read_mesh
    from workbench.pipeline.size_estimate import check_run_fits

    interrupt.check()  # a study that recorded a signal's PETSc.Error as a failed run stops at its next run
    scene = scene_for(run) if scene is None else scene
    check_run_fits(run, where=f"{name} [{run.label}]", field="h_contact")  # studies too: refused before meshing
    interrupt.stage(f"meshing [{run.label}] of {name}")
    mesh = scene.mesh(run, name=name, mesh_cache=mesh_cache, comm=comm, stats_dir=stats_dir)
    progress(f"[{run.label}] {mesh.summary}")
    if meshes is None:
        mesh_data = read_mesh(mesh.files.msh, comm)
    else:
        if mesh.files.key not in meshes:
            meshes[mesh.files.key] = read_mesh(mesh.files.msh, comm)
        mesh_data = meshes[mesh.files.key]
    interrupt.stage(f"the Newton solve [{run.label}] of {name}")
    result = solve_run(run, mesh_data, scene.obstacle(run, mesh), scene.load_path(run, mesh),
                       case=case or f"{name}[{run.label}]", on_step=step_printer(progress, run.label), frames=frames,
                       **solver_overrides)
    interrupt.check()
    for w in result.warnings:
        progress(f"[{run.label}] WARNING: {w}")
    interrupt.stage(f"post-processing [{run.label}] of {name}")
    return scene.compare(run, result, mesh, progress=progress)


def run_case(case: Case, *, paths: OutputPaths, h_contact: float | None = None, ci: bool = False,
             pictures: bool = True) -> dict | None:
    """Run every run of ``case`` and write its results folder ``paths.case(case.name)``.

    Args:
        case: The loaded case.
        paths: The output folder (results, mesh cache, logs).
        h_contact: Override of the contact element size (fraction of the half-width).
        ci: Use the case's ``ci_level`` (coarsest level that must still meet the tolerances).
        pictures: Draw the report's pictures (``pressure.png``, ``budget.png``, the pyvista renders). False is
            the fast path of ``workbench run --no-pictures``: the same data files and ``metrics.json``, a text
            report, and matplotlib / pyvista never imported (``workbench report`` draws the pictures later).

    Returns:
        The metrics dict (on every rank).
    """
    import dolfinx_solver  # noqa: F401

    from mpi4py import MPI

    from fem.output import write_vtk
    from workbench.pipeline.bands import band_checks
    from workbench.pipeline.budget import budget_table, case_error_budget, write_subsurface
    from workbench.pipeline.case_files import write_case_files
    from workbench.reports.case_report import write_case_report

    comm = MPI.COMM_WORLD
    if ci and h_contact is None:
        h_contact = case.discretisation.ci_level or case.discretisation.h_contact
    out = paths.case(case.name)
    refusal = None
    if comm.rank == 0:
        try:
            ensure_dir(paths.mesh_cache, kind="mesh_cache")  # the workbench's own, or refused
        except OutputError as exc:
            refusal = str(exc)
    refusal = comm.bcast(refusal, root=0)  # every rank stops on rank 0's refusal (none waits for it)
    if refusal:
        raise OutputError(refusal)
    log: list[str] = []
    progress = _progress_printer(comm, log)
    progress(f"case {case.name}: {len(case.runs())} run(s), h_c = "
             f"{h_contact or case.discretisation.h_contact} x half-width, {comm.size} MPI process(es)")
    t0 = time.perf_counter()
    try:
        with atomic_dir(out) if comm.rank == 0 else _null_dir() as stage:
            stage = Path(comm.bcast(str(stage) if comm.rank == 0 else None, root=0))
            outcomes = []
            for run in case.runs(h_contact=h_contact):
                frames: list = []
                interrupt.check()
                outcome = run_one(run, name=case.name, mesh_cache=paths.mesh_cache, comm=comm, progress=progress,
                                  frames=frames)
                write_vtk(outcome.result, stage / "vtk" / label_folder(run.label), frames=frames,
                          record_at=getattr(run.loading, "d", None))
                if comm.rank == 0:
                    mark(stage / "vtk", kind="vtk")
                    mark(stage / "vtk" / label_folder(run.label), kind="vtk")
                outcomes.append(outcome)
            budget, subsurface = ({}, None) if ci or h_contact is not None else case_error_budget(
                case, progress=progress,
                solve=lambda r, **kw: run_one(r, name=case.name, mesh_cache=paths.mesh_cache, comm=comm,
                                              progress=lambda _m: None, **kw))
            metrics = case_metrics(case, outcomes, h_contact=h_contact, wall_time_s=time.perf_counter() - t0)
            if budget:
                metrics["error_budget"] = budget
                title = ("three grids, three block sizes" if any("by_W" in r for r in budget.values())
                         else "three grids; finite body, no truncation")
                metrics["case_tables"][f"Error budget ({title})"] = budget_table(budget)
                bands = band_checks(case.bands, budget)  # tolerances that are the budget's band
                metrics["band_checks"] = {k: c._asdict() for k, c in bands.items()}
                metrics["checks"].update({k: c.passed for k, c in bands.items()})
                metrics["pass"] = bool(all(metrics["checks"].values()))
            if subsurface is not None:
                metrics["subsurface"] = subsurface["summary"]
            metrics["mpi_processes"] = comm.size
            interrupt.stage(f"writing the results of {case.name}")
            if comm.rank == 0:
                write_case_files(outcomes, stage)
                if subsurface is not None:
                    write_subsurface(stage, subsurface)
                write_json(stage / "mesh.json", {o.label: o.metrics.get("mesh") for o in outcomes})
                verdict = "PASS" if metrics["pass"] else "FAIL"
                progress(f"case {case.name}: {verdict} in {metrics['wall_time_s']:.1f} s -> {out}")
                write_text(stage / "run.log", "\n".join(log) + "\n")
                write_json(stage / "metrics.json", metrics)
                write_case_report(stage, pictures=pictures)  # from the saved metrics.json and series.json only
            comm.barrier()
            interrupt.check()  # a signal during the last writes: the staging folder goes, the old results stay
            interrupt.stage(f"replacing the results folder of {case.name}")
    except KeyboardInterrupt:
        raise  # the command line prints the one line and exits 130 / 143 (staging already removed)
    except OSError:
        raise  # e.g. ENOSPC: named by the command line
    except CaseError:
        raise  # bad input found late (a run that cannot fit): one line, exit 2
    except Exception as exc:  # noqa: BLE001 - any failure writes logs/<case>.log (the README's promise)
        if interrupt.received() is not None:  # e.g. petsc4py.PETSc.Error 101 made of the signal's exception
            raise interrupt.Interrupted(interrupt.received()) from None
        _fail(case, paths, log, exc, comm)
        raise SystemExit(1) from None
    interrupt.stage(f"finishing {case.name}")
    return metrics


class _null_dir:
    def __enter__(self):
        return None

    def __exit__(self, *exc):
        return False


def _fail(case: Case, paths: OutputPaths, log: list[str], exc: BaseException, comm) -> None:
    if comm.rank != 0:
        return
    path = ensure_dir(paths.logs, kind="logs") / f"{case.name}.log"
    text = "\n".join(log) + "\n\n" + "".join(traceback.format_exception(exc))
    write_text(path, text)
    first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
    if not isinstance(exc, ValueError | RuntimeError):
        first = f"{type(exc).__name__}: {first}"
    first = first if len(first) <= 200 else first[:197] + "..."
    print(f"error: case {case.name} failed: {first} (log: {path}; previous results left intact)",
          file=sys.stderr)
