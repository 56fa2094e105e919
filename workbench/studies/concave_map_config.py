"""The configuration of the concave map (issue 40, item 3): which family members, which loads, which mesh.

:class:`ConcaveMapConfig` names the designs of :mod:`analytic.design_family` by their numbers (mm) and the loads by
the approach past first touch (mm along the design's path: d = d_touch + approach; the FEM is displacement
controlled, so one run per design records every load). The defaults are the map: a close-to-conformal grid of
relative radius x pair separation (10 x 5 = 50 designs), three symmetric members and the paper's two designs, 5
approaches each; :data:`TINY` is the end-to-end test (2 designs x 2 loads on coarse meshes, no meaningful numbers).
Light (no dolfinx): the study and its report both import it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar, NamedTuple

from workbench.studies.config import StudyFolders

__all__ = ["CLASSES", "ConcaveMapConfig", "MapDesign", "TINY", "paper_designs"]

CLASSES = (0.01, 0.05, 0.10)  # the error classes' upper edges: within 1 %, 5 %, 10 %, else beyond
_CC_CONVEX = 41.279  # the paper's close-to-conformal primary convex radius (analytic.design_family.PAPER_MEMBERS)
_CC_GAP = 0.0059758  # its secondary gap at first touch


class MapDesign(NamedTuple):
    """One design of the map: its kind and its family numbers as ``geometry.family`` text (None: the paper's own
    design of that kind, built by :func:`analytic.designs.design`), and a short label."""

    label: str
    kind: str
    family: str | None


def _cc(R: float, sep: float) -> MapDesign:
    """A close-to-conformal member of relative radius R (mm) at the paper's convex radius and secondary gap."""
    r_concave = -1.0 / (1.0 / _CC_CONVEX - 1.0 / R)
    return MapDesign(f"cc_R{R:g}_s{sep:g}", "close_to_conformal",
                     f"radius_convex={_CC_CONVEX},radius_concave={r_concave:.6g},pair_separation={sep:g},"
                     f"central_gap={_CC_GAP}")


def _sym(r_concave: float, sep: float, gap: float) -> MapDesign:
    return MapDesign(f"sym_Rc{-r_concave:g}_s{sep:g}", "symmetric",
                     f"radius_convex=2.9605,radius_concave={r_concave:g},pair_separation={sep:g},central_gap={gap:g}")


def paper_designs() -> tuple[MapDesign, ...]:
    """The paper's two designs (marked on the map)."""
    return (MapDesign("paper_symmetric", "symmetric", None),
            MapDesign("paper_close_to_conformal", "close_to_conformal", None))


def _grid() -> tuple[MapDesign, ...]:
    cc = tuple(_cc(R, sep) for R in (50.0, 80.0, 120.0, 180.0, 260.0, 400.0, 600.0, 900.0, 1400.0, 2000.0)
               for sep in (0.8, 1.6, 2.4, 3.6, 5.0))
    sym = (_sym(-6.81, 9.0, 1.3), _sym(-8.0, 10.0, 1.3), _sym(-6.81, 10.0, 1.6))
    return (*paper_designs(), *cc, *sym)


@dataclass(frozen=True, kw_only=True)
class ConcaveMapConfig(StudyFolders):
    """What the map runs.

    Attributes:
        designs: The designs (:class:`MapDesign`).
        approaches_conformal, approaches_symmetric: The loads of a design of that kind: approaches past first touch
            (mm, increasing, > 0).
        h_contact: The contact element size over the smallest expected half-width (the shipped concave cases: 0.05).
        growth_scale: The grading's ``growth - 1`` over the case's (1: the case's grading; the FEM band's coarse
            pass, :mod:`workbench.studies.concave_map_band`, doubles it with h_contact: every element x 2).
        past_limit_slope: The interacting-patch model is evaluated past its analytic slope limit
            (:data:`analytic.interacting_patches.MAX_SURFACE_SLOPE`, 0.1) at a design whose pairs tilt at most this
            much from the path, its points' notes saying so (:mod:`workbench.studies.concave_map_interacting`);
            None: refused beyond the analytic limit. 0.15 takes the close-to-conformal members (0.10 to 0.14), not
            the symmetric ones (0.41 to 0.43).
        out, mesh_cache: Output folder and mesh cache (None: the workbench defaults).
    """

    study: ClassVar[str] = "concave_map"

    designs: tuple[MapDesign, ...] = _grid()
    approaches_conformal: tuple[float, ...] = (0.002, 0.005, 0.01, 0.02, 0.04)
    approaches_symmetric: tuple[float, ...] = (0.05, 0.1, 0.2, 0.3, 0.45)
    h_contact: float = 0.05
    growth_scale: float = 1.0
    past_limit_slope: float | None = 0.15
    out: Path | None = None
    mesh_cache: Path | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "designs", tuple(MapDesign(*d) for d in self.designs))
        if not self.designs:
            raise ValueError("designs = () out of range: need at least one design")
        labels = [d.label for d in self.designs]
        if len(set(labels)) != len(labels):
            raise ValueError("designs out of range: two designs share a label")
        for name in ("approaches_conformal", "approaches_symmetric"):
            v = getattr(self, name)
            if not (v and all(math.isfinite(a) and 0 < a <= 0.5 for a in v)
                    and all(b > a for a, b in zip(v, v[1:], strict=False))):
                raise ValueError(f"{name} = {v!r} out of range: need increasing approaches 0 < a <= 0.5 mm")
        if not (math.isfinite(self.h_contact) and 0.01 <= self.h_contact <= 1.0):
            raise ValueError(f"h_contact = {self.h_contact!r} out of range: need 0.01 <= h_contact <= 1")
        if not (math.isfinite(self.growth_scale) and 0.25 <= self.growth_scale <= 3.0):
            raise ValueError(f"growth_scale = {self.growth_scale!r} out of range: need 0.25 <= growth_scale <= 3")
        v = self.past_limit_slope
        if v is not None and not (math.isfinite(v) and 0.1 <= v <= 0.3):
            raise ValueError(f"past_limit_slope = {v!r} out of range: need None or 0.1 <= past_limit_slope <= 0.3 "
                             "(the surface slope; 0.1 is the model's analytic limit)")

    def approaches(self, kind: str) -> tuple[float, ...]:
        return self.approaches_symmetric if kind == "symmetric" else self.approaches_conformal


TINY = {"designs": (paper_designs()[1], _cc(120.0, 2.4)), "approaches_conformal": (0.005, 0.01), "h_contact": 0.5}
"""The end-to-end test: 2 close-to-conformal designs x 2 loads on coarse meshes (machinery, not a map)."""
