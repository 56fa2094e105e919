"""dolfinx 0.11 frictionless contact against rigid analytic obstacles (units mm, N, MPa; P in N/mm).

Import ``dolfinx_solver`` happens inside the submodules (before dolfinx). Public API::

    from fem.obstacles import CircleObstacle, ParabolaObstacle, WedgeObstacle, PlaneObstacle, CurveObstacle
    from fem.solver import solve_contact, ContactResult, ContactSolveError
    from fem.output import write_vtk
"""

__all__ = [
    "CircleObstacle",
    "ContactResult",
    "ContactSolveError",
    "CurveObstacle",
    "ParabolaObstacle",
    "PlaneObstacle",
    "WedgeObstacle",
    "solve_contact",
    "write_vtk",
]


def __getattr__(name):  # lazy, so `import fem` does not start dolfinx
    if name in ("CircleObstacle", "ParabolaObstacle", "WedgeObstacle", "PlaneObstacle", "CurveObstacle"):
        from fem import obstacles

        return getattr(obstacles, name)
    if name in ("solve_contact", "ContactResult", "ContactSolveError"):
        from fem import solver

        return getattr(solver, name)
    if name == "write_vtk":
        from fem.output import write_vtk

        return write_vtk
    raise AttributeError(name)
