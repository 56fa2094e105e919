"""The FEM's own band at every point of the concave map (issue 40, item 2: "each model against the FEM with its band").

The map's FEM run of a design (h_contact = 0.05 x the smallest expected half-width, the shipped cases' grid) is
repeated on a grid twice as coarse in every element: h_contact x 2 and the grading ``growth - 1`` x 2 (the error
budget's refinement rule, :mod:`workbench.scenes.concave_budget`). Two grids give Roache's two-grid GCI with an
ASSUMED order (no order can be observed from two values):

    band_q = FS_TWO_GRID |q_coarse - q_fine| / |q_fine| / (r^p - 1),   r = 2,  FS_TWO_GRID = 3,  p = ASSUMED_ORDER

for q = the load P, the largest peak pressure p_max, and each FEM patch's width (patches matched in arc-length
order). p = 1.5 (:data:`workbench.error_budget.FORMAL_ORDER_EDGE`: the square-root edge of the pressure limits the
solution to h^{3/2}; the budget's measured observed orders of contact widths are 1.17 to 1.64) for every quantity:
for P, whose formal order is 2, this errs on the wide side. Where the two grids find a different number of
patches the widths have no band (``None``): the coarse grid does not resolve the patch structure, and no model is
rescued there.

A model counts as within the FEM's band at a point when each error it is compared by (width, p0, and P where it
has one) is at most that quantity's band (the widths: the model's worst width error against the largest patch
band). Such a point counts as within whatever its class (:func:`effective_error`). Pure Python, no dolfinx.
"""

from __future__ import annotations

import math

__all__ = ["ASSUMED_ORDER", "FS_TWO_GRID", "REFINEMENT", "attach_bands", "effective_error", "order_check",
           "point_band", "within_band"]

REFINEMENT = 2.0      # the coarse grid's element size over the map's, everywhere
FS_TWO_GRID = 3.0     # Roache's safety factor for a two-grid GCI (no observed order)
ASSUMED_ORDER = 1.5   # workbench.error_budget.FORMAL_ORDER_EDGE (kept in step by tests/test_concave_map_band.py)


def _gci(fine: float, coarse: float) -> float | None:
    if not (math.isfinite(fine) and math.isfinite(coarse)) or fine == 0:
        return None
    return FS_TWO_GRID * abs(coarse - fine) / abs(fine) / (REFINEMENT**ASSUMED_ORDER - 1.0)


def point_band(fine: dict, coarse: dict) -> dict:
    """The band of one map point from its fine and coarse FEM states (the points' ``P_fem``, ``p_max_fem`` and
    ``fem_patches``): ``{"P", "p0", "width", "n_patches_fine", "n_patches_coarse"}`` (relative; ``width`` is the
    largest patch band, None where the patch counts differ)."""
    fp = sorted(fine["fem_patches"], key=lambda e: e["center"])
    cp = sorted(coarse["fem_patches"], key=lambda e: e["center"])
    width = None
    if fp and len(fp) == len(cp):
        bands = [_gci(2.0 * f["half_width"], 2.0 * c["half_width"]) for f, c in zip(fp, cp, strict=True)]
        width = None if any(b is None for b in bands) else max(bands)
    return {"P": _gci(fine["P_fem"], coarse["P_fem"]), "p0": _gci(fine["p_max_fem"], coarse["p_max_fem"]),
            "width": width, "n_patches_fine": len(fp), "n_patches_coarse": len(cp)}


def within_band(model: dict, band: dict | None) -> bool:
    """Whether a model's errors (``{"P", "width", "p0"}``, None/NaN: not compared) are all within the point's band
    (a quantity without a band rescues nothing)."""
    if band is None:
        return False
    compared = [(model.get(q), band.get(q)) for q in ("P", "width", "p0")]
    compared = [(e, b) for e, b in compared if e is not None and math.isfinite(e)]
    return bool(compared) and all(b is not None and e <= b for e, b in compared)


def effective_error(pt: dict, model: str) -> float:
    """The error the map's rule uses: the model's worst error, or 0 where it is within the FEM's band."""
    e = pt["models"][model]
    worst = math.nan if e["worst"] is None else float(e["worst"])
    return 0.0 if math.isfinite(worst) and e.get("within_fem_band") else worst


def attach_bands(points: list[dict], coarse_points: list[dict]) -> int:
    """Give every point whose design and approach the coarse pass also solved its ``fem_band`` and every model its
    ``within_fem_band``, in place; the others get ``fem_band = None``. Returns how many points got a band."""
    coarse = {(c["design"], round(c["approach_mm"], 9)): c for c in coarse_points}
    n = 0
    for p in points:
        c = coarse.get((p["design"], round(p["approach_mm"], 9)))
        p["fem_band"] = point_band(p, c) if c is not None else None
        n += p["fem_band"] is not None
        for e in p["models"].values():
            e["within_fem_band"] = within_band(e, p["fem_band"])
    return n


def order_check(points: list[dict], middle_points: list[dict], coarse_points: list[dict]) -> dict:
    """The assumed order checked on three grids (the map's, sqrt(2) and 2 times coarser; :func:`workbench.
    error_budget.grid_study`, Roache's three-grid GCI with the observed order) wherever the middle pass solved a
    point and the three grids find the same patches: per quantity ``{"n", "orders" (observed, where asymptotic or
    not), "status" (counts), "covered" (points whose two-grid band is at least the three-grid GCI, or where the
    three-grid study claims no order and the two-grid band is at least its fallback band)}``."""
    from workbench.error_budget import grid_study

    mid = {(c["design"], round(c["approach_mm"], 9)): c for c in middle_points}
    coarse = {(c["design"], round(c["approach_mm"], 9)): c for c in coarse_points}
    out = {q: {"n": 0, "orders": [], "status": {}, "covered": 0} for q in ("P", "p0", "width")}
    h = (1.0, math.sqrt(REFINEMENT), REFINEMENT)
    for p in points:
        key = (p["design"], round(p["approach_mm"], 9))
        if key not in mid or key not in coarse:
            continue
        grids = (p, mid[key], coarse[key])
        values = {"P": [[g["P_fem"]] for g in grids], "p0": [[g["p_max_fem"]] for g in grids]}
        patches = [sorted(g["fem_patches"], key=lambda e: e["center"]) for g in grids]
        if len({len(x) for x in patches}) == 1 and patches[0]:
            values["width"] = [[2.0 * e["half_width"] for e in x] for x in patches]
        for q, per_grid in values.items():
            for k in range(len(per_grid[0])):
                f = tuple(g[k] for g in per_grid)
                study = grid_study(h, f)
                two_grid = _gci(f[0], f[2])
                rec = out[q]
                rec["n"] += 1
                rec["status"][study.status] = rec["status"].get(study.status, 0) + 1
                if math.isfinite(study.observed_order):
                    rec["orders"].append(study.observed_order)
                rec["covered"] += two_grid is not None and two_grid >= study.gci
    return out
