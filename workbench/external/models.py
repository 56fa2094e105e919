"""The workbench's model hierarchy on a case's own scene, as bands an external result can fall into.

``python -m workbench.external.models CASE [--out FILE]`` solves the case's scene with every model of the hierarchy
that applies to it (:func:`model_scope`: ``docs/models.md``; traction halfplane/obstacle x kinematics
small/convective/finite for a rigid indenter, the finite runs neo-Hookean with the validity study's finite settings;
the pairings mortar/node-to-segment for two elastic bodies; the two convection models of two half-planes) on the
case's three budget levels (``budget_levels``, else the three finest ``levels``; a run of two meshed bodies in force
control solves each level from the coarser one's solution, as ``make run``'s budget and the own job do:
:func:`workbench.external.own_job.nests`), writes each run as an external
result (:mod:`workbench.external.own_results`) and measures it with the scorer of the case's scene
(:mod:`workbench.external.scorers`): the same quantities, the same grid study (extrapolated value and band) an
external result gets. For a case with a convective pair each model's ratio b/b0 over the halfplane/small model's is
saved too (what b/b0 is when the convective run is that model). A model that does not apply is listed with the
reason (``not_applicable``), never solved or invented.

Saved for the scorer in ``workbench/external/model_bands/<case>.json`` (the scorer reads JSON only and needs no
solve) with the case's physics (:func:`case_key`); a changed case does not use them. Regenerate after a change of the
solver, the scorer's measures or the case. :func:`workbench.external.scorers.verdict.model_matches` is the verdict's
use of them. Units: mm, N/mm, MPa; ratios dimensionless.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import time
from pathlib import Path
from typing import NamedTuple

__all__ = ["BANDS_DIR", "ModelSpec", "NotApplicable", "model_scope", "case_key", "load_model_bands", "describe",
           "model_levels", "compute", "main"]

BANDS_DIR = Path(__file__).resolve().parent / "model_bands"
DESCRIPTION = {  # what each model assumes (docs/models.md), by (traction, kinematics)
    ("halfplane", "small"): "classical half-plane theory: vertical gap and traction at the undeformed surface",
    ("halfplane", "convective"): "Ciavarella-Hills convective: vertical traction, profile read at the displaced "
                                 "position",
    ("obstacle", "small"): "traction along the obstacle's normal, gap linearised at the undeformed point",
    ("obstacle", "convective"): "traction along the obstacle's normal at the deformed position (deformed normal), "
                                "small strain",
    ("obstacle", "finite"): "finite-strain hyperelasticity (neo-Hookean), contact at the deformed position",
}


class ModelSpec(NamedTuple):
    """One model of the hierarchy: its name, the solver's traction and kinematics, the material law, what else it
    changes in the case's run (geometry fields: a pairing, a convection model), and what it assumes in words."""

    name: str
    traction: str
    kinematics: str
    material_model: str = "linear"
    geometry: tuple[tuple[str, str], ...] = ()
    description: str = ""


class NotApplicable(NamedTuple):
    """A model of the hierarchy that does not apply to a scene, and why."""

    name: str
    reason: str


def _spec(traction: str, kinematics: str, *, geometry=(), suffix: str = "", what: str = "") -> ModelSpec:
    name = f"{traction}/{kinematics}" + (f" ({suffix})" if suffix else "")
    text = what or DESCRIPTION.get((traction, kinematics), "see docs/models.md")
    return ModelSpec(name, traction, kinematics, "neo_hookean" if kinematics == "finite" else "linear",
                     tuple(geometry), f"{name} ({text})")


def model_scope(case) -> tuple[list[ModelSpec], list[NotApplicable]]:
    """The models that apply to the case's scene and those that do not, with the reason (module docstring)."""
    scene = case.runs()[0].geometry.scene
    no_finite_half = NotApplicable("halfplane/finite", "refused by the hierarchy: finite strain needs the traction "
                                   "along the obstacle's current normal (docs/models.md)")
    if scene == "block":
        return ([_spec(t, k) for t, k in (("halfplane", "small"), ("halfplane", "convective"), ("obstacle", "small"),
                                          ("obstacle", "convective"), ("obstacle", "finite"))], [no_finite_half])
    if scene == "concave":
        return ([_spec("obstacle", "small"), _spec("obstacle", "convective")],
                [NotApplicable("halfplane/small, halfplane/convective", "the half-plane traction is vertical, but the "
                               "concave scene presses the particle along its design direction into a curved surface: "
                               "the vertical gap is not the problem's (the case's own runs use the obstacle traction)"),
                 NotApplicable("obstacle/finite", "the concave scene does not support finite kinematics (its schema: "
                               "finite = False)"), no_finite_half])
    two = NotApplicable("obstacle/small, obstacle/convective, obstacle/finite", "two elastic bodies: the contact "
                        "traction acts along the slave's normal on both bodies; the obstacle traction is a rigid "
                        "obstacle's")
    if scene == "two_body":
        pair = [_spec("halfplane", "small", geometry=(("pairing", p),), suffix=p.replace("_", "-"),
                      what=f"two elastic bodies, small strain, {p.replace('_', '-')} pairing of the non-matching "
                           "meshes")
                for p in ("mortar", "node_to_segment")]
        return pair, [two, NotApplicable("halfplane/convective", "the two-body scene supports small "
                                         "kinematics only (its schema)"), no_finite_half]
    if scene == "halfplanes":
        models = [_spec("halfplane", "small", what="two elastic half-planes, small strain: Hertz / the classical wedge "
                        "at E*")]
        models += [_spec("halfplane", "convective", geometry=(("convection", c),), suffix=f"{c} convection",
                         what=("Ciavarella-Hills: the profile moves with the upper body's material point"
                               if c == "profile" else "the full convective pairing of the two meshes"))
                   for c in ("profile", "pairing")]
        return models, [two, no_finite_half,
                        NotApplicable("finite strain of two elastic bodies", "the scene's finite runs (both bodies "
                                      "hyperelastic, the traction along the deformed master normal, the upper body "
                                      "the meshed parabola capped at 3 b0: cases/halfplanes_finite_parabola.toml) "
                                      "are not a model of this hierarchy yet: they solve another body than the flat "
                                      "pair with the gap put in, so no bands are saved for them")]
    return [], [NotApplicable("all", f"no model hierarchy is defined for scene {scene!r}")]


def describe(model: dict) -> str:
    """A saved model's name and what it assumes."""
    return model.get("description") or model["name"]


def case_key(case) -> list:
    """What the saved bands depend on in a case: every run's geometry, material, bodies and loading, and the
    levels they were solved on (mm, MPa; JSON-ready)."""
    out = []
    for run in case.runs():
        out.append(json.loads(json.dumps({"label": run.label, "geometry": dataclasses.asdict(run.geometry),
                                          "material": dataclasses.asdict(run.material),
                                          "bodies": [dataclasses.asdict(b) for b in run.bodies],
                                          "loading": dataclasses.asdict(run.loading)}, default=str)))
    return out + [{"levels": list(model_levels(case))}]


def model_levels(case) -> tuple[float, ...]:
    """The three levels the models are solved on (h_c fractions, coarse first): the budget levels, else the three
    finest levels."""
    disc = case.runs()[0].discretisation
    levels = disc.budget_levels or disc.levels
    return tuple(sorted(levels, reverse=True)[-3:])


def load_model_bands(name: str, *, case=None, folder: Path | None = None) -> dict | None:
    """The saved model bands of case ``name``: None when none are saved, when they are in an older layout, or when
    ``case`` (the loaded case) no longer matches the scene they were solved on (a changed case file)."""
    f = (folder or BANDS_DIR) / f"{name}.json"
    if not f.is_file():
        return None
    data = json.loads(f.read_text())
    if data.get("layout") != 2:
        return None
    if case is not None and data.get("case_key") != case_key(case):
        return None
    return data


def _solve_records(case, scorer, spec: ModelSpec, *, physics, level: float, mesh_cache: Path,
                   start=None) -> tuple[list[dict], object]:
    """One model on one scene at one level: solved (dolfinx), written as an external result and measured; with the
    solve's nested start for the next finer level (``start``: the coarser level's, where
    :func:`workbench.external.own_job.nests` allows it, as the own job and ``make run``'s budget solve their levels;
    None: cold)."""
    from mpi4py import MPI

    from workbench.external.own_results import outcome_groups
    from workbench.external.results import mirror_half
    from workbench.external.scorers.runs import Group
    from workbench.pipeline.run_case import run_one
    from workbench.studies.validity import FINITE_CUTBACKS, FINITE_MAX_IT, FINITE_STEPS, FINITE_THETA

    base = next(r for r in case.runs(h_contact=level) if r.label == physics.run.label)
    finite = spec.kinematics == "finite"
    sol = dataclasses.replace(base.solver, traction=spec.traction, kinematics=spec.kinematics,
                              theta=FINITE_THETA if finite else base.solver.theta)
    # the model's material law for the body and for every meshed body of a scene with several (the finite
    # parabola's neo-Hookean runs, solved as a small-strain model, are linear bodies: the two-body checks refuse a
    # hyperelastic body at small kinematics)
    run = dataclasses.replace(base, solver=sol, material=dataclasses.replace(base.material, model=spec.material_model),
                              bodies=tuple(dataclasses.replace(b, model=spec.material_model) for b in base.bodies),
                              geometry=dataclasses.replace(base.geometry, **dict(spec.geometry)),
                              loading=dataclasses.replace(base.loading, steps=FINITE_STEPS if finite
                                                          else base.loading.steps))
    extra = {"max_cutbacks": FINITE_CUTBACKS, "max_it": FINITE_MAX_IT, "material_model": spec.material_model} \
        if finite else {}
    from workbench.external.own_job import nests

    nested = nests(run)
    if start is not None and nested:
        extra["nested_start"] = start
    outcome = run_one(run, name=f"models_{case.name}", mesh_cache=mesh_cache, comm=MPI.COMM_SELF,
                      progress=lambda _m: None, **extra)
    slave = scorer.bodies(case)[0]
    records = []
    for g in outcome_groups(outcome, label=physics.label, body=slave.name, path=f"{spec.name} h={level:g}"):
        res = mirror_half(g) if scorer.symmetric(case) else g
        rec = scorer.measure(case, Group(physics, g.step, slave, res), h=level, samples_per_element=1)
        records.append({k: v for k, v in rec.items() if not k.startswith("_")} | {"role": "slave", "level": level})
    return records, (outcome.result.nested_start if nested else None)


def _model_key(key: str, scenes) -> str:
    """A scorer's study key of a model's run as the bands name it: without the run's label where the case has one
    scene (:func:`workbench.external.scorers.verdict.model_key` maps an external key the same way)."""
    for p in scenes:
        if p.physics is None and key.startswith(f"{p.label}/"):
            return key[len(p.label) + 1:]
    return key


def _study(row: dict) -> dict:
    keep = ("fine", "extrapolated", "observed_order", "gci", "status", "theory", "ratios", "h", "kind", "max")
    return {k: row[k] for k in keep if k in row} | {"band": row.get("band")}  # the GCI band: a model's load
    # balance is its pressure integral against its reaction (the obstacle traction is not vertical), not an error


def compute(case_name: str, *, mesh_cache: Path, progress=print) -> dict:
    """Solve the applicable models on the case's levels (imports dolfinx; see the module docstring)."""
    import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

    import workbench.scenes  # noqa: F401
    from cases import load_case
    from workbench.external.scorers import scorer_for

    case = load_case(case_name)
    scorer = scorer_for(case)
    specs, not_applicable = model_scope(case)
    levels = model_levels(case)
    scenes = [r for r in scorer.runs(case) if not r.added and (r.physics is not None or r.kinematics == "small")]
    records: dict[str, list[dict]] = {}
    timing = {}
    for spec in specs:
        t0 = time.perf_counter()
        for physics in scenes:
            start = None
            for lv in levels:  # coarse first: a finer level of two bodies starts from the coarser one
                recs, start = _solve_records(case, scorer, spec, physics=physics, level=lv, mesh_cache=mesh_cache,
                                             start=start)
                records.setdefault(spec.name, []).extend(recs)
                q = recs[-1]["quantities"]
                progress(f"{spec.name} [{physics.label}] h_c = {lv:g}: P = {recs[-1]['P']:.6g} N/mm, "
                         + ", ".join(f"{k} = {v:.6g}" for k, v in list(q.items())[:3]))
        timing[spec.name] = time.perf_counter() - t0
    models = []
    reference = records.get(specs[0].name) if specs and specs[0].name.startswith("halfplane/small") else None
    convective_pair = any(r.kinematics == "convective" for r in scorer.runs(case))
    small_label = next((p.label for p in scenes if p.kinematics == "small"), scenes[0].label if scenes else None)
    for spec in specs:
        studies = scorer.studies(case, records[spec.name])
        study = {_model_key(k, scenes): _study(v) for k, v in studies.items() if "[" not in k or "]" != k[-1]
                 or k.split("[", 1)[0] not in ("b_over_b0", "b_over_b0_moment")}
        if convective_pair and reference is not None and spec.name != specs[0].name:
            # the case's convective run (its label: "convective", or the finite parabola's "profile")
            conv = next(r for r in scorer.runs(case) if r.kinematics == "convective")
            # the model's run measured as the small scene, as if it were the convective run: one record per level
            # (a case with several scenes, e.g. small, profile and the finite runs, measures each model once per
            # scene; all of them relabelled made three records of one level)
            relabelled = [r | {"run": conv.label} for r in records[spec.name] if r["run"] == small_label]
            ratio = scorer.studies(case, [r for r in reference if r["run"] == small_label] + relabelled)
            for key in ("b_over_b0", "b_over_b0_moment"):
                if f"{key}[{conv.label}]" in ratio:
                    study[key] = _study(ratio[f"{key}[{conv.label}]"])
        models.append({"name": spec.name, "traction": spec.traction, "kinematics": spec.kinematics,
                       "material_model": spec.material_model, "variant": dict(spec.geometry) or None,
                       "description": spec.description, "seconds": round(timing[spec.name], 1), "study": study})
    return {"layout": 2, "case": case.name, "case_key": case_key(case), "levels": list(levels),
            "scene": case.runs()[0].geometry.scene, "models": models,
            "not_applicable": [n._asdict() for n in not_applicable],
            "measured_as": "the scorer of the case's scene on the model's own run written as an external result",
            "command": f"python -m workbench.external.models {case.name}"}


def main(argv: list[str] | None = None) -> int:
    """Compute and save the model bands of a case (exit 0; 2 bad case)."""
    import workbench.scenes  # noqa: F401
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
    t0 = time.perf_counter()
    data = compute(case.name, mesh_cache=default_paths(None).mesh_cache, progress=lambda m: print(m, flush=True))
    data["seconds"] = round(time.perf_counter() - t0, 1)
    out = Path(args.out) if args.out else BANDS_DIR / f"{case.name}.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    from workbench.atomic import strict_json

    out.write_text(json.dumps(strict_json(data, found={}), indent=1, allow_nan=False) + "\n")
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
