"""The FEM run of one concave map design (issue 40, item 3): the shipped concave case of the design's kind with
``geometry.family`` naming the member and ``loading.d`` the map's displacements. Used by the map
(:mod:`workbench.studies.concave_map`) and by its re-evaluation of the interacting-patch model
(:mod:`workbench.studies.concave_map_interacting`), so neither imports the other. Units: mm.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

from workbench.studies.concave_map_config import ConcaveMapConfig, MapDesign

__all__ = ["design_run"]

_CASE_OF = {"close_to_conformal": "close_to_conformal", "symmetric": "concave_symmetric"}


def design_run(md: MapDesign, cfg: ConcaveMapConfig):
    """The run of one map design and its first touch: ``(run, design, DesignMeasure)``. The shipped case of the
    design's kind at ``cfg.h_contact``, with ``geometry.family`` and ``loading.d = d_touch + approaches``
    (ValueError, one line, if the member fails its construction or its LCP check)."""
    import cases
    from analytic.design_family import measure
    from cases.schema import load_case
    from workbench.scenes.concave import scene_design

    case = load_case(Path(cases.__file__).parent / f"{_CASE_OF[md.kind]}.toml")
    run = case.runs(h_contact=cfg.h_contact)[0]
    if cfg.growth_scale != 1.0:  # the band's coarse pass: the grading coarsened with h_contact (concave_budget's rule)
        disc = run.discretisation
        run = dataclasses.replace(run, discretisation=dataclasses.replace(
            disc, growth=1.0 + (disc.growth - 1.0) * cfg.growth_scale))
    geometry = dataclasses.replace(run.geometry, family=md.family)
    des = scene_design(geometry)
    m = measure(des, kind=md.kind)
    ds = tuple(m.d_touch + a for a in cfg.approaches(md.kind))
    run = dataclasses.replace(run, label=md.label, geometry=geometry,
                              loading=dataclasses.replace(run.loading, d=ds))
    return run, des, m
