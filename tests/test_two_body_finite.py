"""Two hyperelastic bodies at finite strain (:mod:`fem.two_body.finite_problem`): the patch test, the exact
Jacobian, the refusals.

Patch test: the stacked blocks of the small-strain patch test (rollers on the bottom and the left sides, the
upper block's top driven down, its right sides free), lower block Saint Venant-Kirchhoff (E = 200 GPa,
nu = 0.3), upper block neo-Hookean (E = 70 GPa), non-matching meshes, the softer block compressed ~10 %. At
finite strain the two blocks expand sideways by different stretches in general, and the wider one then overhangs
the contact: no homogeneous solution exists. So the upper block's nu is chosen (solved for here) so that both
lateral stretches are equal at the final load; then the exact solution is homogeneous in each body,
``F_k = diag(l1, s_k)``, with ``P_xx = 0`` in each body, the same ``P_yy`` (the contact force per reference
width), and the current contact pressure ``p = -P_yy / l1`` uniform on the current width ``l1 W``. The solution
of a frictionless elastic problem does not depend on the load path, so only the final state is compared.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401

import os

import numpy as np
import pytest
from mpi4py import MPI
from scipy.optimize import fsolve

from fem.elasticity import lame
from fem.options import ContactOptions
from fem.partners import contact_problem
from fem.stepping import LoadStepper
from fem.two_body.finite_problem import FiniteTwoBodyProblem
from fem.two_body.problem import Body, MeshedPartner
from meshes.two_body import build_cylinder_on_block, build_stacked_blocks
from workbench.mesh_io import read_mesh

WIDTH, H_LOWER, H_UPPER = 1.0, 1.0, 0.5
D = 0.08  # mm: the upper block ~9 % shorter, the lower ~3 %
LOWER = ("saint_venant_kirchhoff", 200000.0, 0.3)
UPPER = ("neo_hookean", 70000.0)
PATCH_RTOL = 1e-8


# The cylinder solves (rigid limit at both laws, small-load Hertz: about 40 s cold) run in make slow-tests; the patch
# and Jacobian tests, the small-load patch check and the refusals run in make test.
SLOW = os.environ.get("WORKBENCH_SLOW_TESTS") == "1"
SLOW_REASON = "cylinder solves (about 40 s cold): make slow-tests runs them (WORKBENCH_SLOW_TESTS=1)"

def piola(model: str, E: float, nu: float, l1: float, s: float) -> tuple[float, float]:
    """(P_xx, P_yy) (MPa) of the homogeneous plane-strain deformation F = diag(l1, s)."""
    lm = lame(E=E, nu=nu)
    if model == "saint_venant_kirchhoff":
        exx, eyy = 0.5 * (l1**2 - 1), 0.5 * (s**2 - 1)
        return l1 * (lm.lmbda * (exx + eyy) + 2 * lm.mu * exx), s * (lm.lmbda * (exx + eyy) + 2 * lm.mu * eyy)
    lnJ = np.log(l1 * s)
    return lm.mu * (l1 - 1 / l1) + lm.lmbda * lnJ / l1, lm.mu * (s - 1 / s) + lm.lmbda * lnJ / s


def matched_state() -> tuple[float, float, float, float]:
    """(l1, s_lower, s_upper, nu_upper): the homogeneous state with equal lateral stretches at d = D (no overlap:
    the augmented Lagrangian closes the gap)."""
    def f(z):
        l1, s_l, s_u, nu = z
        pxl, pyl = piola(*LOWER, l1, s_l)
        pxu, pyu = piola(*UPPER, nu, l1, s_u)
        return [pxl, pxu, pyl - pyu, (s_l - 1) * H_LOWER + (s_u - 1) * H_UPPER + D]

    z, _, ok, msg = fsolve(f, [1.0, 0.97, 0.9, 0.2], xtol=1e-14, full_output=True)
    assert ok == 1 or np.max(np.abs(f(z))) < 1e-9, msg
    return tuple(z)


@pytest.fixture(scope="module")
def stacked(tmp_path_factory):
    mf = build_stacked_blocks(width=WIDTH, height_lower=H_LOWER, height_upper=H_UPPER, h_lower=1 / 7,
                              h_upper=1 / 4.3, out_dir=tmp_path_factory.mktemp("mesh"))
    return read_mesh(mf.msh, MPI.COMM_SELF)


def _patch_problem(md, nu_upper: float, *, slave: str = "contact_lower", method: str = "augmented_lagrangian",
                   degree: int = 1, **setup_kw):
    master = "contact_upper" if slave == "contact_lower" else "contact_lower"
    setup = MeshedPartner(bodies=(Body(name="lower", E=LOWER[1], nu=LOWER[2], material_model=LOWER[0]),
                                  Body(name="upper", E=UPPER[1], nu=nu_upper, material_model=UPPER[0])),
                          slave=slave, master=master, driven="driven", driven_body="upper", driven_components=(1,),
                          **({"traction": "master_normal"} | setup_kw))
    opts = ContactOptions.of(target=D, degree=degree, method=method, kinematics="finite", control="displacement",
                             n_steps=4, supports={"clamped": "roller_y", "symmetry": "roller_x"},
                             active_set_predictor=False, predictor="extrapolate")
    return contact_problem(md, setup, opts)


@pytest.mark.parametrize("slave", ["contact_lower", "contact_upper"])
def test_finite_patch_test(stacked, slave):
    l1, s_l, s_u, nu_u = matched_state()
    assert l1 - 1 > 1e-2 and 1 - s_u > 0.08  # finite: the current length differs from the reference one by 1 %
    pb = _patch_problem(stacked, nu_u, slave=slave)
    assert isinstance(pb, FiniteTwoBodyProblem)
    stepper = LoadStepper(pb)
    stepper.run()
    pyy = piola(*LOWER, l1, s_l)[1]
    p_exact = -pyy / l1
    smp = pb.sample()
    P, Pp = pb.measure()
    assert abs(P / (-pyy * WIDTH) - 1) < PATCH_RTOL
    assert abs(Pp / P - 1) < PATCH_RTOL
    assert np.max(np.abs(smp.p / p_exact - 1)) < PATCH_RTOL
    X = pb.V.tabulate_dof_coordinates()[:, :2]
    U = pb.u.x.array.reshape(-1, 2)
    exact = np.zeros_like(U)
    lo, up = pb.body_nodes["lower"], pb.body_nodes["upper"]
    exact[lo] = np.column_stack([(l1 - 1) * X[lo, 0], (s_l - 1) * (X[lo, 1] + H_LOWER)])
    exact[up] = np.column_stack([(l1 - 1) * X[up, 0], (s_l - 1) * H_LOWER + (s_u - 1) * X[up, 1]])
    assert np.max(np.abs(U - exact)) < PATCH_RTOL * D
    assert max(r["iterations"] for r in stepper.records) <= 10


@pytest.fixture(scope="module")
def cylinder(tmp_path_factory):
    a = 0.5
    mf = build_cylinder_on_block(radius=10.0, width=20 * a, height=20 * a, contact_half_width=a, h_contact=a / 5,
                                 out_dir=tmp_path_factory.mktemp("mesh"))
    return read_mesh(mf.msh, MPI.COMM_SELF)


@pytest.fixture(scope="module")
def loaded_cylinder(cylinder):
    """The cylinder on the block at finite strain, pressed 0.03 mm with the penalty law (so the slave overlaps
    the master a little, and the overlaps' cuts exist)."""
    partner = MeshedPartner(bodies=(Body(name="lower", E=210000.0, nu=0.3, material_model="saint_venant_kirchhoff"),
                                    Body(name="upper", E=70000.0, nu=0.25, material_model="neo_hookean")),
                            slave="contact_lower", master="contact_upper", driven="driven", driven_body="upper",
                            traction="master_normal")
    opts = ContactOptions.of(target=3e-2, degree=1, method="penalty", kinematics="finite", control="displacement",
                             n_steps=3, predictor="extrapolate", active_set_predictor=False)
    pb = contact_problem(cylinder, partner, opts)
    LoadStepper(pb).run()
    return pb


def test_jacobian_equals_finite_differences(loaded_cylinder):
    """The assembled Jacobian (hyperelastic bulk + current-configuration mortar terms, both linearised exactly:
    the gap, the deformed master normal, the current length) against central differences of the residual, at a
    contacting state of a curved master (measured 5.9e-9 for the whole, 4.2e-9 for the contact part; 8.8e-8 and
    more before the cuts' motion was linearised)."""
    pb = loaded_cylinder
    rng = np.random.default_rng(1)
    u0 = pb.u.x.array.copy()
    u0[pb.free] += 1e-8 * rng.standard_normal(int(pb.free.sum()))
    q = pb.method.argument(pb.weighted_gaps(u0))
    assert (q > 0).sum() >= 4 and (q <= 0).any()
    x = pb.x.duplicate()
    x.setArray(u0)
    J = pb.A.duplicate()
    pb.snes.computeJacobian(x, J)
    v = np.zeros_like(u0)
    v[pb.free] = rng.standard_normal(int(pb.free.sum()))
    eps = 1e-8 * np.max(np.abs(u0)) / np.max(np.abs(v))
    fp, fm, Jv, vv = x.duplicate(), x.duplicate(), x.duplicate(), x.duplicate()
    x.setArray(u0 + eps * v)
    pb.snes.computeFunction(x, fp)
    x.setArray(u0 - eps * v)
    pb.snes.computeFunction(x, fm)
    vv.setArray(v)
    J.mult(vv, Jv)
    fd = (fp.getArray() - fm.getArray()) / (2 * eps)
    err = np.max(np.abs(fd - Jv.getArray())) / np.max(np.abs(Jv.getArray()))
    print(f"Jacobian vs central differences: full {err:.2e}")
    assert err < 1e-6
    # the contact part alone (the bulk's share would hide it)
    c_fd = (pb.contact_residual(u0 + eps * v) - pb.contact_residual(u0 - eps * v)) / (2 * eps)
    Jc = pb.contact_jacobian(u0) @ v
    err_c = np.max(np.abs(c_fd - Jc)[pb.free]) / np.max(np.abs(Jc))
    print(f"contact part {err_c:.2e}, active nodes {(q > 0).sum()}")
    assert err_c < 1e-6


def test_derivatives_carry_the_moving_cuts(loaded_cylinder):
    """The traction's geometric term ``sum_i c_i dT_i/du`` and the weighted gaps' derivative against central
    differences along a sliding of the upper body (every cut of the segmentation moves). Without the moving bounds
    (fem.two_body.finite_contact: Leibniz's rule at each cut) the geometric term was off by 2.35e-2 along a Newton
    direction of the two-half-planes case, and Newton converged linearly there."""
    pb = loaded_cylinder
    conv = pb.conv
    u0 = pb.u.x.array.copy()
    pc = conv._points(u0)
    assert ((pc.cut0 >= 0) | (pc.cut1 >= 0)).sum() >= 10 and (pc.rho1 == 2).any()  # cuts and bisectors move
    v = np.zeros_like(u0)
    up = pb.body_nodes["upper"]
    v[2 * up] = 1.0  # the upper body slides along x
    v[2 * up + 1] = 0.2 * np.sin(7.0 * conv._X[up, 0])  # and bends a little
    g, D, _, _ = conv.linearise(u0)
    p = pb.method.pressure(g)[0]
    assert (p > 0).sum() >= 4
    _, _, H, _ = conv.linearise(u0, hessian_weights=lambda _g: p)
    eps = 1e-7
    tp, tm = (conv.linearise(u0 + s * eps * v, derivatives=False)[3].T @ p for s in (1.0, -1.0))
    fd, an = (tp - tm) / (2 * eps), H @ v
    err = np.linalg.norm(fd - an) / np.linalg.norm(an)
    gfd = (conv.gaps(u0 + eps * v) - conv.gaps(u0 - eps * v)) / (2 * eps)
    act = p > 0
    gerr = np.max(np.abs(gfd - (D @ v) / pb.gap.W)[act]) / np.max(np.abs(gfd[act]))
    print(f"geometric term {err:.2e}, gap derivative {gerr:.2e}")
    assert err < 1e-5 and gerr < 1e-5


@pytest.mark.parametrize(("change", "match"), [
    ({"degree": 2}, "degree 1 only"),
    ({"pairing": "node_to_segment"}, "pairing='mortar' only"),
    ({"traction": "halfplane"}, "traction='master_normal'"),
])
def test_refusals(stacked, change, match):
    degree = change.pop("degree", 1)
    with pytest.raises(ValueError, match=match):
        _patch_problem(stacked, 0.2, degree=degree, **change)


def test_linear_bodies_are_refused_at_finite_strain(stacked):
    setup = MeshedPartner(bodies=(Body(name="lower", E=1.0, nu=0.3), Body(name="upper", E=1.0, nu=0.3)),
                          slave="contact_lower", master="contact_upper", driven="driven", driven_body="upper",
                          traction="master_normal")
    with pytest.raises(ValueError, match="material_model"):
        contact_problem(stacked, setup, ContactOptions.of(target=1.0, degree=1, method="penalty", kinematics="finite"))
    hyper = MeshedPartner(bodies=(Body(name="lower", E=1.0, nu=0.3, material_model="neo_hookean"),
                                  Body(name="upper", E=1.0, nu=0.3)),
                          slave="contact_lower", master="contact_upper", driven="driven", driven_body="upper")
    with pytest.raises(ValueError, match="needs kinematics='finite'"):
        contact_problem(stacked, hyper, ContactOptions.of(target=1.0, degree=1, method="penalty"))


R_CYL, A_CYL, E_BLOCK, NU_BLOCK = 10.0, 0.5, 210000.0, 0.3


@pytest.fixture(scope="module", params=["neo_hookean", "saint_venant_kirchhoff"])
def rigid_limit(request, tmp_path_factory):
    """p_max (MPa) and the half-width (mm) of the stiff cylinder (E ratio 1e6) on the hyperelastic block at a/R = 0.05
    through the two-body solver (P1 mortar, augmented Lagrangian), and of the rigid circle on the same block
    (the rigid finite-strain solver: P2 Nitsche, traction along the obstacle's normal, as tests/test_finite_hertz.py),
    each at finite strain and at small strain (vertical traction), at the same load."""
    from analytic.hertz import hertz_load_from_half_width
    from analytic.materials import plane_strain_modulus
    from fem.obstacles import CircleObstacle
    from fem.solver import solve_contact

    kw = dict(radius=R_CYL, width=20 * A_CYL, height=20 * A_CYL, contact_half_width=A_CYL, h_contact=A_CYL / 10,
              out_dir=tmp_path_factory.mktemp("mesh"))
    two = read_mesh(build_cylinder_on_block(**kw).msh, MPI.COMM_SELF)
    block = read_mesh(build_cylinder_on_block(indenter=False, **kw).msh, MPI.COMM_SELF)
    P = hertz_load_from_half_width(A_CYL, R_CYL, plane_strain_modulus(E_BLOCK, NU_BLOCK))
    out = {}
    for kin, model, traction in (("small", "linear", "halfplane"), ("finite", request.param, "master_normal")):
        rigid = solve_contact(block, CircleObstacle(center=(0.0, R_CYL), radius=R_CYL), options=ContactOptions.of(
            E=E_BLOCK, nu=NU_BLOCK, kinematics=kin, material_model=model,
            traction="obstacle" if kin == "finite" else "halfplane", contact_group="contact_lower", target=P,
            degree=2, method="nitsche", control="force", n_steps=1))
        partner = MeshedPartner(bodies=(Body(name="lower", E=E_BLOCK, nu=NU_BLOCK, material_model=model),
                                        Body(name="upper", E=1e6 * E_BLOCK, nu=NU_BLOCK, material_model=model)),
                                slave="contact_lower", master="contact_upper", driven="driven", driven_body="upper",
                                traction=traction)
        res = solve_contact(two, partner, options=ContactOptions.of(
            kinematics=kin, target=P, degree=1, method="augmented_lagrangian", control="force", n_steps=4,
            predictor="extrapolate", active_set="geometry"))
        assert abs(res.P / P - 1) < 1e-8
        for name, r in (("rigid", rigid), ("two", res)):
            out[name, kin] = (float(np.max(r.samples.p)), r.patches[0].half_width)
    out["model"] = request.param
    return out


@pytest.mark.skipif(not SLOW, reason=SLOW_REASON)
def test_rigid_limit_finite_strain_effect(rigid_limit):
    """The finite-strain change of p_max against the small-strain solve at the same load, a/R = 0.05: measured
    neo-Hookean +0.443 % (two bodies, E ratio 1e6) and +0.398 % (rigid circle), Saint Venant-Kirchhoff -2.18 % and
    -1.99 %: they agree to a tenth of the effect, inside the rigid case's band for it (tests/test_finite_hertz.py:
    +0.19 % in (0.1, 0.3) % and -0.29 % in (-0.4, -0.2) % at a/R = 0.01, +-33 to 50 % of the effect); asserted:
    a quarter of it. The two discretisations themselves differ by 2.6 % in p_max (P1 mortar on the cylinder's
    chords against P2 Nitsche on the exact circle), at small and finite strain alike."""
    d_two = rigid_limit["two", "finite"][0] / rigid_limit["two", "small"][0] - 1
    d_rigid = rigid_limit["rigid", "finite"][0] / rigid_limit["rigid", "small"][0] - 1
    print(f"{rigid_limit['model']}: finite-strain change of p_max: two bodies {d_two:+.4%}, rigid {d_rigid:+.4%}")
    sign = 1.0 if rigid_limit["model"] == "neo_hookean" else -1.0  # neo-Hookean stiffens in compression, SVK softens
    assert sign * d_two > 0 and sign * d_rigid > 0
    assert abs(d_two - d_rigid) < 0.25 * abs(d_rigid)
    # the two solvers' p_max differ by their discretisations (P1 chords / P2 exact circle), not by the kinematics
    ratio_f = rigid_limit["two", "finite"][0] / rigid_limit["rigid", "finite"][0]
    assert abs(ratio_f - 1) < 0.04
    # the half-width: the two-body edge is interpolated between P1 nodes h = a/10 apart (P2 Nitsche for the rigid
    # circle); measured two/rigid 0.953 (NH), 0.938 (SVK) at finite strain, 0.965 at small strain: its finite-strain
    # change (~1 %) is below that resolution, so only half the node spacing is asserted
    bf = rigid_limit["two", "finite"][1] / rigid_limit["rigid", "finite"][1]
    bs = rigid_limit["two", "small"][1] / rigid_limit["rigid", "small"][1]
    print(f"{rigid_limit['model']}: half-width two/rigid: finite {bf:.4f}, small {bs:.4f}")
    assert abs(bf - 1) < 0.1 and abs(bf / bs - 1) < 0.05


def _cylinder_p_max(tmp_path_factory, a: float, kinematics: str) -> float:
    """p_max (MPa) of the stiff cylinder (E ratio 1e6) on the neo-Hookean (or linear) block at the Hertz load of
    half-width a (h = a/10, W = H = 20 a), two-body solver."""
    from analytic.hertz import hertz_load_from_half_width
    from analytic.materials import composite_modulus
    from fem.solver import solve_contact

    kw = dict(radius=R_CYL, width=20 * a, height=20 * a, contact_half_width=a, h_contact=a / 10,
              out_dir=tmp_path_factory.mktemp("mesh"))
    two = read_mesh(build_cylinder_on_block(**kw).msh, MPI.COMM_SELF)
    model = "neo_hookean" if kinematics == "finite" else "linear"
    partner = MeshedPartner(bodies=(Body(name="lower", E=E_BLOCK, nu=NU_BLOCK, material_model=model),
                                    Body(name="upper", E=1e6 * E_BLOCK, nu=NU_BLOCK, material_model=model)),
                            slave="contact_lower", master="contact_upper", driven="driven", driven_body="upper",
                            traction="master_normal" if kinematics == "finite" else "halfplane")
    P = hertz_load_from_half_width(a, R_CYL, composite_modulus(1e6 * E_BLOCK, NU_BLOCK, E1=E_BLOCK, nu1=NU_BLOCK))
    res = solve_contact(two, partner, options=ContactOptions.of(
        kinematics=kinematics, target=P, degree=1, method="augmented_lagrangian", control="force", n_steps=4,
        predictor="extrapolate", active_set="geometry"))
    return float(np.max(res.samples.p))


@pytest.mark.skipif(not SLOW, reason=SLOW_REASON)
def test_small_loads_reproduce_small_strain_hertz(tmp_path_factory):
    """The finite-strain p_max against the small-strain two-body p_max at the same load is first order in the
    strain a/R (for Hertz a ~ sqrt(P)): measured +1.78e-3 at a/R = 0.02 and +9.50e-4 at a/R = 0.01 (ratio 1.87;
    the half-widths agree to 2e-4 at both, inside the P1 edge resolution)."""
    d = {a: _cylinder_p_max(tmp_path_factory, a, "finite") / _cylinder_p_max(tmp_path_factory, a, "small") - 1
         for a in (0.2, 0.1)}
    print(f"p_max finite/small - 1: a/R = 0.02 {d[0.2]:.3e}, a/R = 0.01 {d[0.1]:.3e}")
    assert 0 < d[0.1] < d[0.2] < 3e-3
    assert 1.6 < d[0.2] / d[0.1] < 2.4


def test_small_loads_reproduce_small_strain_patch(stacked):
    """The stacked blocks (the patch test's bodies, any nu): the load P at the top displacement d at finite strain
    against small strain differs by a relative amount proportional to d (the strain)."""
    rel = {}
    for d in (2e-3, 1e-3):
        P = {}
        for kin in ("small", "finite"):
            lin = kin == "small"
            setup = MeshedPartner(
                bodies=(Body(name="lower", E=LOWER[1], nu=LOWER[2], material_model="linear" if lin else LOWER[0]),
                        Body(name="upper", E=UPPER[1], nu=0.33, material_model="linear" if lin else UPPER[0])),
                slave="contact_lower", master="contact_upper", driven="driven", driven_body="upper",
                driven_components=(1,), traction="halfplane" if lin else "master_normal")
            opts = ContactOptions.of(target=d, degree=1, method="augmented_lagrangian", kinematics=kin,
                                     control="displacement", n_steps=1, active_set_predictor=False,
                                     supports={"clamped": "roller_y", "symmetry": "roller_x"}, predictor="extrapolate")
            pb = contact_problem(stacked, setup, opts)
            LoadStepper(pb).run()
            P[kin] = pb.measure()[0]
        rel[d] = P["finite"] / P["small"] - 1
    print(f"P finite/small - 1: d = 2e-3 {rel[2e-3]:.4e}, d = 1e-3 {rel[1e-3]:.4e}")
    assert abs(rel[1e-3]) < abs(rel[2e-3]) < 1e-2
    assert 1.9 < rel[2e-3] / rel[1e-3] < 2.1


def test_shared_node_pairs_match_the_dense_definition():
    """The contact search's pairs of candidate facets sharing a node (found by sorting) are those of the dense test
    ``np.nonzero(np.triu(shares, 1))``, in its order (k, then i1, then i2), padding excluded: random polylines with
    repeated, reversed and degenerate facets."""
    from fem.two_body.finite_contact import _shared_node_pairs

    rng = np.random.default_rng(7)
    for _ in range(50):
        K, C = int(rng.integers(1, 6)), int(rng.integers(1, 9))
        ends = rng.integers(0, 6, size=(K, C, 2))
        valid = rng.random((K, C)) < 0.8
        shares = (ends[:, :, None, :, None] == ends[:, None, :, None, :]).any(axis=(3, 4))
        shares &= valid[:, :, None] & valid[:, None, :]
        want = np.nonzero(np.triu(shares, 1))
        got = _shared_node_pairs(ends, valid)
        for w, g in zip(want, got, strict=True):
            np.testing.assert_array_equal(g, w)
