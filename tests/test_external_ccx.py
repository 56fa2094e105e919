"""CalculiX on any benchmark (issues 26 and 36): the deck writer, the reader of its results, the runner.

Requirements:
* ``workbench export --format inp`` writes one CalculiX deck per run of any case (the ``inp`` writer of
  :mod:`workbench.external.writers`), importing no dolfinx: CPE6, every body its own ELSET and material, every
  support, the drive (a rigid body's every node; a driven group's prescribed components), one contact pair per
  pair with the benchmark's slave first, ``NLGEOM`` and the neo-Hooke law for a convective run, a hold step after
  every loading step that alone writes output; no field longer than CalculiX's 20 characters;
* a slave surface's nodes come in order along it (:func:`surface_chain`);
* the .frd reader keeps every step's last blocks, turns CPRESS into a force per reference length along a chain of
  any shape, and maps node-to-surface contact's expanded 3D nodes back to the model's nodes;
* the calibration's secant corrections (through the origin, then through the last two runs);
* with ccx: an exported deck runs unchanged; ``workbench external ccx`` on the patch test writes every run and
  level and ``ccx.json``; a truncated .frd is one line, exit 2, nothing written; without ccx: one line, exit 2.
Tests that need ccx skip, naming the reason, where it is missing (``make external`` installs it).
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from workbench.external.frd import FrdData, chain_pressure, read_frd
from workbench.external.mesh_model import MeshModel
from workbench.external.score import main as score_main

ROOT = Path(__file__).resolve().parents[1]
ENV = {**os.environ, "PYTHONPATH": str(ROOT)}
CCX = shutil.which("ccx")
needs_ccx = pytest.mark.skipif(CCX is None, reason="ccx (CalculiX, Debian calculix-ccx) is not installed: "
                                                   "`make external` installs it")


def _export(case: str, out: Path) -> list[Path]:
    from workbench.external.export import export_case

    folder = out / case
    folder.mkdir(parents=True)
    return export_case(case, fmt="inp", h_contact=None or _ci(case), folder=folder, mesh_cache=out / "cache")


def _ci(case: str) -> float:
    import workbench.scenes  # noqa: F401
    from cases import load_case

    d = load_case(case).runs()[0].discretisation
    return d.ci_level or d.h_contact


@pytest.fixture(scope="module")
def decks(tmp_path_factory) -> dict:
    out = tmp_path_factory.mktemp("decks")
    return {case: _export(case, out) for case in ("hertz_cylinder", "patch_test", "wedge_convective")}


def _cards(text: str) -> list[str]:
    return [ln for ln in text.splitlines() if ln.startswith("*")]


def test_export_writes_one_deck_per_run_without_dolfinx(tmp_path):
    code = ("import sys; from workbench.external.export import main; "
            f"rc = main(['wedge_convective', '--format', 'inp', '--out', {str(tmp_path)!r}]); "
            "print(rc, [m for m in ('dolfinx', 'ufl', 'basix') if m in sys.modules])")
    proc = subprocess.run([sys.executable, "-c", code], env=ENV, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert proc.stdout.strip().splitlines()[-1] == "0 []"
    level = tmp_path / "export_wedge_convective" / "h0.05"
    assert sorted(p.name for p in level.glob("*.inp")) == ["wedge_convective_h0.05_convective.inp",
                                                           "wedge_convective_h0.05_small.inp"]


def test_deck_of_a_rigid_indenter(decks):
    (inp,) = decks["hertz_cylinder"]
    text = inp.read_text()
    cards = _cards(text)
    assert "*ELEMENT, TYPE=CPE6, ELSET=E_BLOCK" in cards and "*ELEMENT, TYPE=CPE6, ELSET=E_INDENTER" in cards
    assert "*CONTACT PAIR, INTERACTION=I1, TYPE=SURFACE TO SURFACE" in cards
    assert "S_CONTACT, S_INDENTER_CONTACT" in text  # slave first: the block's top
    assert "N_CLAMPED, 1, 1, 0.\nN_CLAMPED, 2, 2, 0.\nN_SYMMETRY, 1, 1, 0." in text
    assert "*FRICTION" not in text and "NLGEOM" not in text
    # one loading step (no output) and its hold step (output) per reported load; the rigid band's every node moves
    assert cards.count("*STEP, INC=200") == 2 and cards.count("*NODE FILE, FREQUENCY=0") == 1
    assert "DRIVE, 1, 1, 0.0\nDRIVE, 2, 2, -" in text
    nodes = [ln for ln in text.split("*NODE, NSET=NALL\n")[1].split("\n*")[0].splitlines()]
    drive = text.split("*NSET, NSET=DRIVE\n")[1].split("\n*")[0].replace("\n", ", ").split(", ")
    band = text.split("*ELEMENT, TYPE=CPE6, ELSET=E_INDENTER\n")[1].split("\n*")[0].splitlines()
    assert {int(v) for v in drive} == {int(n) for row in band for n in row.split(", ")[1:]}
    assert max(len(f.strip()) for ln in text.splitlines() if ln[:1].isdigit() for f in ln.split(",")) <= 20
    # the rigid circle's mid-edge nodes lie on the circle (surfaces.quadratic), not on its chords
    xy = np.array([[float(v) for v in ln.split(", ")[1:]] for ln in nodes])
    mids = [int(row.split(", ")[4]) - 1 for row in band]  # node 4 of a CPE6: the middle of edge 1-2 (the surface)
    r = np.hypot(xy[mids, 0], xy[mids, 1] - 10.0)
    assert np.min(np.abs(r - 10.0)) < 1e-9


def test_deck_of_two_bodies_drives_the_group_components(decks):
    mortar, node = sorted(decks["patch_test"])  # one deck per run: mortar, node-to-segment
    assert mortar.name.endswith("_mortar.inp") and node.name.endswith("_node-to-segment.inp")
    text = mortar.read_text()
    assert "*ELEMENT, TYPE=CPE6, ELSET=E_LOWER_BLOCK" in text and "*ELEMENT, TYPE=CPE6, ELSET=E_UPPER_BLOCK" in text
    assert "*ELASTIC\n200000.0, 0.3" in text and "*ELASTIC\n70000.0, 0.25" in text
    assert "S_CONTACT_LOWER, S_CONTACT_UPPER" in text
    assert "DRIVE, 2, 2, -0.001" in text and "DRIVE, 1, 1" not in text  # the top slides (Drive.components)
    assert "N_CLAMPED, 2, 2, 0." in text and "N_SYMMETRY, 1, 1, 0." in text
    assert "TYPE=NODE TO SURFACE" in node.read_text() and "TYPE=SURFACE TO SURFACE" in text


def test_deck_of_a_convective_run_is_finite_strain(decks):
    small = next(p for p in decks["wedge_convective"] if p.name.endswith("_small.inp"))
    convective = next(p for p in decks["wedge_convective"] if p.name.endswith("_convective.inp"))
    assert "NLGEOM" not in small.read_text() and "*ELASTIC\n210000.0, 0.0" in small.read_text()
    text = convective.read_text()
    assert "*STEP, INC=200, NLGEOM" in text
    mu, K = 210000.0 / 2.0, 210000.0 / 3.0  # nu = 0: C10 = mu/2, D1 = 2/K
    line = text.split("*HYPERELASTIC, NEO HOOKE\n")[1].splitlines()[0]
    assert [float(v) for v in line.split(",")] == pytest.approx([mu / 2.0, 2.0 / K], rel=1e-12)


def test_a_case_with_finite_runs_has_its_convective_runs_named_not_modelled():
    """CalculiX answers a convective run with NLGEOM, labelled ``finite``; a case with finite runs of its own
    (halfplanes_finite_parabola) would then get results under a label that is none of its runs (the scorer refused
    them): there the convective runs are named as not modelled, with the finite runs that answer them."""
    from types import SimpleNamespace

    from workbench.external.inp import ccx_runs

    def run(label, kinematics, law="linear"):
        return SimpleNamespace(label=label, kinematics=kinematics, material_model=law)

    with_finite = SimpleNamespace(reference={}, runs=[run("small", "small"), run("profile", "convective"),
                                                      run("pairing", "convective"),
                                                      run("neo_hookean", "finite", "neo_hookean")])
    modelled, skipped = ccx_runs(with_finite)
    assert [m.label for m in modelled] == ["small", "neo_hookean"]
    assert set(skipped) == {"profile", "pairing"} and "neo_hookean" in skipped["profile"]
    without = SimpleNamespace(reference={}, runs=[run("small", "small"), run("convective", "convective")])
    modelled, skipped = ccx_runs(without)
    assert [m.label for m in modelled] == ["small", "finite"] and not skipped


def test_surface_chain_orders_any_facets():
    from workbench.external.surface_chain import is_horizontal, surface_chain

    nodes = np.array([[2.0, 0.0], [0.0, 0.0], [1.0, 0.0], [0.5, 0.0], [1.5, 0.0]])
    model = MeshModel(nodes, {"c": np.array([[0, 1, 2, 0, 0, 0]])},
                      {"s": np.array([[2, 0, 4], [1, 2, 3]])})  # out of order, one reversed
    chain = surface_chain(model, "s")
    assert chain.tolist() == [1, 3, 2, 4, 0]
    assert is_horizontal(nodes[chain]) and not is_horizontal(np.array([[0.0, 0.0], [3.0, 4.0]]))
    ring = MeshModel(nodes, {}, {"s": np.array([[0, 1], [1, 2], [2, 0]])})
    with pytest.raises(ValueError, match="closed"):
        surface_chain(ring, "s")


def test_chain_pressure_per_reference_length_and_expanded_nodes():
    """A chain of three nodes stretched by 2 % (u1 = 0.02 X): p = CPRESS * 1.02; a node whose CPRESS only its
    expanded 3D nodes carry (node-to-surface) takes theirs."""
    ids = np.array([1, 2, 3])
    X = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    comps = ["COPEN", "CSLIP1", "CSLIP2", "CPRESS", "CSHEAR1", "CSHEAR2"]
    contact = np.zeros((5, 6))
    contact[:, 3] = [10.0, 20.0, 0.0, 30.0, 30.0]  # nodes 1, 2, 3 and node 3's expanded nodes 3 + 3*2 + 1, + 2
    disp = np.column_stack([0.02 * X[:, 0], np.zeros(3), np.zeros(3), np.zeros(3)])
    step = {"CONTACT": (comps, np.array([1, 2, 3, 10, 11]), contact), "DISP": (["D1", "D2", "D3", "ALL"], ids, disp)}
    data = FrdData(ids, X, step, {2: step})
    p, stretch = chain_pressure(data, step=2, chain=np.array([1, 2, 3]), where="t")
    assert stretch == pytest.approx([1.02, 1.02, 1.02], rel=1e-12)
    assert p == pytest.approx([10.2, 20.4, 0.0], rel=1e-12)  # node 3 has its own CPRESS (0): kept
    del step["CONTACT"]
    step["CONTACT"] = (comps, np.array([1, 2, 10, 11]), contact[[0, 1, 3, 4]])
    p, _ = chain_pressure(data, step=2, chain=np.array([1, 2, 3]), where="t")
    assert p[2] == pytest.approx(30.0 * 1.02, rel=1e-12)


def test_calibration_secant():
    from workbench.external.ccx_solve import _corrected

    one = [{"d": [1.0, 2.0], "P": [50.0, 0.0]}]
    assert _corrected(one, [100.0, 10.0]) == [2.0, 4.0]  # through the origin; no load: twice the approach
    two = one + [{"d": [2.0, 4.0], "P": [90.0, 10.0]}]
    assert _corrected(two, [100.0, 10.0]) == pytest.approx([2.25, 4.0])


def test_external_without_ccx_one_line_exit_2(tmp_path):
    env = {**ENV, "PATH": str(Path(sys.executable).parent)}
    proc = subprocess.run([sys.executable, "-m", "workbench", "external", "ccx", "hertz_cylinder", "--out",
                           str(tmp_path / "o")], env=env, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1 and "ccx" in proc.stderr
    assert not (tmp_path / "o").exists()


@pytest.fixture(scope="module")
def ccx_run(decks, tmp_path_factory):
    if CCX is None:
        pytest.skip("ccx (CalculiX, Debian calculix-ccx) is not installed: `make external` installs it")
    from workbench.external.ccx_solve import run_ccx

    work = tmp_path_factory.mktemp("ccx")
    (src,) = decks["hertz_cylinder"]
    inp = work / src.name
    shutil.copyfile(src, inp)
    run_ccx(inp, exe=CCX)  # the exported deck, unchanged
    return inp


@needs_ccx
def test_exported_deck_runs_and_reads_back(ccx_run):
    from workbench.external.ccx_solve import dat_forces

    data = read_frd(ccx_run.with_suffix(".frd"))
    assert sorted(data.steps) == [2]  # the hold step only
    comps, ids, vals = data.steps[2]["CONTACT"]
    (t, force), = dat_forces(ccx_run.with_suffix(".dat"))
    assert t == pytest.approx(2.0) and 3000 < -2.0 * force[1] < 6000  # a half model: twice its reaction
    assert vals[:, comps.index("CPRESS")].max() > 4000


@needs_ccx
def test_truncated_frd_one_line_exit_2(ccx_run, tmp_path, capsys):
    lines = ccx_run.with_suffix(".frd").read_text().splitlines()
    bad = tmp_path / "truncated.frd"
    bad.write_text("\n".join(lines[: len(lines) // 2]) + "\n")
    assert score_main(["hertz_cylinder", str(bad), "--format", "frd", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and str(bad) in err and "truncated" in err
    assert not (tmp_path / "o").exists()


@needs_ccx
def test_external_ccx_patch_test_every_run_and_level(tmp_path):
    """Three levels of the patch test (about 5 s): both runs at every level, the loads per step, ccx.json; the
    segment-to-segment run is uniform to 1e-3 away from the free edge (its end node doubles its excess with every
    halving of h), the node-to-surface run is not (corner and mid-edge nodes alternate, about +-40 %)."""
    from workbench.external.ccx import main as ccx_main

    assert ccx_main(["ccx", "patch_test", "--levels", "3", "--out", str(tmp_path)]) == 0
    folder = tmp_path / "external_ccx_patch_test"
    summary = json.loads((folder / "ccx.json").read_text())
    entry = summary["geometries"]["patch_test"]
    levels = entry["levels"]
    assert not entry["score"].startswith("not scored") and not entry["score_node_to_surface"].startswith("not")
    assert (folder / "score" / "score.json").is_file() and (folder / "score_node_to_surface" / "score.json").is_file()
    assert [lv["level"] for lv in levels] == pytest.approx([0.143, 0.0714, 0.0357])
    for lv in levels:
        assert [r["run"] for r in lv["runs"]] == ["mortar", "node-to-segment"] and not lv["failed"]
        assert lv["process_wall_s"] > 0 and lv["not_modelled"] == {}
        assert lv["results"] == {"": "result.csv", "node_to_surface": "result_node_to_surface.csv"}
        for run, name in (("mortar", "result.csv"), ("node-to-segment", "result_node_to_surface.csv")):
            sel = np.genfromtxt(folder / f"h{lv['level']:g}" / name, delimiter=",", names=True, dtype=None,
                                encoding="utf-8")
            assert set(sel["run"].tolist()) == {run}
            P = float(sel["P_N_per_mm"][0])
            assert 88 < P < 89.5 and set(sel["step"].tolist()) == {0} and set(sel["body"].tolist()) == {"lower_block"}
            dev = np.abs(sel["p_MPa"] / P - 1.0)  # W = 1 mm
            inside = sel["x_mm"] < 1.0 - 2.0 * lv["h_contact"]
            if run == "mortar":  # measured: 1.7e-4, 5.1e-4, 8.0e-4 inside; 0.46 %, 0.84 %, 1.7 % at the free end
                assert dev[inside].max() < 2e-3 and dev.max() < 0.03, dev.max()
            else:  # measured: corner nodes about 0.65 P/W, mid-edge nodes about 1.3 P/W
                assert 0.2 < dev.max() < 1.0, dev.max()
