"""``workbench score`` on the workbench's own runs, one CI-level case per scene (issue 36 acceptance): each run
written in the external csv format (:mod:`workbench.external.own_results`: run, step, body columns, the samples at
full precision) scores back to the case's own key numbers to 1e-9.

Requirements: the scorer measures an external result with the code the workbench measures its own runs with, so
the same samples give the same numbers: block (p_max, edge half-width, load, RMS; b/b0 of the convective pair),
concave (per step P and p_max, per patch load, edge and moment widths, eq. (4)/(5), the Hertz superposition),
two bodies (the exact circle's p_max, edge and moment half-widths and their errors; the patch test's uniformity
for both pairings), two half-planes (p_max and both half-widths per run, b/b0 from the edges and the moments).
Each case runs once at its CI level in-process (``run_one``, a few seconds each).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
from cases import load_case
from workbench.external.own_results import groups_csv, outcome_groups
from workbench.external.score import main as score_main
from workbench.external.scorers import scorer_for
from workbench.scenes import scene_for

RTOL = 1e-9


def _close(a: float, b: float, what: str, rtol: float = RTOL) -> None:
    assert math.isfinite(a) and math.isfinite(b), (what, a, b)
    assert abs(a - b) <= rtol * max(abs(a), abs(b), 1e-300), f"{what}: score {a!r} vs own {b!r} ({a / b - 1:.3e})"


@pytest.fixture(scope="module")
def own_runs(tmp_path_factory):
    """case -> (case, outcomes, the scene's judge) at the CI level, solved once per module."""
    from mpi4py import MPI

    from workbench.pipeline.run_case import run_one

    cache: dict = {}
    mesh = Path(tmp_path_factory.mktemp("mesh"))

    def solve(name: str):
        if name not in cache:
            case = load_case(name)
            runs = case.runs(h_contact=case.discretisation.ci_level)
            outcomes = [run_one(r, name=name, mesh_cache=mesh, comm=MPI.COMM_SELF, progress=lambda _m: None)
                        for r in runs]
            cache[name] = (case, outcomes, scene_for(runs[0]).judge(case, outcomes))
        return cache[name]

    return solve


def _scored(case, outcomes, folder: Path, *, only: str | None = None) -> dict:
    """The outcomes written as one external csv (the scorer's run labels, the slave body) and scored by the
    command; ``score.json``."""
    scorer = scorer_for(case)
    runs = scorer.runs(case)
    groups = []
    for o in outcomes:
        if only is not None and o.run.label != only:
            continue
        srun = next(r for r in runs if o.run.label == r.label or o.run.label in r.aliases)
        groups += outcome_groups(o, label=srun.label, body=scorer.bodies(case)[0].name)
    folder.mkdir(parents=True, exist_ok=True)
    f = folder / "own.csv"
    f.write_text(groups_csv(groups))
    assert score_main([case.name, str(f), "--out", str(folder / "out")]) == 0
    return json.loads((folder / "out" / f"score_{case.name}" / "score.json").read_text())


def _level(score: dict, run: str, step: int = 0) -> dict:
    return next(lv for lv in score["levels"] if lv["run"] == run and lv["step"] == step and lv["role"] == "slave")


def test_block_convective_pair_round_trip(own_runs, tmp_path):
    case, outcomes, judged = own_runs("parabola_convective")
    score = _scored(case, outcomes, tmp_path)
    for o in outcomes:
        lv, m = _level(score, o.run.label), o.metrics
        for key, mk in (("P", "P"), ("P_integral", "P_pressure"), ("p_max", "p_max"),
                        ("half_width", "patch_half_width")):
            _close(lv[key], m[mk], f"{o.run.label} {key}")
        rms = m["errors"]["rms" if o.run.label == "small" else "rms_vs_classical"]
        _close(lv["errors"]["rms"], rms, f"{o.run.label} rms")
        _close(abs(lv["errors"]["p_max"]), m["errors"]["p_max" if o.run.label == "small" else "p_max_vs_classical"],
               f"{o.run.label} p_max error")
    small, conv = _level(score, "small"), _level(score, "convective")
    _close(conv["quantities"]["half_width"] / small["quantities"]["half_width"], judged.analytic["b_over_b0_fem"],
           "b/b0 (edges)")


def test_block_wedge_two_scenes_round_trip(own_runs, tmp_path):
    case, outcomes, _ = own_runs("wedge")
    score = _scored(case, outcomes, tmp_path)
    assert {r["label"] for r in score["runs"]} == {"theta=pi/20", "theta=pi/5"}
    for o in outcomes:
        lv, m = _level(score, o.run.label), o.metrics
        for key, mk in (("P", "P"), ("P_integral", "P_pressure"), ("half_width", "patch_half_width")):
            _close(lv[key], m[mk], f"{o.run.label} {key}")
        _close(abs(lv["errors"]["half_width"]), m["errors"]["half_width"], f"{o.run.label} half-width error")
        _close(lv["errors"]["rms"], m["errors"]["rms"], f"{o.run.label} rms")


def _numbers(a, b, where: str) -> int:
    """Every number of ``b`` (the case's step entry) in ``a`` (the score's) to RTOL; the count compared."""
    if isinstance(b, dict):
        return sum(_numbers(a[k], v, f"{where}.{k}") for k, v in b.items())
    if isinstance(b, list):
        assert len(a) == len(b), where
        return sum(_numbers(x, y, f"{where}[{i}]") for i, (x, y) in enumerate(zip(a, b, strict=True)))
    if isinstance(b, float) and math.isfinite(b):
        _close(float(a), b, where, rtol=RTOL if abs(b) > 1e-12 else 1.0)
        return 1
    return 0


def test_concave_per_step_and_patch_round_trip(own_runs, tmp_path):
    """Every number of every step's entry of metrics.json (loads, peaks, patches and their widths, eq. (4)/(5),
    the LCP pairs, the fits and the superposition) to 1e-9, the pressure's resultant (summed from the samples
    with the particle's normal; the FEM assembles it) to 1e-6."""
    case, outcomes, _ = own_runs("concave_symmetric")
    (o,) = outcomes
    score = _scored(case, outcomes, tmp_path)
    compared = 0
    for i, step in enumerate(o.metrics["steps"]):
        lv = _level(score, "small", i)
        mine = lv["step_measures"]
        _close(lv["P"], step["P"], f"step {i} P")
        # the resultant along the particle's direction: the FEM assembles its form, the score sums the samples
        # with the particle's normal at the sample points (measured 4.4e-9 to 1.1e-7 apart: another quadrature)
        _close(mine["P_pressure"], step["P_pressure"], f"step {i} P_pressure (samples)", rtol=1e-6)
        own = {k: v for k, v in step.items() if k not in ("label", "iterations", "warnings", "P_pressure")}
        compared += _numbers(mine, own, f"step {i}")
    assert compared > 100
    assert score["studies"] == {} and "fewer than three" in score["verdict"]  # one level: no grid study


def test_two_body_cylinder_round_trip(own_runs, tmp_path):
    case, outcomes, _ = own_runs("elastic_cylinder_dissimilar")
    (o,) = outcomes
    score = _scored(case, outcomes, tmp_path)
    lv, m = _level(score, "small"), o.metrics
    for key, mk in (("P", "P"), ("P_integral", "P_pressure"), ("p_max", "p_max"), ("half_width", "patch_half_width"),
                    ("half_width_moment", "half_width_moment")):
        _close(lv[key], m[mk], key)
    for key in ("p_max", "half_width", "half_width_moment"):
        _close(lv["errors"][key], m["analytic"]["signed"][key], f"{key} error")
    _close(lv["errors"]["rms"], m["errors"]["rms"], "rms")


@pytest.mark.parametrize("pairing", ["mortar", "node-to-segment"])
def test_patch_test_uniformity_round_trip(own_runs, tmp_path, pairing):
    case, outcomes, _ = own_runs("patch_test")
    o = next(o for o in outcomes if o.run.label == pairing)
    score = _scored(case, outcomes, tmp_path, only=pairing)
    key = "patch_uniformity" if pairing == "mortar" else "patch_uniformity_node_to_segment"
    lv = _level(score, "small")
    assert lv["quantities"]["uniformity"] == pytest.approx(o.metrics["errors"][key], rel=RTOL, abs=1e-15)
    _close(lv["P"], o.metrics["P"], "P")
    st = score["studies"]["uniformity"]
    assert st["kind"] == "bound" and st["within_tolerance"] is (pairing == "mortar")


def test_halfplanes_round_trip(own_runs, tmp_path):
    case, outcomes, judged = own_runs("halfplanes_beta_pos")
    score = _scored(case, outcomes, tmp_path)
    for o in outcomes:
        lv, m = _level(score, o.run.label), o.metrics
        for key, mk in (("P", "P"), ("P_integral", "P_pressure"), ("p_max", "p_max"),
                        ("half_width", "patch_half_width"), ("half_width_moment", "half_width_moment")):
            _close(lv[key], m[mk], f"{o.run.label} {key}")
    small, conv = _level(score, "small"), _level(score, "convective")
    for q, key in (("half_width", "b_over_b0_fem"), ("half_width_moment", "b_over_b0_moment_fem")):
        _close(conv["quantities"][q] / small["quantities"][q], judged.analytic[key], key)


def test_own_three_levels_are_their_own_model(own_runs, tmp_path):
    """hertz_cylinder's own run on the model bands' three levels, scored with the levels as --h: every study
    extrapolates to the saved halfplane/small band's value (the bands are measured by the same scorer), and the
    verdict names that model and no model of another traction."""
    from mpi4py import MPI

    from workbench.external.models import load_model_bands, model_levels
    from workbench.pipeline.run_case import run_one

    case = load_case("hertz_cylinder")
    bands = load_model_bands(case.name, case=case)
    assert bands is not None, "regenerate: python -m workbench.external.models hertz_cylinder"
    files = []
    for lv in model_levels(case):
        (run,) = case.runs(h_contact=lv)
        o = run_one(run, name="own3", mesh_cache=tmp_path / "mesh", comm=MPI.COMM_SELF, progress=lambda _m: None)
        f = tmp_path / f"h{lv:g}.csv"
        f.write_text(groups_csv(outcome_groups(o, label="small", body="body")))
        files.append(str(f))
    out = tmp_path / "out"
    assert score_main(["hertz_cylinder", *files, "--h", *map(str, model_levels(case)), "--out", str(out)]) == 0
    score = json.loads((out / "score_hertz_cylinder" / "score.json").read_text())
    own = next(m for m in bands["models"] if m["name"] == "halfplane/small")
    # the saved bands were measured on another machine (or an earlier round-off of the same solver): the solves
    # meet snes_rtol 1e-10, which the three-level extrapolation amplifies by at most its factors, so the values
    # agree on the scale of the solver's tolerance (1e-8), not bit for bit; the bands are 1.6e-5 to 1.9e-3 of them
    for key, st in own["study"].items():
        _close(score["studies"][key]["extrapolated"], st["extrapolated"], key, rtol=1e-8)
    inside = [r["model"] for r in score["models"]["models"] if r["contains"]]
    assert "halfplane/small" in inside and not any(m.startswith("obstacle") for m in inside), inside
