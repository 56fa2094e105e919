"""Two elastic bodies on non-matching meshes: the contact patch test, the exact Jacobian, the refusals.

Patch test (Taylor and Papadopoulos 1991): two blocks of different materials stacked on rollers and pressed by a
uniform displacement of the upper block's top. The exact solution is a uniform stress, so the contact pressure
is uniform and equal to P / W. Mortar (segment-to-segment) carries it exactly on non-matching meshes;
node-to-segment does not (its error is measured and reported here, it is not a tolerance).
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401

import numpy as np
import pytest
from mpi4py import MPI

from fem.options import ContactOptions
from fem.stepping import LoadStepper
from fem.two_body.problem import Body, MeshedPartner, TwoBodyProblem
from meshes.two_body import build_stacked_blocks
from workbench.mesh_io import read_mesh

WIDTH = 1.0
PATCH_RTOL = 1e-8


@pytest.fixture(scope="module")
def stacked(tmp_path_factory):
    mf = build_stacked_blocks(width=WIDTH, height_lower=1.0, height_upper=0.5, h_lower=1 / 7, h_upper=1 / 4.3,
                              out_dir=tmp_path_factory.mktemp("mesh"))
    return read_mesh(mf.msh, MPI.COMM_SELF)


def _problem(md, *, pairing="mortar", method="penalty", degree=2, slave="contact_upper"):
    master = "contact_lower" if slave == "contact_upper" else "contact_upper"
    setup = MeshedPartner(bodies=(Body(name="lower", E=200.0, nu=0.3), Body(name="upper", E=70.0, nu=0.25)),
                         slave=slave, master=master, driven="driven", driven_body="upper", driven_components=(1,),
                         pairing=pairing)
    opts = ContactOptions.of(target=1e-3, degree=degree, method=method, control="displacement",
                          n_steps=2, supports={"clamped": "roller_y", "symmetry": "roller_x"},
                          active_set_predictor=False, predictor="extrapolate")
    return TwoBodyProblem(md, setup, opts)


def _solve(pb):
    stepper = LoadStepper(pb)
    stepper.run()
    smp = pb.sample()
    P, Pp = pb.measure()
    return stepper, smp, P, Pp


def test_no_coincident_nodes_on_the_contact_surfaces(stacked):
    pb = _problem(stacked)
    xs = np.vstack([pb.slave_geom.a, pb.slave_geom.b])
    xm = np.vstack([pb.master_geom.a, pb.master_geom.b])
    inner = lambda x: x[(x[:, 0] > 1e-12) & (x[:, 0] < WIDTH - 1e-12)]  # noqa: E731  (the corners are shared)
    dist = np.min(np.abs(inner(xs)[:, None, 0] - inner(xm)[None, :, 0]))
    assert dist > 1e-3 * WIDTH


@pytest.mark.parametrize("method", ["penalty", "augmented_lagrangian"])
@pytest.mark.parametrize("degree", [1, 2])
@pytest.mark.parametrize("slave", ["contact_upper", "contact_lower"])
def test_mortar_passes_the_patch_test(stacked, method, degree, slave):
    stepper, smp, P, Pp = _solve(_problem(stacked, method=method, degree=degree, slave=slave))
    assert P > 0
    assert abs(Pp / P - 1) < 1e-9
    assert np.max(np.abs(smp.p / (P / WIDTH) - 1)) < PATCH_RTOL
    assert max(r["iterations"] for r in stepper.records) <= 4


@pytest.mark.parametrize("degree", [1, 2])
def test_node_to_segment_fails_the_patch_test(stacked, degree):
    """Its pressure error on these meshes is several percent (measured 7 % for P1, 12 % for P2)."""
    _, smp, P, _ = _solve(_problem(stacked, pairing="node_to_segment", degree=degree))
    err = np.max(np.abs(smp.p / (P / WIDTH) - 1))
    assert err > 1e-2


@pytest.mark.parametrize("pairing", ["mortar", "node_to_segment"])
def test_jacobian_equals_finite_differences(stacked, pairing):
    """The assembled Jacobian (bulk + contact coupling across the meshes) against central differences of the
    residual, at a state where some contact nodes are active and some are open."""
    pb = _problem(stacked, pairing=pairing)
    _solve(pb)
    rng = np.random.default_rng(1)
    u0 = pb.u.x.array.copy()
    u0[pb.free] += 1e-5 * rng.standard_normal(int(pb.free.sum()))
    g = pb.gap.gap(u0)
    q = pb.method.argument(g)
    assert (q > 0).any()
    x = pb.x.duplicate()
    x.setArray(u0)
    J = pb.A.duplicate()
    pb.snes.computeJacobian(x, J)
    v = np.zeros_like(u0)
    v[pb.free] = rng.standard_normal(int(pb.free.sum()))
    eps = 1e-9 * np.max(np.abs(u0)) / np.max(np.abs(v))
    # the law is piecewise linear: the difference is exact while no node changes side
    assert np.all(np.abs(q) > 2 * pb.method.kappa * np.max(np.abs(pb.gap.D @ (eps * v)) / pb.gap.W))
    fp, fm, Jv, vv = x.duplicate(), x.duplicate(), x.duplicate(), x.duplicate()
    x.setArray(u0 + eps * v)
    pb.snes.computeFunction(x, fp)
    x.setArray(u0 - eps * v)
    pb.snes.computeFunction(x, fm)
    vv.setArray(v)
    J.mult(vv, Jv)
    fd = (fp.getArray() - fm.getArray()) / (2 * eps)
    err = np.max(np.abs(fd - Jv.getArray())) / np.max(np.abs(Jv.getArray()))
    assert err < 1e-6


def test_refusals(stacked):
    with pytest.raises(ValueError, match="nitsche"):
        _problem(stacked, method="nitsche")
    with pytest.raises(ValueError, match="pairing"):
        _problem(stacked, pairing="segment")
    setup = _problem(stacked).setup  # slave: the upper block's bottom, normal (0, -1)
    with pytest.raises(ValueError, match="ContactOptions.body must be None"):
        TwoBodyProblem(stacked, setup, ContactOptions.of(E=1.0, nu=0.3, target=1.0, method="penalty",
                                                         kinematics="finite", material_model="neo_hookean"))
    with pytest.raises(ValueError, match=r"kinematics='finite' needs bodies\['lower'\].material_model"):
        TwoBodyProblem(stacked, setup, ContactOptions.of(target=1.0, method="penalty", kinematics="finite"))
    with pytest.raises(ValueError, match="flat slave surface with normal"):
        TwoBodyProblem(stacked, setup, ContactOptions.of(target=1.0, method="penalty",
                                                      kinematics="convective"))
