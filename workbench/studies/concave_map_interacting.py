"""The interacting-patch model at the concave map's points, continued along each design's path (issue 40, item 3).

:class:`InteractingTrack` follows one design from first touch through its map loads in the order of d: the state
at each load is continued from the previous one in steps of at most :data:`STEP` mm (:func:`analytic.force_law.
_continued`, the continuation ``workbench forcelaw`` uses; a cold solve at the larger loads did not converge at 38
of the first run's 275 points), and the state at the FEM's measured load P starts from the state at d. The model
gives the patches and peak at P and the load P(d) at the FEM's d (Flamant's depth convention, r_ref = the body's
depth). A design whose pairs face different directions is refused (the static check of :mod:`analytic.force_law`);
a state past the analytic validity limit is compared and its note names the limit.

Past the analytic slope limit (``past_limit``, the map's ``ConcaveMapConfig.past_limit_slope``): a design whose
pairs tilt beyond :data:`analytic.interacting_patches.MAX_SURFACE_SLOPE` but at most ``past_limit`` is evaluated
anyway, and every note of its points starts with :data:`PAST_LIMIT_NOTE`. The analytic limit keeps its meaning
(the model is not claimed there); the map measures whether it is conservative. A tilt beyond ``past_limit``
(the symmetric members, 0.41 to 0.43: pairs facing directions 22 deg apart) stays refused.

:func:`reevaluate` recomputes this model on the points of a solved map (``workbench concave-map --reevaluate``):
the FEM states are the stored ones, no FEM runs.
"""

from __future__ import annotations

import math

from workbench.studies.concave_map_models import FemPatch, ModelErrors, PredictedPatch, compare
from workbench.studies.concave_map_rule import PAST_LIMIT_NOTE

__all__ = ["PAST_LIMIT_NOTE", "STEP", "InteractingTrack", "reevaluate"]

STEP = 0.002  # mm: the largest continuation step (workbench forcelaw's default row spacing)


class InteractingTrack:
    """The interacting-patch model along one design's path (module docstring)."""

    def __init__(self, des, m, *, E_star: float, nu: float, depth: float, past_limit: float | None = None) -> None:
        from analytic.force_law import _static_validity, design_gap, pair_tilts

        self.des, self.m, self.E_star, self.nu, self.depth = des, m, E_star, nu, depth
        why = _static_validity(m)
        tilt = max(t for _, t in pair_tilts(m))
        self.past = f"{PAST_LIMIT_NOTE} ({why})" if why and past_limit is not None and tilt <= past_limit else ""
        self.refused = f"outside the model: {why}" if why and not self.past else ""
        self.dg = None if self.refused else design_gap(des, m)
        self.prev, self.prev_d = None, m.d_touch

    def _to(self, d: float):
        """The state at d, continued from the last one in n steps of at most STEP; where that fails, once more from
        the same state in 4 n + 1 steps (other intermediate states: a patch born exactly at an intermediate state
        can fail the model's interpenetration check, cc_R900_s3.6 at d_touch + 0.00833 mm)."""
        prev, prev_d = self.prev, self.prev_d
        try:
            return self._steps(d, retry=False)
        except ValueError:
            self.prev, self.prev_d = prev, prev_d
            return self._steps(d, retry=True)

    def _steps(self, d: float, *, retry: bool):
        import numpy as np

        from analytic.force_law import _continued

        n = max(1, math.ceil((d - self.prev_d) / STEP - 1e-9))
        n = 4 * n + 1 if retry else n
        for dd in np.linspace(self.prev_d, d, n + 1)[1:]:
            self.prev = _continued(self.dg, self.prev, float(dd), d0=self.prev_d, E_star=self.E_star,
                                   depth=self.depth, n_terms=32)
            self.prev_d = float(dd)
        return self.prev

    def compare(self, fem: list[FemPatch], *, d: float, P: float) -> ModelErrors:
        """The model's errors against the FEM state (patches, load P) at d (loads in increasing d)."""
        import numpy as np

        from analytic.force_law import validity
        from analytic.interacting_patches import solve_patches

        if self.refused or not P > 0:
            note = self.refused or "no load"
            return compare([], [], math.nan, note=note)._replace(note=note)
        try:
            at_d = self._to(d)
            start = [(pt.centre, pt.half_width) for pt in at_d.patches] or None
            at_P = solve_patches(self.dg.gap, E_star=self.E_star, r_ref=self.depth, P=P, nu=self.nu, n_terms=32,
                                 start=start)
        except (RuntimeError, ValueError) as exc:
            self.prev, self.prev_d = None, d  # the next load starts afresh from here
            note = f"model not solved: {' '.join(str(exc).split())[:200]}" + (f"; {self.past}" if self.past else "")
            return compare([], [], math.nan, note=note)._replace(note=note)
        curve = self.des.concave

        def s_of(x: float) -> float:
            y = float(self.dg.concave.y(np.array([x]))[0][0])
            return float(curve.arc_length(curve.project(np.array([[x, y]])).t)[0])

        patches = [PredictedPatch(s_of(pt.centre - pt.half_width), s_of(pt.centre + pt.half_width))
                   for pt in at_P.patches]
        p0 = max((pt.p0 for pt in at_P.patches), default=math.nan)
        limit = validity(at_P, self.dg, depth=self.depth)
        note = "; ".join(t for t in (self.past, f"outside the model's analytic limit: {limit}" if limit else "") if t)
        return compare(fem, patches, p0, P_model=at_d.P, P_fem=P, same_count=True, note=note)


def reevaluate(points: list[dict], cfg, *, progress=print) -> int:
    """Recompute the interacting-patch model (and each point's best model) on a solved map's points in place, from
    their stored FEM states, for the designs of ``cfg`` (the others are left as stored); returns the number of
    designs re-evaluated. ``cfg``: the map's :class:`workbench.studies.concave_map_config.ConcaveMapConfig` (its
    designs, its cases for the material, its ``past_limit_slope``)."""
    from analytic import materials
    from workbench.studies.concave_map_config import MapDesign
    from workbench.studies.concave_map_design import design_run

    want = {d.label for d in cfg.designs}
    by: dict[str, list[dict]] = {}
    for p in points:
        if p["design"] in want:
            by.setdefault(p["design"], []).append(p)
    for i, (label, pts) in enumerate(by.items()):
        md = MapDesign(label, pts[0]["kind"], pts[0]["family"])
        run, des, m = design_run(md, cfg)
        E_star = materials.plane_strain_modulus(run.material.E, run.material.nu)
        track = InteractingTrack(des, m, E_star=E_star, nu=run.material.nu, depth=m.numbers.depth,
                                 past_limit=cfg.past_limit_slope)
        for p in sorted(pts, key=lambda q: q["d_mm"]):
            fem = [FemPatch(e["center"], e["half_width"], e["p_max"], e["P"]) for e in p["fem_patches"]]
            p["models"]["interacting"] = track.compare(fem, d=p["d_mm"], P=p["P_fem"]).as_dict()
            ranked = sorted((e["worst"], name) for name, e in p["models"].items()
                            if e["worst"] is not None and math.isfinite(e["worst"]))
            p["best_model"] = ranked[0][1] if ranked else None
            p["best_class"] = p["models"][p["best_model"]]["class"] if ranked else "n/a"
            p["best_error"] = ranked[0][0] if ranked else math.nan
        progress(f"[{i + 1}/{len(by)}] {label}: interacting-patch model re-evaluated")
    return len(by)
