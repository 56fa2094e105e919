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
    # the boundary moved as Flamant's field at the target: the bottom-right corner, against an evaluation that
    # shares no code with analytic.flamant (integrated from Flamant's stresses, _flamant_by_integration)
    W = 20 * A
    ux, uy = _flamant_by_integration(W / 2, W, P=P_TARGET, E=E, nu=NU, r_ref=W)
    got = one.u.eval(np.array([[W / 2, -W, 0.0]]), np.array([_cell_at(one.u, W / 2, -W)], dtype=np.int32))
    # the boundary dof holds the interpolated closed form (round-off); the quadrature is good to ~1e-11
    np.testing.assert_allclose(got, [ux, uy], rtol=1e-8)
    # and the closed form of analytic.flamant agrees with the integration (it is what fem/far_field.py imposes)
    np.testing.assert_allclose(flamant_displacement(W / 2, -W, P=P_TARGET, E=E, nu=NU, r_ref=W), [ux, uy],
                               rtol=1e-9)


def _flamant_by_integration(x, depth, *, P, E, nu, r_ref):
    """(u_x, u_y) at (x, -depth) from Flamant's stress field alone (Johnson, Contact Mechanics eq. 2.15):
    sigma_x = -2P x^2 z / (pi r^4), sigma_z = -2P z^3 / (pi r^4), tau_xz = -2P x z^2 / (pi r^4), z = depth.

    Plane-strain strains, then displacements by path integrals with the rigid motion fixed as the module's:
    on the axis x = 0, u_x = 0 and the rotation vanish (symmetry) and u_z(0, r_ref) = 0, so
        u_z(0, D) = int_{r_ref}^{D} eps_z(0, z) dz,   u_x(x, D) = int_0^x eps_x(s, D) ds,
        u_z(x, D) = u_z(0, D) + int_0^x [2 eps_xz(s, D) - d/dz u_x(s, D)] ds,
    with d/dz u_x(s, D) = int_0^s d/dz eps_x(t, D) dt (u_x = 0 on the axis at every depth).
    """
    from scipy.integrate import quad

    def stress(px, z):
        r4 = (px * px + z * z) ** 2
        return -2 * P * px * px * z / (np.pi * r4), -2 * P * z**3 / (np.pi * r4), -2 * P * px * z * z / (np.pi * r4)

    def eps(px, z):
        sx, sz, txz = stress(px, z)
        return ((1 + nu) / E * ((1 - nu) * sx - nu * sz), (1 + nu) / E * ((1 - nu) * sz - nu * sx),
                (1 + nu) / E * txz)

    def deps_x_dz(px, z, h=1e-5):
        return (eps(px, z * (1 + h))[0] - eps(px, z * (1 - h))[0]) / (2 * h * z)

    opts = dict(epsabs=0.0, epsrel=1e-11, limit=200)
    uz_axis = quad(lambda z: eps(0.0, z)[1], r_ref, depth, **opts)[0] if depth != r_ref else 0.0
    ux = quad(lambda s: eps(s, depth)[0], 0.0, x, **opts)[0]
    dux_dz = lambda s: quad(lambda t: deps_x_dz(t, depth), 0.0, s, **opts)[0]  # noqa: E731
    uz = uz_axis + quad(lambda s: 2 * eps(s, depth)[2] - dux_dz(s), 0.0, x, **opts)[0]
    return ux, -uz


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
