"""What a case file of the concave scene may say: its geometry record and checks (:class:`cases.schema.SceneSchema`).

A concave elastic body under the rigid convex particle of the close-to-conformal paper, displacement-controlled
(:mod:`workbench.scenes.concave`). Registered with the case schema by :func:`workbench.scenes.base.register_scene`
(``ConcaveScene.schema``). Units: mm.
"""

from __future__ import annotations

from dataclasses import dataclass

from cases.schema import CaseError, Geometry, Run, SceneSchema

__all__ = ["CONCAVE_SCHEMA", "ConcaveGeometry", "DESIGNS", "family_member"]

DESIGNS = ("symmetric", "close_to_conformal")  # analytic.designs


@dataclass(frozen=True)
class ConcaveGeometry(Geometry):
    """Geometry of a concave scene (``scene = "concave"``, ``indenter = "particle"``).

    Attributes:
        design: Concave configuration, ``"symmetric"`` or ``"close_to_conformal"`` (:mod:`analytic.designs`).
        family: None (the paper's design), or a member of that kind by its family numbers (mm,
            :class:`analytic.design_family.FamilyMember`): ``"radius_convex=..,radius_concave=..,pair_separation=..,
            central_gap=..[,depth=..]"``.
    """

    design: str | None = None
    family: str | None = None


def family_member(design: str, family: str):
    """The :class:`analytic.design_family.FamilyMember` of kind ``design`` named by ``family`` (``key=value,...``,
    mm; :func:`analytic.design_family.parse_family`, the one parser); ValueError: one line."""
    from analytic.design_family import parse_family

    return parse_family(design, family, field="geometry.family")


def _check_geometry(run: Run, where: str) -> None:
    if run.geometry.design is None:
        raise CaseError(f"{where}: geometry.design is required for a concave scene; "
                        f"allowed values: {', '.join(repr(d) for d in DESIGNS)}")
    if run.geometry.family is not None:
        try:
            family_member(run.geometry.design, run.geometry.family)
        except ValueError as exc:
            raise CaseError(f"{where}: {exc}") from None


CONCAVE_SCHEMA = SceneSchema(
    name="concave",
    geometry=ConcaveGeometry,
    indenters={"particle": frozenset({"design", "family"})},
    predictions={"particle": ("hertz_superposition", "elliptical_fit")},
    controls=("displacement",),
    choices={"design": DESIGNS},
    tolerances={
        "load_balance": "|P - P_pressure| / P",
        "fit_rms": "elliptical-fit RMS / p0 (upper bound)",
        "patch_size": "relative mismatch of eq. (4) and eq. (5) patch sizes",
    },
    band_quantities=("load_symmetry", "first_contact_width", "width_moment", "width_fem"),
    band_note="optionally name[k], patch k",
    budget_widths="its body is the real geometry",
    check_geometry=_check_geometry,
)
