"""The documented pitfall of docs/models.md: in obstacle mode a straight wedge face makes ``small`` and
``convective`` kinematics the same model (the linearised distance to a straight face is exact), while in
half-plane mode they differ by the Ciavarella-Hills convective effect."""

from __future__ import annotations

import dolfinx_solver  # noqa: F401

import math

from mpi4py import MPI

from cases import load_case
from workbench.pipeline.run_case import run_one

CASE = """
[case]
name = "pitfall"
[material]
E = 210000.0
nu = 0.0
[geometry]
scene = "block"
indenter = "wedge"
wedge_angle = 0.6283185307179586
wedge_slope = "paper"
width_factor = 40.0
height_factor = 40.0
[loading]
control = "force"
half_width = 0.5
steps = 3
[discretisation]
degree = 2
h_contact = 0.1
[solver]
method = "nitsche"
traction = "{traction}"
[[variant]]
label = "small"
solver = {{ kinematics = "small" }}
[[variant]]
label = "convective"
solver = {{ kinematics = "convective" }}
"""


def _half_widths(tmp_path, traction: str) -> dict:
    path = tmp_path / f"pitfall_{traction}.toml"
    path.write_text(CASE.format(traction=traction))
    return {run.label: run_one(run, name=f"pitfall_{traction}", mesh_cache=tmp_path / "mesh", comm=MPI.COMM_WORLD,
                               progress=lambda _m: None).metrics["patch_half_width"]
            for run in load_case(path).runs()}


def test_small_equals_convective_for_a_straight_face_in_obstacle_mode(tmp_path):
    b = _half_widths(tmp_path, "obstacle")
    assert abs(b["convective"] / b["small"] - 1) < 1e-9, b  # measured 8.9e-16 (h_c = b/10)


def test_small_and_convective_differ_in_halfplane_mode(tmp_path):
    b = _half_widths(tmp_path, "halfplane")
    # The convective effect against the Ciavarella-Hills theory, not just its sign: wedge_slope = "paper" is the
    # profile m |x| with m = theta = pi/5, and a rigid indenter on nu = 0 gives beta = -1/2, so the converged
    # b/b0 = 1.16457 (analytic.convective; first order 1.16094). Band 3 %: both runs share the block (W = H = 40 b,
    # its effect cancels in the ratio), and each half-width is a zero crossing located to a fraction of
    # h_c = b/10 by the square-root edge model (<= 0.2 h = 2 % of b per run, measured 1.1 % off in the ratio).
    # A sign error of the convective term gives ~0.86, no effect gives 1.0.
    from analytic.convective import converged_b_over_b0, wedge_profile

    theory = converged_b_over_b0(wedge_profile(math.pi / 5), beta=-0.5)
    assert abs(b["convective"] / b["small"] / theory - 1) < 0.03, (b, theory)
