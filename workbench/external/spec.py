"""A benchmark as a JSON spec that a person can implement by hand in any code.

:func:`spec` turns a :class:`workbench.external.benchmark.Benchmark` (and the statistics of its mesh) into one JSON
object: the units and conventions, the mesh file and what each of its physical groups is, the bodies and their
materials, the contact pairs, the supports in words and groups, the load or displacement schedule with the steps to
report, every run and what it means, the exact geometry (the surfaces with their formulas, the concave designs' spline
control points), what to report (the csv columns ``workbench score`` reads, per step and per body), and the
reference theory with its predictions at the case's target load and how the score evaluates it at the load the
result carries. :func:`write_spec` writes it (``<stem>.json`` beside ``<stem>.msh``). Units mm, N, MPa.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from workbench.external.benchmark import UNITS, Benchmark

__all__ = ["spec", "write_spec", "SPEC_VERSION"]

SPEC_VERSION = 1
_COMPONENTS = {(0,): "u_x = 0", (1,): "u_y = 0", (0, 1): "u_x = u_y = 0"}
_LEVEL = {"block": "h_c / a (a: the classical half-width at the target load)",
          "concave": "h_c / a_est (a_est = sqrt(R delta): the smallest patch half-width at the first step in contact)",
          "two_body": "h_c / a (cylinder) or h / W (the patch test's lower block)",
          "halfplanes": "h_c / b0 (b0: the classical half-width at the target load)"}
CONVENTIONS = [
    "2D plane strain, thickness 1 mm: loads are N per mm of thickness; quasi-static; frictionless contact.",
    "Positions in results are the slave surface's reference (material) coordinates; pressures compression positive.",
    "A rigid body is meshed (a band of cells along its contact surface): prescribe the drive's displacement on every "
    "one of its nodes; its exact surface is in geometry.surfaces for codes with analytic rigid surfaces.",
    "Mesh: straight-sided 3-node triangles, counter-clockwise; each facet (i, j) runs with its body on its left (its "
    "outward normal is j - i turned by -90 degrees). A code with quadratic elements adds a node at the middle of each "
    "edge, on the exact surface for the groups of geometry.surfaces "
    "(workbench.external.benchmarks.surfaces.quadratic).",
]


def _groups(bench: Benchmark, stats: dict) -> dict:
    """Each physical group of the mesh and what it is (derived from the bodies, pairs, supports and drive)."""
    what: dict[str, str] = {}
    for b in bench.bodies:
        what[b.cells] = f"cells of the {'rigid' if b.rigid else 'elastic'} body '{b.name}'"
    for p in bench.pairs:
        what[p.slave] = f"contact surface of '{p.slave_body}' (slave: its pressure is reported)"
        what[p.master] = f"contact surface of '{p.master_body}' (master)"
    for s in bench.supports:
        what[s.group] = f"support: {_COMPONENTS.get(tuple(s.components), s.components)} ({s.note})"
    if bench.drive.group:
        what[bench.drive.group] = f"driven: the prescribed displacement of '{bench.drive.body}' (components " \
                                  f"{list(bench.drive.components)})"
    out = {}
    for name, g in stats.get("groups", {}).items():
        out[name] = {**g, "what": what.get(name, "a free boundary (no condition)")}
    return out


def _drive(bench: Benchmark) -> dict:
    d = bench.drive
    force = d.control == "force"
    moved = (f"every node of the rigid body '{d.body}'" if d.group is None
             else f"the group '{d.group}' of '{d.body}' (components {list(d.components)}; the others free)")
    half = " A half model carries half of it: report the full-body load (twice the reaction)." if d.half_model else ""
    schedule = (f"Load {moved} along {list(d.direction)} to each load of 'report' (P, N/mm, the full body).{half} A "
                "code that drives the displacement may instead move it by d and report the load it carries: the score "
                "evaluates the theory at that load. Keep the increments small enough that the contact zone moves by "
                "about one element per increment (some codes search contact once per increment and miss pairs "
                "otherwise: docs/external.md)."
                if force else
                f"Move {moved} by d along {list(d.direction)}, through each d of 'report' (mm) in order; report at "
                "each.")
    return {"control": d.control, "moved": moved, "direction": list(d.direction),
            "report": list(d.report), "report_unit": "N/mm (full-body load P)" if force else "mm (displacement d)",
            "body": d.body, "group": d.group, "components": list(d.components), "half_model": d.half_model,
            "schedule": schedule}


def spec(bench: Benchmark, *, stats: dict, files: dict | None = None) -> dict:
    """The JSON spec of ``bench`` (module docstring); ``stats``: the mesh's counts
    (:func:`workbench.external.benchmarks.base.mesh_stats`); ``files``: format -> file name written beside it."""
    return {
        "spec": "contact-workbench benchmark", "version": SPEC_VERSION,
        "case": bench.case, "scene": bench.scene, "description": bench.description,
        "level": {"value": bench.level, "meaning": _LEVEL.get(bench.scene, "h_c over the case's length"),
                  "h_contact_mm": bench.h_contact},
        "units": dict(UNITS), "conventions": CONVENTIONS,
        "mesh": {"file": bench.mesh.name, "format": "gmsh MSH 4.1 (ASCII), named physical groups",
                 "nodes": stats.get("nodes"), "cells": stats.get("cells"), "groups": _groups(bench, stats)},
        "bodies": [{"name": b.name, "cells": b.cells, "rigid": b.rigid,
                    "material": None if b.material is None else {"E_MPa": b.material.E, "nu": b.material.nu,
                                                                 "model": b.material.model}}
                   for b in bench.bodies],
        "contact": [{"slave": p.slave, "master": p.master, "slave_body": p.slave_body, "master_body": p.master_body,
                     "friction": "none"} for p in bench.pairs],
        "supports": [{"group": s.group, "components": list(s.components),
                      "held": _COMPONENTS.get(tuple(s.components), str(s.components)), "note": s.note}
                     for s in bench.supports],
        "drive": _drive(bench),
        "runs": [{"label": r.label, "kinematics": r.kinematics, "meaning": r.meaning, "traction": r.traction,
                  "material_model": r.material_model} for r in bench.runs],
        "geometry": bench.geometry,
        "reference": bench.reference,
        "report": {**bench.report, "files": "one csv per mesh level (its runs, steps and bodies told apart by the "
                                            "run, step and body columns)",
                   "command": f"workbench score {bench.case} LEVEL1.csv LEVEL2.csv LEVEL3.csv"},
        "tolerances": dict(bench.tolerances),
        "files": dict(files or {}),
    }


def _clean(obj):
    """JSON-ready: tuples as lists, paths as names, non-finite floats as None (strict JSON has no NaN)."""
    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if isinstance(obj, Path):
        return obj.name
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if hasattr(obj, "item") and not isinstance(obj, (str, bytes)):
        return _clean(obj.item())
    return obj


def write_spec(bench: Benchmark, path: Path, *, stats: dict, files: dict | None = None) -> Path:
    """Write the spec of ``bench`` as strict JSON to ``path``."""
    path.write_text(json.dumps(_clean(spec(bench, stats=stats, files=files)), indent=1, allow_nan=False) + "\n")
    return path
