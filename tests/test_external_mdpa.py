"""The Kratos writer (workbench/external/mdpa.py) on the two-body cases' meshes: groups, counts, materials, the
contact surfaces' orientation, the drive schedule, what Kratos cannot model. No Kratos needed (text only)."""

from __future__ import annotations

import dataclasses
import json
import re

import numpy as np
import pytest
from kratos_benchmarks import two_body_benchmark

from workbench.external.benchmark import Run
from workbench.external.mdpa import (
    ELEMENTS,
    MAX_STEP_FRACTION,
    NotModelled,
    drive_steps,
    kratos_deck,
    kratos_model,
    kratos_runs,
    write_kratos,
)


def _blocks(text: str) -> dict:
    """``Begin X NAME`` ... ``End X`` blocks of an .mdpa: (kind, name) -> list of rows (split)."""
    out, cur = {}, None
    for line in text.splitlines():
        s = line.split("//")[0].strip()
        if s.startswith("Begin "):
            parts = s.split()
            if cur is None:
                cur = (parts[1], parts[2] if len(parts) > 2 else "")
                out.setdefault(cur, [])
            continue
        if s.startswith("End ") and cur is not None and s.split()[1] == cur[0]:
            cur = None
            continue
        if cur is not None and s:
            out[cur].append(s.split())
    return out


def _submodelparts(text: str) -> dict:
    """Sub model part name -> {"Nodes": ids, "Elements": ids, "Conditions": ids}."""
    out = {}
    for m in re.finditer(r"Begin SubModelPart (\w+)\n(.*?)\nEnd SubModelPart\n", text, flags=re.S):
        body = m.group(2)
        out[m.group(1)] = {k: [int(v) for v in re.search(rf"Begin SubModelPart{k}\n(.*?)End SubModelPart{k}",
                                                          body, flags=re.S).group(1).split()]
                           for k in ("Nodes", "Elements", "Conditions")}
    return out


@pytest.fixture(scope="module")
def cylinder(tmp_path_factory):
    cache = tmp_path_factory.mktemp("mesh_cache")
    return two_body_benchmark("elastic_cylinder_dissimilar", level=0.1, mesh_cache=cache)


def test_two_body_deck_groups_counts_materials(cylinder):
    """Every body its own nodes and elements, one contact pair with both sides, the supports and the drive."""
    bench, mesh = cylinder
    deck = kratos_deck(bench, mesh, kratos_model(bench.runs[0]))
    stem = f"{bench.case}_h0.1_small"
    text = deck.files[f"{stem}.mdpa"]
    blocks = _blocks(text)
    nodes = {int(r[0]): (float(r[1]), float(r[2])) for r in blocks[("Nodes", "")]}
    n_lower, n_upper = (len(mesh.group_nodes(g)) for g in ("lower", "upper"))
    assert len(nodes) == n_lower + n_upper  # the bodies share no node in this mesh
    elements = [r for (kind, name), rows in blocks.items() if kind == "Elements" for r in rows]
    assert {name for kind, name in blocks if kind == "Elements"} == {ELEMENTS["small"]}
    assert len(elements) == len(mesh.cells["lower"]) + len(mesh.cells["upper"])
    parts = _submodelparts(text)
    lower, upper = (f"Body_{b.name}" for b in bench.bodies)
    assert len(parts[lower]["Elements"]) == len(mesh.cells["lower"])
    assert len(parts[upper]["Nodes"]) == n_upper
    slave, master = parts["Contact_0_Slave"], parts["Contact_0_Master"]
    assert len(slave["Conditions"]) == len(mesh.facets["contact_lower"])
    assert len(master["Conditions"]) == len(mesh.facets["contact_upper"])
    assert sorted(parts["Contact_0"]["Conditions"]) == sorted(slave["Conditions"] + master["Conditions"])
    assert set(slave["Nodes"]) <= set(parts[lower]["Nodes"]) and set(master["Nodes"]) <= set(parts[upper]["Nodes"])
    assert len(parts["Drive"]["Nodes"]) == len(mesh.group_nodes("driven"))
    assert set(parts["Drive"]["Nodes"]) <= set(parts[upper]["Nodes"])
    assert len(parts["Support_clamped"]["Nodes"]) == len(mesh.group_nodes("clamped"))
    materials = json.loads(deck.files["StructuralMaterials.json"])["properties"]
    got = {m["model_part_name"]: m["Material"]["Variables"] for m in materials}
    for b in bench.bodies:
        v = got[f"Structure.Body_{b.name}"]
        assert (v["YOUNG_MODULUS"], v["POISSON_RATIO"], v["THICKNESS"]) == (b.material.E, b.material.nu, 1.0)
    params = json.loads(deck.files["ProjectParameters_small.json"])
    alm = params["processes"]["contact_process_list"][0]["Parameters"]
    assert alm["contact_model_part"] == {"0": ["Contact_0"]}
    assert alm["assume_master_slave"] == {"0": ["Contact_0_Slave"]}
    assert params["solver_settings"]["model_import_settings"]["input_filename"] == stem


def test_contact_conditions_have_their_body_on_the_left(cylinder):
    """Each LineCondition2D2N (i, j) runs with its own body on its left: the body's centroid of the triangle holding
    the segment lies left of j - i."""
    bench, mesh = cylinder
    text = kratos_deck(bench, mesh, kratos_model(bench.runs[0])).files[f"{bench.case}_h0.1_small.mdpa"]
    blocks = _blocks(text)
    nodes = {int(r[0]): np.array([float(r[1]), float(r[2])]) for r in blocks[("Nodes", "")]}
    tris = [tuple(int(v) for v in r[2:5]) for (kind, _), rows in blocks.items() if kind == "Elements" for r in rows]
    by_edge = {}
    for t in tris:
        for i, j in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            by_edge[frozenset((i, j))] = t
    conds = blocks[("Conditions", "LineCondition2D2N")]
    assert len(conds) == len(mesh.facets["contact_lower"]) + len(mesh.facets["contact_upper"])
    for r in conds:
        i, j = int(r[2]), int(r[3])
        centroid = np.mean([nodes[n] for n in by_edge[frozenset((i, j))]], axis=0)
        d, c = nodes[j] - nodes[i], centroid - nodes[i]
        assert d[0] * c[1] - d[1] * c[0] > 0


def test_force_control_job_and_standalone_drive(cylinder):
    """Force control: the job's targets are the loads; the standalone table ramps in steps of at most
    MAX_STEP_FRACTION h_c, both components of the driven top prescribed (x held, y along -d)."""
    bench, mesh = cylinder
    deck = kratos_deck(bench, mesh, kratos_model(bench.runs[0]))
    job = json.loads(deck.files["job_small.json"])
    assert job["control"] == "force" and job["targets"] == list(bench.drive.report) and job["schedule"] is None
    assert job["max_step"] == pytest.approx(MAX_STEP_FRACTION * bench.h_contact)
    assert job["slaves"] == [{"pair": 0, "part": "Contact_0_Slave", "body": "block", "surface": "contact_lower"}]
    table = np.loadtxt(deck.files["drive_small.csv"].splitlines()[1:], delimiter=",")
    assert np.all(np.diff(table[:, 0]) == 1.0) and table[0].tolist() == [0.0, 0.0, 0.0]
    assert np.all(table[:, 1] == 0.0) and np.all(np.abs(np.diff(table[:, 2])) <= job["max_step"] * (1 + 1e-12))
    params = json.loads(deck.files["ProjectParameters_small.json"])
    drive = params["processes"]["drive_process_list"][0]["Parameters"]
    assert drive["constrained"] == [True, True, True] and drive["value"][2] == 0.0
    assert drive["value"][1]["filename"] == "drive_small.csv" and drive["value"][1]["second_column_id"] == 2
    assert params["problem_data"]["end_time"] == float(len(table) - 1)


def test_patch_test_displacement_schedule_and_free_slide(tmp_path):
    """The patch test: the top prescribed in y only (x free), rollers as supports, the schedule ends at the
    reported d."""
    bench, mesh = two_body_benchmark("patch_test", level=0.143, mesh_cache=tmp_path)
    written = write_kratos(bench, mesh, tmp_path)
    names = {p.name for p in written}
    assert {"StructuralMaterials.json", "kratos_runs.json", "job_small.json", "drive_small.csv"} <= names
    params = json.loads((tmp_path / "ProjectParameters_small.json").read_text())
    drive = params["processes"]["drive_process_list"][0]["Parameters"]
    assert drive["constrained"][:2] == [False, True] and drive["value"][0] is None
    supports = {p["Parameters"]["model_part_name"]: p["Parameters"] for p in
                params["processes"]["constraints_process_list"]}
    assert supports["Structure.Support_clamped"]["constrained"][:2] == [False, True]
    assert supports["Structure.Support_symmetry"]["constrained"][:2] == [True, False]
    job = json.loads((tmp_path / "job_small.json").read_text())
    assert job["schedule"]["d"][-1] == pytest.approx(0.001) and job["schedule"]["report"][-1] == 0


def test_drive_steps():
    d, report = drive_steps((0.46, 0.47, 1.0), max_step=0.1)
    assert d[4] == pytest.approx(0.46) and report[4] == 0 and report[:4] == [None] * 4
    assert d[5] == pytest.approx(0.47) and report[5] == 1
    assert d[-1] == pytest.approx(1.0) and report[-1] == 2 and len(d) == 5 + 1 + 6
    assert max(np.diff([0.0, *d])) <= 0.1 + 1e-12
    with pytest.raises(ValueError, match="max_step"):
        drive_steps((1.0,), max_step=0.0)


def test_what_kratos_cannot_model(cylinder):
    """Convective runs are named with the reason; finite runs use the total Lagrangian element; a quadratic mesh
    is refused (Kratos's 2D mortar conditions are linear)."""
    bench, mesh = cylinder
    runs = (Run(label="small", kinematics="small", meaning=""), Run(label="convective", kinematics="convective",
                                                                    meaning=""),
            Run(label="finite", kinematics="finite", meaning="", material_model="neo_hookean"))
    models, skipped = kratos_runs(dataclasses.replace(bench, runs=runs))
    assert [m.run for m in models] == ["small", "finite"] and list(skipped) == ["convective"]
    assert "b/b0" in skipped["convective"] and models[1].element == ELEMENTS["finite"]
    assert "St Venant-Kirchhoff" in models[1].meaning and "neo_hookean" in models[1].meaning
    with pytest.raises(NotModelled, match="linear"):
        kratos_deck(bench, mesh.quadratic(), models[0])


def test_runs_that_differ_only_in_the_pairing_are_one_kratos_run(cylinder):
    """The patch test's mortar and node-to-segment runs are one problem meshed the same way: Kratos (one 2D contact
    discretisation, its ALM mortar) runs it once and names the other with the reason (two copies in one result
    would be one run twice, which the scorer refuses)."""
    bench, _mesh = cylinder
    runs = (Run(label="mortar", kinematics="small", meaning=""), Run(label="node-to-segment", kinematics="small",
                                                                     meaning=""))
    models, skipped = kratos_runs(dataclasses.replace(bench, runs=runs))
    assert [m.run for m in models] == ["mortar"] and list(skipped) == ["node-to-segment"]
    assert "'mortar'" in skipped["node-to-segment"] and "run once" in skipped["node-to-segment"]
