"""The ``halfplane`` far field (fem/far_field.py): the block's outer boundary moves as Flamant's half-plane.

Requirements: (1) it removes most of the finite-block error (Hertz cylinder, a/R = 0.05, P2, h_c = a/10: the
moment half-width 2 sqrt(M2/M0) changes between W = 20 a and 80 a by less than a tenth of what it changes with
the clamped block); (2) the rigid-motion reference r_ref does not change the contact (only the approach d);
(3) displacement control is refused; (4) a bad or unsupported case value gives one line and exit 2.
"""

import dolfinx_solver  # noqa: F401

import numpy as np
import pytest
from dolfinx.io import gmsh as dgmsh
from mpi4py import MPI
from probe_cases import PROBE_BLOCK

import fem.far_field as far_field_module
from analytic.flamant import flamant_displacement
from analytic.hertz import hertz_load_from_half_width
from fem.elasticity import plane_strain_modulus
from fem.far_field import far_field_supports
from fem.obstacles import CircleObstacle
from fem.solver import solve_contact
from meshes.block import build_block_mesh
from workbench.cli import main

R, E, NU = 10.0, 200e3, 0.3
A = 0.05 * R
P_TARGET = hertz_load_from_half_width(A, R, plane_strain_modulus(E=E, nu=NU))


@pytest.fixture(scope="module")
def meshes(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("far_field")
    out = {}
    for W in (20, 80):
        mf = build_block_mesh(width=W * A, height=W * A, contact_half_width=A, h_contact=A / 10, half_model=True,
                              out_dir=tmp, name=f"ff{W}")
        out[W] = dgmsh.read_from_msh(str(mf.msh), MPI.COMM_WORLD, 0, gdim=2)
    return out


def _solve(mesh, far_field, **kw):
    return solve_contact(mesh, CircleObstacle(center=(0.0, R), radius=R), E=E, nu=NU, degree=2, method="nitsche",
                         traction="halfplane", control="force", target=P_TARGET, n_steps=kw.pop("n_steps", 1),
                         symmetric_half=True, supports=far_field_supports(far_field=far_field, symmetric_half=True),
                         **kw)


def _moment(res):
    s = res.samples
    return 2.0 * np.sqrt(np.sum(s.weight * s.p * s.s**2) / np.sum(s.weight * s.p))


def test_halfplane_far_field_removes_the_block_size_error(meshes):
    m = {(ff, W): _moment(_solve(meshes[W], ff)) for ff in ("clamped", "halfplane") for W in (20, 80)}
    clamped = abs(m["clamped", 20] / m["clamped", 80] - 1.0)
    halfplane = abs(m["halfplane", 20] / m["halfplane", 80] - 1.0)
    assert clamped > 5e-4, m  # the clamped block's truncation is visible at this resolution
    assert halfplane < 0.1 * clamped, (halfplane, clamped)


def test_reference_depth_moves_the_body_not_the_contact(meshes, monkeypatch):
    base = _solve(meshes[20], "halfplane")
    monkeypatch.setattr(far_field_module, "reference_depth", lambda mesh: 3.0 * 20 * A)
    other = _solve(meshes[20], "halfplane")
    # u_y changes by the uniform 2 (1 - nu^2) P ln(3) / (pi E): d takes it, the contact does not
    shift = 2 * (1 - NU**2) * P_TARGET * np.log(3.0) / (np.pi * E)
    assert abs((other.d - base.d) - shift) < 1e-6 * shift
    np.testing.assert_allclose(other.samples.p, base.samples.p, rtol=0, atol=1e-7 * np.max(base.samples.p))


def test_load_levels_scale_the_far_field(meshes):
    """Three force levels (the far field at each level's load) end on the one-step answer."""
    one, three = _solve(meshes[20], "halfplane"), _solve(meshes[20], "halfplane", n_steps=3)
    np.testing.assert_allclose(three.samples.p, one.samples.p, rtol=0, atol=1e-7 * np.max(one.samples.p))
    # the boundary moved as Flamant's field at the target: the bottom-right corner
    W = 20 * A
    ux, uy = flamant_displacement(W / 2, -W, P=P_TARGET, E=E, nu=NU, r_ref=W)
    got = one.u.eval(np.array([[W / 2, -W, 0.0]]), np.array([_cell_at(one.u, W / 2, -W)], dtype=np.int32))
    np.testing.assert_allclose(got, [ux, uy], rtol=1e-9)


def _cell_at(u, x, y):
    import dolfinx.geometry as geo

    mesh = u.function_space.mesh
    pts = np.array([[x, y, 0.0]])
    tree = geo.bb_tree(mesh, 2)
    return geo.compute_colliding_cells(mesh, geo.compute_collisions_points(tree, pts), pts).links(0)[0]


def test_displacement_control_is_refused(meshes):
    with pytest.raises(ValueError, match="halfplane.*control='force'"):
        solve_contact(meshes[20], CircleObstacle(center=(0.0, R), radius=R), E=E, nu=NU, control="displacement",
                      target=1e-3, symmetric_half=True,
                      supports=far_field_supports(far_field="halfplane", symmetric_half=True))


def test_far_field_supports_vocabulary():
    assert far_field_supports(far_field="clamped", symmetric_half=True) is None
    assert far_field_supports(far_field="halfplane", symmetric_half=False) == {"clamped": "halfplane",
                                                                              "sides": "halfplane"}
    with pytest.raises(ValueError, match="far_field must be"):
        far_field_supports(far_field="roller", symmetric_half=True)


BLOCK = PROBE_BLOCK.replace("radius = 10.0\n", 'radius = 10.0\nfar_field = "FAR"\n')
CONCAVE = """
[case]
name = "probe"
[material]
E = 214000.0
nu = 0.3
[geometry]
scene = "concave"
indenter = "particle"
design = "symmetric"
far_field = "halfplane"
[loading]
control = "displacement"
d = [0.6]
"""


@pytest.mark.parametrize("text, words", [
    (BLOCK.replace("FAR", "infinite"), ["geometry.far_field", "'clamped'", "'halfplane'"]),
    (CONCAVE, ["geometry.far_field", "not used by a concave scene"]),
])
def test_bad_far_field_exit_2_one_line(text, words, tmp_path, capsys):
    p = tmp_path / "probe.toml"
    p.write_text(text)
    out = tmp_path / "results"
    code = main(["run", str(p), "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    assert len(err.splitlines()) == 1, err
    for w in words:
        assert w in err, (w, err)
    assert not out.exists()


def test_case_field_reaches_the_solver_options(tmp_path):
    """``[geometry] far_field`` goes through the case wiring into the solver's supports."""
    from cases import load_case
    from workbench.scenes.base import LoadPath
    from workbench.scenes.wiring import solver_options

    for far, supports in (("clamped", None), ("halfplane", {"clamped": "halfplane", "sides": "halfplane",
                                                            "symmetry": "roller_x"})):
        p = tmp_path / f"{far}.toml"
        p.write_text(BLOCK.replace("FAR", far))
        run = load_case(p).runs()[0]
        opts = solver_options(run, LoadPath("force", 100.0, 1, symmetric_half=True))
        assert opts.supports == supports
