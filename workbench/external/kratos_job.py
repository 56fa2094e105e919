"""The Kratos job: runs INSIDE the Kratos venv (``.venv-kratos``); imports only Kratos, numpy and the standard library.

Usage: ``.venv-kratos/bin/python kratos_job.py FOLDER`` (the working directory is set to FOLDER). FOLDER holds what
:func:`workbench.external.mdpa.write_kratos` wrote: per run ``job_<run>.json``, ``ProjectParameters_<run>.json``,
the ``.mdpa`` and ``StructuralMaterials.json``. For each job (in file-name order) the job:

1. builds Kratos's ``StructuralMechanicsAnalysis`` from the run's ``ProjectParameters`` WITHOUT its
   ``drive_process_list`` (the standalone deck's drive table): the job drives itself, prescribing ``d * direction``
   on the components ``components`` of every node of the sub model part ``Drive``, one solution step per ``d``;
2. displacement control: the steps of ``schedule`` (each step at most ``max_step`` mm); force control: steps of at
   most ``max_step`` until the load passes the next target (the step length from the secant of the last two loads
   when that is shorter), then secant (regula falsi inside the bracket) steps on ``d`` until
   ``|P / target - 1| <= load_rtol``, at most ``max_corrections`` of them;
3. checks that every step converged: Kratos carries on after a step that did not (it only logs "Max iterations
   exceeded"); a step that did not, a load not reached, a non-finite value are named failures, never results;
4. at each reported step, for every slave surface: the pressure ``p = -SCALE_FACTOR * LAGRANGE_MULTIPLIER_CONTACT_
   PRESSURE`` on its ACTIVE nodes (0 on the others; the nodal unknown is the pressure over the scale factor), the
   nodes' reference positions, and the load ``P = load_factor * sum(REACTION . direction)`` over the drive's nodes
   (N/mm; ``load_factor`` 2 for a half model).

Writes ``result.csv`` (``x_mm, y_mm, p_MPa, P_N_per_mm, h_mm, d_mm, run, step, body``: one row per slave node and
reported step, positions in mm in the reference configuration, pressures in MPa compression positive) and
``kratos_job.json`` (per run: every step's d, P, Newton iterations, convergence and wall time; the scale factor
and penalty; import, initialisation and solve times). Kratos's own log goes to stdout (the runner sends it to
``kratos.log``). Exit 0 done; 3 a named failure (one line on stderr starting ``error:``, ``kratos_job.json`` written
with it); 2 a bad job folder.
"""

from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

EXIT_FAILED = 3
EXIT_BAD_INPUT = 2


class JobFailure(RuntimeError):
    """A run that did not give a result (one line: what, where)."""


def _kratos():
    """Kratos's modules (imported here, so that this file imports without Kratos)."""
    import KratosMultiphysics as KM
    import KratosMultiphysics.ContactStructuralMechanicsApplication as CSMA
    import KratosMultiphysics.LinearSolversApplication  # noqa: F401  (sparse_lu)
    import KratosMultiphysics.StructuralMechanicsApplication  # noqa: F401
    from KratosMultiphysics.StructuralMechanicsApplication.structural_mechanics_analysis import (
        StructuralMechanicsAnalysis,
    )

    return KM, CSMA, StructuralMechanicsAnalysis


def _tributary_stretch(part) -> dict:
    """Node id -> its tributary length on the surface now over its tributary length in the reference configuration
    (half of each adjacent segment): the pressure per reference length is the nodal pressure (per deformed length:
    the mortar's nodal force is the multiplier times the deformed tributary length) times this."""
    now, ref = {}, {}
    for cond in part.Conditions:
        a, b = cond.GetNodes()
        ln = math.hypot(b.X - a.X, b.Y - a.Y)
        l0 = math.hypot(b.X0 - a.X0, b.Y0 - a.Y0)
        for n in (a, b):
            now[n.Id] = now.get(n.Id, 0.0) + 0.5 * ln
            ref[n.Id] = ref.get(n.Id, 0.0) + 0.5 * l0
    return {i: now[i] / ref[i] for i in now}


class _Driven:
    """One Kratos analysis stepped by the job (the drive's displacement set per step)."""

    def __init__(self, job: dict, folder: Path):
        KM, self.CSMA, Analysis = _kratos()
        self.KM = KM
        params = KM.Parameters((folder / job["parameters"]).read_text())
        if params["processes"].Has("drive_process_list"):
            params["processes"].RemoveValue("drive_process_list")
        self.model = KM.Model()
        self.sim = Analysis(self.model, params)
        self.sim.Initialize()
        self.mp = self.model[params["solver_settings"]["model_part_name"].GetString()]
        self.drive = self.mp.GetSubModelPart(job["drive_part"])
        driven = {n.Id for n in self.drive.Nodes}
        ids = {n.Id: n for s in self.mp.GetSubModelPartNames() if s.startswith("Support_")
               for n in self.mp.GetSubModelPart(s).Nodes if n.Id not in driven}
        self.supports = list(ids.values())  # every supported node once, none of the drive's
        self.direction = [float(c) for c in job["direction"]]
        self.components = [int(c) for c in job["components"]]
        self.load_factor = float(job["load_factor"])
        self.steps: list[dict] = []
        self.variables = (KM.DISPLACEMENT_X, KM.DISPLACEMENT_Y)

    def solve(self, d: float) -> dict:
        """One solution step at approach ``d`` (mm): its record; JobFailure if it did not converge."""
        KM, sim = self.KM, self.sim
        t0 = time.perf_counter()
        sim.time = sim._AdvanceTime()
        for node in self.drive.Nodes:
            for c in self.components:
                node.Fix(self.variables[c])
                node.SetSolutionStepValue(self.variables[c], d * self.direction[c])
        sim.InitializeSolutionStep()
        converged = bool(sim.SolveSolutionStep())
        iterations = int(self.mp.ProcessInfo[KM.NL_ITERATION_NUMBER])
        sim.FinalizeSolutionStep()
        sim.OutputSolutionStep()
        load = self.load()
        rec = {"step": len(self.steps) + 1, "d": d, "P": load, "P_supports": self.load(self.supports),
               "iterations": iterations, "converged": converged, "wall_s": time.perf_counter() - t0}
        self.steps.append(rec)
        if not converged:
            raise JobFailure(f"step {rec['step']} (d = {d:.6g} mm) did not converge in {iterations} Newton "
                             "iterations (Kratos carries on after such a step; its result is not used)")
        if not math.isfinite(load):
            raise JobFailure(f"step {rec['step']} (d = {d:.6g} mm): the load is {load}")
        return rec

    def load(self, nodes=None) -> float:
        """The drive's reaction along its direction (N/mm, the full body); ``nodes``: the supports' instead (their
        reaction against the direction: the load balance)."""
        KM = self.KM
        sign, nodes = (1.0, self.drive.Nodes) if nodes is None else (-1.0, nodes)
        rx = sum(n.GetSolutionStepValue(KM.REACTION_X) for n in nodes)
        ry = sum(n.GetSolutionStepValue(KM.REACTION_Y) for n in nodes)
        return sign * self.load_factor * (rx * self.direction[0] + ry * self.direction[1])

    def pressure_rows(self, job: dict, *, step: int, load: float, d: float) -> list[dict]:
        """The slave surfaces' nodes at this state (see the module docstring)."""
        KM, CSMA = self.KM, self.CSMA
        scale = self.mp.ProcessInfo[KM.SCALE_FACTOR]
        rows = []
        for slave in job["slaves"]:
            part = self.mp.GetSubModelPart(slave["part"])
            stretch = _tributary_stretch(part)
            for node in part.Nodes:
                lm = node.GetSolutionStepValue(CSMA.LAGRANGE_MULTIPLIER_CONTACT_PRESSURE)
                p = -scale * lm if node.Is(KM.ACTIVE) else 0.0
                if not math.isfinite(p):
                    raise JobFailure(f"step {step}: a non-finite pressure at node {node.Id}")
                rows.append({"x_mm": node.X0, "y_mm": node.Y0, "p_MPa": max(p, 0.0) * stretch[node.Id],
                             "p_current_MPa": max(p, 0.0), "stretch": stretch[node.Id], "P_N_per_mm": load,
                             "h_mm": job["h_contact"], "d_mm": d, "run": job["run"], "step": step,
                             "body": slave["body"], "lm_negative": p < 0})
        rows.sort(key=lambda r: (r["body"], r["x_mm"], r["y_mm"]))
        return rows

    def info(self) -> dict:
        KM = self.KM
        return {"scale_factor": self.mp.ProcessInfo[KM.SCALE_FACTOR],
                "initial_penalty": self.mp.ProcessInfo[KM.INITIAL_PENALTY]}

    def finalize(self) -> None:
        self.sim.Finalize()


def _displacement(run: _Driven, job: dict, report) -> None:
    """Every step of the schedule; ``report(k, record)`` at the step that reaches target ``k``."""
    sched = job["schedule"]
    for d, k in zip(sched["d"], sched["report"], strict=True):
        rec = run.solve(float(d))
        if k is not None:
            report(int(k), rec)


def _force(run: _Driven, job: dict, report) -> None:
    """Ramp and secant to every target load (see the module docstring); ``report(k, record)`` at the state that
    carries target ``k``."""
    h, rtol, most = float(job["max_step"]), float(job["load_rtol"]), int(job["max_corrections"])
    points = [(0.0, 0.0)]  # (d, P) of the converged steps
    for k, target in enumerate(float(t) for t in job["targets"]):
        ramp = 0
        while points[-1][1] < target:
            d, P = points[-1]
            step = h
            if len(points) >= 2 and P > points[-2][1]:
                (d0, p0) = points[-2]
                step = min(h, max(0.05 * h, 1.05 * (target - P) * (d - d0) / (P - p0)))
            rec = run.solve(d + step)
            points.append((rec["d"], rec["P"]))
            ramp += 1
            if ramp > 100000:
                raise JobFailure(f"target {k} (P = {target:.6g} N/mm) not reached after {ramp} steps "
                                 f"(d = {rec['d']:.6g} mm, P = {rec['P']:.6g} N/mm)")
        below = max((p for p in points if p[1] < target), key=lambda p: p[0], default=(0.0, 0.0))
        above = points[-1]
        rec = run.steps[-1]
        for _ in range(most):
            if abs(rec["P"] / target - 1.0) <= rtol:
                break
            (d0, p0), (d1, p1) = points[-2], points[-1]
            d = d1 + (target - p1) * (d1 - d0) / (p1 - p0) if p1 != p0 else math.nan
            if not (min(below[0], above[0]) < d < max(below[0], above[0])):  # outside the bracket: regula falsi
                d = below[0] + (target - below[1]) * (above[0] - below[0]) / (above[1] - below[1])
            rec = run.solve(d)
            points.append((rec["d"], rec["P"]))
            if rec["P"] < target:
                below = (rec["d"], rec["P"])
            else:
                above = (rec["d"], rec["P"])
        if abs(rec["P"] / target - 1.0) > rtol:
            raise JobFailure(f"target {k}: the load {rec['P']:.6g} N/mm is {rec['P'] / target - 1:+.3%} from "
                             f"P = {target:.6g} N/mm after {most} secant steps (allowed: {rtol:g})")
        report(k, rec)


COLUMNS = ("x_mm", "y_mm", "p_MPa", "P_N_per_mm", "h_mm", "d_mm", "run", "step", "body", "p_current_MPa", "stretch")


def run_job(job: dict, folder: Path) -> tuple[list[dict], dict]:
    """One run: (its result rows, its record for ``kratos_job.json``)."""
    t0 = time.perf_counter()
    run = _Driven(job, folder)
    t1 = time.perf_counter()
    record = {"run": job["run"], "element": job["element"], "control": job["control"], "targets": job["targets"],
              "steps": run.steps, "failure": None}
    rows, reported = [], []

    def report(k: int, rec: dict) -> None:  # the state just solved
        rows.extend(run.pressure_rows(job, step=k, load=rec["P"], d=rec["d"]))
        reported.append({"step": k, "d": rec["d"], "P": rec["P"], "at_step": rec["step"]})

    record["reported"] = reported
    try:
        (_displacement if job["control"] == "displacement" else _force)(run, job, report)
        record.update(run.info())
    except JobFailure as exc:
        record["failure"] = str(exc)
    finally:
        t2 = time.perf_counter()
        run.finalize()
    record["times_s"] = {"initialize": t1 - t0, "solve": t2 - t1, "total": time.perf_counter() - t0}
    record["iterations"] = sum(s["iterations"] for s in run.steps)
    record["negative_multipliers"] = sum(r.pop("lm_negative") for r in rows)
    return rows, record


def main(argv: list[str] | None = None) -> int:
    """Run every job of the folder (module docstring)."""
    import os

    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 1 or not Path(argv[0]).is_dir():
        print("error: usage: kratos_job.py FOLDER (a folder written by workbench.external.mdpa)", file=sys.stderr)
        return EXIT_BAD_INPUT
    folder = Path(argv[0]).resolve()
    jobs = sorted(folder.glob("job_*.json"))
    if not jobs:
        print(f"error: {folder}: no job_*.json", file=sys.stderr)
        return EXIT_BAD_INPUT
    os.chdir(folder)  # the parameter files name the mdpa and the materials relative to it
    t0 = time.perf_counter()
    _kratos()
    summary = {"import_s": time.perf_counter() - t0, "threads": os.environ.get("OMP_NUM_THREADS"), "runs": []}
    rows: list[dict] = []
    failure = None
    for path in jobs:
        job = json.loads(path.read_text())
        r, rec = run_job(job, folder)
        summary["runs"].append(rec)
        if rec["failure"]:
            failure = f"Kratos run {job['run']!r} of {job['case']} at level {job['level']:g}: {rec['failure']}"
            break
        rows += r
    summary["failure"] = failure
    (folder / "kratos_job.json").write_text(json.dumps(summary, indent=1))
    if failure:
        print(f"error: {failure}", file=sys.stderr)
        return EXIT_FAILED
    with open(folder / "result.csv", "w") as fh:
        fh.write(",".join(COLUMNS) + "\n")
        for r in rows:
            fh.write(",".join(repr(r[c]) if isinstance(r[c], float) else str(r[c]) for c in COLUMNS) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
