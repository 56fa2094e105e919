"""The rigid limit of two elastic bodies: an elastic cylinder E_c = k E on an elastic block reproduces the rigid
exact-circle indenter on the same block, node for node.

Node-to-segment with the augmented Lagrangian collocates the vertical gap at the block's top nodes, with
Simpson's nodal weights, which is the rigid solver's nodal augmented Lagrangian with ``traction="halfplane"``;
the initial gap is measured to the exact circle (``CircleSurface``). So the two solves differ only by the
cylinder's compliance: measured, the nodal pressures agree to 2.8e-6 of p_max at k = 1e6 and to 1.5e-8 at
k = 1e9 (h_contact = a/10), the patch half-width to 1.1e-7 and 4e-10.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401

import numpy as np
import pytest
from mpi4py import MPI

from analytic.hertz import hertz_load_from_half_width
from analytic.materials import plane_strain_modulus
from fem.obstacles import CircleObstacle
from fem.options import ContactOptions
from fem.solver import solve_contact
from fem.two_body.geometry import CircleSurface
from fem.two_body.problem import Body, MeshedPartner
from meshes.two_body import build_cylinder_on_block
from workbench.mesh_io import read_mesh

R, A, E, NU = 10.0, 0.5, 210000.0, 0.3


@pytest.fixture(scope="module")
def meshes(tmp_path_factory):
    kw = dict(radius=R, width=20 * A, height=20 * A, contact_half_width=A, h_contact=A / 10,
              out_dir=tmp_path_factory.mktemp("mesh"))
    two = read_mesh(build_cylinder_on_block(**kw).msh, MPI.COMM_SELF)
    block = read_mesh(build_cylinder_on_block(indenter=False, **kw).msh, MPI.COMM_SELF)
    return block, two


def _options(**extra):
    P = hertz_load_from_half_width(A, R, plane_strain_modulus(E, NU))
    return ContactOptions.of(target=P, degree=2, method="augmented_lagrangian", control="force",
                          n_steps=1, predictor="extrapolate", active_set="geometry", active_set_update="edge_fit",
                          **extra)


@pytest.fixture(scope="module")
def rigid(meshes):
    block, _ = meshes
    return solve_contact(block, CircleObstacle(center=(0.0, R), radius=R),
                 options=_options(E=E, nu=NU, traction="halfplane", contact_group="contact_lower"))


def test_the_block_is_the_same_mesh(meshes):
    block, two = meshes
    lower = two.cell_tags.find(two.physical_groups["lower"].tag)
    x_two = two.mesh.geometry.x[np.unique(two.mesh.geometry.dofmaps[0][lower])]
    x_blk = block.mesh.geometry.x
    assert x_two.shape == x_blk.shape
    key = lambda x: x[np.lexsort((x[:, 1], x[:, 0]))]  # noqa: E731
    assert np.array_equal(key(x_two), key(x_blk))


@pytest.mark.parametrize(("ratio", "p_tol", "b_tol"), [(1e6, 1e-5, 1e-6), (1e9, 1e-7, 1e-8)])
def test_stiff_cylinder_reproduces_the_rigid_indenter(meshes, rigid, ratio, p_tol, b_tol):
    _, two = meshes
    partner = MeshedPartner(bodies=(Body(name="lower", E=E, nu=NU), Body(name="upper", E=ratio * E, nu=NU)),
                            slave="contact_lower", master="contact_upper", driven="driven", driven_body="upper",
                            pairing="node_to_segment", master_surface=CircleSurface((0.0, R), R))
    res = solve_contact(two, partner, options=_options())
    s_r, s_t = rigid.samples, res.samples
    assert np.allclose(s_r.s, s_t.s, rtol=0.0, atol=1e-12 * R)
    assert abs(res.P / rigid.P - 1) < 1e-9
    assert np.max(np.abs(s_t.p - s_r.p)) / np.max(s_r.p) < p_tol
    (pr,), (pt,) = rigid.patches, res.patches
    assert abs(pt.half_width / pr.half_width - 1) < b_tol
    assert max(res.newton_iterations) <= max(rigid.newton_iterations) + 2  # Uzawa solves included in both
