"""A benchmark as a Kratos Multiphysics model: ``.mdpa``, ``ProjectParameters.json``, ``StructuralMaterials.json``.

Any :class:`workbench.external.benchmark.Benchmark` with its linear :class:`workbench.external.mesh_model.MeshModel`
becomes, per run Kratos can model (:func:`kratos_model`), a model that Kratos 10.4 runs unchanged
(``python -c "...StructuralMechanicsAnalysis..."`` on ``ProjectParameters_<run>.json``), and a ``job_<run>.json``
that the workbench's job (:mod:`workbench.external.kratos_job`) reads. Units mm, N, MPa; plane strain, thickness
1 mm (loads N/mm). Layout (measured in /work/kratos/NOTES.md, the exploration this follows):

* every body its own nodes (a mesh node shared by two bodies' cells is duplicated) and its own sub model part
  ``Body_<name>`` (nodes, elements) with its own properties: ``SmallDisplacementElement2D3N`` for a small-strain
  run, ``TotalLagrangianElement2D3N`` for a finite one, ``LinearElasticPlaneStrain2DLaw`` (under the total
  Lagrangian element: St Venant-Kirchhoff) with ``E``, ``nu``, ``THICKNESS`` 1;
* a rigid body is meshed (its band of cells, :attr:`Body.rigid`) and EVERY node of it is prescribed
  (``d * direction``): exactly rigid, its elements carry no strain. Its properties take the largest elastic
  ``E`` (Kratos derives the ALM penalty and scale factor from each side's ``E`` / h and uses the smaller, so the
  rigid side never lowers them);
* the contact surfaces: ``LineCondition2D2N`` segments, each oriented with its own body on its left (the
  counter-clockwise traversal); per pair ``k`` the sub model parts ``Contact_<k>`` (both surfaces: the ALM
  process's ``contact_model_part``), ``Contact_<k>_Slave`` (its ``assume_master_slave``: the slave surface's nodes
  are SLAVE, the rest MASTER) and ``Contact_<k>_Master``. Only linear (``2D2N``) mortar conditions exist in
  2D, so the mesh must be linear;
* the supports: ``Support_<group>`` (nodes), the listed components held at 0
  (``assign_vector_variable_process``, the others free);
* the drive: ``Drive`` (the rigid body's nodes, or the driven group's), the components of ``Drive.components``
  prescribed to ``d(t) * direction`` from the table ``drive_<run>.csv`` (time = step number, one step per unit
  time; ``end_time`` = the number of steps, exact in floating point). The steps never move the drive by more
  than ``max_step``, default :data:`MAX_STEP_FRACTION` h_c: larger increments miss contact pairs (NOTES pitfall
  1). Measured on hertz_cylinder's benchmark (rigid band, force control, from first contact): steps of h_c did not
  converge at h_c/a = 0.025 (40 Newton iterations, the load diverging) and took 14 iterations at 0.1; steps of
  h_c / 5 converge in 3-6 iterations each at both levels. Displacement control steps through every reported
  ``d``; force control ramps to the approach estimate (the workbench's job instead ramps until the load passes
  each target and then corrects ``d`` by secant steps: :mod:`workbench.external.kratos_job`);
* the contact: ``ALMContactProcess``, frictionless mortar augmented Lagrangian (``ALMContactFrictionless``),
  automatic penalty and scale factor; ``contact_residual_criterion``; Eigen SparseLU.

Pressure (NOTES section 3): the nodal unknown ``LAGRANGE_MULTIPLIER_CONTACT_PRESSURE`` is the pressure over
``SCALE_FACTOR`` (negative in compression): ``p = -SCALE_FACTOR * LM`` on ACTIVE slave nodes, 0 elsewhere; the
load ``P`` is the drive's reaction along ``-direction`` (doubled for a half model). This module writes text
only: no Kratos import.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

import numpy as np

from workbench.external.benchmark import Benchmark, Body, Run
from workbench.external.mesh_model import MeshModel
from workbench.external.writers import DeckWriter, register_writer

__all__ = ["KratosModel", "KratosDeck", "kratos_model", "kratos_runs", "kratos_deck", "write_kratos", "drive_steps",
           "NotModelled", "LAW", "ELEMENTS", "JOB_VERSION", "MAX_STEP_FRACTION"]

LAW = "LinearElasticPlaneStrain2DLaw"
ELEMENTS = {"small": "SmallDisplacementElement2D3N", "finite": "TotalLagrangianElement2D3N"}
JOB_VERSION = 1
LOAD_RTOL = 1e-3  # the job's force control: the secant on d stops when the load is this close to the target
MAX_CORRECTIONS = 8  # secant steps per target at most
MAX_STEP_FRACTION = 0.2  # the largest drive increment per step, over the contact element size (module docstring)

# What each kinematics of a benchmark run becomes in Kratos (the words go into the report and docs/external.md).
_SMALL = ("small strain (SmallDisplacementElement2D3N, linear elastic plane strain) with finite sliding: Kratos "
          "moves the mesh, so the mortar pairing, the gap and the traction (along the contact normal) are taken in the "
          "current configuration, the counterpart of the workbench's obstacle/convective model, not the small-sliding "
          "pairing of the undeformed configuration this run asks for. Kratos's small-sliding variant (solver "
          "move_mesh_flag false) carries the patch test to round-off but did not converge on a curved or wedge contact "
          "(hertz_cylinder, a wedge: the active set cycles), so it is not used")
_FINITE = ("finite strain (TotalLagrangianElement2D3N with LinearElasticPlaneStrain2DLaw: St Venant-Kirchhoff); "
           "contact on the current configuration along the normal")
_NOT_CONVECTIVE = ("its counterpart in Kratos, small strain with finite sliding (the contact in the current "
                   "configuration), is exactly the computation of Kratos's small run (Kratos has no small-sliding "
                   "contact that converges here): b/b0 between two Kratos runs would be 1 by construction, so the "
                   "convective shift cannot be measured with Kratos; its small run is scored, and the model bands say "
                   "which of the workbench's models it matches")


class NotModelled(ValueError):
    """A run (or a benchmark) Kratos cannot model; the message says why (one line)."""


class KratosModel(NamedTuple):
    """How Kratos models one run: its element, constitutive law and what that means against the workbench's
    model hierarchy (``docs/models.md``)."""

    run: str
    kinematics: str
    element: str
    law: str
    meaning: str


def kratos_model(run: Run) -> KratosModel:
    """The Kratos model of ``run``; :class:`NotModelled` (with the reason) where there is none."""
    if run.kinematics == "small":
        return KratosModel(run.label, "small", ELEMENTS["small"], LAW, _SMALL)
    if run.kinematics == "finite":
        meaning = _FINITE
        if run.material_model not in ("linear", "saint_venant_kirchhoff"):
            meaning += (f"; the case's law is {run.material_model}: Kratos's StructuralMechanicsApplication has no "
                        "hyperelastic plane-strain law, so St Venant-Kirchhoff stands in (the laws differ at second "
                        "order in the strain)")
        return KratosModel(run.label, "finite", ELEMENTS["finite"], LAW, meaning)
    if run.kinematics == "convective":
        raise NotModelled(f"run {run.label!r} (convective): {_NOT_CONVECTIVE}")
    raise NotModelled(f"run {run.label!r}: kinematics {run.kinematics!r}; Kratos models: small, finite")


def kratos_runs(bench: Benchmark) -> tuple[list[KratosModel], dict[str, str]]:
    """The runs of ``bench`` Kratos models, and the others with the reason (run label -> reason)."""
    models, skipped = [], {}
    for run in bench.runs:
        try:
            model = kratos_model(run)
        except NotModelled as exc:
            skipped[run.label] = str(exc)
            continue
        same = next((m for m in models if (m.kinematics, m.element) == (model.kinematics, model.element)), None)
        if same is not None:  # the patch test's mortar and node-to-segment runs: one problem, two pairings
            skipped[run.label] = (f"run {run.label!r}: for Kratos the computation of run {same.run!r} (the runs "
                                  "differ only in the workbench's pairing of the meshes; Kratos's one 2D contact "
                                  "discretisation is its ALM mortar), so it is run once")
            continue
        models.append(model)
    return models, skipped


def drive_steps(targets: tuple[float, ...], *, max_step: float) -> tuple[list[float], list[int | None]]:
    """The step ends ``d_1 .. d_n`` (mm) from 0 through every target ``d`` (ascending or not), no step longer than
    ``max_step``, and for each step the index of the target it reaches (None between targets)."""
    if not (math.isfinite(max_step) and max_step > 0):
        raise ValueError(f"max_step = {max_step!r}; allowed: a finite step > 0 mm")
    d, report, prev = [], [], 0.0
    for k, t in enumerate(targets):
        n = max(1, math.ceil(abs(t - prev) / max_step - 1e-9))
        for i in range(1, n + 1):
            d.append(prev + (t - prev) * i / n)
            report.append(k if i == n else None)
        prev = t
    return d, report


def _name(text: str) -> str:
    """A Kratos sub model part name from a group or body name (letters, digits, underscores)."""
    return re.sub(r"[^A-Za-z0-9_]", "_", text)


@dataclass(frozen=True)
class _Numbering:
    """Kratos ids: every body's own copy of its mesh nodes, its elements, and each facet's body."""

    node_ids: dict  # body name -> {mesh node index: Kratos node id}
    coords: list  # (kratos id, x, y)
    edge_body: dict  # frozenset edge -> (body name, oriented (i, j) with the body on the left)


def _number(bench: Benchmark, mesh: MeshModel) -> _Numbering:
    node_ids, coords, edge_body, nid = {}, [], {}, 0
    for body in bench.bodies:
        tri = mesh.cells[body.cells]
        ids = {}
        for n in np.unique(tri.reshape(-1)):
            nid += 1
            ids[int(n)] = nid
            coords.append((nid, float(mesh.nodes[n, 0]), float(mesh.nodes[n, 1])))
        node_ids[body.name] = ids
        for a, b, c in tri[:, :3]:  # counter-clockwise (read_msh): each edge in cycle order has the cell on its left
            for i, j in ((a, b), (b, c), (c, a)):
                edge_body.setdefault(frozenset((int(i), int(j))), []).append((body.name, (int(i), int(j))))
    return _Numbering(node_ids, coords, edge_body)


def _facets_of(group: str, mesh: MeshModel, num: _Numbering, *, body: str | None = None) -> list[tuple[str, int, int]]:
    """The facets of ``group`` as (body, Kratos id i, Kratos id j), oriented with their body on the left; ``body``
    picks that body's copy where an edge bounds cells of two bodies."""
    if group not in mesh.facets:
        raise ValueError(f"mesh group {group!r} missing; facet groups: {sorted(mesh.facets)}")
    out = []
    for i, j in mesh.facets[group][:, :2]:
        owners = num.edge_body.get(frozenset((int(i), int(j))), [])
        if body is not None:
            owners = [o for o in owners if o[0] == body]
        if len(owners) != 1:
            where = f"of body {body!r} " if body else ""
            raise ValueError(f"facet ({i}, {j}) of group {group!r} is the edge of {len(owners)} cells {where}"
                             "(allowed: a boundary edge of exactly one body's cells)")
        name, (a, b) = owners[0]
        out.append((name, num.node_ids[name][a], num.node_ids[name][b]))
    return out


class KratosDeck(NamedTuple):
    """The files of one run: their names and texts (written by :func:`write_kratos`)."""

    model: KratosModel
    files: dict  # file name -> text


def _elastic(bench: Benchmark) -> list[Body]:
    return [b for b in bench.bodies if not b.rigid]


def _supports(bench: Benchmark) -> list[dict]:
    out = []
    for s in bench.supports:
        out.append({"python_module": "assign_vector_variable_process", "kratos_module": "KratosMultiphysics",
                    "Parameters": {"model_part_name": f"Structure.Support_{_name(s.group)}",
                                   "variable_name": "DISPLACEMENT",
                                   "constrained": [0 in s.components, 1 in s.components, True],
                                   "value": [0.0 if 0 in s.components else None,
                                             0.0 if 1 in s.components else None, 0.0]}})
    return out


def _drive_process(bench: Benchmark, table: str) -> dict:
    comps = bench.drive.components
    value = []
    for c in (0, 1):
        if c not in comps:
            value.append(None)
        elif bench.drive.direction[c] == 0.0:
            value.append(0.0)
        else:
            value.append({"name": "csv_table", "filename": table, "delimiter": ",", "skiprows": 1,
                          "first_column_id": 0, "second_column_id": 1 + c})
    return {"python_module": "assign_vector_variable_process", "kratos_module": "KratosMultiphysics",
            "Parameters": {"model_part_name": "Structure.Drive", "variable_name": "DISPLACEMENT",
                           "constrained": [0 in comps, 1 in comps, True], "value": [*value, 0.0]}}


def _parameters(bench: Benchmark, model: KratosModel, *, stem: str, n_steps: int, table: str) -> dict:
    pairs = {str(k): [f"Contact_{k}"] for k in range(len(bench.pairs))}
    slaves = {str(k): [f"Contact_{k}_Slave"] for k in range(len(bench.pairs))}
    return {
        "problem_data": {"problem_name": stem, "parallel_type": "OpenMP", "echo_level": 1, "start_time": 0.0,
                         "end_time": float(n_steps)},
        "solver_settings": {
            "model_part_name": "Structure", "domain_size": 2, "solver_type": "Static", "echo_level": 1,
            "analysis_type": "non_linear",
            "model_import_settings": {"input_type": "mdpa", "input_filename": stem},
            "material_import_settings": {"materials_filename": "StructuralMaterials.json"},
            "contact_settings": {"mortar_type": "ALMContactFrictionless"},
            "time_stepping": {"time_step": 1.0},
            "block_builder": True, "line_search": False, "clear_storage": True, "reform_dofs_at_each_step": True,
            "compute_reactions": True, "convergence_criterion": "contact_residual_criterion",
            "displacement_relative_tolerance": 1e-6, "displacement_absolute_tolerance": 1e-12,
            "residual_relative_tolerance": 1e-6, "residual_absolute_tolerance": 1e-12, "max_iteration": 40,
            "linear_solver_settings": {"solver_type": "LinearSolversApplication.sparse_lu"},
        },
        "processes": {
            "constraints_process_list": _supports(bench),
            "drive_process_list": [_drive_process(bench, table)],
            "contact_process_list": [{
                "python_module": "alm_contact_process",
                "kratos_module": "KratosMultiphysics.ContactStructuralMechanicsApplication",
                "process_name": "ALMContactProcess",
                "Parameters": {"model_part_name": "Structure", "contact_model_part": pairs,
                               "assume_master_slave": slaves, "contact_type": "Frictionless"}}],
        },
        "output_processes": {},
    }


def _materials(bench: Benchmark, model: KratosModel, prop: dict) -> dict:
    e_max = max(b.material.E for b in _elastic(bench))
    out = []
    for body in bench.bodies:
        E, nu = (e_max, 0.3) if body.rigid else (body.material.E, body.material.nu)
        out.append({"model_part_name": f"Structure.Body_{_name(body.name)}", "properties_id": prop[body.name],
                    "Material": {"constitutive_law": {"name": model.law},
                                 "Variables": {"YOUNG_MODULUS": E, "POISSON_RATIO": nu, "THICKNESS": 1.0,
                                               "DENSITY": 1.0},
                                 "Tables": {}}})
    return {"properties": out}


def _mdpa(bench: Benchmark, mesh: MeshModel, model: KratosModel, num: _Numbering, prop: dict) -> tuple[str, dict]:
    """The ``.mdpa`` text and the job's facts (slave parts, drive part)."""
    out = ["Begin ModelPartData", "End ModelPartData", ""]
    for p in range(len(bench.bodies) + 1):
        out += [f"Begin Properties {p}", "End Properties", ""]
    out.append("Begin Nodes")
    out += [f"{i:8d} {x!r} {y!r} 0.0" for i, x, y in num.coords]
    out += ["End Nodes", ""]
    elements, eid = {}, 0
    for body in bench.bodies:
        rows = []
        ids = num.node_ids[body.name]
        for a, b, c in mesh.cells[body.cells][:, :3]:
            eid += 1
            rows.append(f"{eid:8d} {prop[body.name]} {ids[int(a)]} {ids[int(b)]} {ids[int(c)]}")
        elements[body.name] = (eid - len(rows) + 1, eid)
        out += [f"Begin Elements {model.element} // body {body.name}", *rows, "End Elements", ""]
    # contact surfaces: LineCondition2D2N, the body on the left
    cid, surfaces = 0, {}
    for pair in bench.pairs:
        for group, body in ((pair.slave, pair.slave_body), (pair.master, pair.master_body)):
            if group in surfaces:
                continue
            segs = _facets_of(group, mesh, num, body=bench.body(body).name)
            rows, first = [], cid + 1
            for _, i, j in segs:
                cid += 1
                rows.append(f"{cid:8d} {prop[body]} {i} {j}")
            surfaces[group] = ((first, cid), sorted({n for _, i, j in segs for n in (i, j)}))
            out += [f"Begin Conditions LineCondition2D2N // surface {group} of {body}", *rows, "End Conditions", ""]

    def part(name: str, nodes, elems=(), conds=(), indent: str = "") -> list[str]:
        lines = [f"{indent}Begin SubModelPart {name}"]
        for tag, items in (("Nodes", nodes), ("Elements", elems), ("Conditions", conds)):
            lines.append(f"{indent}    Begin SubModelPart{tag}")
            lines += [f"{indent}        {i}" for i in items]
            lines.append(f"{indent}    End SubModelPart{tag}")
        return [*lines, f"{indent}End SubModelPart", ""]

    for body in bench.bodies:
        lo, hi = elements[body.name]
        out += part(f"Body_{_name(body.name)}", sorted(num.node_ids[body.name].values()), range(lo, hi + 1))
    for k, pair in enumerate(bench.pairs):
        (s_lo, s_hi), s_nodes = surfaces[pair.slave]
        (m_lo, m_hi), m_nodes = surfaces[pair.master]
        out += part(f"Contact_{k}", sorted({*s_nodes, *m_nodes}), (),
                    sorted({*range(s_lo, s_hi + 1), *range(m_lo, m_hi + 1)}))
        out += part(f"Contact_{k}_Slave", s_nodes, (), range(s_lo, s_hi + 1))
        out += part(f"Contact_{k}_Master", m_nodes, (), range(m_lo, m_hi + 1))
    for s in bench.supports:
        nodes = sorted({n for _, i, j in _facets_of(s.group, mesh, num) for n in (i, j)})
        out += part(f"Support_{_name(s.group)}", nodes)
    drive = bench.drive
    if drive.group is not None:  # a facet group (of the elastic body ``drive.body``, when it names one)
        drive_nodes = sorted({n for _, i, j in _facets_of(drive.group, mesh, num, body=drive.body) for n in (i, j)})
    elif drive.body is not None:
        if not bench.body(drive.body).rigid:
            raise ValueError(f"drive body {drive.body!r} is elastic; allowed: a rigid body (or a driven group)")
        drive_nodes = sorted(num.node_ids[drive.body].values())
    else:
        raise ValueError("the drive names neither a rigid body nor a driven group")
    for body in bench.bodies:
        if body.rigid and body.name != drive.body:
            raise ValueError(f"rigid body {body.name!r} is not the driven one; allowed: one rigid body, the drive's")
    out += part("Drive", drive_nodes)
    return "\n".join(out), {"drive_nodes": len(drive_nodes)}


def _approach(bench: Benchmark) -> float | None:
    """The approach (mm) the standalone deck ramps to under force control: the benchmark's estimate if it gives
    one (``reference["approach_mm"]``), else None."""
    d = bench.reference.get("approach_mm") if isinstance(bench.reference, dict) else None
    return float(d) if isinstance(d, (int, float)) and math.isfinite(d) and d > 0 else None


def kratos_deck(bench: Benchmark, mesh: MeshModel, model: KratosModel, *, max_step: float | None = None,
                approach: float | None = None) -> KratosDeck:
    """The files of one run (see the module docstring). ``max_step``: the largest drive increment per step (mm,
    default :data:`MAX_STEP_FRACTION` times the contact element size ``bench.h_contact``); ``approach``: the
    standalone deck's final approach under force control (mm; default the benchmark's estimate, else 20 steps of
    ``max_step``)."""
    if mesh.order != 1:
        raise NotModelled("Kratos's 2D mortar contact conditions are linear only (ALMFrictionlessMortarContact"
                          "Condition2D2N): the mesh must have 3-node triangles and 2-node facets")
    if not _elastic(bench):
        raise ValueError("no elastic body")
    step = MAX_STEP_FRACTION * bench.h_contact if max_step is None else max_step
    stem = f"{bench.case}_h{bench.level:g}_{_name(model.run)}"
    prop = {b.name: k + 1 for k, b in enumerate(bench.bodies)}
    num = _number(bench, mesh)
    mdpa, facts = _mdpa(bench, mesh, model, num, prop)
    dr = bench.drive
    if dr.control == "displacement":
        targets = tuple(float(v) for v in dr.report)
    elif dr.control == "force":
        d_end = approach or _approach(bench) or 20 * step
        targets = (d_end,)
    else:
        raise ValueError(f"drive control {dr.control!r}; allowed: force, displacement")
    d, report = drive_steps(targets, max_step=step)
    table = f"drive_{_name(model.run)}.csv"
    rows = ["time,u_x_mm,u_y_mm", "0.0,0.0,0.0"]
    rows += [f"{k + 1:.1f},{v * dr.direction[0]!r},{v * dr.direction[1]!r}" for k, v in enumerate(d)]
    params = _parameters(bench, model, stem=stem, n_steps=len(d), table=table)
    job = {
        "version": JOB_VERSION, "case": bench.case, "level": bench.level, "h_contact": bench.h_contact,
        "run": model.run, "kinematics": model.kinematics, "element": model.element, "meaning": model.meaning,
        "parameters": f"ProjectParameters_{_name(model.run)}.json",
        "control": dr.control, "targets": [float(v) for v in dr.report],
        "schedule": {"d": d, "report": report} if dr.control == "displacement" else None,
        "max_step": step, "direction": list(dr.direction), "components": list(dr.components),
        "load_factor": 2.0 if dr.half_model else 1.0, "load_rtol": LOAD_RTOL, "max_corrections": MAX_CORRECTIONS,
        "slaves": [{"pair": k, "part": f"Contact_{k}_Slave", "body": p.slave_body, "surface": p.slave}
                   for k, p in enumerate(bench.pairs)],
        "drive_part": "Drive", "drive_nodes": facts["drive_nodes"],
    }
    files = {f"{stem}.mdpa": mdpa + "\n", f"ProjectParameters_{_name(model.run)}.json": json.dumps(params, indent=1),
             "StructuralMaterials.json": json.dumps(_materials(bench, model, prop), indent=1),
             table: "\n".join(rows) + "\n", f"job_{_name(model.run)}.json": json.dumps(job, indent=1)}
    return KratosDeck(model, files)


def write_kratos(bench: Benchmark, mesh: MeshModel, folder: Path, *, max_step: float | None = None,
                 approach: float | None = None) -> list[Path]:
    """Write the Kratos files of every run Kratos models into ``folder`` (created by the caller), and
    ``kratos_runs.json`` naming the runs it cannot model with the reason; returns the paths written.
    :class:`NotModelled` if it models none."""
    models, skipped = kratos_runs(bench)
    if not models:
        raise NotModelled(f"{bench.case}: Kratos models none of its runs: " + "; ".join(skipped.values()))
    written, materials = [], None
    for model in models:
        deck = kratos_deck(bench, mesh, model, max_step=max_step, approach=approach)
        for name, text in deck.files.items():
            if name == "StructuralMaterials.json":
                if materials is not None and materials != text:  # one law for every run (the element differs)
                    raise ValueError("runs with different materials files")
                materials = text
            (folder / name).write_text(text)
            if folder / name not in written:
                written.append(folder / name)
    summary = {"modelled": [m._asdict() for m in models], "not_modelled": skipped}
    (folder / "kratos_runs.json").write_text(json.dumps(summary, indent=1))
    written.append(folder / "kratos_runs.json")
    return written


def _write_exported(exported, *, approach: float | None = None) -> list[Path]:
    """The ``mdpa`` deck writer of ``workbench export`` (:mod:`workbench.external.writers`): Kratos's files of an
    exported benchmark, into its folder, on its linear mesh."""
    return write_kratos(exported.benchmark, exported.model, exported.folder, approach=approach)


def _cannot(case) -> str | None:
    """Why Kratos models no run of ``case`` (None: it models at least one: small or finite kinematics)."""
    kinds = {run.solver.kinematics for run in case.runs()}
    if kinds & {"small", "finite"}:
        return None
    return f"its runs' kinematics are {', '.join(sorted(kinds))}; Kratos models small and finite: {_NOT_CONVECTIVE}"


register_writer(DeckWriter("mdpa", "Kratos Multiphysics: .mdpa, ProjectParameters_<run>.json, "
                           "StructuralMaterials.json (linear mesh, ALM frictionless mortar)", _write_exported, _cannot))
