"""The region the concave map validated for the force law (issue 40, items 3 and 4): written from map points,
read by ``workbench forcelaw``, inside and outside by hand. Pure Python (no FEM, no force-law solve) except the
last test, which runs the command on the stored region."""

from __future__ import annotations

import dataclasses
import math

import pytest

from analytic.design_family import PAPER_MEMBERS, parse_family
from workbench.forcelaw_region import region_from_points, validated_approach

CC = "radius_convex=41.279,radius_concave={rc:.6g},pair_separation={s:g},central_gap=0.0059758"


def _rc(R: float) -> float:
    return -1.0 / (1.0 / 41.279 - 1.0 / R)


def _points(label, R, s, errors, *, family=True, kind="close_to_conformal"):
    fam = CC.format(rc=_rc(R), s=s) if family else None
    return [{"design": label, "kind": kind, "family": fam, "approach_mm": a,
             "models": {"interacting": {"P": e, "width": e, "p0": e, "worst": e, "class": "-", "note": "",
                                        "within_fem_band": False}}}
            for a, e in zip((0.002, 0.005, 0.01, 0.02, 0.04), errors, strict=False)]


@pytest.fixture
def region():
    ok, bad = [0.01] * 5, [0.2] * 5
    pts = (_points("a", 100, 1.0, ok) + _points("b", 100, 2.0, [0.01, 0.01, 0.06, 0.01, 0.01])
           + _points("c", 200, 1.0, ok) + _points("d", 200, 2.0, ok) + _points("e", 300, 1.0, bad)
           + _points("paper_close_to_conformal", 234, 2.4, [0.01, 0.02, 0.2, 0.2, 0.2], family=False))
    failures = [{"design": "f", "kind": "close_to_conformal", "family": CC.format(rc=_rc(300), s=2.0)}]
    return region_from_points(pts, failures, edge=0.05)


def _member(R, s, **kw):
    return dataclasses.replace(parse_family("close_to_conformal", CC.format(rc=_rc(R), s=s)), **kw)


def test_the_region_by_hand(region):
    by = {n["design"]: n["approach_max_mm"] for n in region["nodes"]}
    assert {n["design"]: n["ends"] for n in region["nodes"]}["b"] == "at approach 0.01 mm it is 6 % off the FEM"
    # every map load up to the approach within 5 %; b breaks at its third load, e at its first; f failed
    assert by == {"a": 0.04, "b": 0.005, "c": 0.04, "d": 0.04, "e": 0.0, "f": None}
    assert region["named"]["close_to_conformal"]["approach_max_mm"] == 0.005
    assert region["fixed"] == {"radius_convex": 41.279, "central_gap": 0.0059758, "depth": 20.0}
    # inside: on a node, on a grid line, inside a cell (the smallest of its nodes)
    assert validated_approach(_member(200, 1.0), region) == 0.04
    assert validated_approach(_member(150, 1.0), region) == 0.04
    assert validated_approach(_member(150, 1.5), region) == 0.005
    assert validated_approach(PAPER_MEMBERS["close_to_conformal"], region) == 0.005


@pytest.mark.parametrize(("member", "why"), [
    (lambda: _member(90, 1.5), "relative radius"),                  # below the grid's R
    (lambda: _member(150, 2.5), "pair separation"),                 # beyond the grid's s
    (lambda: _member(250, 1.0), "first map load of e"),             # a cell with a node beyond at its first load
    (lambda: _member(250, 1.5), "failed or is missing"),            # a cell with a failed design
    (lambda: _member(150, 1.5, central_gap=0.004), "central_gap"),  # a number the map held fixed
    (lambda: PAPER_MEMBERS["symmetric"], "kind 'symmetric'"),
])
def test_outside_is_one_line(region, member, why):
    with pytest.raises(ValueError, match="outside the region the concave map validated") as exc:
        validated_approach(member(), region)
    assert why in str(exc.value) and "\n" not in str(exc.value)


def test_no_region_is_refused():
    with pytest.raises(ValueError, match="no map has been written"):
        validated_approach(_member(150, 1.5), None)


def test_a_point_within_the_fem_band_counts_as_within():
    pts = _points("a", 100, 1.0, [0.01, 0.2, 0.01, 0.01, 0.01]) + _points("c", 200, 1.0, [0.01] * 5)
    assert {n["design"]: n["approach_max_mm"] for n in region_from_points(pts, [])["nodes"]}["a"] == 0.002
    pts[1]["models"]["interacting"]["within_fem_band"] = True
    assert {n["design"]: n["approach_max_mm"] for n in region_from_points(pts, [])["nodes"]}["a"] == 0.04
    assert math.isclose(_member(150, 1.0).relative_radius, 150.0, rel_tol=1e-5)


def test_the_command_writes_the_region_from_a_map_folder(tmp_path, monkeypatch, capsys):
    """``workbench concave-map --out DIR --write-region`` reads DIR's points (no FEM) and writes the region file
    inside DIR (never the shipped one); without a solved map it refuses in one line and creates nothing."""
    import json

    import workbench.forcelaw_region as fr
    from workbench.owned import ensure_dir
    from workbench.studies.concave_map import main

    shipped = tmp_path / "shipped.json"
    monkeypatch.setattr(fr, "REGION_FILE", shipped)
    assert main(["--out", str(tmp_path / "none"), "--write-region"]) == 2
    assert "missing" in capsys.readouterr().err and not (tmp_path / "none").exists()
    out = tmp_path / "map"
    ensure_dir(out, kind="concave_map", kinds=("concave_map",))
    pts = _points("a", 100, 1.0, [0.01] * 5) + _points("c", 200, 1.0, [0.01, 0.2, 0.01, 0.01, 0.01])
    (out / "concave_map.json").write_text(json.dumps(
        {"summary": {"points": len(pts), "designs": 2, "failed_designs": 0}, "points": pts, "failures": []}))
    assert main(["--out", str(out), "--write-region"]) == 0
    assert not shipped.exists()
    region = json.loads((out / "forcelaw_region.json").read_text())
    assert {n["design"]: n["approach_max_mm"] for n in region["nodes"]} == {"a": 0.04, "c": 0.002}
    assert "0 points with the FEM's band" in region["source"]
