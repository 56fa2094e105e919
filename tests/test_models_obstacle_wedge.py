"""The documented pitfall of docs/models.md: in obstacle mode a straight wedge face makes ``small`` and
``convective`` kinematics the same model (the linearised distance to a straight face is exact), while in
half-plane mode they differ by the Ciavarella-Hills convective effect."""

from __future__ import annotations

import dolfinx_solver  # noqa: F401

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
    assert b["convective"] / b["small"] - 1 > 0.1, b  # the convective effect: measured +15.2 % at h_c = b/10
