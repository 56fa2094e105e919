"""Rigid wedge, small vs convective kinematics (Ciavarella-Hills convective effect), half-plane traction.

Scene: wedge slope m = pi/5 (C&H's small-angle convention m = theta for theta = pi/5; the lead may pass
tan(theta) instead), nu = 0 (beta = -1/2 for a rigid indenter), E = 1 GPa, block W = H = 40 b0 (half model),
P2, h_contact = b0/20 with apex refinement, Nitsche, force control at P = E* m b0 (b0 = 1 mm, classical).

Checks: both runs converge; the small-kinematics half-width matches the classical b0 = P/(E* m) within 2 %
(log-singular apex and the one-Gauss-spacing edge error; measured about -1 %); the ratio b/b0 (convective over
small, same load) matches the converged C&H fixed point (analytic.convective) within 3 % (the FEM block is
finite and the edge is resolved to ~1 %; measured 1.15-1.16 vs 1.1646 for h = b0/10 ... b0/40).
"""

import dolfinx_solver  # noqa: F401

import numpy as np
from dolfinx.io import gmsh as dgmsh
from mpi4py import MPI

from analytic.convective import converged_b_over_b0, wedge_first_order, wedge_profile
from analytic.materials import beta_rigid_indenter
from analytic.wedge import wedge_half_width, wedge_load_from_half_width, wedge_slope
from fem.elasticity import plane_strain_modulus
from fem.obstacles import WedgeObstacle
from fem.solver import solve_contact
from meshes.block import build_block_mesh

E, NU, B0 = 1000.0, 0.0, 1.0


def test_wedge_convective_vs_small(tmp_path):
    m = wedge_slope(np.pi / 5, convention="paper")
    e_star = plane_strain_modulus(E=E, nu=NU)
    P = wedge_load_from_half_width(B0, m, e_star)
    mf = build_block_mesh(width=40 * B0, height=40 * B0, contact_half_width=1.1 * B0, h_contact=B0 / 20,
                          half_model=True, apex_refinement=True, out_dir=tmp_path, name="wedge")
    md = dgmsh.read_from_msh(str(mf.msh), MPI.COMM_WORLD, 0, gdim=2)
    b = {}
    for kin in ("small", "convective"):
        res = solve_contact(md, WedgeObstacle(slope=m), E=E, nu=NU, method="nitsche", kinematics=kin,
                            traction="halfplane", control="force", target=P, n_steps=4, symmetric_half=True)
        assert len(res.patches) == 1
        assert abs(res.P / P - 1.0) <= 1e-9
        b[kin] = res.patches[0].half_width
        print(f"\nwedge {kin}: ndofs={res.ndofs} b={b[kin]:.5f} its={res.newton_iterations}")
    ratio = b["convective"] / b["small"]
    beta = beta_rigid_indenter(NU)
    theory = converged_b_over_b0(wedge_profile(m), beta=beta)
    print(f"b/b0 = {ratio:.4f} (C&H fixed point {theory:.4f}, first order {wedge_first_order(m, beta):.4f}, "
          f"h = b0/20, P2)")
    assert abs(b["small"] / wedge_half_width(P, m, e_star) - 1.0) <= 0.02, b
    assert abs(ratio / theory - 1.0) <= 0.03, ratio
