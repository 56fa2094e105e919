"""The mesh is a function of the case: portable gmsh inputs, the fingerprint, the perturbation hook.

Cause (measured, docs/architecture.md): the concave geometry is computed with numpy/scipy whose last bits depend
on the machine's OpenBLAS kernel and numpy SIMD level; gmsh turns a last-bit change of its input into another
mesh. The builders round (or snap to a frozen table) every float they hand to gmsh.
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from analytic.curves import BSpline
from analytic.designs import DESIGN_NAMES, design
from meshes.block import build_block_mesh
from meshes.concave import build_concave_mesh, refine_intervals
from meshes.fingerprint import MeshFingerprint
from meshes.frozen import frozen_control_points
from meshes.portable import PERTURB_ENV, perturb_amplitude

H_COARSE = 0.3  # mm: a concave mesh of a few hundred cells (about a second)


def _concave(tmp_path, sub, **kw):
    return build_concave_mesh(design="symmetric", h_contact=H_COARSE, out_dir=tmp_path / sub, write_xdmf=False,
                              **kw)


def _block(tmp_path, sub, a=0.5, **kw):
    return build_block_mesh(width=20 * a, height=20 * a, contact_half_width=a, h_contact=a / 5,
                            half_model=True, out_dir=tmp_path / sub, write_xdmf=False, **kw)


def test_fingerprint_is_written_and_stable_from_run_to_run(tmp_path, monkeypatch):
    monkeypatch.delenv(PERTURB_ENV, raising=False)
    a = _concave(tmp_path, "a", stats_dir=tmp_path / "case")
    b = _concave(tmp_path, "b")  # another cache: built again from scratch
    assert not a.cached and not b.cached
    fp = a.stats["fingerprint"]
    assert set(fp) == set(MeshFingerprint._fields)
    assert fp == b.stats["fingerprint"]
    assert a.msh.read_bytes() == b.msh.read_bytes()
    assert fp["n_nodes"] == a.stats["n_nodes"] and fp["n_cells"] == a.stats["n_cells"] > 0
    assert fp["facets"]["contact"] == a.stats["n_contact_edges"] and fp["facets"]["clamped"] > 0
    assert fp["geometry_source"] == "frozen" and fp["perturb"] == 0.0
    written = json.loads((tmp_path / "case" / "mesh.json").read_text())
    assert written["fingerprint"] == fp
    blk = [_block(tmp_path, s).stats["fingerprint"] for s in ("c", "d")]
    assert blk[0] == blk[1] and blk[0]["geometry_source"] == "parameters" and "symmetry" in blk[0]["facets"]


def test_perturbation_changes_the_cache_key_and_the_concave_mesh(tmp_path, monkeypatch):
    monkeypatch.delenv(PERTURB_ENV, raising=False)
    plain = _concave(tmp_path, "cache")
    monkeypatch.setenv(PERTURB_ENV, "1e-14")
    pert = _concave(tmp_path, "cache")  # same cache folder: must not reuse the unperturbed mesh
    assert pert.key != plain.key and not pert.cached
    fp0, fp1 = plain.stats["fingerprint"], pert.stats["fingerprint"]
    assert fp1["perturb"] == 1e-14 and fp1["gmsh_input_sha256"] != fp0["gmsh_input_sha256"]
    assert fp1["coords_sha256"] != fp0["coords_sha256"]  # gmsh gives another (equally valid) mesh
    assert pert.stats["min_angle_deg"] > 20.0
    again = _concave(tmp_path, "cache")  # the perturbed one is reused for a perturbed run
    assert again.cached and again.key == pert.key
    monkeypatch.delenv(PERTURB_ENV)
    back = _concave(tmp_path, "cache")
    assert back.cached and back.key == plain.key and back.stats["fingerprint"] == fp0


def _ulp(x, n=1):
    x = np.asarray(x, dtype=float)
    for _ in range(n):
        x = np.nextafter(x, np.inf)
    return x


def test_rounding_makes_the_gmsh_input_invariant_under_last_bit_changes(tmp_path, monkeypatch):
    """What another machine does to the upstream floats (a few ULPs), done here by hand: same gmsh input."""
    monkeypatch.delenv(PERTURB_ENV, raising=False)
    des = design("symmetric")
    ivs = refine_intervals(des)
    ref = build_concave_mesh(design=des, h_contact=H_COARSE, refine_at=ivs, out_dir=tmp_path / "a",
                             write_xdmf=False)
    shifted = des._replace(concave=BSpline(_ulp(des.concave.control_points, 3), degree=des.concave.degree))
    other = build_concave_mesh(design=shifted, h_contact=float(_ulp(H_COARSE, 2)),
                               refine_at=[tuple(_ulp(iv, 5)) for iv in ivs], out_dir=tmp_path / "b",
                               write_xdmf=False)
    assert other.stats["fingerprint"]["gmsh_input_sha256"] == ref.stats["fingerprint"]["gmsh_input_sha256"]
    assert other.key == ref.key
    assert other.msh.read_bytes() == ref.msh.read_bytes()
    blk = [_block(tmp_path, s, a=a) for s, a in (("c", 0.5), ("d", float(_ulp(0.5, 2))))]
    assert blk[0].key == blk[1].key and blk[0].msh.read_bytes() == blk[1].msh.read_bytes()


@pytest.mark.parametrize("name", DESIGN_NAMES)
def test_the_frozen_control_points_are_the_designs(name):
    cp = design(name).concave.control_points
    frozen = frozen_control_points(name, cp)
    assert frozen is not None, f"meshes/data/concave_{name}.json no longer matches the design: refreeze it"
    assert np.max(np.abs(frozen - cp)) < 1e-12


def test_a_changed_design_falls_back_to_rounded_points(tmp_path, monkeypatch):
    monkeypatch.delenv(PERTURB_ENV, raising=False)
    des = design("symmetric")
    cp = np.array(des.concave.control_points)
    cp[100:140, 1] -= 1e-6  # a real (small) design change inside the body, away from the ends
    files = build_concave_mesh(design=des._replace(concave=BSpline(cp, degree=3)), h_contact=H_COARSE,
                               out_dir=tmp_path, write_xdmf=False)
    assert files.stats["fingerprint"]["geometry_source"] == "rounded"
    assert files.stats["contact_node_deviation_max"] < 1e-10


@pytest.mark.parametrize("text", ["abc", "nan", "inf", "-1e-15", "2e-6"])
def test_bad_perturbation_is_refused(text):
    with pytest.raises(ValueError, match=f"{PERTURB_ENV} = .*; allowed: "):
        perturb_amplitude({PERTURB_ENV: text})


def test_bad_perturbation_is_one_line_exit_2_nothing_written(tmp_path):
    import os

    text = "1e-3"
    proc = subprocess.run([sys.executable, "-m", "workbench", "mesh", "hertz_cylinder", "--out", str(tmp_path / "o")],
                          env={**os.environ, PERTURB_ENV: text}, capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"error: {PERTURB_ENV} = ") and "allowed:" in lines[0]
    assert not (tmp_path / "o").exists()


def test_good_perturbation_values():
    assert perturb_amplitude({}) == 0.0 and perturb_amplitude({PERTURB_ENV: ""}) == 0.0
    assert perturb_amplitude({PERTURB_ENV: "1e-14"}) == 1e-14 and perturb_amplitude({PERTURB_ENV: "1e-6"}) == 1e-6


def test_every_shipped_ci_mesh_keeps_a_rounding_margin(tmp_path, monkeypatch):
    """Every rounded gmsh input of every shipped case's CI mesh lies > 1e-3 grid units from a rounding midpoint
    (> 250 times the machine spread measured between OpenBLAS kernels), so another machine rounds it the same."""
    from mpi4py import MPI

    from cases import case_names, load_case
    from workbench.pipeline.case_mesh import case_meshes

    monkeypatch.delenv(PERTURB_ENV, raising=False)
    for name in case_names():
        case = load_case(name)
        h = case.discretisation.ci_level or case.discretisation.h_contact
        for label, f in case_meshes(case, mesh_cache=tmp_path, comm=MPI.COMM_SELF, h_contact=h).items():
            assert f.stats["gmsh_input_rounding_margin"] > 1e-3, (name, label)
            if case.geometry.scene == "concave":
                assert f.stats["fingerprint"]["geometry_source"] == "frozen", (name, label)


def test_metrics_json_carries_the_mesh_fingerprint(tmp_path, monkeypatch):
    """``workbench run`` writes the fingerprint into metrics.json's runs and mesh.json; a fresh ``workbench mesh``
    into another folder (another cache) gives the same fingerprint."""
    monkeypatch.delenv(PERTURB_ENV, raising=False)
    run = subprocess.run([sys.executable, "-m", "workbench", "run", "hertz_cylinder", "--ci", "--out",
                          str(tmp_path / "a")], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    m = json.loads((tmp_path / "a" / "hertz_cylinder" / "metrics.json").read_text())
    on_disk = json.loads((tmp_path / "a" / "hertz_cylinder" / "mesh.json").read_text())
    for r in m["runs"]:
        fp = r["mesh_fingerprint"]
        assert set(fp) == set(MeshFingerprint._fields) and fp == on_disk[r["label"]]["fingerprint"]
    from mpi4py import MPI

    from cases import load_case
    from workbench.pipeline.case_mesh import case_meshes

    case = load_case("hertz_cylinder")
    again = case_meshes(case, mesh_cache=tmp_path / "b", comm=MPI.COMM_SELF,
                        h_contact=case.discretisation.ci_level or case.discretisation.h_contact)
    assert {label: f.stats["fingerprint"] for label, f in again.items()} == \
        {r["label"]: r["mesh_fingerprint"] for r in m["runs"]}
