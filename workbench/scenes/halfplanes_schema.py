"""What a case file of the two-half-planes scene may say: its geometry record and checks (issue 25).

Two elastic half-planes with a gap profile (:mod:`workbench.scenes.halfplanes`): the FE twin of the half-plane
theory of dissimilar materials. The bodies are the case's two ``[[body]]`` tables (:data:`BODY_ROLES`): the first
is the lower, flat body (Ciavarella and Hills's body 2, the slave surface), the second the upper body that carries
the profile (their body 1, the "indenter", driven through its top). Dundurs' beta follows from the two
(:func:`analytic.materials.bimaterial`, body 1 = the upper one); a rigid upper body is not a body of this scene
(that is the block scene). Registered with the case schema by :func:`workbench.scenes.base.register_scene`.
Units: mm, N, MPa.

Kinematics ``small`` and ``convective`` take linear bodies and the traction along the flat slave's normal
(``traction = "halfplane"``). ``finite`` (issue 39: :mod:`fem.two_body.finite_problem`) takes a hyperelastic law
per body (``[[body]] model``, or a variant's ``body = [{model = ...}, {model = ...}]``), the traction along the
deformed master normal (``traction = "obstacle"``: for two bodies the upper body's current normal), degree 1 and
mortar pairing, and a profile meshed as itself: the parabola (its upper body meshed as the real parabola, capped,
:mod:`workbench.scenes.halfplanes`) or the shaped wedge (``wedge_body = "shaped"``; the flat wedge is an analytic
gap, which finite strain has not).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from cases.schema import CaseError, Geometry, Run, SceneSchema
from vocabulary import FINITE, HYPERELASTIC_MODELS
from workbench.scenes.two_body_schema import PAIR_RANGES, PAIRINGS, check_method_and_models

__all__ = ["BODY_ROLES", "HALFPLANES_SCHEMA", "HalfplanesGeometry", "PROFILES"]

PROFILES = ("parabola", "wedge")
APEX = ("refined", "cut", "none")  # a wedge's apex (HalfplanesGeometry.apex)
WEDGE_BODY = ("flat", "shaped")  # a wedge's upper body (HalfplanesGeometry.wedge_body)
CONVECTIONS = ("profile", "pairing")  # fem.two_body.problem.CONVECTIONS (the scene layer may not import fem)
BODY_ROLES = ("first: the lower, flat body (Ciavarella-Hills's body 2; slave surface, held at its bottom)",
              "second: the upper body that carries the profile (their body 1; master surface, driven through its top)")


@dataclass(frozen=True)
class HalfplanesGeometry(Geometry):
    """Geometry of the two-half-planes scene (``scene = "halfplanes"``, ``indenter = "parabola"`` or ``"wedge"``).

    Attributes:
        radius: parabola: R (mm): the upper body's reference surface is ``y = X1^2 / (2 R)`` above its flat face.
        wedge_angle: wedge: the external angle theta (rad), 0 < theta < pi/2; the reference surface is
            ``y = m |X1|`` with the face slope m of ``wedge_slope`` (as the block scene's wedge).
        wedge_slope: wedge: ``"exact"`` (m = tan(theta)) or ``"paper"`` (m = theta, Ciavarella and Hills's
            small-angle slope). The profile is analytic here (not meshed), so either is the exact h = m |x| of the
            half-plane theory; the choice only names m.
        apex: wedge: how the slope's jump at X1 = 0 is integrated: ``"refined"`` (both contact lines get a node at
            x = 0, refined there to a quarter of their contact size, and the mortar segments are cut at the
            apex's projection), ``"cut"`` (the segments cut, the plain meshes) or ``"none"`` (neither: Gauss
            segments straddle the kink; for measuring what it costs, docs/models.md).
        width_factor, height_factor: each block's W and H over the classical half-width b0 (>= 10).
        pairing: ``"mortar"`` (segment-to-segment) or ``"node_to_segment"``.
        size_ratio: the upper body's element size over the lower body's on the contact (not 1).
        convection: what a ``convective`` run moves: ``"profile"`` (Ciavarella and Hills's eq. (8): the points
            opposite in the undeformed state carry the displacements and forces, the profile is read at the
            convected abscissa; the theory's own model) or ``"pairing"`` (the particles that touch now carry them:
            a consistent pairing of two deformable bodies, which differs from the theory at the order of the effect
            when the upper body deforms; docs/models.md).
        wedge_body: wedge: ``"flat"`` (the upper block is flat at y = 0 and carries the wedge as an analytic gap: the
            half-plane idealisation) or ``"shaped"`` (the upper body is the wedge itself, its faces ``y = m |x|``
            meshed: the real geometry the idealisation stands for; small kinematics only, the apex refined or cut).
    """

    radius: float | None = None
    wedge_angle: float | None = None
    wedge_slope: str = "exact"
    apex: str = "refined"
    width_factor: float = 160.0
    height_factor: float = 160.0
    pairing: str = "mortar"
    size_ratio: float = 0.77
    convection: str = "profile"
    wedge_body: str = "flat"


_COMMON = frozenset({"width_factor", "height_factor", "pairing", "size_ratio", "convection"})


def _check_geometry(run: Run, where: str) -> None:
    g, sol = run.geometry, run.solver
    if g.indenter == "parabola" and g.radius is None:
        raise CaseError(f"{where}: geometry.radius is required for the two-half-planes parabola scene")
    if g.indenter == "wedge" and g.wedge_angle is None:
        raise CaseError(f"{where}: geometry.wedge_angle is required for the two-half-planes wedge scene; "
                        "allowed: 0 < wedge_angle < pi/2 (rad)")
    if sol.kinematics not in ("small", "convective", FINITE):
        raise CaseError(f"{where}: solver.kinematics = {sol.kinematics!r} is not available for two elastic "
                        "half-planes; allowed: 'small', 'convective', 'finite'")
    if sol.kinematics == FINITE:
        _check_finite(run, where)
        return
    if sol.traction != "halfplane":
        raise CaseError(f"{where}: solver.traction = {sol.traction!r} is not available for two elastic half-planes "
                        "(the contact traction acts along the flat slave's normal on both bodies); allowed: "
                        "'halfplane'")
    if g.wedge_body == "shaped" and sol.kinematics != "small":
        raise CaseError(f"{where}: geometry.wedge_body = 'shaped' needs solver.kinematics = 'small' (the convective "
                        f"models read the profile above a flat face), got {sol.kinematics!r}; allowed with "
                        "convective: geometry.wedge_body = 'flat'")
    if g.wedge_body == "shaped" and g.apex == "none":
        raise CaseError(f"{where}: geometry.apex = 'none' is not available with geometry.wedge_body = 'shaped' (the "
                        "shaped wedge's apex is a mesh corner, where the mortar segments are always cut); allowed: "
                        "'refined', 'cut'")
    check_method_and_models(run, where, model_reason="is not available for two elastic half-planes")


def _check_finite(run: Run, where: str) -> None:
    """What finite kinematics of the two half-planes supports (module docstring); the generic model check that
    follows refuses a traction other than 'obstacle' (:func:`cases.checks`)."""
    g = run.geometry
    if g.indenter != "parabola" and not (g.indenter == "wedge" and g.wedge_body == "shaped"):
        raise CaseError(f"{where}: solver.kinematics = 'finite' is not available for the two-half-planes "
                        f"{g.indenter} with wedge_body = {g.wedge_body!r} (the wedge at finite strain is meshed as "
                        "itself); allowed: indenter = 'parabola', or 'wedge' with wedge_body = 'shaped'")
    if run.discretisation.degree != 1:
        raise CaseError(f"{where}: discretisation.degree = {run.discretisation.degree} is not available with "
                        "solver.kinematics = 'finite' for two elastic half-planes; allowed: 1")
    if g.pairing != "mortar":
        raise CaseError(f"{where}: geometry.pairing = {g.pairing!r} is not available with solver.kinematics = "
                        "'finite' for two elastic half-planes; allowed: 'mortar'")
    for i, body in enumerate(run.bodies):
        if body.model not in HYPERELASTIC_MODELS:
            raise CaseError(f"{where}: body[{i}].model = {body.model!r} is not available with solver.kinematics = "
                            f"'finite'; allowed: {', '.join(map(repr, HYPERELASTIC_MODELS))}")
    check_method_and_models(run, where, model_reason="", models=False)


def _check_load(run: Run, where: str) -> None:
    if run.loading.control != "force":
        raise CaseError(f"{where}: loading.control must be 'force' (with P or half_width) for two half-planes, "
                        f"got {run.loading.control!r}")


def _check_case(case, runs, where: str) -> None:
    if "convective" in case.analytic.predictions:
        kins = sorted({r.solver.kinematics for r in runs})
        if "small" not in kins or len(kins) < 2:
            raise CaseError(f"{where}: analytic.predictions 'convective' compares a small and a convective (or "
                            f"finite) run of the same case; got kinematics {kins} (add [[variant]] tables for "
                            "both)")


HALFPLANES_SCHEMA = SceneSchema(
    name="halfplanes",
    geometry=HalfplanesGeometry,
    indenters={"parabola": frozenset({"radius"} | _COMMON),
               "wedge": frozenset({"wedge_angle", "wedge_slope", "apex", "wedge_body"} | _COMMON)},
    predictions={"parabola": ("hertz", "convective"), "wedge": ("wedge", "convective")},
    controls=("force",),
    choices={"pairing": PAIRINGS, "convection": CONVECTIONS, "wedge_slope": ("exact", "paper"), "apex": APEX,
             "wedge_body": WEDGE_BODY},
    ranges={"wedge_angle": (0.0, math.pi / 2, False, False, "0 < wedge_angle < pi/2 (rad)"), **PAIR_RANGES},
    tolerances={
        "load_balance": "|P - P_pressure| / P",
        "p_max": "small run, parabola: peak pressure against Hertz at the measured load and E* (relative)",
        "half_width": "small run: contact half-width against the classical one (Hertz; wedge b = P / (E* m))",
        "half_width_moment": "small run: moment half-width 2 sqrt(M2/M0) against the classical one (Hertz's a; "
                             "the wedge's 2 b / sqrt(6)) (relative)",
        "rms": "small run: RMS(p - p_classical) / p_ref over the contact (p_ref: Hertz's p0; the wedge's P / (2 b))",
        "b_over_b0": "FEM b/b0 of the edges (convective over small, same load) against converged Ciavarella-Hills",
        "b_over_b0_moment": "FEM moment ratio b/b0 (2 sqrt(M2/M0)) against converged Ciavarella-Hills's (relative)",
        "rms_convective": "convective run: RMS(p - p_Ciavarella-Hills) / p_ref over the contact",
        "newton_iterations": "largest number of Newton iterations of a load step (absolute)",
    },
    band_quantities=("p_max", "half_width", "half_width_moment", "b_over_b0", "b_over_b0_moment"),
    bodies=BODY_ROLES,
    finite=True,
    check_geometry=_check_geometry,
    check_load=_check_load,
    check_case=_check_case,
)
