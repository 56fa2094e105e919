"""A solve started from the converged solution of a coarser mesh of the same problem (nested iteration, issue 38).

What the error budget's grid hierarchy needs: its levels are meshes of one geometry, each finer than the last.
Solved cold, every level repeats the coarse level's work (the first active set from the rigid overlap, the
force-control secant from the unloaded state) and the Newton iterations grow with the mesh. Started from the
coarser level's converged state, interpolated, a level only corrects the discretisation difference:

* the displacement: each body's coarse displacement evaluated at the fine dof coordinates, in that body's own
  coarse cells (the bodies touch: a fine node on the contact surface must not take the other body's value);
  a fine node outside every coarse cell of its body (a curved boundary meshed at another size) takes the value
  of the closest coarse cell, extrapolated;
* the method's surface unknowns (the augmented Lagrangian's multiplier, a pressure in MPa: mesh-independent),
  interpolated linearly in the slave surface coordinate X1, zero outside the coarse contact;
* the active set: the coarse contact runs (X1 intervals), prescribed for the first Newton iteration;
* the load parameter: the coarse level's converged d; in force control the rigid obstacle's problem solves d with
  u (:mod:`fem.force_newton`), other problems correct it as a cold solve does.

The converged answer does not depend on the start (frictionless small-strain contact has no load path; at finite
strain a hyperelastic frictionless problem is conservative, and a start near the solution is what the load path
only approximates). The start changes the iterations, not the tolerances: each level converges to its own
``snes_rtol``, relative to its own first residual.

Two meshed bodies: serial, as the two-body problem is (:mod:`fem.two_body.problem`). A rigid obstacle
(:class:`fem.problem.ContactProblem`, any number of processes): the coarse state's active set and d only, the
displacement starting from the unloaded state (its bulk is linear, so an interpolated displacement saves no
iteration; finite strain is refused). A problem without the hook ``nested_guess`` refuses the option
(ValueError, one line).
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

__all__ = ["NestedStart", "evaluate_in_cells", "nested_start_of"]


class NestedStart(NamedTuple):
    """The converged state of a coarser mesh of the same problem.

    Attributes:
        d: the load parameter of the converged state (mm).  P: its load (N/mm).
        u: the converged displacement (a dolfinx Function on the coarse mesh, mm).
        body_cells: the coarse cells of each body, in the partner's body order.
        X1: the coarse slave nodes' surface coordinate (mm), sorted.  surface: the method's nodal unknowns at
            those nodes (empty: the method has none).
        zones: the coarse contact runs (X1 intervals; the first may start at -inf).
    """

    d: float
    P: float
    u: Any
    body_cells: tuple[np.ndarray, ...]
    X1: np.ndarray
    surface: np.ndarray
    zones: tuple[tuple[float, float], ...]


def nested_start_of(problem, stepper) -> NestedStart | None:
    """The :class:`NestedStart` a finished solve hands to a finer mesh (None: the problem has no hook). Called
    after every solve: it reuses what the solve already holds (the last converged state's d, P and contact runs,
    the result's displacement Function), so it adds no surface sampling and no copy of u."""
    source = getattr(problem, "nested_source", None)
    if source is None:
        return None
    last = stepper.states[-1]
    return source(d=float(last.d), P=float(last.P), zones=last.zone)


def evaluate_in_cells(u, points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """The values of the Function ``u`` at ``points`` (n x 3), each looked up in the cells ``cells`` of u's mesh
    only (n x value size); a point in none of them is evaluated in the closest one."""
    import dolfinx.geometry as geo

    mesh = u.function_space.mesh
    tdim = mesh.topology.dim
    cells = np.asarray(cells, dtype=np.int32)
    tree = geo.bb_tree(mesh, tdim, entities=cells, padding=1e-10)
    found = geo.compute_colliding_cells(mesh, geo.compute_collisions_points(tree, points), points)
    owner = np.full(points.shape[0], -1, dtype=np.int32)
    first, has = found.offsets[:-1], np.diff(found.offsets) > 0
    owner[has] = found.array[first[has]]
    missing = np.flatnonzero(owner < 0)
    if missing.size:
        mid = geo.create_midpoint_tree(mesh, tdim, cells)
        owner[missing] = geo.compute_closest_entity(tree, mid, mesh, points[missing])
    return u.eval(points, owner)
