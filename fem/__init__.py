"""dolfinx 0.11 frictionless plane-strain contact of an elastic body against a contact partner: a rigid analytic
obstacle or a second meshed elastic body on a non-matching mesh (units mm, N, MPa; P in N/mm).

Both partners are solved by one load stepping through one declared protocol, :class:`PartnerProblem`
(:mod:`fem.partner_problem`): :class:`ContactProblem` (rigid obstacle) and
:class:`fem.two_body.problem.TwoBodyProblem` (two bodies) implement it. Import ``dolfinx_solver`` happens inside
the submodules (before dolfinx). Public API::

    from fem.obstacles import CircleObstacle, ParabolaObstacle, WedgeObstacle, PlaneObstacle, CurveObstacle
    from fem.two_body.problem import MeshedPartner, Body  # the deformable partner
    from fem.solver import solve_contact, ContactOptions, ContactResult, ContactSolveError
    from fem.partner_problem import PartnerProblem  # what the load stepping asks of a contact problem
    from fem.problem import ContactProblem          # spaces, supports, forms, measures, NonlinearProblem
    from fem.stepping import LoadStepper            # load steps, cut-backs, force control, predictors
    from fem.methods import REGISTRY, register      # contact methods (both partners), one module each
    from fem.output import write_vtk
    from fem.hyperelastic import bulk_law         # material models: linear, St Venant-Kirchhoff, neo-Hookean
"""

__all__ = [
    "CircleObstacle",
    "ContactOptions",
    "ContactProblem",
    "ContactResult",
    "ContactSolveError",
    "CurveObstacle",
    "LoadStepper",
    "MeshedPartner",
    "ParabolaObstacle",
    "PartnerProblem",
    "PlaneObstacle",
    "WedgeObstacle",
    "method_names",
    "register",
    "solve_contact",
    "write_vtk",
]

_FROM = {
    "fem.obstacles": ("CircleObstacle", "ParabolaObstacle", "WedgeObstacle", "PlaneObstacle", "CurveObstacle"),
    "fem.solver": ("solve_contact", "ContactResult", "ContactSolveError", "ContactOptions"),
    "fem.partner_problem": ("PartnerProblem",),
    "fem.problem": ("ContactProblem",),
    "fem.two_body.problem": ("MeshedPartner",),
    "fem.stepping": ("LoadStepper",),
    "fem.methods": ("method_names", "register"),
    "fem.output": ("write_vtk",),
}


def __getattr__(name):  # lazy, so `import fem` does not start dolfinx
    import importlib

    for module, names in _FROM.items():
        if name in names:
            return getattr(importlib.import_module(module), name)
    raise AttributeError(name)
