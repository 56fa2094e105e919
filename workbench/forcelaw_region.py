"""The region the concave map validated for the force law (issue 40, items 3 and 4), as data the command reads.

``workbench/forcelaw_region.json`` is written from a solved map by ``workbench concave-map --out DIR
--write-region`` (:func:`region_from_points`) and read by ``workbench forcelaw`` (:func:`validated_approach`). It
holds, for the interacting-patch model at the class edge ``edge`` (relative error of widths, p0 and P; a point
within the FEM's own band counts as within):

* ``grid``: the close-to-conformal designs of the map by their family numbers (the numbers a user types,
  :func:`analytic.design_family.parse_family`): the relative radius R and the pair separation s of each grid
  node, and the numbers the map held fixed (radius_convex, central_gap, depth);
* per node ``approach_max_mm``: the largest map load (approach past first touch, mm) up to which EVERY map load
  of that design kept the model within ``edge`` (0: not even the first; None: the design failed);
* ``named``: the same for the paper's design by its name (``close_to_conformal``).

A member is inside when its kind is the grid's, its fixed numbers are the map's (to ``FIXED_RTOL``), and (R, s)
lies in the grid's rectangle; its validated approach is the smallest over the grid nodes of the cell around it (the
nodes themselves on a grid line). A positive value is the region: from first touch up to that approach. Everything
else is outside, one line naming why. Between the nodes the region is an interpolation of the map, not a
measurement (docs/concave_map.md).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

__all__ = ["FIXED_RTOL", "REGION_FILE", "load_region", "region_from_points", "validated_approach"]

REGION_FILE = Path(__file__).with_name("forcelaw_region.json")
FIXED_RTOL = 1e-3   # a fixed number of the map's grid matches to this (relative)
_ON_NODE = 1e-4     # a number on a grid line to this (relative; the grid's numbers have 4 significant digits)
_FIXED = ("radius_convex", "central_gap", "depth")


def _approach_max(points: list[dict], model: str, edge: float) -> tuple[float, str]:
    """The largest approach up to which every point (one design's loads) keeps ``model`` within ``edge``, and why
    the next load is not (its error, or the model's note where it gave none; "" after the last load)."""
    from workbench.studies.concave_map_band import effective_error

    best = 0.0
    for p in sorted(points, key=lambda q: q["approach_mm"]):
        e = effective_error(p, model)
        if not (math.isfinite(e) and e <= edge):
            note = " ".join(p["models"][model]["note"].split())
            why = (f"is {100 * e:.3g} % off the FEM" if math.isfinite(e) else f"gave nothing ({note})")
            return best, f"at approach {p['approach_mm']:.4g} mm it {why}"
        best = round(p["approach_mm"], 9)  # d - d_touch: drop the subtraction's last bits (0.020000000000000018)
    return best, ""


def _grid(v: float) -> float:
    """A grid number as the map's configuration names it (4 significant digits: the concave radius is written with
    6, which moves R by up to 1e-5 relative)."""
    return float(f"{v:.4g}")


def region_from_points(points: list[dict], failures: list[dict], *, edge: float = 0.05,
                       model: str = "interacting", source: str = "") -> dict:
    """The region record from a solved map's points (with their FEM bands attached) and failures."""
    from analytic.design_family import parse_family

    by_design: dict[str, list[dict]] = {}
    for p in points:
        by_design.setdefault(p["design"], []).append(p)
    nodes, fixed = [], None
    for label, pts in by_design.items():
        p0 = pts[0]
        if p0["kind"] != "close_to_conformal" or p0["family"] is None:
            continue
        mem = parse_family(p0["kind"], p0["family"])
        fixed = fixed or {k: getattr(mem, k) for k in _FIXED}
        if any(not math.isclose(getattr(mem, k), fixed[k], rel_tol=FIXED_RTOL) for k in _FIXED):
            continue  # the grid holds these fixed; a design off them is not a grid node
        a, why = _approach_max(pts, model, edge)
        nodes.append({"design": label, "relative_radius": _grid(mem.relative_radius),
                      "pair_separation": _grid(mem.pair_separation), "approach_max_mm": a, "ends": why})
    for f in failures:
        if f["kind"] == "close_to_conformal" and f["family"]:
            mem = parse_family(f["kind"], f["family"])
            nodes.append({"design": f["design"], "relative_radius": _grid(mem.relative_radius),
                          "pair_separation": _grid(mem.pair_separation), "approach_max_mm": None,
                          "ends": "the design failed"})
    named = {pts[0]["design"].removeprefix("paper_"): dict(zip(("approach_max_mm", "ends"),
                                                               _approach_max(pts, model, edge), strict=True))
             for pts in by_design.values() if pts[0]["family"] is None}
    return {"model": model, "edge": edge, "kind": "close_to_conformal", "fixed": fixed, "fixed_rtol": FIXED_RTOL,
            "nodes": nodes, "named": named, "source": source,
            "note": "approach_max_mm: the largest map load (mm past first touch) up to which every map load of the "
                    "design kept the model within edge (a point within the FEM's band counts as within); between "
                    "grid nodes the smallest of the cell's nodes (an interpolation of the map, not a measurement)"}


def load_region(path: Path | None = None) -> dict | None:
    """The stored region (default :data:`REGION_FILE`), or None where no map has been written into it."""
    path = REGION_FILE if path is None else path
    return json.loads(path.read_text(encoding="utf-8")) if path.is_file() else None


def _bracket(values: list[float], v: float) -> list[float] | None:
    """The grid values of the cell around v (v itself on a grid line); None outside the grid's range."""
    vs = sorted(set(values))
    for x in vs:
        if math.isclose(x, v, rel_tol=_ON_NODE):
            return [x]
    lo = [x for x in vs if x < v]
    hi = [x for x in vs if x > v]
    return [lo[-1], hi[0]] if lo and hi else None


def validated_approach(mem, region: dict | None) -> float:
    """The approach past first touch (mm) up to which the map validated the force law of ``mem``
    (:class:`analytic.design_family.FamilyMember`). ValueError (one line): outside the validated region."""
    head = f"design {mem.name!r} out of range: outside the region the concave map validated"
    if region is None:
        raise ValueError(f"{head}: no map has been written into {REGION_FILE.name} (workbench concave-map "
                         "--write-region)")
    edge = f"{100 * region['edge']:g} %"
    if mem.name in region["named"]:
        a, why = region["named"][mem.name]["approach_max_mm"], region["named"][mem.name]["ends"]
        if not a:
            raise ValueError(f"{head}: the interacting-patch model is not within {edge} of the FEM at the map's first "
                             f"load of this design: {why}")
        return a
    if mem.kind != region["kind"]:
        raise ValueError(f"{head}: kind {mem.kind!r} (the map validated {region['kind']!r} only; the "
                         "interacting-patch model's validity limit refuses a design whose pairs face different "
                         "directions)")
    for k, v in region["fixed"].items():
        if not math.isclose(getattr(mem, k), v, rel_tol=region["fixed_rtol"]):
            raise ValueError(f"{head}: {k} = {getattr(mem, k):.6g} mm (the map held {k} = {v:.6g} mm)")
    nodes = region["nodes"]
    R, s = mem.relative_radius, mem.pair_separation
    rs = _bracket([n["relative_radius"] for n in nodes], R)
    ss = _bracket([n["pair_separation"] for n in nodes], s)
    if rs is None or ss is None:
        lo_R, hi_R = min(n["relative_radius"] for n in nodes), max(n["relative_radius"] for n in nodes)
        lo_s, hi_s = min(n["pair_separation"] for n in nodes), max(n["pair_separation"] for n in nodes)
        raise ValueError(f"{head}: relative radius {R:.4g} mm, pair separation {s:.4g} mm (the map's grid: R in "
                         f"[{lo_R:.4g}, {hi_R:.4g}] mm, s in [{lo_s:.4g}, {hi_s:.4g}] mm)")
    cell = [n for n in nodes if any(math.isclose(n["relative_radius"], x, rel_tol=_ON_NODE) for x in rs)
            and any(math.isclose(n["pair_separation"], x, rel_tol=_ON_NODE) for x in ss)]
    values = [n["approach_max_mm"] for n in cell]
    if len(cell) != len(rs) * len(ss) or any(v is None for v in values):
        raise ValueError(f"{head}: a design of its grid cell failed or is missing (R {R:.4g} mm, s {s:.4g} mm)")
    a = min(values)
    if a <= 0:
        worst = next(n for n in cell if n["approach_max_mm"] <= 0)
        raise ValueError(f"{head}: at R {R:.4g} mm, s {s:.4g} mm the interacting-patch model is not within {edge} "
                         f"of the FEM at the first map load of {worst['design']} (a design of its grid cell): "
                         f"{worst['ends']}")
    return a
