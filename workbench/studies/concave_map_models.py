"""The models the concave map compares with the FEM, and the error classes (issue 40, item 3). Pure numpy.

Every model is evaluated at one FEM state (a design at a displacement d, its FEM total load P and its FEM patches:
centre s and half-width along the undeformed concave surface's arc length, peak p_max, load), and gives per FEM
patch a predicted width and overall a peak pressure p0 (and, where it has one, the load at d):

* ``hertz_lcp``: Hertz superposition at the LCP pairs (eq. (5), :mod:`analytic.superposition`): each plausible,
  overlapping LCP pair is given to the FEM patch nearest to it and carries an equal share of that patch's
  MEASURED load; its Hertz patch has 2a of eq. (5) with the pair's relative radius. In 2D Hertz has no
  load-indentation law without a depth convention, so this model is compared at the measured load only (widths,
  p0), never by P(delta).
* ``hertz_intersections``: the same at the intersection-based pairs (:func:`intersection_pairs`: the crossings of
  the undeformed curves that bound one FEM patch's overlap give one pair at their mean arc length with the mean of
  their relative radii, as a DEM code places its contact point between the intersections; the paper's finding is
  that these radii mislead).
* ``interacting``: the interacting-patch model (:mod:`analytic.interacting_patches`: all patches together, the
  real gap, the half-plane's log coupling): widths and p0 at the measured load, and P at the FEM's d (Flamant's
  depth convention with r_ref = the body's depth, the workbench's; the one P(delta) comparison of the map).

A predicted patch's width is the extent of its Hertz patches (their union) or the model's 2b; a FEM patch that no
prediction matches, or a different number of patches (interacting), counts as a width error of 1 (beyond).
Errors are relative: |model - FEM| / FEM. The class of an error is the first edge of
:data:`workbench.studies.concave_map_config.CLASSES` it stays within: ``"1%"``, ``"5%"``, ``"10%"``, else
``"beyond"``; ``"n/a"`` where the model gives nothing (refused, or no loaded patch).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from analytic.hertz import patch_width_eq5
from analytic.superposition import ContactPair as HertzPair
from analytic.superposition import superpose
from workbench.studies.concave_map_config import CLASSES

__all__ = ["CLASS_NAMES", "FemPatch", "ModelErrors", "PredictedPatch", "classify", "compare", "hertz_at_pairs",
           "intersection_pairs"]

CLASS_NAMES = ("1%", "5%", "10%", "beyond")


class FemPatch(NamedTuple):
    """One FEM contact patch: centre and half-width (mm of arc length), peak pressure (MPa), load (N/mm)."""

    center: float
    half_width: float
    p_max: float
    P: float


class PredictedPatch(NamedTuple):
    """A model's patch: its extent (mm of arc length)."""

    lo: float
    hi: float


class ModelErrors(NamedTuple):
    """A model's relative errors at one state (NaN: not compared), the worst of them, its class and a note."""

    P: float
    width: float
    p0: float
    worst: float
    cls: str
    note: str

    def as_dict(self) -> dict:
        return {"P": self.P, "width": self.width, "p0": self.p0, "worst": self.worst, "class": self.cls,
                "note": self.note}


def classify(error: float) -> str:
    """The class of a relative error: ``"1%"``, ``"5%"``, ``"10%"``, ``"beyond"``; ``"n/a"`` for NaN."""
    if not math.isfinite(error):
        return "n/a" if math.isnan(error) else "beyond"
    for edge, name in zip(CLASSES, CLASS_NAMES, strict=False):
        if abs(error) <= edge:
            return name
    return "beyond"


def _rel(model: float, ref: float) -> float:
    return abs(model - ref) / abs(ref) if ref else math.nan


def compare(fem: list[FemPatch], predicted: list[PredictedPatch], p0: float, *, P_model: float = math.nan,
            P_fem: float = math.nan, same_count: bool = False, note: str = "") -> ModelErrors:
    """A model's errors against the FEM patches: the worst patch width (each FEM patch against the predicted patch
    nearest to its centre; none, or with ``same_count`` a different number of patches: 1), the peak pressure
    against the FEM's largest peak, and the load where the model has one (``P_model`` at the FEM's d)."""
    if not fem:
        return ModelErrors(math.nan, math.nan, math.nan, math.nan, "n/a", note or "no FEM patch")
    if not predicted or (same_count and len(predicted) != len(fem)):
        width = 1.0
    else:
        width = 0.0
        for f in fem:
            near = min(predicted, key=lambda q: abs(0.5 * (q.lo + q.hi) - f.center))
            width = max(width, _rel(near.hi - near.lo, 2.0 * f.half_width))
    p0_err = _rel(p0, max(f.p_max for f in fem)) if predicted else 1.0
    P_err = _rel(P_model, P_fem) if math.isfinite(P_model) else math.nan
    worst = max(e for e in (width, p0_err, P_err) if not math.isnan(e))
    return ModelErrors(P_err, width, p0_err, worst, classify(worst), note)


def hertz_at_pairs(fem: list[FemPatch], pairs: list[tuple[float, float]], *, E_star: float
                   ) -> tuple[list[PredictedPatch], float]:
    """Hertz superposition at the pairs ``(s, R)`` (mm): each pair carries an equal share of the measured load of
    the FEM patch nearest to it; per FEM patch, the extent of its pairs' Hertz patches (eq. (5)); and the peak of
    the superposed pressure (MPa). No pair or no FEM patch: ``([], nan)``."""
    pairs = [(s, R) for s, R in pairs if math.isfinite(R) and R > 0]
    if not fem or not pairs:
        return [], math.nan
    owner = [min(range(len(fem)), key=lambda k, s=s: abs(fem[k].center - s)) for s, _ in pairs]
    hertz, predicted = [], []
    for k, f in enumerate(fem):
        mine = [pairs[j] for j in range(len(pairs)) if owner[j] == k]
        if not mine or not f.P > 0:
            continue
        share = f.P / len(mine)
        ext = []
        for s, R in mine:
            a = 0.5 * patch_width_eq5(share, R, E_star)
            hertz.append(HertzPair(s=s, R=R, P=share))
            ext += [s - a, s + a]
        predicted.append(PredictedPatch(min(ext), max(ext)))
    if not hertz:
        return [], math.nan
    lo, hi = min(q.lo for q in predicted), max(q.hi for q in predicted)
    grid = np.linspace(lo, hi, 8001)
    p = superpose(hertz, E_star=E_star, s=grid).p
    return predicted, float(np.max(p))


def intersection_pairs(fem: list[FemPatch], crossings: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """The intersection-based pairs ``(s, R)``: the crossings ``(s, R)`` (mm) with a finite positive relative radius,
    each given to the FEM patch nearest to it; per FEM patch one pair at their mean s with their mean R."""
    crossings = [(s, R) for s, R in crossings if math.isfinite(R) and R > 0]
    if not fem:
        return []
    out = []
    for k in range(len(fem)):
        mine = [c for c in crossings if min(range(len(fem)), key=lambda j, s=c[0]: abs(fem[j].center - s)) == k]
        if mine:
            out.append((sum(c[0] for c in mine) / len(mine), sum(c[1] for c in mine) / len(mine)))
    return out
