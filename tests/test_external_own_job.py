"""The workbench's own job of ``workbench external workbench`` / ``compare`` (:mod:`workbench.external.own_job`): a
level of two meshed bodies in force control starts from the coarser levels' solution (nested iteration), and lands
on the answer a cold solve gives."""

from __future__ import annotations

import csv

import numpy as np

from cases import load_case
from workbench.external.own_job import nests, solve_level


def _p(path) -> np.ndarray:
    with open(path, newline="") as fh:
        return np.array([float(row["p_MPa"]) for row in csv.DictReader(fh)])


def test_which_runs_nest():
    assert all(nests(r) for r in load_case("elastic_cylinder").runs())  # two bodies, force control
    assert not any(nests(r) for r in load_case("hertz_cylinder").runs())  # a rigid obstacle
    assert not any(nests(r) for r in load_case("patch_test").runs())  # displacement control, recorded steps


def test_a_two_body_level_nested_from_the_coarser_one_gives_the_cold_answer(tmp_path):
    cache = tmp_path / "mesh_cache"
    cold = solve_level("elastic_cylinder", 0.05, tmp_path / "cold", mesh_cache=cache)
    nested = solve_level("elastic_cylinder", 0.05, tmp_path / "nested", mesh_cache=cache, coarser=(0.1,))
    (c,), (n,) = (rec["geometries"]["elastic_cylinder"]["runs"] for rec in (cold, nested))
    assert c["nested_from"] == [] and [x["h_contact"] for x in n["nested_from"]] == [0.1]
    assert n["wall_s"] > n["solve_s"] + n["nested_from"][0]["solve_s"]  # the coarser solve is in the level's time
    assert n["iterations"] < c["iterations"], (n, c)
    assert abs(n["P"] - c["P"]) <= 1e-9 * abs(c["P"])
    pc, pn = _p(tmp_path / "cold" / "result.csv"), _p(tmp_path / "nested" / "result.csv")
    assert pc.shape == pn.shape and np.abs(pn - pc).max() <= 1e-6 * pc.max()


def _files(case_name: str) -> dict[str, str]:
    from workbench.external.own_job import file_names
    from workbench.external.scorers import scorer_for

    case = load_case(case_name)
    scored = scorer_for(case).runs(case)
    pairs = [(r.label, next(s.label for s in scored if r.label in (s.label, *s.aliases))) for r in case.runs()]
    return dict(zip([label for label, _ in pairs], file_names(pairs), strict=True))


def test_a_second_run_reported_as_one_benchmark_run_gets_a_file_of_its_own():
    # the finite parabola's two convective runs are both "profile": the second one not beside the first (the reader
    # refuses two loads for one run in a file), whichever run the file began with
    files = _files("halfplanes_finite_parabola")
    assert files == {"small": "result.csv", "profile": "result.csv", "pairing": "result_pairing.csv",
                     "neo_hookean": "result.csv", "svk": "result.csv"}, files
    assert sorted(_files("patch_test").values()) == ["result.csv", "result_node-to-segment.csv"]


def test_the_finite_parabola_has_model_bands_and_the_verdict_finds_them():
    """The saved bands of the case with several scenes keep each run's label ("small/p_max"); the verdict's key of
    a run named as its kinematics drops it ("p_max"), and finds the band under either."""
    from workbench.external.models import load_model_bands
    from workbench.external.scorers.verdict import model_matches

    case = load_case("halfplanes_finite_parabola")
    bands = load_model_bands(case.name, case=case)
    assert bands is not None, "regenerate: python -m workbench.external.models halfplanes_finite_parabola"
    names = [m["name"] for m in bands["models"]]
    assert names[0] == "halfplane/small" and len(names) == 3, names
    assert all("b_over_b0_moment" in m["study"] for m in bands["models"][1:])  # the convective ratio, per model
    small = bands["models"][0]["study"]["small/half_width_moment"]
    score = {"runs": [{"label": "small", "kinematics": "small"}],
             "studies": {"small/half_width_moment": {"extrapolated": small["extrapolated"], "uncertainty": 1e-6,
                                                     "group": {"run": "small", "quantity": "half_width_moment"}}}}
    rows = model_matches(score, bands, tolerance=1e-9)["small/half_width_moment"]["models"]
    assert [r["model"] for r in rows if r["contains"]] == ["halfplane/small"], rows
