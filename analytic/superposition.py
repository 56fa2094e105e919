"""Superposition of independent Hertz line contacts along the arc length of a concave surface.

The prediction the close-to-conformal paper tests (and its FEM refutes when the pairs are close): each
contact pair i (an LCP solution) is treated as an independent 2D Hertz contact centred at its arc-length
position s_i on the concave boundary, with its own relative radius R_i and load P_i, and the pressures
are summed along s:
    p(s) = sum_i p0_i sqrt(max(1 - (s - s_i)^2 / a_i^2, 0)),
    a_i = sqrt(4 P_i R_i / (pi E*)), p0_i = 2 P_i / (pi a_i)        (:mod:`analytic.hertz`).
Units: mm, N/mm, MPa. Arc length along the undeformed concave boundary (the paper's parameter). The
half-plane idealisation of each patch is assumed; interaction between patches is ignored by
construction, and overlapping ellipses are simply added.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from analytic.hertz import HertzContact, hertz, hertz_pressure

__all__ = ["ContactPair", "Superposition", "split_load", "superpose"]


class ContactPair(NamedTuple):
    """One contact pair on the concave surface.

    Attributes:
        s: Arc-length position of the pair on the undeformed concave boundary (mm).
        R: Relative radius 1/R = 1/R_convex + 1/R_concave (concave negative), R > 0 (mm).
        P: Load carried by this patch, the integral of its pressure (N/mm).
    """

    s: float
    R: float
    P: float


class Superposition(NamedTuple):
    """Summed Hertz pressure (mm, MPa).

    Attributes:
        s: Evaluation positions (mm).
        p: Summed pressure at ``s`` (MPa).
        patches: One :class:`~analytic.hertz.HertzContact` per pair (same order).
        centers: Arc-length centres of the patches (mm).
        overlapping: True if two patches [s_i - a_i, s_i + a_i] overlap (superposition then merely adds).
    """

    s: np.ndarray
    p: np.ndarray
    patches: tuple[HertzContact, ...]
    centers: tuple[float, ...]
    overlapping: bool


def split_load(total: float, n_pairs: int, *, weights: Sequence[float] | None = None) -> tuple[float, ...]:
    """Split a total load (N/mm) among ``n_pairs`` patches.

    Assumption (stated because 2D Hertz has no local load-indentation law to decide it): the split is by
    given non-negative ``weights`` normalised to sum 1, equal shares by default (exact for the paper's
    symmetrical configuration by symmetry; an assumption anywhere else). The loads are patch pressure
    integrals, not force components: for inclined patches the caller converts.
    """
    total = float(total)
    if not (total > 0.0 and math.isfinite(total)):
        raise ValueError(f"total = {total!r} out of range: need 0 < total < inf (N/mm)")
    if int(n_pairs) < 1:
        raise ValueError(f"n_pairs = {n_pairs!r} out of range: need n_pairs >= 1")
    w = np.ones(int(n_pairs)) if weights is None else np.asarray(weights, dtype=float)
    if w.shape != (int(n_pairs),) or np.any(w < 0.0) or not w.sum() > 0.0:
        raise ValueError(f"weights = {weights!r} out of range: need {n_pairs} non-negative values, sum > 0")
    return tuple(float(v) for v in total * w / w.sum())


def superpose(
    pairs: Sequence[ContactPair], *, E_star: float, s: np.ndarray | None = None, n_points: int = 2001
) -> Superposition:
    """Sum independent Hertz distributions of the ``pairs`` along the arc length.

    Args:
        pairs: Contact pairs (position, relative radius, patch load); pairs with P = 0 are skipped.
        E_star: Composite plane-strain modulus (MPa).
        s: Evaluation positions (mm); default: ``n_points`` spanning all patches with a 10 % margin.
        n_points: Number of default positions.
    """
    if len(pairs) == 0:
        raise ValueError("pairs = [] out of range: need at least one contact pair")
    active = [pr for pr in pairs if pr.P != 0.0]
    patches = tuple(hertz(pr.P, pr.R, E_star) for pr in active)
    centers = tuple(float(pr.s) for pr in active)
    if s is None:
        lo = min(c - h.half_width for c, h in zip(centers, patches, strict=True))
        hi = max(c + h.half_width for c, h in zip(centers, patches, strict=True))
        margin = 0.1 * (hi - lo)
        s = np.linspace(lo - margin, hi + margin, int(n_points))
    s = np.asarray(s, dtype=float)
    p = np.zeros_like(s)
    for c, h in zip(centers, patches, strict=True):
        p += hertz_pressure(s, a=h.half_width, p0=h.p0, center=c)
    spans = sorted((c - h.half_width, c + h.half_width) for c, h in zip(centers, patches, strict=True))
    overlapping = any(spans[i + 1][0] < spans[i][1] for i in range(len(spans) - 1))
    return Superposition(s=s, p=p, patches=patches, centers=centers, overlapping=overlapping)
