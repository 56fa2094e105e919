# # Hertz line contact: a rigid cylinder pressed on an elastic block
#
# A literate example in the style of the dolfinx demos: geometry and theory, mesh, obstacle, solve,
# compare, plot. Run it with `.venv/bin/python examples/hertz_contact.py`; it writes to
# `$EXAMPLE_OUT` (default `results/examples/hertz_contact/` of this checkout). `tests/test_examples.py`
# runs it and asserts its numbers.
#
# Units: mm, N, MPa; P is a load per unit thickness (N/mm). Plane strain.
#
# Hertz (2D): a rigid cylinder of radius R on a half-plane of modulus E* = E / (1 - nu^2) under the load P
# has the half-width a = sqrt(4 P R / (pi E*)) and p(x) = p0 sqrt(1 - x^2 / a^2), p0 = 2 P / (pi a).

# +
import dolfinx_solver  # noqa: F401  (the wheel's MPI and PETSc, before dolfinx)

import os
from pathlib import Path

import gmsh
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from dolfinx.io import gmsh as gmsh_io
from mpi4py import MPI

from analytic.hertz import hertz, hertz_load_from_half_width, hertz_pressure
from analytic.materials import plane_strain_modulus
from fem.obstacles import CircleObstacle
from fem.solver import solve_contact
from meshes.block import build_block_mesh

out = Path(os.environ.get("EXAMPLE_OUT", Path(__file__).resolve().parents[1] / "results/examples/hertz_contact"))
E, nu, R, a_target = 210e3, 0.3, 10.0, 0.5  # steel block, R = 10 mm, a/R = 0.05
E_star = plane_strain_modulus(E, nu)
P = hertz_load_from_half_width(a_target, R, E_star)
# -

# ## Mesh
# Half of a 40 a x 40 a block (symmetry edge x = 0, clamped bottom), elements of a/20 on the contact zone,
# growing geometrically away from it. Named physical groups: `contact`, `clamped`, `symmetry`.

# +
files = build_block_mesh(width=40 * a_target, height=40 * a_target, contact_half_width=a_target,
                         h_contact=a_target / 20, half_model=True, out_dir=out / "mesh", name="hertz_example")
gmsh.initialize(interruptible=False)
gmsh.option.setNumber("General.Terminal", 0)
mesh_data = gmsh_io.read_from_msh(str(files.msh), MPI.COMM_WORLD, 0, gdim=2)
# -

# ## Obstacle and solve
# The rigid body is an analytic circle touching the block top at the origin. Nitsche contact, P2,
# force control to P; `halfplane` traction (vertical gap and traction, as the half-plane theory assumes).

# +
obstacle = CircleObstacle(center=(0.0, R), radius=R)
result = solve_contact(mesh_data, obstacle, E=E, nu=nu, degree=2, method="nitsche", traction="halfplane",
                       control="force", target=P, n_steps=1, symmetric_half=True)
# -

# ## Compare with Hertz at the measured load
# In 2D there is no universal load-indentation law, so the theory is evaluated at the FEM's own load.

# +
theory = hertz(result.P, R, E_star)
patch = max(result.patches, key=lambda pt: pt.P)
error_p0 = abs(patch.p_max - theory.p0) / theory.p0
error_a = abs(patch.half_width - theory.half_width) / theory.half_width
x, p = result.samples.s, result.samples.p
inside = x <= theory.half_width
rms = np.sqrt(np.mean((p[inside] - hertz_pressure(x[inside], a=theory.half_width, p0=theory.p0)) ** 2)) / theory.p0
print(f"P = {result.P:.6g} N/mm, {result.ndofs} dofs, Newton its {result.newton_iterations}")
print(f"p0: FEM {patch.p_max:.6g}, Hertz {theory.p0:.6g} MPa ({error_p0:.2e}); "
      f"a: FEM {patch.half_width:.6g}, Hertz {theory.half_width:.6g} mm ({error_a:.2e}); RMS/p0 {rms:.2e}")
# -

# ## Plot

# +
xs = np.linspace(0.0, 1.3 * theory.half_width, 400)
fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(xs, hertz_pressure(xs, a=theory.half_width, p0=theory.p0), "k-", label="Hertz (at measured P)")
ax.plot(x, p, "o", ms=3, label="FEM (Nitsche, P2)")
ax.set(xlabel="x (mm)", ylabel="contact pressure p (MPa)", xlim=(0, 1.3 * theory.half_width))
ax.legend()
fig.savefig(out / "pressure.png", dpi=120, bbox_inches="tight")
plt.close(fig)
# -
