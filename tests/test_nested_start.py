"""A solve started from a coarser mesh's converged state (``nested_start``, fem/nested_start.py): nested iteration.

Requirements (issue 38, item 1):
1. Two elastic bodies (a cylinder on a block, non-matching meshes, augmented Lagrangian: Newton inside an Uzawa
   loop, force control): the solve on a mesh twice as fine started from the coarse solution reaches the same
   answer as its cold solve (P, d, peak pressure, moment half-width within 1e-8 relative: both stop at
   tolerances 1e-10) in fewer Newton iterations than the cold solve, with no load path (one "nested" solve, then
   force corrections only).
2. The interpolation keeps each body's displacement: the coarse solution evaluated at the fine mesh's dofs
   differs from the fine converged solution by the discretisation error only (below 1 % of max|u|), in both
   bodies, including the contact surfaces where the bodies touch.
3. Refused in one line: nested_start with warm_start or record_at (ValueError naming nested_start).
4. A rigid obstacle (issue 38, item 1 for a single level): a fine mesh started from a coarse mesh's active set and
   d reaches its cold answer with at most 3 Newton iterations per solve and no analytic predictor; a nonlinear
   bulk (finite strain, a hyperelastic material) is refused in one line.
"""

import dolfinx_solver  # noqa: F401

import numpy as np
import pytest
from mpi4py import MPI

from analytic.hertz import hertz_load_from_half_width
from fem.nested_start import evaluate_in_cells
from fem.obstacles import CircleObstacle
from fem.options import ContactOptions
from fem.solver import solve_contact
from fem.two_body.geometry import CircleSurface
from fem.two_body.problem import Body, MeshedPartner
from measures.contact import moment_half_width
from meshes.block import build_block_mesh
from meshes.two_body import build_cylinder_on_block
from workbench.mesh_io import read_mesh

R, A, E, NU = 10.0, 0.5, 210000.0, 0.3
PARTNER = MeshedPartner(bodies=(Body(name="lower", E=E, nu=NU), Body(name="upper", E=E / 4, nu=0.2)),
                        slave="contact_lower", master="contact_upper", driven="driven", driven_body="upper",
                        master_surface=CircleSurface((0.0, R), R), pairing="mortar")


def _mesh(tmp_path_factory, h):
    files = build_cylinder_on_block(radius=R, width=20 * A, height=20 * A, contact_half_width=A, h_contact=h,
                                    out_dir=tmp_path_factory.mktemp("nested"), name=f"nested_{int(A / h)}")
    return read_mesh(files.msh, MPI.COMM_SELF)


def _options(**kw):
    P = hertz_load_from_half_width(A, R, PARTNER.combined_modulus())
    return ContactOptions.of(**(dict(target=P, degree=2, method="augmented_lagrangian", control="force", n_steps=3,
                                      kinematics="small") | kw))


@pytest.fixture(scope="module")
def fine_mesh(tmp_path_factory):
    return _mesh(tmp_path_factory, A / 10)


@pytest.fixture(scope="module")
def solves(tmp_path_factory, fine_mesh):
    coarse_mesh = _mesh(tmp_path_factory, A / 5)
    coarse = solve_contact(coarse_mesh, PARTNER, options=_options())
    cold = solve_contact(fine_mesh, PARTNER, options=_options())
    nested = solve_contact(fine_mesh, PARTNER, options=_options(nested_start=coarse.nested_start))
    return coarse, cold, nested


def _moment(r):
    return moment_half_width(r.samples.s, r.samples.p, r.samples.weight, center=0.0)


def test_nested_start_reaches_the_cold_answer_in_fewer_iterations(solves):
    coarse, cold, nested = solves
    kinds = [r["kind"] for r in nested.load_steps]
    assert kinds[0] == "nested" and set(kinds[1:]) <= {"force-correction"}, kinds
    assert sum(nested.newton_iterations) < sum(cold.newton_iterations), (nested.newton_iterations,
                                                                          cold.newton_iterations)
    assert nested.P == pytest.approx(cold.P, rel=1e-8)
    assert nested.d == pytest.approx(cold.d, rel=1e-8)
    assert np.max(nested.samples.p) == pytest.approx(np.max(cold.samples.p), rel=1e-8)
    assert _moment(nested) == pytest.approx(_moment(cold), rel=1e-8)
    assert nested.d != pytest.approx(coarse.d, rel=1e-8)  # the levels differ: the start is not the answer


def test_the_interpolated_start_is_each_bodys_own_displacement(solves):
    coarse, cold, _ = solves
    start, fine_u = coarse.nested_start, cold.u
    assert len(start.body_cells) == 2 and all(c.size for c in start.body_cells)
    X = fine_u.function_space.tabulate_dof_coordinates()
    ref = fine_u.x.array.reshape(-1, 2)
    scale = np.max(np.abs(ref))
    # a fine dof takes its own body's coarse value (its body's cells): on the contact surfaces, where the bodies
    # touch and their displacements differ, only the right body's value is close
    off = [np.max(np.abs(evaluate_in_cells(start.u, X, cells)[:, :2] - ref), axis=1) for cells in start.body_cells]
    assert np.max(np.minimum(*off)) < 1e-2 * scale, np.max(np.minimum(*off)) / scale
    assert np.max(np.maximum(*off)) > 1e-2 * scale  # the other body's value is not (the test can fail)


def test_nested_start_is_refused_with_warm_start_or_record_at(solves, fine_mesh):
    coarse, cold, _ = solves
    with pytest.raises(ValueError, match="nested_start"):
        solve_contact(fine_mesh, PARTNER, options=_options(nested_start=coarse.nested_start,
                                                           warm_start=cold.warm_start))
    with pytest.raises(ValueError, match="nested_start"):
        solve_contact(fine_mesh, PARTNER, options=_options(nested_start=coarse.nested_start, control="displacement",
                                                           target=0.01, record_at=(0.005, 0.01)))


def test_a_rigid_obstacle_starts_from_a_coarser_mesh(tmp_path):
    """A rigid circle on a half block, Nitsche P2, force control with no analytic predictor: the fine mesh (8 times
    finer at the contact) started from the coarse solve's active set and d reaches its cold answer (P, d and the
    peak pressure within 1e-9: both stop at tolerances 1e-10) with one nested solve and at most 3 Newton
    iterations per solve, where the cold solve's load path needs more than 3 in a step."""
    from analytic.materials import plane_strain_modulus

    meshes = {}
    for n in (4, 32):
        mf = build_block_mesh(width=20 * A, height=20 * A, contact_half_width=A, h_contact=A / n, half_model=True,
                              out_dir=tmp_path, name=f"nested_rigid_{n}")
        meshes[n] = read_mesh(mf.msh, MPI.COMM_SELF)
    obstacle = CircleObstacle(center=(0.0, R), radius=R)
    kw = dict(E=E, nu=NU, degree=2, method="nitsche", kinematics="small", traction="halfplane", symmetric_half=True,
              control="force", target=hertz_load_from_half_width(A, R, plane_strain_modulus(E, NU)), n_steps=1,
              predictor="extrapolate")
    coarse = solve_contact(meshes[4], obstacle, **kw)
    cold = solve_contact(meshes[32], obstacle, **kw)
    nested = solve_contact(meshes[32], obstacle, nested_start=coarse.nested_start, **kw)
    assert nested.load_steps[0]["kind"] == "nested"
    assert {s["kind"] for s in nested.load_steps[1:]} <= {"force-correction"}
    assert max(nested.newton_iterations) <= 3 < max(cold.newton_iterations)
    for key in ("P", "d"):
        assert abs(getattr(nested, key) - getattr(cold, key)) <= 1e-9 * abs(getattr(cold, key))
    p_n, p_c = max(p.p_max for p in nested.patches), max(p.p_max for p in cold.patches)
    assert abs(p_n - p_c) <= 1e-9 * p_c


def test_a_rigid_nested_start_refuses_a_nonlinear_bulk():
    """The rigid problem starts a nested solve from the unloaded state: finite strain or a hyperelastic material is
    refused in one line naming nested_start and what is allowed."""
    from types import SimpleNamespace

    from fem.problem import ContactProblem

    def problem(kin, law):
        me = SimpleNamespace(options=SimpleNamespace(kinematics=kin, material_model=law), n_u=4)
        me.linear_bulk = ContactProblem.linear_bulk.fget(me)
        return me

    for kin, law in (("finite", "neo_hookean"), ("small", "neo_hookean")):
        me = problem(kin, law)
        with pytest.raises(ValueError, match="nested_start: .*allowed: kinematics small or convective") as err:
            ContactProblem.nested_guess(me, None)
        assert "\n" not in str(err.value)
    ok = problem("convective", "linear")
    assert np.array_equal(ContactProblem.nested_guess(ok, None), np.zeros(4))
