"""Study: where Hertz superposition holds over the concave design family, and where the interacting-patch model must
replace it (issue 40, item 3; ``workbench concave-map``, ``make concave-map``).

For every design of :class:`workbench.studies.concave_map_config.ConcaveMapConfig` (a member of
:mod:`analytic.design_family`, LCP-checked by the concave scene) one displacement-controlled FEM run records the
loads d = d_touch + approach. The run is the shipped concave case of the design's kind
(``cases/close_to_conformal.toml`` or ``cases/concave_symmetric.toml``: its material, solver and contact
resolution) with ``geometry.family`` naming the member and ``loading.d`` the map's displacements, solved by
:func:`workbench.pipeline.run_case.run_one` (:func:`workbench.studies.scene_point.run_point`); a run that raises is
named by :func:`workbench.studies.scene_point.run_failure`. At every recorded load the three models of
:mod:`workbench.studies.concave_map_models` are compared with the FEM and classified. Writes
``<out>/concave_map.json`` (config, summary, every point), ``concave_map.csv``, ``concave_map.md`` and
``concave_map.png`` (:mod:`workbench.studies.concave_map_report`). Units: mm, N/mm, MPa.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
import time
from pathlib import Path

from workbench.studies.concave_map_config import TINY, ConcaveMapConfig
from workbench.studies.concave_map_design import design_run
from workbench.studies.concave_map_interacting import InteractingTrack
from workbench.studies.concave_map_models import (
    FemPatch,
    compare,
    hertz_at_pairs,
    intersection_pairs,
)
from workbench.studies.config import to_json

__all__ = ["design_run", "evaluate_step", "main", "run_map"]

def evaluate_step(step: dict, *, des, m, E_star: float, track) -> dict:
    """One map point: the FEM state of a recorded step and each model's errors (module docstring); ``track``: the
    design's :class:`workbench.studies.concave_map_interacting.InteractingTrack` (steps in increasing d)."""
    from workbench.scenes.concave import lcp_at

    fem = [FemPatch(e["center"], e["half_width"], e["p_max"], e["P"]) for e in step["patches"]]
    d, P = step["d"], step["P"]
    models = {}
    pred, p0 = hertz_at_pairs(fem, [(q["s"], q["R"]) for q in step["lcp_pairs"]], E_star=E_star)
    models["hertz_lcp"] = compare(fem, pred, p0, note="at the measured patch loads")
    lcp = lcp_at(des, d)
    curve = des.concave
    inter = [(float(curve.arc_length([c.t_a])[0]), c.relative_radius) for c in lcp.intersections]
    pred, p0 = hertz_at_pairs(fem, intersection_pairs(fem, inter), E_star=E_star)
    models["hertz_intersections"] = compare(fem, pred, p0, note="at the measured patch loads")
    models["interacting"] = track.compare(fem, d=d, P=P)
    ranked = sorted((e.worst, name) for name, e in models.items() if math.isfinite(e.worst))
    best = ranked[0][1] if ranked else None
    main = max(fem, key=lambda f: f.P) if fem else None
    sep_over_contact = (m.numbers.separation_over_contact(P=main.P, E_star=E_star)
                        if main is not None and main.P > 0 else math.nan)
    return {"d_mm": d, "approach_mm": d - m.d_touch, "P_fem": P, "p_max_fem": step["p_max"],
            "fem_patches": [f._asdict() for f in fem], "separation_over_contact": sep_over_contact,
            "models": {k: e.as_dict() for k, e in models.items()}, "best_model": best,
            "best_class": models[best].cls if best else "n/a", "best_error": ranked[0][0] if ranked else math.nan}


def run_map(cfg: ConcaveMapConfig, *, progress=print) -> tuple[list[dict], list[dict]]:
    """Solve every design (one FEM run each, in this process, one at a time) and evaluate every recorded load:
    (points, failures). A design that fails its construction or whose run raises is a failure record."""
    from analytic import materials
    from workbench.studies.scene_point import run_failure, run_point

    points, failures = [], []
    for i, md in enumerate(cfg.designs):
        t0 = time.perf_counter()
        try:
            run, des, m = design_run(md, cfg)
            out = run_point(run, name=f"concave_map_{md.label}", mesh_cache=cfg.cache_dir, case="concave_map")
        except Exception as exc:  # noqa: BLE001  (named by run_failure, recorded, the map goes on)
            failures.append({"design": md.label, "kind": md.kind, "family": md.family, "error": run_failure(exc)})
            progress(f"[{i + 1}/{len(cfg.designs)}] {md.label}: {failures[-1]['error']}")
            continue
        E_star = materials.plane_strain_modulus(run.material.E, run.material.nu)
        numbers = dataclasses.asdict(m.numbers)
        track = InteractingTrack(des, m, E_star=E_star, nu=run.material.nu, depth=m.numbers.depth,
                                 past_limit=cfg.past_limit_slope)
        for step in sorted(out.comparison, key=lambda st: st["d"]):
            pt = evaluate_step(step, des=des, m=m, E_star=E_star, track=track)
            points.append({"design": md.label, "kind": md.kind, "family": md.family, "paper": md.family is None,
                           "numbers": numbers, "relative_radius": m.numbers.relative_radius,
                           "d_touch_mm": m.d_touch, "cells": out.metrics["mesh"].get("cells"), **pt})
        progress(f"[{i + 1}/{len(cfg.designs)}] {md.label}: {len(out.comparison)} loads, "
                 f"{time.perf_counter() - t0:.1f} s")
    return points, failures


def _write_region(out: Path) -> Path:
    """``<out>/forcelaw_region.json`` from the solved map in ``out`` (with the FEM's band where the coarse pass
    exists): :func:`workbench.forcelaw_region.region_from_points`. Written inside the output folder only; the
    shipped region (:data:`workbench.forcelaw_region.REGION_FILE`) is a maintainer's copy of it."""
    import json

    from workbench.atomic import write_json
    from workbench.forcelaw_region import region_from_points
    from workbench.studies.concave_map_band import attach_bands

    data = json.loads((out / "concave_map.json").read_text(encoding="utf-8"))
    coarse = out / "concave_map_coarse.json"
    banded = attach_bands(data["points"], json.loads(coarse.read_text(encoding="utf-8"))["points"]
                          if coarse.is_file() else [])
    s = data["summary"]
    source = (f"workbench concave-map: {s['points']} points, {s['designs'] - s['failed_designs']} of {s['designs']} "
              f"designs solved, {banded} points with the FEM's band")
    target = out / "forcelaw_region.json"
    write_json(target, region_from_points(data["points"], data.get("failures", []), source=source))
    return target


class _Parser(argparse.ArgumentParser):
    """argparse whose errors are one stderr line and exit code 2."""

    def error(self, message: str):  # type: ignore[override]
        print(f"{self.prog}: error: {' '.join(message.split())}", file=sys.stderr)
        raise SystemExit(2)


def main(argv: list[str] | None = None) -> int:
    """CLI ``workbench concave-map [--out DIR] [--mesh-cache DIR] [--tiny] [--coarse] [--designs L,...] [--report]
    [--reevaluate] [--past-limit SLOPE | --no-past-limit] [--write-region]``; bad options: one line, exit 2.

    ``--coarse`` solves the same designs on the band's coarse grid (:mod:`workbench.studies.concave_map_band`) into
    ``concave_map_coarse.json``; ``--middle`` on a grid sqrt(2) coarser (the band's order check) into
    ``concave_map_middle.json``; ``--designs`` keeps only the named designs (a subset; with ``--reevaluate`` the
    designs re-evaluated, the others kept as stored); ``--past-limit``/``--no-past-limit`` set
    ``ConcaveMapConfig.past_limit_slope``; ``--report`` solves nothing
    and writes the report again from the JSON files in the folder (with the FEM's band where the coarse file
    exists)."""
    from workbench.atomic import write_json
    from workbench.studies.concave_map_band import REFINEMENT

    ap = _Parser(prog="workbench concave-map", description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=None, help="output folder (default: <results>/concave_map)")
    ap.add_argument("--mesh-cache", type=Path, default=None, help="mesh cache (default: <results>/mesh_cache)")
    ap.add_argument("--tiny", action="store_true", help="2 close-to-conformal designs x 2 loads on coarse meshes "
                    "(the end-to-end test: the machinery, not a map)")
    ap.add_argument("--coarse", action="store_true", help="the FEM band's coarse pass: every element x 2 "
                    "-> concave_map_coarse.json")
    ap.add_argument("--middle", action="store_true", help="the band's order check: every element x sqrt(2) "
                    "-> concave_map_middle.json (with --designs: on a subset)")
    ap.add_argument("--designs", default=None, help="comma-separated design labels: solve only these")
    ap.add_argument("--report", action="store_true", help="solve nothing; write the report from the folder's JSON")
    ap.add_argument("--reevaluate", action="store_true", help="solve no FEM; the interacting-patch model again "
                    "(continued along each design's path) on the folder's stored FEM states, then the report")
    ap.add_argument("--past-limit", type=float, default=None, metavar="SLOPE", help="evaluate the interacting-patch "
                    "model past its analytic slope limit (0.1) at designs whose pairs tilt at most SLOPE, the notes "
                    "saying so (0.1 to 0.3; default 0.15: the close-to-conformal members, not the symmetric ones)")
    ap.add_argument("--no-past-limit", action="store_true", help="refuse the interacting-patch model beyond its "
                    "analytic slope limit (the map's first runs)")
    ap.add_argument("--write-region", action="store_true", help="solve nothing; write the region the map validated "
                    "for the force law into <out>/forcelaw_region.json (copy it into workbench/ to ship it)")
    args = ap.parse_args(argv)
    try:
        opts = dict(TINY if args.tiny else {})
        if args.past_limit is not None and args.no_past_limit:
            raise ValueError("--past-limit and --no-past-limit out of range: one of them")
        if args.past_limit is not None or args.no_past_limit:
            opts["past_limit_slope"] = None if args.no_past_limit else args.past_limit
        cfg = ConcaveMapConfig(out=args.out, mesh_cache=args.mesh_cache, **opts)
        if args.designs is not None:
            want = [t.strip() for t in args.designs.split(",") if t.strip()]
            unknown = [t for t in want if t not in {d.label for d in cfg.designs}]
            if unknown or not want:
                raise ValueError(f"--designs {','.join(unknown)[:60] or args.designs!r} out of range: need labels "
                                 "of the map's designs (concave_map.csv's first column)")
            cfg = dataclasses.replace(cfg, designs=tuple(d for d in cfg.designs if d.label in want))
        if args.coarse and args.middle:
            raise ValueError("--coarse and --middle out of range: one pass at a time")
        if args.middle:
            cfg = dataclasses.replace(cfg, h_contact=math.sqrt(REFINEMENT) * cfg.h_contact,
                                      growth_scale=math.sqrt(REFINEMENT) * cfg.growth_scale)
        if args.coarse:
            cfg = dataclasses.replace(cfg, h_contact=REFINEMENT * cfg.h_contact,
                                      growth_scale=REFINEMENT * cfg.growth_scale)
    except ValueError as exc:
        print(f"workbench concave-map: error: {exc}", file=sys.stderr)
        return 2
    if (args.report or args.write_region or args.reevaluate) and not (cfg.out_dir / "concave_map.json").is_file():
        print(f"workbench concave-map: error: --report/--write-region: {cfg.out_dir / 'concave_map.json'} missing: "
              "need a solved map", file=sys.stderr)
        return 2
    from workbench.owned import ensure_dir
    from workbench.paths import OutputError

    try:
        ensure_dir(cfg.out_dir, kind="concave_map", kinds=("concave_map",))  # the workbench's own, or refused
        ensure_dir(cfg.cache_dir, kind="mesh_cache", kinds=("mesh_cache",))
    except OutputError as exc:
        print(f"workbench concave-map: error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    out = cfg.out_dir
    from workbench.studies.concave_map_report import write_report

    if args.reevaluate:
        import json

        from workbench.studies.concave_map_interacting import reevaluate

        data = json.loads((out / "concave_map.json").read_text(encoding="utf-8"))
        n = reevaluate(data["points"], cfg)
        data["summary"]["interacting_reevaluated"] = True
        data["summary"]["past_limit_slope"] = cfg.past_limit_slope
        data["config"]["past_limit_slope"] = cfg.past_limit_slope
        write_json(out / "concave_map.json", data)
        write_report(out)
        print(f"concave-map: interacting-patch model re-evaluated at {n} designs (past its slope limit up to "
              f"{cfg.past_limit_slope}) -> {out}")
        return 0
    if args.report or args.write_region:
        if args.report:
            write_report(out)
            print(f"concave-map: report written again -> {out}")
        if args.write_region:
            print(f"concave-map: region written -> {_write_region(out)}")
        return 0
    t0 = time.perf_counter()
    points, failures = run_map(cfg)
    summary = {"designs": len(cfg.designs), "failed_designs": len(failures), "points": len(points),
               "tiny": bool(args.tiny), "wall_time_s": time.perf_counter() - t0}
    name = ("concave_map_coarse.json" if args.coarse else "concave_map_middle.json" if args.middle
            else "concave_map.json")
    write_json(out / name, {"config": to_json(cfg), "summary": summary, "points": points, "failures": failures})
    if (out / "concave_map.json").is_file():
        write_report(out)
    print(f"concave-map{' (coarse pass)' if args.coarse else ' (middle pass)' if args.middle else ''}: "
          f"{len(points)} points from "
          f"{len(cfg.designs) - len(failures)} of {len(cfg.designs)} designs ({len(failures)} failed), "
          f"{summary['wall_time_s']:.0f} s -> {out / name}")
    return 0
