"""The combinations the two-body problem supports (ValueError naming the option; numpy-free).

Kinematics ``small`` and ``convective`` take linear bodies (``Body.material_model = "linear"``); ``finite``
(:mod:`fem.two_body.finite_problem`) takes a hyperelastic law per body, P1 (degree 1), mortar pairing, the
traction along the deformed master normal (``traction = "master_normal"``), the facets as the master's surface
(no ``master_surface``) and the penalty or augmented Lagrangian law. Everything else is refused in one line.
"""

from __future__ import annotations

from analytic import materials
from fem.two_body.laws import law_for
from vocabulary import (
    CONVECTIONS,
    CONVECTIVE,
    FINITE,
    HALFPLANE,
    HYPERELASTIC_MODELS,
    MASTER_NORMAL,
    PAIRINGS,
    TWO_BODY_KINEMATICS,
    TWO_BODY_TRACTIONS,
    model_conflict,
)

__all__ = ["check_two_body"]


def _check_finite(setup, opts) -> None:
    """What finite kinematics of two bodies supports (module docstring)."""
    for b in setup.bodies:
        if model_conflict(kinematics=FINITE, material_model=b.material_model) is not None:
            raise ValueError(f"kinematics='finite' needs bodies[{b.name!r}].material_model in {HYPERELASTIC_MODELS}, "
                             f"got {b.material_model!r}")
    if opts.degree != 1:
        raise ValueError(f"kinematics='finite' for two elastic bodies supports degree 1 only, got {opts.degree}")
    if setup.pairing != "mortar":
        raise ValueError(f"kinematics='finite' for two elastic bodies supports pairing='mortar' only, got "
                         f"{setup.pairing!r}")
    if setup.traction != MASTER_NORMAL:
        raise ValueError(f"kinematics='finite' for two elastic bodies needs traction='master_normal' (the traction "
                         f"along the deformed master normal), got {setup.traction!r}")
    if setup.master_surface is not None:
        raise ValueError("kinematics='finite' for two elastic bodies measures the gap to the deformed master facets: "
                         "give no master_surface")


def check_two_body(setup, opts, mesh_data) -> None:
    """The combinations the two-body problem supports (ValueError naming the option)."""
    if mesh_data.mesh.comm.size > 1:
        raise ValueError("two-body contact runs on one process (the pairing needs both surfaces there); "
                         "run it without mpiexec")
    if opts.kinematics not in TWO_BODY_KINEMATICS:
        raise ValueError(f"kinematics={opts.kinematics!r} is not available for two elastic bodies; allowed: 'small' "
                         "(pairing fixed in the reference configuration), 'convective' (pairing follows the "
                         "relative tangential displacement) or 'finite' (hyperelastic bodies, contact in the current "
                         "configuration)")
    if opts.degree not in (1, 2):
        raise ValueError(f"degree must be 1 or 2 for two elastic bodies, got {opts.degree}")
    if opts.body is not None:
        raise ValueError("two elastic bodies take their materials from MeshedPartner.bodies (displacement "
                         "formulation): give the options no body (E, nu, material_model, formulation, traction, "
                         "contact_group, quadrature_degree, sample_degree: ContactOptions.body must be None)")
    if not opts.split_jacobian:
        raise ValueError("split_jacobian=False is not available for two elastic bodies (their elastic stiffness is "
                         "always assembled once, the contact terms per Newton iteration)")
    if setup.traction not in TWO_BODY_TRACTIONS:
        raise ValueError(f"traction must be one of {TWO_BODY_TRACTIONS}, got {setup.traction!r}")
    if opts.kinematics == FINITE:
        _check_finite(setup, opts)
    else:
        for b in setup.bodies:
            if b.material_model != "linear":
                raise ValueError(f"bodies[{b.name!r}].material_model={b.material_model!r} needs kinematics='finite' "
                                 f"(got {opts.kinematics!r}); small and convective kinematics use 'linear'")
    if setup.traction == MASTER_NORMAL and opts.kinematics not in (CONVECTIVE, FINITE):
        raise ValueError("traction='master_normal' needs kinematics='convective' or 'finite' (small kinematics pairs "
                         "and pushes along the slave normal: traction='halfplane')")
    if setup.convection not in CONVECTIONS:
        raise ValueError(f"convection must be one of {CONVECTIONS}, got {setup.convection!r}")
    if setup.convection == "profile" and (setup.master_surface is None or setup.traction != HALFPLANE):
        raise ValueError("convection='profile' needs master_surface (the master's exact profile) and "
                         "traction='halfplane'")
    if setup.pairing not in PAIRINGS:
        raise ValueError(f"pairing must be one of {PAIRINGS}, got {setup.pairing!r}")
    if len(setup.bodies) != 2 or setup.bodies[0].name == setup.bodies[1].name:
        raise ValueError("two-body contact needs exactly two bodies with different names")
    groups = mesh_data.physical_groups
    for b in setup.bodies:
        if b.name not in groups:
            raise ValueError(f"body {b.name!r} is not a physical group of the mesh; known: {sorted(groups)}")
        materials.validate_modulus(b.E, f"bodies[{b.name!r}].E")
        materials.validate_poisson(b.nu, f"bodies[{b.name!r}].nu")
    for g in (setup.slave, setup.master, setup.driven):
        if g not in groups:
            raise ValueError(f"facet group {g!r} is not a physical group of the mesh; known: {sorted(groups)}")
    if setup.driven_body not in {b.name for b in setup.bodies}:
        raise ValueError(f"driven_body must name one of the bodies, got {setup.driven_body!r}")
    if opts.supports and "halfplane" in opts.supports.values():
        raise ValueError("supports 'halfplane' is not available for two elastic bodies")
    law_for(opts.method)
