"""What a case file of the concave scene may say: its geometry record and checks (:class:`cases.schema.SceneSchema`).

A concave elastic body under the rigid convex particle of the close-to-conformal paper, displacement-controlled
(:mod:`workbench.scenes.concave`). Registered with the case schema by :func:`workbench.scenes.base.register_scene`
(``ConcaveScene.schema``). Units: mm.
"""

from __future__ import annotations

from dataclasses import dataclass

from cases.schema import CaseError, Geometry, Run, SceneSchema

__all__ = ["CONCAVE_SCHEMA", "ConcaveGeometry", "DESIGNS", "FAMILY_NUMBERS", "family_member"]

DESIGNS = ("symmetric", "close_to_conformal")  # analytic.designs
FAMILY_NUMBERS = ("radius_convex", "radius_concave", "pair_separation", "central_gap", "depth")  # the last optional


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
    :data:`FAMILY_NUMBERS`, mm); its name ``<kind>_family_<hash>`` names its meshes. ValueError: one line."""
    import hashlib

    from analytic.design_family import FamilyMember

    values: dict[str, float] = {}
    for item in filter(None, (t.strip() for t in family.split(","))):
        key, eq, val = item.partition("=")
        key = key.strip()
        if key not in FAMILY_NUMBERS or not eq or key in values:
            raise ValueError(f"geometry.family item {item[:40]!r} out of range: need key=value once per key, "
                             f"keys in {FAMILY_NUMBERS}")
        try:
            values[key] = float(val)
        except ValueError:
            raise ValueError(f"geometry.family {key} = {val.strip()[:40]!r} out of range: need a number (mm)") from None
    missing = [k for k in FAMILY_NUMBERS[:4] if k not in values]
    if missing:
        raise ValueError(f"geometry.family lacks {', '.join(missing)}: need all of {FAMILY_NUMBERS[:4]} "
                         "(depth optional, 20 mm)")
    tag = hashlib.sha256(repr((design, sorted(values.items()))).encode()).hexdigest()[:10]
    return FamilyMember(name=f"{design}_family_{tag}", kind=design, **values)


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
