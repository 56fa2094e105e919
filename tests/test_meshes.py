"""Mesh builders (meshes/): named groups, sizes, quality, cache, refinement levels, spline fidelity."""

import dolfinx_solver  # noqa: F401  (before dolfinx)

import json

import meshio
import numpy as np
import pytest
from dolfinx.io import XDMFFile
from dolfinx.io import gmsh as dgmsh
from mpi4py import MPI

from analytic.designs import design
from meshes.block import build_block_mesh
from meshes.concave import build_concave_mesh
from meshes.quality import triangle_angles

A = 0.5  # Hertz half-width of the default cylinder scene (mm)
MIN_ANGLE = 20.0  # acceptance: minimum triangle angle (deg)


def _groups_nonempty(files, names):
    """Every named group exists and is non-empty, read back with meshio and with dolfinx."""
    mesh = meshio.read(files.msh)
    assert set(names) <= set(mesh.field_data)
    for name in names:
        tag, dim = mesh.field_data[name]
        kind = "triangle" if dim == 2 else "line"
        tags = mesh.cell_data_dict["gmsh:physical"][kind]
        assert np.count_nonzero(tags == tag) > 0, name
    data = dgmsh.read_from_msh(str(files.msh), MPI.COMM_SELF, 0, gdim=2)
    assert set(names) <= set(data.physical_groups)
    for name in names:
        dim, tag = data.physical_groups[name]
        tags = data.cell_tags if dim == 2 else data.facet_tags
        assert np.count_nonzero(tags.values == tag) > 0, name
    return mesh


def test_default_hertz_block_fast_named_quality_and_cached(tmp_path):
    # no wall-time assertion: the machine may be shared (mesh times are in `make bench`)
    files = build_block_mesh(width=40 * A, height=40 * A, contact_half_width=A, h_contact=A / 20,
                             out_dir=tmp_path, name="hertz", stats_dir=tmp_path / "case")
    assert not files.cached
    mesh = _groups_nonempty(files, ["contact", "clamped", "sides", "body"])
    st = files.stats
    assert st["contact_h_max"] <= A / 20
    assert st["min_angle_deg"] >= MIN_ANGLE
    # stats recomputed independently from the file
    tri = mesh.cells_dict["triangle"]
    assert triangle_angles(mesh.points, tri).min() == pytest.approx(st["min_angle_deg"], rel=1e-12)
    assert len(tri) == st["n_cells"]
    # contact edges cover the whole top y = 0
    cid = mesh.field_data["contact"][0]
    lines = mesh.cells_dict["line"][mesh.cell_data_dict["gmsh:physical"]["line"] == cid]
    pts = mesh.points[np.unique(lines)]
    assert np.allclose(pts[:, 1], 0.0) and pts[:, 0].min() == -20 * A and pts[:, 0].max() == 20 * A
    assert json.loads((tmp_path / "case" / "mesh.json").read_text())["n_cells"] == st["n_cells"]
    # XDMF: mesh + facet tags readable by dolfinx
    with XDMFFile(MPI.COMM_SELF, str(files.xdmf), "r") as f:
        msh = f.read_mesh(name="mesh")
        msh.topology.create_connectivity(1, 2)
        ft = f.read_meshtags(msh, name="facet_tags")
    assert msh.topology.index_map(2).size_local == st["n_cells"]
    assert set(np.unique(ft.values)) == {v[1] for k, v in st["physical_groups"].items() if v[0] == 1}
    # a rerun with the same parameters does not remesh
    again = build_block_mesh(width=40 * A, height=40 * A, contact_half_width=A, h_contact=A / 20,
                             out_dir=tmp_path, name="hertz")
    assert again.cached and again.key == files.key and again.stats["n_cells"] == st["n_cells"]
    other = build_block_mesh(width=40 * A, height=40 * A, contact_half_width=A, h_contact=A / 21,
                             out_dir=tmp_path, name="hertz", write_xdmf=False)
    assert not other.cached and other.key != files.key


def test_half_model_with_apex_refinement(tmp_path):
    files = build_block_mesh(width=40 * A, height=40 * A, contact_half_width=A, h_contact=A / 20,
                             half_model=True, apex_refinement=True, out_dir=tmp_path, name="wedge",
                             write_xdmf=False)
    mesh = _groups_nonempty(files, ["contact", "clamped", "sides", "symmetry", "body"])
    assert mesh.points[:, 0].min() == 0.0
    assert files.stats["min_angle_deg"] >= MIN_ANGLE
    # apex size 0.25 h_c; the first edge spans sizes growing by (g - 1) per unit length: ~(1 + (g - 1)/2) x
    assert files.stats["contact_h_min"] <= 0.25 * A / 20 * 1.2


def test_cell_count_over_three_levels(tmp_path):
    # Size h = h_c + (g - 1) d: cells ~ C1 / h_c (graded band along the refined segment) + C2 log(1/h_c)
    # (fan around its ends) + C3 (far field). Halving h_c multiplies the count by a factor in (1, 2) that
    # tends to 2 as h_c -> 0; expected band for h_c = a/20 .. a/80: [1.4, 2.1].
    counts = []
    for h in (A / 20, A / 40, A / 80):
        f = build_block_mesh(width=40 * A, height=40 * A, contact_half_width=A, h_contact=h, out_dir=tmp_path,
                             name="lvl", write_xdmf=False)
        assert f.stats["contact_h_max"] <= h
        assert f.stats["min_angle_deg"] >= MIN_ANGLE
        counts.append(f.stats["n_cells"])
    ratios = np.array(counts[1:]) / np.array(counts[:-1])
    assert np.all((ratios > 1.4) & (ratios < 2.1)), f"cells {counts}, ratios {ratios}"


@pytest.mark.parametrize("name", ["symmetric", "close_to_conformal"])
def test_concave_mesh_follows_the_analytic_spline(tmp_path, name):
    des = design(name)
    files = build_concave_mesh(design=des, h_contact=0.1, out_dir=tmp_path, write_xdmf=False)
    mesh = _groups_nonempty(files, ["contact", "clamped", "body"])
    st = files.stats
    # gmsh's OCC B-spline is built from the same control points/knots: nodes on the curve to round-off
    assert st["contact_node_deviation_max"] < 1e-10
    assert st["contact_h_max"] <= 0.1
    assert st["min_angle_deg"] >= MIN_ANGLE
    x_min, x_max, y_bot = des.body_box
    assert mesh.points[:, 0].min() == pytest.approx(x_min) and mesh.points[:, 1].min() == pytest.approx(y_bot)


def test_bad_arguments_raise_value_error(tmp_path):
    kw = dict(width=20.0, height=20.0, contact_half_width=0.5, h_contact=0.05, out_dir=tmp_path)
    with pytest.raises(ValueError, match="h_contact"):
        build_block_mesh(**{**kw, "h_contact": 0.0})
    with pytest.raises(ValueError, match="width"):
        build_block_mesh(**{**kw, "width": 1.0})
    with pytest.raises(ValueError, match="growth"):
        build_block_mesh(**kw, growth=1.0)
    with pytest.raises(ValueError, match="refine_at"):
        build_concave_mesh(design="symmetric", h_contact=0.1, refine_at=[(0.5, 0.4)], out_dir=tmp_path)


def test_a_name_with_a_dot_keeps_the_parameters_in_the_cache_key(tmp_path):
    """``cyl_0.05`` once lost its key to ``Path.with_suffix``: another mesh under that name came from the cache."""
    from meshes.cache import cache_paths
    from meshes.two_body import build_stacked_blocks

    assert cache_paths(tmp_path, "cyl_0.05", "abc")["msh"].name == "cyl_0.05-abc.msh"
    kw = dict(width=1.0, height_lower=1.0, height_upper=0.5, out_dir=tmp_path, name="blocks_h_0.25")
    coarse = build_stacked_blocks(h_lower=0.25, h_upper=0.4, **kw)
    fine = build_stacked_blocks(h_lower=0.125, h_upper=0.2, **kw)
    assert not fine.cached and fine.msh != coarse.msh
    assert fine.stats["cells"] > 2 * coarse.stats["cells"]
