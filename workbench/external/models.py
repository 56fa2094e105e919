"""The workbench's model hierarchy on a case's own scene, as bands an external result can fall into.

``python -m workbench.external.models CASE [--out FILE]`` solves the case's run with every model of the
hierarchy (:data:`workbench.studies.config.VALIDITY_MODELS`: traction halfplane/obstacle x kinematics
small/convective/finite, ``docs/models.md``; finite with the neo-Hookean law and the validity study's finite
settings) on the case's three ``budget_levels`` (h_c / a), and writes per model and measure the ratios to the
classical theory at each run's measured load (``p_max / p0``, ``half_width_moment / a``, ``half_width / a``, as
the scorer computes them: :mod:`workbench.external.score`), the grid study (:func:`workbench.error_budget.grid_study`:
extrapolated value and GCI band) and the model's fields (``traction``, ``kinematics``, ``material_model``: the
names a case's ``metrics.json`` gives every run). Saved for the scorer in ``workbench/external/model_bands/
<case>.json`` (the scorer reads JSON only and needs no solve); regenerate after a change of the solver or case.

:func:`consistent_models` is the verdict's use of it: the models whose band of a measure contains an external
extrapolated value (|external - model| <= U_external + U_model). Units: mm, N/mm, MPa; ratios dimensionless.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

__all__ = ["BANDS_DIR", "MEASURES", "scene_key", "load_model_bands", "consistent_models", "describe", "compute", "main"]

BANDS_DIR = Path(__file__).resolve().parent / "model_bands"
MEASURES = {"p_max": 2.0, "half_width_moment": 2.0, "half_width": 1.5}  # measure -> formal order
DESCRIPTION = {  # what each model assumes (docs/models.md), by (traction, kinematics)
    ("halfplane", "small"): "classical half-plane theory: vertical gap and traction at the undeformed surface",
    ("halfplane", "convective"): "Ciavarella-Hills convective: vertical traction, profile read at the displaced "
                                 "position",
    ("obstacle", "small"): "traction along the obstacle's normal, gap linearised at the undeformed point",
    ("obstacle", "convective"): "traction along the obstacle's normal at the deformed position (deformed normal), "
                                "small strain",
    ("obstacle", "finite"): "finite-strain hyperelasticity (neo-Hookean), contact at the deformed position",
}


def describe(model: dict) -> str:
    """``traction/kinematics`` and what the model assumes."""
    key = (model["traction"], model["kinematics"])
    return f"{key[0]}/{key[1]} ({DESCRIPTION.get(key, 'see docs/models.md')})"


def scene_key(run) -> dict:
    """What the saved bands depend on in a case run (mm, MPa): compared before they are used."""
    g, m, ld = run.geometry, run.material, run.loading
    return {"E": m.E, "nu": m.nu, "indenter": g.indenter, "radius": g.radius, "half_width": ld.half_width,
            "P": ld.P, "width_factor": g.width_factor, "height_factor": g.height_factor,
            "half_model": g.half_model, "budget_levels": list(run.discretisation.budget_levels)}


def load_model_bands(case: str, *, run=None, folder: Path | None = None) -> dict | None:
    """The saved model bands of ``case``: None when none are saved, or when ``run`` (the case's run) no longer
    matches the scene they were solved on (a changed case file: regenerate them)."""
    f = (folder or BANDS_DIR) / f"{case}.json"
    if not f.is_file():
        return None
    data = json.loads(f.read_text())
    if run is not None and data.get("scene") != json.loads(json.dumps(scene_key(run))):
        return None
    return data


def consistent_models(bands: dict, *, measure: str, value: float, uncertainty: float) -> list[dict]:
    """The models whose extrapolated ``measure`` lies within ``uncertainty`` + its own band of ``value``, each
    ``{"traction", "kinematics", "material_model", "extrapolated", "band", "distance"}`` (ratios)."""
    out = []
    for m in bands["models"]:
        st = m.get("study", {}).get(measure)
        if not st or st.get("extrapolated") is None or not math.isfinite(st["extrapolated"]):
            continue
        dist = abs(value - st["extrapolated"])
        if dist <= uncertainty + st["band"]:
            out.append({k: m[k] for k in ("traction", "kinematics", "material_model")}
                       | {"extrapolated": st["extrapolated"], "band": st["band"], "distance": dist})
    return out


def _ratios(cmp, result, run) -> dict:
    from measures.contact import moment_half_width

    th = cmp.theory
    s = result.samples
    finite = run.solver.kinematics == "finite"
    x = s.x[:, 0] if finite else s.s
    hw_m = 2.0 * moment_half_width(x, s.p, s.weight, center=0.0)
    return {"P": float(result.P), "p_max": cmp.p_max / th.p_ref, "half_width": cmp.half_width / th.half_width,
            "half_width_moment": hw_m / th.half_width}


def compute(case_name: str, *, mesh_cache: Path, progress=print) -> dict:
    """Solve the hierarchy on the case's budget levels (imports dolfinx; see the module docstring)."""
    import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

    from dataclasses import replace

    from mpi4py import MPI

    from cases import load_case
    from workbench.error_budget import grid_study
    from workbench.pipeline.run_case import run_one
    from workbench.studies.config import VALIDITY_MODELS
    from workbench.studies.validity import FINITE_CUTBACKS, FINITE_MAX_IT, FINITE_STEPS, FINITE_THETA

    case = load_case(case_name)
    levels = sorted(case.runs()[0].discretisation.budget_levels, reverse=True)
    models = []
    for traction, kinematics in VALIDITY_MODELS:
        finite = kinematics == "finite"
        rec = {"traction": traction, "kinematics": kinematics,
               "material_model": "neo_hookean" if finite else "linear", "levels": {}, "study": {}}
        for lv in levels:
            run = case.runs(h_contact=lv)[0]
            sol = replace(run.solver, traction=traction, kinematics=kinematics,
                          theta=FINITE_THETA if finite else run.solver.theta)
            run = replace(run, solver=sol, material=replace(run.material, model=rec["material_model"]),
                          loading=replace(run.loading, steps=FINITE_STEPS if finite else run.loading.steps))
            extra = {"max_cutbacks": FINITE_CUTBACKS, "max_it": FINITE_MAX_IT} if finite else {}
            if finite:
                extra["material_model"] = rec["material_model"]
            out = run_one(run, name=f"models_{case.name}", mesh_cache=mesh_cache, comm=MPI.COMM_SELF,
                          progress=lambda _m: None, **extra)
            rec["levels"][f"{lv:g}"] = r = _ratios(out.comparison, out.result, run)
            progress(f"{traction}/{kinematics} h_c/a = {lv:g}: P = {r['P']:.6g} N/mm, p_max/p0 = {r['p_max']:.6f}, "
                     f"a_mom/a = {r['half_width_moment']:.6f}")
        hs = tuple(levels)
        for key, order in MEASURES.items():
            f = tuple(rec["levels"][f"{h:g}"][key] for h in hs)
            gs = grid_study(hs, f, expected_order=order, formal_order=order)
            rec["study"][key] = {"fine": gs.fine, "extrapolated": gs.extrapolated, "gci": gs.gci,
                                 "band": gs.gci * abs(gs.fine), "status": gs.status,
                                 "observed_order": gs.observed_order if math.isfinite(gs.observed_order) else None}
        models.append(rec)
    run = case.runs()[0]
    g, a = run.geometry, run.loading.half_width
    return {"case": case.name, "scene": scene_key(run), "levels_h_over_a": levels, "nu": run.material.nu,
            "a_over_R": None if g.radius is None or a is None else a / g.radius,
            "theory": "ratios to Hertz (p0, a) at each run's measured load P", "models": models,
            "command": f"python -m workbench.external.models {case.name}"}


def main(argv: list[str] | None = None) -> int:
    """Compute and save the model bands of a case (exit 0; 2 bad case)."""
    from cases import CaseError, load_case
    from workbench.paths import default_paths

    p = argparse.ArgumentParser(prog="python -m workbench.external.models", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("case")
    p.add_argument("--out", default=None, help="the JSON file (default workbench/external/model_bands/CASE.json)")
    args = p.parse_args(argv)
    try:
        case = load_case(args.case)
    except CaseError as exc:
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    data = compute(case.name, mesh_cache=default_paths(None).mesh_cache, progress=lambda m: print(m, flush=True))
    out = Path(args.out) if args.out else BANDS_DIR / f"{case.name}.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(data, indent=1, allow_nan=False) + "\n")
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
