"""Two elastic bodies over E ratios 1e-3 to 1e3 and Poisson's ratios up to 0.499 on either side (issue 24): every
solve converges, the contact load balances the support reaction, and a near-incompressible body is named.

Measured on the elastic cylinder (a/R = 0.05, h_contact = a/10, W = 40 a, penalty, mortar): E_upper / E_lower
1e-3 ... 1e3 converge in <= 4 Newton iterations per step with p_max within 0.3 % of the exact circle at the combined
modulus; nu = 0.499 on either side converges (p_max +2.6 % block, +0.4 % cylinder: volumetric locking of the
displacement formulation, named by the warning); the worst pair, a stiff cylinder (1e3) on a nu = 0.499 block,
takes 10 Newton iterations and its peak is 19 % off (locking).
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401

import pytest
from mpi4py import MPI

from analytic.circle import circle_contact
from analytic.hertz import hertz_load_from_half_width
from fem.options import ContactOptions
from fem.solver import solve_contact
from fem.two_body.geometry import CircleSurface
from fem.two_body.problem import Body, MeshedPartner
from meshes.two_body import build_cylinder_on_block
from workbench.mesh_io import read_mesh

R, A, E = 10.0, 0.5, 210000.0


@pytest.fixture(scope="module")
def mesh(tmp_path_factory):
    files = build_cylinder_on_block(radius=R, width=40 * A, height=40 * A, contact_half_width=A, h_contact=A / 10,
                                    out_dir=tmp_path_factory.mktemp("mesh"))
    return read_mesh(files.msh, MPI.COMM_SELF)


@pytest.mark.parametrize(("ratio", "nu_lower", "nu_upper", "p_tol", "max_its"),
                         [(1e-3, 0.3, 0.3, 3e-3, 4), (1e3, 0.3, 0.3, 3e-3, 4), (1.0, 0.499, 0.3, 5e-2, 4),
                          (1.0, 0.3, 0.499, 1e-2, 4)])
def test_extreme_pairs_converge(mesh, ratio, nu_lower, nu_upper, p_tol, max_its):
    partner = MeshedPartner(bodies=(Body(name="lower", E=E, nu=nu_lower), Body(name="upper", E=ratio * E, nu=nu_upper)),
                            slave="contact_lower", master="contact_upper", driven="driven", driven_body="upper",
                            master_surface=CircleSurface((0.0, R), R))
    E_star = partner.combined_modulus()
    opts = ContactOptions(E=E, nu=nu_lower, target=hertz_load_from_half_width(A, R, E_star), degree=2,
                          method="penalty", control="force", n_steps=1, predictor="extrapolate", active_set="geometry",
                          active_set_update="edge_fit")
    res = solve_contact(mesh, partner, options=opts)
    th = circle_contact(res.P, R, E_star)
    assert abs(res.P - res.P_pressure) <= 1e-9 * res.P
    assert max(res.newton_iterations) <= max_its
    assert abs(res.patches[0].p_max / th.p0 - 1) < p_tol
    assert any(w.startswith("near-incompressible") for w in res.warnings) == (max(nu_lower, nu_upper) >= 0.45)
