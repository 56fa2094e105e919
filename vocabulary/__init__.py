"""The workbench's vocabularies, written once: the allowed words of every model and solver choice, and the rules
that combine them.

The bottom layer (beside :mod:`analytic` and :mod:`measures`; pure Python, no numpy): :mod:`cases` (the case
files' choices), :mod:`fem` (the solver's options and registries) and :mod:`workbench` (scenes, studies) import the
lists from here, so a new word is added in one place. Where a layer checks a combination it asks
:func:`model_conflict` and words the refusal for its own readers (a case file's ``solver.kinematics``, the solver's
``kinematics=``), so the rule itself is written once. The meanings of the words are documented where they act
(:class:`fem.options.ContactOptions`, :mod:`fem.contact_forms`, :mod:`fem.two_body.problem`, ``docs/models.md``).
"""

from __future__ import annotations

from typing import NamedTuple

__all__ = [
    "NITSCHE", "PENALTY", "AUGMENTED_LAGRANGIAN", "METHODS", "TWO_BODY_METHODS", "FINITE_METHODS",
    "SMALL", "CONVECTIVE", "FINITE", "KINEMATICS", "TWO_BODY_KINEMATICS",
    "LINEAR", "SAINT_VENANT_KIRCHHOFF", "NEO_HOOKEAN", "MATERIAL_MODELS", "HYPERELASTIC_MODELS",
    "OBSTACLE", "HALFPLANE", "MASTER_NORMAL", "TRACTIONS", "TWO_BODY_TRACTIONS",
    "DISPLACEMENT", "MIXED", "AUTO", "FORMULATIONS", "CASE_FORMULATIONS",
    "FORCE", "CONTROLS", "CASE_CONTROLS",
    "LINEAR_SOLVERS", "PREDICTORS", "ACTIVE_SETS", "ACTIVE_SET_UPDATES", "SUPPORT_KINDS",
    "PAIRINGS", "CONVECTIONS", "RIGID", "MESHED", "PARTNER_KINDS", "Conflict", "model_conflict",
]

# -- contact methods (fem.methods: one registry, rigid obstacle and two meshed bodies) ----------------------
NITSCHE = "nitsche"
PENALTY = "penalty"
AUGMENTED_LAGRANGIAN = "augmented_lagrangian"
METHODS = (NITSCHE, PENALTY, AUGMENTED_LAGRANGIAN)
# two meshed bodies: Nitsche's terms need the slave traction across the non-matching interface (not built)
TWO_BODY_METHODS = (PENALTY, AUGMENTED_LAGRANGIAN)
# methods with a finite-strain form (current-configuration pressure, surface Jacobian ds/dS; fem.contact_forms)
FINITE_METHODS = METHODS

# -- kinematics ---------------------------------------------------------------------------------------------
SMALL = "small"  # gap at the undeformed position, small strain
CONVECTIVE = "convective"  # the partner evaluated at the deformed position X + u, small strain
FINITE = "finite"  # finite-strain hyperelasticity (total Lagrangian), contact at the deformed position
KINEMATICS = (SMALL, CONVECTIVE, FINITE)
TWO_BODY_KINEMATICS = (SMALL, CONVECTIVE, FINITE)  # finite: hyperelastic bodies, P1 mortar (fem.two_body)

# -- bulk material models (fem.hyperelastic) ----------------------------------------------------------------
LINEAR = "linear"  # small-strain Hooke (kinematics small or convective)
SAINT_VENANT_KIRCHHOFF = "saint_venant_kirchhoff"
NEO_HOOKEAN = "neo_hookean"
MATERIAL_MODELS = (LINEAR, SAINT_VENANT_KIRCHHOFF, NEO_HOOKEAN)
HYPERELASTIC_MODELS = (SAINT_VENANT_KIRCHHOFF, NEO_HOOKEAN)  # finite kinematics only, and it needs one

# -- the direction of the gap and traction ------------------------------------------------------------------
OBSTACLE = "obstacle"  # along the rigid obstacle's normal
HALFPLANE = "halfplane"  # vertical (rigid) or the slave normal (two bodies), as half-plane theory assumes
MASTER_NORMAL = "master_normal"  # two bodies, convective: the deformed master's normal
TRACTIONS = (OBSTACLE, HALFPLANE)  # against a rigid obstacle (the case files' [solver] traction)
TWO_BODY_TRACTIONS = (HALFPLANE, MASTER_NORMAL)

# -- bulk formulation ---------------------------------------------------------------------------------------
DISPLACEMENT = "displacement"
MIXED = "mixed"  # Taylor-Hood u-p
AUTO = "auto"  # case files only: resolved by nu (cases.schema.effective_formulation)
FORMULATIONS = (DISPLACEMENT, MIXED)
CASE_FORMULATIONS = (AUTO, *FORMULATIONS)

# -- load control -------------------------------------------------------------------------------------------
FORCE = "force"
CONTROLS = (DISPLACEMENT, FORCE)
CASE_CONTROLS = (FORCE, DISPLACEMENT)  # the order a case file's error line lists them in

# -- the Newton solve and the load stepping (fem.linear_solver, fem.stepping) --------------------------------
LINEAR_SOLVERS = ("lu", "lu_reuse", "gamg", "auto")
PREDICTORS = ("auto", "hertz", "extrapolate", "hertz_zone")
ACTIVE_SETS = ("extrapolate", "geometry")
# "newton": one prescribed iteration, then semismooth Newton; "edge_fit": prescribed iterations with the edges
# extrapolated from the pressure until the set repeats, then semismooth Newton (fem.active_set_update)
ACTIVE_SET_UPDATES = ("newton", "edge_fit")
SUPPORT_KINDS = ("clamped", "roller_x", "roller_y", "free", "halfplane")  # halfplane: fem/far_field.py

# -- contact partners (fem.partners): a rigid analytic curve, or a second meshed elastic body ----------------
RIGID = "rigid"
MESHED = "meshed"
PARTNER_KINDS = (RIGID, MESHED)

# -- two meshed bodies (fem.two_body) -----------------------------------------------------------------------
PAIRINGS = ("mortar", "node_to_segment")
CONVECTIONS = ("pairing", "profile")  # what convective kinematics moves (MeshedPartner.convection)


class Conflict(NamedTuple):
    """A refused combination: the option ``name`` (``"material_model"``, ``"traction"``, ``"formulation"``,
    ``"method"``) has ``value``, but ``given`` (``"kinematics"``) needs one of ``allowed``."""

    name: str
    value: str
    given: str
    given_value: str
    allowed: tuple[str, ...]


def model_conflict(*, kinematics: str, material_model: str, traction: str | None = None,
                   formulation: str | None = None, method: str | None = None) -> Conflict | None:
    """The first broken rule of the model hierarchy (``docs/models.md``), or None.

    In this order: finite kinematics needs a hyperelastic material model (and small or convective kinematics the
    linear one); finite kinematics needs ``traction = "obstacle"``, the displacement formulation and a method of
    :data:`FINITE_METHODS`. An argument left None is not checked. The caller words the refusal.
    """
    if kinematics == FINITE:
        if material_model not in HYPERELASTIC_MODELS:
            return Conflict("material_model", material_model, "kinematics", kinematics, HYPERELASTIC_MODELS)
        if traction is not None and traction != OBSTACLE:
            return Conflict("traction", traction, "kinematics", kinematics, (OBSTACLE,))
        if formulation is not None and formulation != DISPLACEMENT:
            return Conflict("formulation", formulation, "kinematics", kinematics, (DISPLACEMENT,))
        if method is not None and method not in FINITE_METHODS:
            return Conflict("method", method, "kinematics", kinematics, FINITE_METHODS)
    elif material_model != LINEAR:
        return Conflict("material_model", material_model, "kinematics", kinematics, (LINEAR,))
    return None
