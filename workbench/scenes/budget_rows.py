"""Error-budget rows of the scenes that run their own budget (two bodies): one quantity's grid study in h, its
truncation study in 1/W, the iterative error and round-off, against a theory and an alternative.

Used by :mod:`workbench.scenes.two_body_budget` and :mod:`workbench.scenes.halfplanes_budget` (the block scenes'
budget is :mod:`workbench.scenes.block_budget`'s). Every term is relative; ``uncertainty`` is their sum
(:func:`workbench.error_budget.uncertainty`).
"""

from __future__ import annotations

import dataclasses
import math

from cases.schema import Run
from workbench.error_budget import ROUNDOFF_FLOOR, grid_study, iterative_error, uncertainty
from workbench.scenes.numbers import ESTIMATE, VERDICT, declare

# a row's uncertainty estimates describe the noise of its value; its band verdicts are compared exactly
declare("budget_fields", __name__, observed_order=ESTIMATE, gci=ESTIMATE, truncation=ESTIMATE,
        theory_in_band=VERDICT, alt_in_band=VERDICT)

__all__ = ["budget_row", "with_grid"]


def with_grid(run: Run, *, h: float, W: float, h_coarse: float) -> Run:
    """The run on grid h (h_c / b0, the grading refined with it) and block size W (W / b0, width = height)."""
    growth = 1.0 + (run.discretisation.growth - 1.0) * h / h_coarse
    disc = dataclasses.replace(run.discretisation, h_contact=h, growth=growth)
    geo = dataclasses.replace(run.geometry, width_factor=W, height_factor=W)
    return dataclasses.replace(run, discretisation=disc, geometry=geo)


def budget_row(q: str, levels, widths, by_h, by_W, tight, *, tight_note: str, theory: float, theory_name: str,
               alt_name: str, formal_order: float = 2.0, theory_uncertainty: float | None = None) -> dict:
    """One budget row of quantity ``q`` from its values on the grids (``by_h``: the levels at W_max, fine first;
    ``by_W``: W -> values at the finest level; each a dict with ``q`` and ``"alt " + q``, the alternative theory's
    value) and the tight re-solve's (or None): Richardson in h (``formal_order``), the 1/W correction, the
    iterative error, round-off and ``theory_uncertainty``; ``theory_in_band`` and ``alt_in_band`` against
    ``theory`` and the alternative."""
    values = [v[q] for v in by_h]
    fine = values[0]
    iterative = iterative_error(fine, None if tight is None else tight[q])
    floor = ((iterative or 0.0) + ROUNDOFF_FLOOR) * abs(fine)
    g = grid_study(tuple(levels), tuple(values), reference=theory, floor=floor, formal_order=formal_order)
    w_vals = [by_W[W][q] for W in widths]
    gw = grid_study(tuple(1.0 / W for W in widths), tuple(w_vals), floor=floor)
    if gw.status == "asymptotic":
        correction, truncation, t_status = gw.extrapolated - by_W[widths[-1]][q], gw.gci, "extrapolated in 1/W"
    else:
        correction = 0.0
        truncation = (max(w_vals) - min(w_vals)) / abs(fine)
        t_status = f"spread ({gw.status})"
    x = g.extrapolated + correction
    total = uncertainty(g.gci, truncation, iterative, ROUNDOFF_FLOOR, theory_uncertainty)
    band = total * abs(fine)
    alt = by_h[0][f"alt {q}"]
    def num(v):
        return None if math.isnan(v) else v

    row = {"fine": fine, "extrapolated": x, "observed_order": num(g.observed_order),
           "band_order": num(g.band_order), "gci": g.gci, "status": g.status,
           "truncation": truncation, "truncation_status": t_status, "truncation_correction": correction / abs(fine),
           "iterative": iterative, "roundoff": ROUNDOFF_FLOOR, "uncertainty": total, "theory": theory,
           "theory_name": theory_name,
           "theory_in_band": bool(abs(theory - x) <= band), "error_vs_theory": abs(x - theory),
           "alt_theory": alt_name, "alt_value": alt, "alt_in_band": bool(abs(alt - x) <= band),
           "by_h": {str(h): v for h, v in zip(levels, values, strict=True)},
           "by_W": {str(W): v for W, v in zip(widths, w_vals, strict=True)}}
    if theory_uncertainty is not None:
        row["theory_uncertainty"] = theory_uncertainty
    if iterative is None:
        row["iterative_status"] = tight_note or "not measured"
    return row
