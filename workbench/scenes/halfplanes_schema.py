"""What a case file of the two-half-planes scene may say: its geometry record and checks (issue 25).

Two elastic half-planes with a gap profile (:mod:`workbench.scenes.halfplanes`): the FE twin of the half-plane
theory of dissimilar materials. The bodies are the case's two ``[[body]]`` tables (:data:`BODY_ROLES`): the first
is the lower, flat body (Ciavarella and Hills's body 2, the slave surface), the second the upper body that carries
the profile (their body 1, the "indenter", driven through its top). Dundurs' beta follows from the two
(:func:`analytic.materials.bimaterial`, body 1 = the upper one); a rigid upper body is not a body of this scene
(that is the block scene). Registered with the case schema by :func:`workbench.scenes.base.register_scene`.
Units: mm, N, MPa.
"""

from __future__ import annotations

from dataclasses import dataclass

from cases.schema import CaseError, Geometry, Run, SceneSchema
from workbench.scenes.two_body_schema import PAIRINGS, TWO_BODY_METHODS

__all__ = ["BODY_ROLES", "HALFPLANES_SCHEMA", "HalfplanesGeometry", "PROFILES"]

PROFILES = ("parabola",)
CONVECTIONS = ("profile", "pairing")  # fem.two_body.problem.CONVECTIONS (the scene layer may not import fem)
BODY_ROLES = ("first: the lower, flat body (Ciavarella-Hills's body 2; slave surface, held at its bottom)",
              "second: the upper body that carries the profile (their body 1; master surface, driven through its top)")


@dataclass(frozen=True)
class HalfplanesGeometry(Geometry):
    """Geometry of the two-half-planes scene (``scene = "halfplanes"``, ``indenter = "parabola"``).

    Attributes:
        radius: R (mm): the upper body's reference surface is ``y = X1^2 / (2 R)`` above its flat face.
        width_factor, height_factor: each block's W and H over the classical half-width b0 (>= 10).
        pairing: ``"mortar"`` (segment-to-segment) or ``"node_to_segment"``.
        size_ratio: the upper body's element size over the lower body's on the contact (not 1).
        convection: what a ``convective`` run moves: ``"profile"`` (Ciavarella and Hills's eq. (8): the points
            opposite in the undeformed state carry the displacements and forces, the profile is read at the
            convected abscissa; the theory's own model) or ``"pairing"`` (the particles that touch now carry them:
            a consistent pairing of two deformable bodies, which differs from the theory at the order of the effect
            when the upper body deforms; docs/models.md).
    """

    radius: float | None = None
    width_factor: float = 160.0
    height_factor: float = 160.0
    pairing: str = "mortar"
    size_ratio: float = 0.77
    convection: str = "profile"


def _check_geometry(run: Run, where: str) -> None:
    g, sol = run.geometry, run.solver
    if g.radius is None:
        raise CaseError(f"{where}: geometry.radius is required for the two-half-planes {g.indenter} scene")
    if sol.kinematics not in ("small", "convective"):
        raise CaseError(f"{where}: solver.kinematics = {sol.kinematics!r} is not available for two elastic "
                        "half-planes; allowed: 'small', 'convective'")
    if sol.traction != "halfplane":
        raise CaseError(f"{where}: solver.traction = {sol.traction!r} is not available for two elastic half-planes "
                        "(the contact traction acts along the flat slave's normal on both bodies); allowed: "
                        "'halfplane'")
    if sol.method not in TWO_BODY_METHODS:
        raise CaseError(f"{where}: solver.method = {sol.method!r} is not available for two elastic bodies "
                        f"(nitsche needs the slave traction); allowed: {', '.join(map(repr, TWO_BODY_METHODS))}")
    for i, body in enumerate(run.bodies):
        if body.model != "linear":
            raise CaseError(f"{where}: body[{i}].model = {body.model!r} is not available for two elastic "
                            "half-planes; allowed: 'linear'")


def _check_load(run: Run, where: str) -> None:
    if run.loading.control != "force":
        raise CaseError(f"{where}: loading.control must be 'force' (with P or half_width) for two half-planes, "
                        f"got {run.loading.control!r}")


def _check_case(case, runs, where: str) -> None:
    if "convective" in case.analytic.predictions:
        kins = sorted({r.solver.kinematics for r in runs})
        if kins != ["convective", "small"]:
            raise CaseError(f"{where}: analytic.predictions 'convective' compares a small and a convective run "
                            f"of the same case; got kinematics {kins} (add [[variant]] tables for both)")


HALFPLANES_SCHEMA = SceneSchema(
    name="halfplanes",
    geometry=HalfplanesGeometry,
    indenters={"parabola": frozenset({"radius", "width_factor", "height_factor", "pairing", "size_ratio",
                                           "convection"})},
    predictions={"parabola": ("hertz", "convective")},
    controls=("force",),
    choices={"pairing": PAIRINGS, "convection": CONVECTIONS},
    ranges={"size_ratio": (0.2, 5.0, False, False, "0.2 < size_ratio < 5, not 1"),
            "radius": (0.0, 1e8, False, True, "0 < radius <= 1e8 (mm)"),
            "width_factor": (10.0, 1e6, True, True, "10 <= width_factor <= 1e6"),
            "height_factor": (10.0, 1e6, True, True, "10 <= height_factor <= 1e6")},
    tolerances={
        "load_balance": "|P - P_pressure| / P",
        "p_max": "small run: peak pressure against Hertz at the measured load and E* (relative)",
        "half_width": "small run: contact half-width against Hertz (relative)",
        "half_width_moment": "small run: moment half-width 2 sqrt(M2/M0) against Hertz's a (relative)",
        "rms": "small run: RMS(p - p_Hertz) / p0 over the contact",
        "b_over_b0": "FEM b/b0 of the edges (convective over small, same load) against converged Ciavarella-Hills",
        "b_over_b0_moment": "FEM moment ratio b/b0 (2 sqrt(M2/M0)) against converged Ciavarella-Hills's (relative)",
        "rms_convective": "convective run: RMS(p - p_Ciavarella-Hills) / p0 over the contact",
        "newton_iterations": "largest number of Newton iterations of a load step (absolute)",
    },
    band_quantities=("p_max", "half_width", "half_width_moment", "b_over_b0", "b_over_b0_moment"),
    bodies=BODY_ROLES,
    check_geometry=_check_geometry,
    check_load=_check_load,
    check_case=_check_case,
)
