"""Contact partners: what the elastic body (or bodies) of a mesh is pressed against, and the one solve for all.

Two kinds of partner (units mm, N, MPa):

* a **rigid analytic curve** (:mod:`fem.obstacles`: circle, parabola, wedge, plane, spline curve), moved by d
  along its direction; the contact terms are dolfinx forms on the body's contact facets
  (:class:`fem.problem.ContactProblem`);
* a **deformable meshed surface** (:class:`fem.two_body.problem.MeshedPartner`): a second elastic body in the
  same mesh, with its own material, paired across non-matching facets by mortar or node-to-segment; the contact
  terms couple both bodies' dofs (:class:`fem.two_body.problem.TwoBodyProblem`).

The options (:class:`fem.options.ContactOptions`) hold the contact law, the load path and the Newton solve for
both; a rigid obstacle's body and material are ``options.body`` (:class:`fem.options.RigidBody`), two meshed
bodies' are the partner's (``options.body`` is None). Both problems implement the protocol
:class:`fem.partner_problem.PartnerProblem` that :class:`fem.stepping.LoadStepper` drives, so
:func:`fem.solver.solve_contact` (which builds the problem here) is one Newton (PETSc SNES with the linear solver
of :mod:`fem.linear_solver`), one load-stepping driver, one active-set logic (the prescribed-active-set predictor
on runs of X1) and one results contract (:class:`fem.solver.ContactResult`) for every partner.
"""

from __future__ import annotations

from fem.options import ContactOptions
from vocabulary import FINITE, MESHED, RIGID

__all__ = ["contact_problem", "partner_kind"]


def partner_kind(partner) -> str:
    """``"meshed"`` for a :class:`fem.two_body.problem.MeshedPartner`, ``"rigid"`` for an obstacle."""
    from fem.two_body.problem import MeshedPartner

    return MESHED if isinstance(partner, MeshedPartner) else RIGID


def contact_problem(mesh_data, partner, options: ContactOptions):
    """The contact problem of ``mesh_data`` against ``partner`` (ValueError naming a bad option)."""
    if partner_kind(partner) == MESHED:
        from fem.two_body.problem import TwoBodyProblem

        if options.kinematics == FINITE:
            from fem.two_body.finite_problem import FiniteTwoBodyProblem

            return FiniteTwoBodyProblem(mesh_data, partner, options)
        return TwoBodyProblem(mesh_data, partner, options)
    if options.body is None:
        raise ValueError("a rigid obstacle needs the body's material: give E and nu (ContactOptions.body, a "
                         "RigidBody record)")
    from fem.options import check_options
    from fem.problem import ContactProblem

    check_options(options, mesh_data=mesh_data, obstacle=partner)
    return ContactProblem(mesh_data, partner, options)

