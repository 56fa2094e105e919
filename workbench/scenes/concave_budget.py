"""Error budget of a concave case: every step's P, peak pressure and FEM patch widths over three grids.

The scene is solved again on the three ``[discretisation] budget_levels`` (h_c as a fraction of the smallest
predicted patch half-width), the grading refined with them (``growth - 1`` proportional to h_c, the case's
growth on the coarsest level: every element shrinks by the same factor). Each quantity goes through
:func:`workbench.error_budget.grid_study` in h (fine value, Richardson value, observed order, GCI, named status).

The concave body is the real geometry, not a truncated half-plane: ``truncation`` is 0. ``theory`` of a patch
width is eq. (4) of the paper, the Hertz width of that patch at its own FEM load and peak (the superposition
the scene tests), null for P and the peak. A step whose patch count differs between levels is named, not
studied. Every P row also carries the load balance ``|P - P_pressure| / P`` of every level.
"""

from __future__ import annotations

import dataclasses
import math

from cases.schema import Case, Run
from workbench.error_budget import grid_study
from workbench.scenes.base import SceneBudget

__all__ = ["concave_error_budget", "refined_run", "json_number"]


def refined_run(run: Run, *, h: float, h_coarse: float) -> Run:
    """The run on level h with the grading ``1 + (growth - 1) h / h_coarse`` (every element shrinks by the
    same factor, the far field too)."""
    growth = 1.0 + (run.discretisation.growth - 1.0) * h / h_coarse
    d = dataclasses.replace(run.discretisation, h_contact=h, growth=growth)
    return dataclasses.replace(run, discretisation=d)


def json_number(v):
    """A finite float, or None (JSON null) for None/NaN/inf."""
    return None if v is None or (isinstance(v, float) and not math.isfinite(v)) else float(v)


def concave_error_budget(case: Case, *, solve, progress=print) -> SceneBudget:
    """The budget of a concave case (empty without ``budget_levels``).

    Args:
        case: The case (its ``[discretisation] budget_levels``).
        solve: ``solve(run) -> Outcome`` (the pipeline's run, bound to the mesh cache and communicator).
        progress: One-line progress printer.
    """
    levels = sorted(case.discretisation.budget_levels)
    if not levels:
        return SceneBudget({}, title="Error budget (three grids; finite body, no truncation)")
    budget: dict[str, dict] = {}
    runs: dict[str, list] = {}
    for run in case.runs():
        steps = []
        for h in levels:
            o = solve(refined_run(run, h=h, h_coarse=levels[-1]))
            progress(f"[budget {run.label}] h_c = {h:g} a: {o.metrics['ndofs']} dofs")
            steps.append(o.metrics.get("steps", []))
        runs[run.label] = steps
        pre = "" if len(case.runs()) == 1 else f"{run.label}/"
        for i, fine in enumerate(steps[0]):
            per = [st[i] if i < len(st) else None for st in steps]
            if any(p is None for p in per):
                continue
            tag = f"{pre}step{i + 1} (d = {fine['d']:g} mm)"
            for q in ("P", "p_max"):
                budget[f"{tag} {q}"] = _row(levels, [p[q] for p in per], None)
            budget[f"{tag} P"]["load_balance_by_h"] = {
                str(h): abs(p["P"] - p["P_pressure"]) / abs(p["P"]) if p["P"] else None
                for h, p in zip(levels, per, strict=True)}
            counts = {len(p["patches"]) for p in per}
            if len(counts) != 1:
                budget[f"{tag} patches"] = {"fine": float(len(fine["patches"])), "extrapolated": None,
                                           "observed_order": None, "gci": None, "truncation": 0.0,
                                           "theory": None, "theory_in_band": None,
                                           "status": f"patch count differs between levels: {sorted(counts)}"}
                continue
            for k, pt in enumerate(fine["patches"]):
                budget[f"{tag} width_fem[{k}]"] = _row(
                    levels, [p["patches"][k]["width_fem"] for p in per], pt.get("width_eq4"))
    return SceneBudget(budget, title="Error budget (three grids; finite body, no truncation)", runs=runs)


def _row(levels, values, theory) -> dict:
    if not all(v is not None and math.isfinite(v) for v in values):
        return {"fine": json_number(values[0]), "extrapolated": None, "observed_order": None, "gci": None,
                "truncation": 0.0, "theory": json_number(theory), "theory_in_band": None,
                "status": "undefined (non-finite value on a level)",
                "by_h": {str(h): json_number(v) for h, v in zip(levels, values, strict=True)}}
    g = grid_study(tuple(levels), tuple(values))
    band = g.gci * abs(g.fine)
    return {"fine": g.fine, "extrapolated": g.extrapolated, "observed_order": json_number(g.observed_order),
            "gci": g.gci, "truncation": 0.0, "theory": json_number(theory),
            "theory_in_band": None if theory is None else bool(abs(theory - g.extrapolated) <= band),
            "status": g.status, "truncation_status": "n/a (finite body)",
            "by_h": dict(zip([str(v) for v in levels], values, strict=True)),
            "error_vs_theory": None if theory is None else abs(g.extrapolated - theory) / abs(theory),
            **({"theory_name": "eq. (4) Hertz width"} if theory is not None else {})}
