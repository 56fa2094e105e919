"""One reference solve, measured in the same run as a study, so that a study's wall time on a loaded machine can
be read as a ratio (issue 27, point 4: "where the machine is loaded, report the ratio to one reference solve
measured in the same run").

The reference: ``cases/hertz_cylinder.toml`` as the case file sets it (its default level) through the case pipeline
(:func:`workbench.pipeline.run_case.run_one`) on ``MPI.COMM_SELF``, solved once (JIT and mesh caches filled),
then timed :data:`REPEATS` times; the best solver time is kept (s). It runs as one point on the study's own
executor, so under MPI it is measured on a worker rank like the study's points.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["REFERENCE_CASE", "REPEATS", "reference_solve", "measure_reference"]

REFERENCE_CASE = "hertz_cylinder"
REPEATS = 3


def reference_solve(mesh_cache: str) -> dict:
    """The reference solve (a point function: module level); ``{"case", "h_contact", "ndofs", "solve_s"}``."""
    from mpi4py import MPI

    from cases import load_case
    from workbench.pipeline.run_case import run_one

    case = load_case(REFERENCE_CASE)
    run = case.runs()[0]

    def once():
        return run_one(run, name=f"reference_{REFERENCE_CASE}", mesh_cache=Path(mesh_cache), comm=MPI.COMM_SELF,
                       progress=lambda _: None).metrics

    m = once()  # warm-up: JIT, mesh
    best = min(once()["wall_time_s"] for _ in range(REPEATS))
    return {"case": REFERENCE_CASE, "h_contact": run.discretisation.h_contact, "ndofs": m["ndofs"],
            "solve_s": best}


def measure_reference(*, executor, mesh_cache) -> dict:
    """The reference solve, with where it ran: on an MPI executor one point on a worker rank (where the study's
    points ran), on a local one in this process (no pool started for one point)."""
    from workbench.studies.executor import ExecutorChoice, run_points

    where = executor if executor.kind == "mpi" else ExecutorChoice("local", 1)
    return run_points(reference_solve, [str(mesh_cache)], executor=where)[0]
