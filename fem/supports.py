"""Supports of a contact problem, resolved once for every partner: physical group -> support kind.

The kinds (:data:`vocabulary.SUPPORT_KINDS`) and the displacement components each one fixes (:data:`COMPONENTS`,
0 = x, 1 = y); ``halfplane`` prescribes Flamant's far field on both components (:mod:`fem.far_field`, rigid
obstacle only). Defaults: the group ``clamped`` clamped, and for a half model the ``symmetry`` group on rollers
(x fixed). :class:`fem.problem.ContactProblem` and :class:`fem.two_body.problem.TwoBodyProblem` both call
:func:`resolve_supports`.
"""

from __future__ import annotations

from vocabulary import SUPPORT_KINDS

__all__ = ["COMPONENTS", "resolve_supports", "group_facets"]

COMPONENTS = {"clamped": (0, 1), "roller_x": (0,), "roller_y": (1,), "free": (), "halfplane": (0, 1)}


def resolve_supports(mesh_data, supports: dict | None, symmetric_half: bool) -> dict:
    """Physical group name -> support kind, with the defaults (clamped ``clamped``; roller_x ``symmetry``);
    ValueError naming an unknown kind or group."""
    groups = mesh_data.physical_groups
    if supports is None:
        supports = {"clamped": "clamped"}
        if symmetric_half:
            supports["symmetry"] = "roller_x"
    for name, kind in supports.items():
        if kind not in SUPPORT_KINDS:
            raise ValueError(f"supports[{name!r}] must be one of {SUPPORT_KINDS}, got {kind!r}")
        if name not in groups:
            raise ValueError(f"supports names unknown physical group {name!r}; known: {sorted(groups)}")
    return supports


def group_facets(mesh_data, name: str):
    """The facet indices of the physical group ``name``."""
    return mesh_data.facet_tags.find(mesh_data.physical_groups[name].tag)
