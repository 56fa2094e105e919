"""What a case file of the two-body scene may say: its geometry record and checks (:class:`cases.schema.SceneSchema`).

Two elastic bodies on non-matching meshes (:mod:`workbench.scenes.two_body`). Their materials are the case's two
``[[body]]`` tables (``name``, ``E``, ``nu``, ``model = "linear"``; :data:`BODY_ROLES`): the first is the lower body
(the block, slave side), the second the upper one (the indenter, driven); ``[material]`` is refused, and so are the
former ``[geometry] upper_E`` / ``upper_nu``, with a line saying to write ``[[body]]``. Registered with the case
schema by :func:`workbench.scenes.base.register_scene` (``TwoBodyScene.schema``). Units: mm, N, MPa.
"""

from __future__ import annotations

from dataclasses import dataclass

from cases.schema import CaseError, Geometry, Run, SceneSchema
from vocabulary import PAIRINGS, TWO_BODY_METHODS

__all__ = ["BODY_ROLES", "TWO_BODY_SCHEMA", "TwoBodyGeometry", "PAIRINGS", "PAIR_RANGES", "TWO_BODY_METHODS",
           "check_method_and_models"]

# the geometry ranges both two-body scenes share (the meshed bodies' size ratio, a radius, the blocks over the contact)
PAIR_RANGES = {"size_ratio": (0.2, 5.0, False, False, "0.2 < size_ratio < 5, not 1"),
               "radius": (0.0, 1e8, False, True, "0 < radius <= 1e8 (mm)"),
               "width_factor": (10.0, 1e6, True, True, "10 <= width_factor <= 1e6"),
               "height_factor": (10.0, 1e6, True, True, "10 <= height_factor <= 1e6")}
# [[body]] order: the lower body carries the slave surface (the gap is integrated on it), the upper one is driven.
BODY_ROLES = ("first: the lower body (the block, slave surface, held at its bottom)",
              "second: the upper body (the half disk or upper block, master surface, driven through its top)")


@dataclass(frozen=True)
class TwoBodyGeometry(Geometry):
    """Geometry of a two-body scene (``scene = "two_body"``).

    Attributes:
        indenter: ``"cylinder"`` (an elastic half disk of radius R on an elastic block, compared with the exact
            circle's half-plane theory at the combined modulus) or ``"stacked"`` (two stacked blocks pressed by a
            uniform displacement: the contact patch test, exact answer a uniform pressure P / W).
        radius: R (mm), cylinder.
        width_factor, height_factor: the block's W and H over the Hertz half-width (cylinder, >= 10).
        block_width, height_lower, height_upper: the blocks of the patch test (mm).
        upper_E, upper_nu: no longer read: refused with a line saying to write ``[[body]]`` (the bodies' materials).
        pairing: ``"mortar"`` (segment-to-segment) or ``"node_to_segment"``.
        size_ratio: the upper body's element size over the lower body's on the contact surface (non-matching
            meshes: not 1).
    """

    radius: float | None = None
    width_factor: float = 40.0
    height_factor: float = 40.0
    block_width: float | None = None
    height_lower: float | None = None
    height_upper: float | None = None
    upper_E: float | None = None
    upper_nu: float | None = None
    pairing: str = "mortar"
    size_ratio: float = 0.77


_COMMON = frozenset({"pairing", "size_ratio"})


def _check_geometry(run: Run, where: str) -> None:
    g, sol = run.geometry, run.solver
    needs = ("radius",) if g.indenter == "cylinder" else ("block_width", "height_lower", "height_upper")
    for key in ("upper_E", "upper_nu"):
        if getattr(g, key) is not None:
            raise CaseError(f"{where}: geometry.{key} is no longer read; allowed: the bodies' materials as two "
                            "[[body]] tables (name, E, nu), the lower body first (cases/elastic_cylinder.toml)")
    for key in needs:
        if getattr(g, key) is None:
            raise CaseError(f"{where}: geometry.{key} is required for a two-body {g.indenter} scene")
    if sol.kinematics != "small":
        raise CaseError(f"{where}: solver.kinematics = {sol.kinematics!r} is not available for two elastic bodies "
                        "yet; allowed: 'small'")
    check_method_and_models(run, where, model_reason="needs finite kinematics, which two elastic bodies do not "
                                                      "support yet")


def check_method_and_models(run: Run, where: str, *, model_reason: str, models: bool = True) -> None:
    """The contact methods two elastic bodies support (:data:`TWO_BODY_METHODS`) and (``models``) linear body
    models; a bad value is a one-line :class:`CaseError` (``model_reason``: why a non-linear model is refused on
    the scene)."""
    sol = run.solver
    if sol.method not in TWO_BODY_METHODS:
        raise CaseError(f"{where}: solver.method = {sol.method!r} is not available for two elastic bodies "
                        f"(nitsche needs the slave traction); allowed: {', '.join(map(repr, TWO_BODY_METHODS))}")
    for i, body in enumerate(run.bodies if models else ()):
        if body.model != "linear":
            raise CaseError(f"{where}: body[{i}].model = {body.model!r} {model_reason}; allowed: 'linear'")


def _check_load(run: Run, where: str) -> None:
    g, ld = run.geometry, run.loading
    if g.indenter == "stacked" and ld.control != "displacement":
        raise CaseError(f"{where}: loading.control must be 'displacement' (with d) for the patch test, "
                        f"got {ld.control!r}")
    if g.indenter == "cylinder" and ld.control != "force":
        raise CaseError(f"{where}: loading.control must be 'force' (with P or half_width) for the elastic "
                        f"cylinder, got {ld.control!r}")


TWO_BODY_SCHEMA = SceneSchema(
    name="two_body",
    geometry=TwoBodyGeometry,
    indenters={"cylinder": frozenset({"radius", "width_factor", "height_factor"}) | _COMMON,
               "stacked": frozenset({"block_width", "height_lower", "height_upper"}) | _COMMON},
    predictions={"cylinder": ("exact_circle",), "stacked": ("uniform",)},
    controls=("force", "displacement"),
    choices={"pairing": PAIRINGS},
    ranges={**PAIR_RANGES,
            "block_width": (0.0, 1e8, False, True, "0 < block_width <= 1e8 (mm)"),
            "height_lower": (0.0, 1e8, False, True, "0 < height_lower <= 1e8 (mm)"),
            "height_upper": (0.0, 1e8, False, True, "0 < height_upper <= 1e8 (mm)")},
    tolerances={
        "load_balance": "|P - P_pressure| / P",
        "p_max": "peak pressure against the exact circle at the measured load (relative)",
        "half_width_moment": "moment half-width sqrt(M2/M0) against the exact circle's (relative)",
        "rms": "RMS(p - p_exact_circle) / p0 over the contact",
        "patch_uniformity": "max |p / (P/W) - 1| over the contact nodes (mortar run)",
        "newton_iterations": "largest number of Newton iterations of a load step (absolute)",
    },
    band_quantities=("p_max", "half_width", "half_width_moment"),
    bodies=BODY_ROLES,
    check_geometry=_check_geometry,
    check_load=_check_load,
)
