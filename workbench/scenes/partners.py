"""The meshed contact partner of the two-body scenes, built in one place.

Both two-body scenes (:mod:`workbench.scenes.two_body`, :mod:`workbench.scenes.halfplanes`) mesh two bodies whose
cell groups are ``"lower"`` and ``"upper"`` (the case's first and second ``[[body]]``), contact facet groups
``contact_lower`` (slave) and ``contact_upper`` (master), and drive the upper body through its ``driven`` facets.
"""

from __future__ import annotations

from cases.schema import Run

__all__ = ["meshed_partner"]


def meshed_partner(run: Run, *, master_surface, driven_components: tuple[int, ...] = (0, 1), **options):
    """The upper body of a two-body run as the meshed contact partner (:class:`fem.two_body.problem.MeshedPartner`).

    Args:
        run: The run; ``run.bodies`` is (lower, upper) with E (MPa), nu and the bulk law (``model``: linear, or a
            hyperelastic law with finite kinematics), ``run.geometry.pairing`` the pairing.
        master_surface: The upper body's exact reference surface for the initial gap (e.g.
            :class:`fem.two_body.geometry.CircleSurface`), or None (its facets).
        driven_components: The displacement components prescribed on the driven facets.
        options: Further :class:`~fem.two_body.problem.MeshedPartner` fields (``traction``, ``convection``,
            ``cut_kinks``).
    """
    from fem.two_body.problem import Body, MeshedPartner

    lower, upper = run.bodies
    return MeshedPartner(bodies=(Body(name="lower", E=lower.E, nu=lower.nu, label=lower.name,
                                      material_model=lower.model),
                                 Body(name="upper", E=upper.E, nu=upper.nu, label=upper.name,
                                      material_model=upper.model)),
                         slave="contact_lower", master="contact_upper", driven="driven", driven_body="upper",
                         driven_components=driven_components, pairing=run.geometry.pairing,
                         master_surface=master_surface, **options)
