"""``workbench export`` for every case (issue 36; 15 cases): every case as a benchmark another code can run.

Requirements: every shipped case exports at its CI level into ``export_<case>/h<level>/`` (the wedge: one sub-folder
per indenter angle); the ``.msh`` reads back with its named groups (the scene's, plus ``indenter`` and
``indenter_contact`` for a rigid indenter); the rigid band's surface nodes lie on the exact indenter surface to
1e-9 mm (circle, parabola, wedge, the concave designs' B-spline particle); the wedge's apex is a node; the halfplanes
cases' upper body is shaped (its contact nodes on the parabola or the wedge); facets run with their body on the left;
the spec is strict JSON holding the schedule, the runs and the theory; each body's material is the case's. Bad input
(unknown case, bad format, bad level, a format without a writer, a folder in the way) is one ``error:`` line, exit 2,
nothing written. The export is a function of the case (twice: the same bytes). One output folder for the module.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from cases import case_names, load_case
from workbench.external.benchmarks import surfaces
from workbench.external.export import level_sequence
from workbench.external.export import main as export_main
from workbench.external.mesh_model import read_msh

ROOT = Path(__file__).resolve().parents[1]
GROUPS = {  # the physical groups of each scene's benchmark mesh
    "block": {"body", "contact", "clamped", "sides", "symmetry", "indenter", "indenter_contact"},
    "concave": {"body", "contact", "clamped", "indenter", "indenter_contact"},
    "two_body": {"lower", "upper", "contact_lower", "contact_upper", "clamped", "driven", "sides"},
    "halfplanes": {"lower", "upper", "contact_lower", "contact_upper", "clamped", "driven", "sides"},
}
ON_SURFACE = 1e-9  # mm


def _strict(text: str) -> dict:
    def refuse(name):
        raise ValueError(f"non-strict JSON constant {name}")
    return json.loads(text, parse_constant=refuse)


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    """Every case at its CI level, all formats, into one output folder: {case: [(spec, model, folder), ...]}."""
    out = tmp_path_factory.mktemp("export")
    found = {}
    for name in case_names():
        assert export_main([name, "--out", str(out)]) == 0, name
        folder = out / f"export_{name}"
        specs = sorted(folder.rglob(f"{name}*_h*.json"))
        found[name] = [(_strict(s.read_text()), read_msh(s.with_suffix(".msh")), s.parent) for s in specs]
    return out, found


def test_every_case_exports_one_folder_per_level_with_its_groups(exported):
    out, found = exported
    assert len(found) == 15
    for name, parts in found.items():
        case = load_case(name)
        lv = level_sequence(case)[0]
        assert (out / f"export_{name}" / f"h{lv:g}").is_dir(), name
        assert len(parts) == (2 if name == "wedge" else 1), name
        for spec, model, folder in parts:
            assert spec["level"]["value"] == lv and spec["case"] == name
            groups = set(model.cells) | set(model.facets)
            stacked = "lower_block" in spec["geometry"]  # the patch test: rollers on its x = 0 edges
            assert groups == GROUPS[spec["scene"]] | ({"symmetry"} if stacked else set()), name
            assert set(spec["mesh"]["groups"]) == groups
            assert spec["mesh"]["nodes"] == len(model.nodes)
            assert (folder / spec["mesh"]["file"]).is_file()
            used = np.unique(np.concatenate([c.reshape(-1) for c in model.cells.values()]))
            assert len(used) == len(model.nodes), name  # no unused node
    wedge = [folder.name for _, _, folder in found["wedge"]]
    assert wedge == ["theta_pi_20", "theta_pi_5"]


def test_spec_holds_schedule_runs_theory_and_the_case_materials(exported):
    _, found = exported
    for name, parts in found.items():
        case = load_case(name)
        runs = case.runs()
        for spec, _, _ in parts:
            drive = spec["drive"]
            assert drive["report"] and all(v > 0 for v in drive["report"]), name
            assert drive["control"] == runs[0].loading.control
            if drive["control"] == "displacement":
                assert drive["report"] == list(runs[0].loading.d)
            assert spec["reference"]["predictions"] and spec["reference"]["how_scored"], name
            assert spec["runs"] and all(r["meaning"] for r in spec["runs"]), name
            labels = {r["label"] for r in spec["runs"]}
            assert labels <= {r.label for r in runs}
            assert {"x_mm", "p_MPa", "step", "run", "body"} <= set(spec["report"]["columns"])
            elastic = [b for b in spec["bodies"] if not b["rigid"]]
            if case.bodies:  # [[body]]: each by name
                assert {b["name"]: (b["material"]["E_MPa"], b["material"]["nu"]) for b in elastic} == {
                    b.name: (b.E, b.nu) for b in case.bodies}, name
            else:
                assert [(b["material"]["E_MPa"], b["material"]["nu"]) for b in elastic] == [
                    (case.material.E, case.material.nu)], name
            assert all(b["material"] is None for b in spec["bodies"] if b["rigid"])


def _on_surface_distance(desc: dict | None, nodes: np.ndarray, spec: dict) -> np.ndarray:
    if desc is None:  # the wedge: y = m |x|
        m = spec["geometry"]["indenter"]["slope"] if "indenter" in spec["geometry"] else None
        return np.abs(nodes[:, 1] - m * np.abs(nodes[:, 0]))
    if desc["kind"] == "circle":
        return np.abs(np.linalg.norm(nodes - np.asarray(desc["center"]), axis=1) - desc["radius"])
    if desc["kind"] == "parabola":
        return np.abs(nodes[:, 1] - nodes[:, 0] ** 2 / (2.0 * desc["radius"]))
    proj = surfaces.projector(desc)
    return np.linalg.norm(proj(nodes) - nodes, axis=1)


def test_rigid_band_nodes_lie_on_the_exact_indenter_surface(exported):
    _, found = exported
    seen = set()
    for name, parts in found.items():
        for spec, model, _ in parts:
            if "indenter_contact" not in model.facets:
                continue
            nodes = model.nodes[model.group_nodes("indenter_contact")]
            desc = spec["geometry"]["surfaces"].get("indenter_contact")
            dev = _on_surface_distance(desc, nodes, spec)
            assert dev.max() < ON_SURFACE, (name, float(dev.max()))
            seen.add(desc["kind"] if desc else "wedge")
            # the band moves with the indenter: its cells hold every node of its surface
            assert set(model.group_nodes("indenter_contact")) <= set(model.group_nodes("indenter"))
    assert seen == {"circle", "parabola", "wedge", "bspline"}


def test_wedge_apex_is_a_node_of_both_surfaces(exported):
    _, found = exported
    for name in ("wedge", "wedge_convective", "halfplanes_wedge_beta_neg", "halfplanes_wedge_rigid_limit"):
        for spec, model, _ in found[name]:
            master = spec["contact"][0]["master"]
            for group in (master, spec["contact"][0]["slave"]):
                xy = model.nodes[model.group_nodes(group)]
                assert np.any(np.all(xy == 0.0, axis=1)), (name, group)


def test_halfplanes_upper_body_is_shaped(exported):
    _, found = exported
    for name in ("halfplanes_beta_pos", "halfplanes_beta_neg", "halfplanes_wedge_beta_neg"):
        spec, model, _ = found[name][0]
        xy = model.nodes[model.group_nodes("contact_upper")]
        up = spec["geometry"]["upper"]
        if up["shape"] == "parabola":
            dev = np.abs(xy[:, 1] - xy[:, 0] ** 2 / (2.0 * up["radius"]))
        else:
            m = up["slope"]
            dev = np.abs(xy[:, 1] - m * np.abs(xy[:, 0]))
        assert dev.max() < ON_SURFACE, (name, float(dev.max()))
        assert xy[:, 1].max() == pytest.approx(up["face_end_height"], rel=1e-9)  # the face reaches |x| = W/2
        assert "shaped body" in spec["reference"]["idealisations"][0]
        assert "parabola_cap" not in up


def test_halfplanes_finite_case_exports_the_body_its_finite_runs_mesh(exported):
    """A case with finite-strain runs: the upper face is the parabola over |x| <= 3 b0, flat beyond (the scene's
    finite geometry), in the mesh, the spec's geometry and its surface description (the projector of the score)."""
    _, found = exported
    spec, model, _ = found["halfplanes_finite_parabola"][0]
    up = spec["geometry"]["upper"]
    R, cap = up["radius"], up["parabola_cap"]
    assert cap == pytest.approx(3.0 * spec["reference"]["predictions"]["hertz"]["half_width"], rel=1e-6)
    xy = model.nodes[model.group_nodes("contact_upper")]
    onto = surfaces.projector(spec["geometry"]["surfaces"]["contact_upper"])
    assert np.abs(onto(xy) - xy).max() < ON_SURFACE
    assert np.abs(xy[:, 0]).max() > 2 * cap and xy[:, 1].max() == pytest.approx(cap**2 / (2 * R), rel=1e-9)
    assert up["face_end_height"] == pytest.approx(cap**2 / (2 * R), rel=1e-12)
    assert "flat beyond" in spec["reference"]["idealisations"][0]


def test_facets_run_with_their_body_on_the_left(exported):
    """The block's top faces up (+y), the indenter's surface down, along the outward normal (dy, -dx)."""
    _, found = exported
    for name in ("hertz_cylinder", "parabola_convective", "wedge", "concave_symmetric"):
        spec, model, _ = found[name][0]
        for group, sign in (("contact", 1.0), ("indenter_contact", -1.0)):
            f = model.facets[group]
            d = model.nodes[f[:, 1]] - model.nodes[f[:, 0]]
            normal_y = -d[:, 0]
            near = np.abs(model.nodes[f[:, 0], 0]) < 0.5 * spec["level"]["h_contact_mm"] / spec["level"]["value"]
            assert np.all(sign * normal_y[near] > 0), (name, group)


def test_quadratic_puts_the_curved_surfaces_mid_nodes_on_them(exported):
    _, found = exported
    spec, model, _ = found["hertz_cylinder"][0]
    q = surfaces.quadratic(model, spec["geometry"]["surfaces"])
    mid = q.facets["indenter_contact"][:, 2]
    c, R = np.asarray([0.0, 10.0]), 10.0
    assert np.abs(np.linalg.norm(q.nodes[mid] - c, axis=1) - R).max() < 1e-12
    plain = model.quadratic()
    chord = plain.nodes[plain.facets["indenter_contact"][:, 2]]
    assert np.abs(np.linalg.norm(chord - c, axis=1) - R).max() > 1e-7  # the chords' middles: off by h^2 / (8 R)


def test_concave_position_is_the_arc_length_of_every_contact_node(exported):
    """x_mm of a concave result is the arc length s of the undeformed spline: the spec gives s at every node of
    'contact' (increasing with X), every arc between two nodes at least its chord (to the 2e-7 mm of the
    workbench's arc length, analytic.curves, against a 100 times finer table). The polyline through the
    nodes is no substitute: each chord is shorter than its arc by about h^3 / (24 R^2) (measured at
    concave_symmetric's CI level: 2.6e-5 mm in one element of the groove, R = 0.6 mm; 4.4e-4 mm summed over the
    refined zone, 0.017 mm over the whole surface)."""
    for name in ("concave_symmetric", "close_to_conformal"):
        spec, model, _ = exported[1][name][0]
        table = spec["report"]["arc_length"]
        X, s = np.asarray(table["X_mm"]), np.asarray(table["s_mm"])
        nodes = model.nodes[model.group_nodes("contact")]
        assert np.array_equal(np.sort(nodes[:, 0]), X) and np.all(np.diff(s) > 0) and s[0] == 0.0
        xy = nodes[np.argsort(nodes[:, 0])]
        step = np.linalg.norm(np.diff(xy, axis=0), axis=1)
        assert np.all(np.diff(s) - step > -1e-6), name  # the workbench's arc length: within 2e-7 mm


def test_export_is_a_function_of_the_case(exported, tmp_path):
    out, found = exported
    assert export_main(["patch_test", "--out", str(tmp_path)]) == 0
    for ext in ("msh", "json"):
        a = (out / "export_patch_test" / "h0.143" / f"patch_test_h0.143.{ext}").read_bytes()
        b = (tmp_path / "export_patch_test" / "h0.143" / f"patch_test_h0.143.{ext}").read_bytes()
        assert a == b, ext


def test_levels_and_earlier_levels_kept(tmp_path, capsys):
    assert level_sequence(load_case("patch_test"))[:3] == (0.143, 0.0714, 0.0357)
    assert level_sequence(load_case("hertz_cylinder"))[:3] == (0.1, 0.05, 0.025)
    assert level_sequence(load_case("concave_symmetric"))[:3] == (0.1, 0.05, 0.025)
    assert export_main(["patch_test", "--levels", "2", "--format", "msh", "--out", str(tmp_path)]) == 0
    assert export_main(["patch_test", "--level", "0.2", "--format", "json", "--out", str(tmp_path)]) == 0
    folder = tmp_path / "export_patch_test"
    assert sorted(p.name for p in folder.iterdir() if p.is_dir()) == ["h0.0714", "h0.143", "h0.2"]
    printed = capsys.readouterr().out.split()
    assert str(folder / "h0.2" / "patch_test_h0.2.json") in printed


BAD = [
    (["no_such_case"], "no_such_case"),
    (["hertz_cylinder", "--format", "xyz"], "--format"),
    (["hertz_cylinder", "--level", "0"], "--level"),
    (["hertz_cylinder", "--level", "nan"], "--level"),
    (["hertz_cylinder", "--level", "1.5"], "--level"),
    (["hertz_cylinder", "--h-contact", "-1"], "--h-contact"),
    (["hertz_cylinder", "--levels", "0"], "--levels"),
    (["hertz_cylinder", "--levels", "7"], "--levels"),
    (["hertz_cylinder", "--levels", "2", "--level", "0.1"], "--levels"),
    (["hertz_cylinder", "--level", "1e-7"], "--level"),  # the size estimate
    (["hertz_cylinder", "--format", "inp,mdpa"], "--format"),
]


@pytest.mark.parametrize(("argv", "word"), BAD, ids=[" ".join(a) for a, _ in BAD])
def test_bad_input_is_one_line_exit_2_nothing_written(argv, word, tmp_path, capsys):
    out = tmp_path / "o"
    assert export_main([*argv, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error: ") and word in err[0], err
    assert not out.exists()


def test_a_folder_in_the_way_is_refused(tmp_path, capsys):
    out = tmp_path / "o"
    (out / "export_patch_test").mkdir(parents=True)
    (out / "export_patch_test" / "mine.txt").write_text("the user's\n")
    assert export_main(["patch_test", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "export_patch_test" in err[0] and "not written by the workbench" in err[0]
    assert sorted(p.name for p in out.rglob("*")) == ["export_patch_test", "mine.txt"]


def test_command_line_exports_a_concave_case_without_dolfinx(tmp_path):
    """The real command line (a subprocess): exit 0, the files printed, no dolfinx imported (the concave body is
    meshed without XDMF)."""
    code = ("import sys; from workbench.external.export import main; rc = main(['close_to_conformal', '--out', "
            f"{str(tmp_path)!r}]); print(rc, [m for m in ('dolfinx', 'ufl', 'basix') if m in sys.modules])")
    env = {**os.environ, "PYTHONPATH": str(ROOT), "HOME": str(tmp_path / "home")}
    (tmp_path / "home").mkdir()
    proc = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert proc.stdout.strip().splitlines()[-1] == "0 []"
    assert not any((tmp_path / "home").iterdir())  # nothing in the home folder (gmsh's FLTK preferences)
    spec = _strict((tmp_path / "export_close_to_conformal" / "h0.1" / "close_to_conformal_h0.1.json").read_text())
    steps = spec["reference"]["predictions"]["steps"]
    assert [s["d"] for s in steps] == spec["drive"]["report"] == [0.46, 0.47, 0.48, 0.5, 0.7, 1.0]
    assert all(math.isfinite(p["R"]) for s in steps for p in s["pairs"])


def test_the_elastic_bodies_are_the_workbench_run_meshes(exported):
    """Every benchmark but the halfplanes' (shaped on purpose) is built on the mesh ``workbench run --ci`` solves:
    its fingerprint (node coordinates on a 1e-9 grid) is the one tests/data/key_numbers_ci.json records; the rigid band
    adds its own nodes and cells only."""
    numbers = json.loads((ROOT / "tests" / "data" / "key_numbers_ci.json").read_text())["numbers"]
    for name, parts in exported[1].items():
        for spec, model, _ in parts:
            built = spec["mesh"]["built_from"]
            if spec["scene"] == "halfplanes":
                assert "shaped" in built["what"]
                continue
            label = next(r["label"] for r in spec["runs"])
            key = f"{name}/runs/{label}/mesh_fingerprint/"
            assert built["coords_sha256"] == numbers[key + "coords_sha256"], name
            band = len(model.cells.get("indenter", ()))
            assert spec["mesh"]["cells"] - band == numbers[key + "n_cells"], name
