"""The concave map (issue 40, item 3): the error classes and the models' comparison by hand, the family members
named by a case file, the paper's two designs as the present cases, and the tiny configuration end to end."""

from __future__ import annotations

import json
import math

import pytest

from analytic import hertz
from workbench.studies.concave_map_config import TINY, ConcaveMapConfig, MapDesign
from workbench.studies.concave_map_models import (
    FemPatch,
    PredictedPatch,
    classify,
    compare,
    hertz_at_pairs,
    intersection_pairs,
)
from workbench.studies.concave_map_report import hertz_rule

E_STAR = 214000.0 / (1 - 0.3**2)


@pytest.mark.parametrize(("error", "cls"), [(0.0, "1%"), (0.0099, "1%"), (0.01, "1%"), (0.0101, "5%"), (-0.03, "5%"),
                                            (0.05, "5%"), (0.07, "10%"), (0.1, "10%"), (0.1001, "beyond"),
                                            (3.0, "beyond"), (math.inf, "beyond"), (math.nan, "n/a")])
def test_classify_by_hand(error, cls):
    assert classify(error) == cls


def test_compare_by_hand():
    fem = [FemPatch(center=1.0, half_width=0.5, p_max=100.0, P=80.0)]
    # width 1.02 against 1.0 (2 %), p0 103 against 100 (3 %), P 0.9 against 1.0 (10 %)
    e = compare(fem, [PredictedPatch(0.49, 1.51)], 103.0, P_model=0.9, P_fem=1.0)
    assert e.width == pytest.approx(0.02) and e.p0 == pytest.approx(0.03) and e.P == pytest.approx(0.1)
    assert e.worst == pytest.approx(0.1) and e.cls == "10%"
    e = compare(fem, [PredictedPatch(0.495, 1.505)], 100.5)  # no load law: P not compared
    assert math.isnan(e.P) and e.worst == pytest.approx(0.01) and e.cls == "1%"
    # a FEM patch without a prediction, or a different number of patches, is a width error of 1 (beyond)
    assert compare(fem, [], math.nan).cls == "beyond"
    two = [PredictedPatch(0.5, 1.5), PredictedPatch(3.0, 3.1)]
    assert compare(fem, two, 100.0, same_count=True).width == 1.0
    assert compare([], [], math.nan).cls == "n/a"


def test_hertz_at_pairs_is_hertz_for_one_pair():
    """One pair in one FEM patch carries its whole load: 2a of eq. (5) and Hertz's p0 = 2P/(pi a)."""
    P, R = 500.0, 234.0
    fem = [FemPatch(center=2.0, half_width=0.4, p_max=600.0, P=P)]
    pred, p0 = hertz_at_pairs(fem, [(2.01, R)], E_star=E_STAR)
    a = 0.5 * hertz.patch_width_eq5(P, R, E_STAR)
    assert a == pytest.approx(math.sqrt(4 * P * R / (math.pi * E_STAR)), rel=1e-12)
    assert pred == [PredictedPatch(2.01 - a, 2.01 + a)]
    assert p0 == pytest.approx(2 * P / (math.pi * a), rel=1e-6)
    # two pairs near one FEM patch share its load equally; the prediction spans both Hertz patches
    pred, _ = hertz_at_pairs(fem, [(1.9, R), (2.1, R)], E_star=E_STAR)
    a2 = 0.5 * hertz.patch_width_eq5(P / 2, R, E_STAR)
    assert pred[0].lo == pytest.approx(1.9 - a2) and pred[0].hi == pytest.approx(2.1 + a2)
    assert hertz_at_pairs(fem, [(2.0, -5.0)], E_star=E_STAR) == ([], pytest.approx(math.nan, nan_ok=True))


def test_intersection_pairs_by_hand():
    """The crossings bounding one FEM patch become one pair at their mean s with their mean R; a crossing of no
    positive radius is dropped; each crossing goes to its nearest FEM patch."""
    fem = [FemPatch(center=1.0, half_width=0.2, p_max=1.0, P=1.0), FemPatch(center=5.0, half_width=0.1, p_max=1.0,
                                                                            P=1.0)]
    got = intersection_pairs(fem, [(0.7, 40.0), (1.3, 60.0), (4.9, 20.0), (5.2, -3.0)])
    assert got == [(pytest.approx(1.0), pytest.approx(50.0)), (4.9, 20.0)]
    assert intersection_pairs([], [(1.0, 2.0)]) == []


def _point(sep, err):
    return {"separation_over_contact": sep, "models": {"hertz_lcp": {"worst": err}}}


def test_hertz_rule_by_hand():
    pts = [_point(1.0, 0.5), _point(2.0, 0.08), _point(3.0, 0.04), _point(5.0, 0.01), _point(8.0, 0.02)]
    rule = hertz_rule(pts)
    assert rule["threshold"] == 3.0 and rule["n_above"] == 3 and rule["n_below"] == 2
    assert rule["worst_above"] == pytest.approx(0.04)
    assert math.isinf(hertz_rule([_point(1.0, 0.5), _point(9.0, 0.2)])["threshold"])
    assert hertz_rule([])["threshold"] is None


def test_config_is_a_map_and_refuses_bad_values():
    cfg = ConcaveMapConfig()
    assert len(cfg.designs) >= 50 and len(cfg.approaches_conformal) >= 5 and len(cfg.approaches_symmetric) >= 5
    assert sum(d.family is None for d in cfg.designs) == 2  # the paper's two designs are on the map
    tiny = ConcaveMapConfig(**TINY)
    assert len(tiny.designs) == 2 and len(tiny.approaches("close_to_conformal")) == 2
    with pytest.raises(ValueError, match="approaches_conformal"):
        ConcaveMapConfig(approaches_conformal=(0.02, 0.01))
    with pytest.raises(ValueError, match="h_contact"):
        ConcaveMapConfig(h_contact=0.0)
    assert cfg.past_limit_slope == 0.15 and ConcaveMapConfig(past_limit_slope=None).past_limit_slope is None
    with pytest.raises(ValueError, match="past_limit_slope"):
        ConcaveMapConfig(past_limit_slope=0.05)  # below the analytic limit: no meaning


def _family_text(mem) -> str:
    return ",".join(f"{k}={getattr(mem, k)!r}" for k in ("radius_convex", "radius_concave", "pair_separation",
                                                         "central_gap", "depth"))


@pytest.mark.parametrize("kind", ["close_to_conformal", "symmetric"])
def test_paper_designs_by_their_numbers_are_the_present_cases(kind):
    """A case naming the paper's design by its family numbers builds the present case's design float for float (the
    same control points and name, hence the same mesh and key numbers); the map's paper point is the shipped case
    with only loading.d changed."""
    import dataclasses

    import numpy as np

    from analytic.design_family import PAPER_MEMBERS
    from analytic.designs import design
    from workbench.scenes.concave import scene_design
    from workbench.studies.concave_map import design_run

    paper = design(kind)
    geometry = dataclasses.replace(_shipped_run(kind).geometry, family=_family_text(PAPER_MEMBERS[kind]))
    built = scene_design(geometry)
    assert built.name == paper.name
    assert np.array_equal(built.concave.control_points, paper.concave.control_points)
    assert np.array_equal(built.particle.pieces[0].control_points, paper.particle.pieces[0].control_points)
    assert scene_design(dataclasses.replace(geometry, family=None)) is paper
    if kind == "close_to_conformal":
        cfg = ConcaveMapConfig(**TINY)
        run, des, m = design_run(MapDesign("p", kind, None), cfg)
        shipped = _shipped_run(kind)
        assert des is paper and run.material == shipped.material and run.solver == shipped.solver
        assert run.discretisation == dataclasses.replace(shipped.discretisation, h_contact=cfg.h_contact)
        assert m.d_touch == pytest.approx(0.45957, abs=2e-5)
        assert run.loading.d == pytest.approx([m.d_touch + a for a in cfg.approaches_conformal])


def _shipped_run(kind):
    from pathlib import Path

    import cases
    import workbench.scenes  # noqa: F401  (registers the scenes)
    from cases.schema import load_case

    name = "close_to_conformal" if kind == "close_to_conformal" else "concave_symmetric"
    return load_case(Path(cases.__file__).parent / f"{name}.toml").runs()[0]


def test_case_file_names_a_family_member(tmp_path):
    import workbench.scenes  # noqa: F401
    from cases import CaseError
    from cases.schema import load_case

    text = (Path_of_case("close_to_conformal").read_text().replace(
        'design = "close_to_conformal"',
        'design = "close_to_conformal"\nfamily = "radius_convex=30,radius_concave=-40,pair_separation=3,'
        'central_gap=0.004"'))
    (tmp_path / "fam.toml").write_text(text.replace('name = "close_to_conformal"', 'name = "fam"'))
    run = load_case(tmp_path / "fam.toml").runs()[0]
    assert run.geometry.family.startswith("radius_convex=30")
    bad = text.replace("central_gap=0.004", "central_gap=0.004,colour=1")
    (tmp_path / "bad.toml").write_text(bad.replace('name = "close_to_conformal"', 'name = "bad"'))
    with pytest.raises(CaseError, match=r"geometry\.family item 'colour=1' out of range") as exc:
        load_case(tmp_path / "bad.toml")
    assert "\n" not in str(exc.value)


def Path_of_case(name):  # noqa: N802
    from pathlib import Path

    import cases

    return Path(cases.__file__).parent / f"{name}.toml"


def test_tiny_map_end_to_end(tmp_path):
    """The tiny configuration: 2 designs x 2 loads solved through run_one, every file written, every point
    classified for every model, the report opening on the rule and saying it is the tiny run."""
    from workbench.studies.concave_map import main

    out = tmp_path / "concave_map"
    assert main(["--tiny", "--out", str(out), "--mesh-cache", str(tmp_path / "mesh_cache")]) == 0
    for f in ("concave_map.json", "concave_map.csv", "concave_map.md", "concave_map.png"):
        assert (out / f).stat().st_size > 0, f
    data = json.loads((out / "concave_map.json").read_text())
    assert data["summary"]["points"] == 4 and data["summary"]["failed_designs"] == 0
    for p in data["points"]:
        assert p["P_fem"] > 0 and p["fem_patches"]
        assert set(p["models"]) == {"hertz_lcp", "hertz_intersections", "interacting"}
        for e in p["models"].values():
            assert e["class"] in ("1%", "5%", "10%", "beyond", "n/a")
        assert p["models"]["interacting"]["P"] is not None  # the one P(delta) comparison
    assert sum(p["paper"] for p in data["points"]) == 2
    md = (out / "concave_map.md").read_text().splitlines()
    assert md[0].startswith("# Concave map") and "TINY run" in md[2]
    assert "Hertz superposition" in md[4]
    assert len((out / "concave_map.csv").read_text().splitlines()) == 5


@pytest.mark.parametrize(("argv", "field"), [
    (["--past-limit", "0.05"], "past_limit_slope"),
    (["--past-limit", "0.2", "--no-past-limit"], "--past-limit"),
])
def test_past_limit_options_refuse_bad_values_in_one_line(tmp_path, capsys, argv, field):
    from workbench.studies.concave_map import main

    assert main([*argv, "--out", str(tmp_path / "m"), "--report"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and field in err, err
    assert not (tmp_path / "m").exists()
