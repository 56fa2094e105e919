"""Solution verification of one quantity over three grids: Richardson extrapolation, observed order, GCI.

Roache's grid convergence index as ASME V&V 20 and Celik et al. (J. Fluids Eng. 130, 078001, 2008) state it.
Grids 1 (fine), 2, 3 (coarse) with representative sizes h1 < h2 < h3 and values f1, f2, f3;
``r21 = h2/h1``, ``r32 = h3/h2``, ``e21 = f2 - f1``, ``e32 = f3 - f2``, ``s = sign(e32/e21)``. The observed order p
solves ``p = |ln|e32/e21| + q(p)| / ln r21`` with ``q(p) = ln((r21^p - s)/(r32^p - s))`` (fixed point; q = 0 for a
constant ratio). Then
    f_ext = (r21^p f1 - f2) / (r21^p - 1),     GCI_fine = Fs |e21 / f1| / (r21^p - 1),   Fs = 1.25.
``s < 0`` means the sequence oscillates: no order and no extrapolation are claimed (:class:`GridStudy` says
``"oscillating"``), and the band falls back to the spread ``Fs max|f_i - f1| / |f1|``. Differences that do not
shrink on refinement (``|e32/e21| <= ln r32 / ln r21``, no positive order fits) are ``"diverging"``, with the
same fallback. An observed order far
from the expected one (outside [expected/2, 2 expected]) is named ``"not asymptotic"``; a difference at
round-off (``|e21|, |e32| <= 1e-14 |f1|``) is ``"converged"`` with GCI 0. All GCIs are relative.
"""

from __future__ import annotations

import math
from typing import NamedTuple

__all__ = ["FS", "GridStudy", "grid_study"]

FS = 1.25  # safety factor of the GCI for a three-grid study (Roache)
_ROUNDOFF = 1e-14


class GridStudy(NamedTuple):
    """Three-grid verification of one quantity.

    Attributes:
        fine: value on the finest grid.
        extrapolated: Richardson value (the fine value where no order can be claimed).
        observed_order: p, or NaN.
        gci: relative fine-grid uncertainty (dimensionless).
        status: ``"asymptotic"``, ``"not asymptotic"``, ``"oscillating"``, ``"diverging"`` or ``"converged"``.
    """

    fine: float
    extrapolated: float
    observed_order: float
    gci: float
    status: str

    def contains(self, value: float) -> bool:
        """True when ``value`` lies in the band ``extrapolated +- gci |fine|``."""
        return abs(value - self.extrapolated) <= self.gci * abs(self.fine)


def _order(e21: float, e32: float, r21: float, r32: float) -> float:
    s = math.copysign(1.0, e32 / e21)
    p = abs(math.log(abs(e32 / e21))) / math.log(r21)
    for _ in range(200):
        q = math.log((r21**p - s) / (r32**p - s))
        p_new = abs(math.log(abs(e32 / e21)) + q) / math.log(r21)
        if abs(p_new - p) <= 1e-13 * max(1.0, p):
            return p_new
        p = p_new
    return p


def grid_study(h: tuple[float, float, float], f: tuple[float, float, float], *,
               expected_order: float | None = None) -> GridStudy:
    """Verify one quantity from its values ``f`` on three grids of sizes ``h`` (any order; sorted fine first).

    Raises:
        ValueError: fewer or more than three grids, equal or non-positive sizes, or a non-finite value.
    """
    if len(h) != 3 or len(f) != 3:
        raise ValueError(f"grid_study needs exactly 3 grids, got {len(h)} sizes and {len(f)} values")
    if not all(math.isfinite(v) for v in (*h, *f)) or min(h) <= 0:
        raise ValueError(f"grid sizes must be > 0 and values finite, got h = {h}, f = {f}")
    (h1, f1), (h2, f2), (h3, f3) = sorted(zip(h, f, strict=True))
    if not h1 < h2 < h3:
        raise ValueError(f"grid sizes must differ, got {sorted(h)}")
    e21, e32 = f2 - f1, f3 - f2
    scale = max(abs(f1), 1e-300)
    if abs(e21) <= _ROUNDOFF * scale and abs(e32) <= _ROUNDOFF * scale:
        return GridStudy(f1, f1, math.nan, 0.0, "converged")
    if e21 == 0.0 or e32 == 0.0 or e32 / e21 < 0:
        spread = max(abs(f2 - f1), abs(f3 - f1)) / scale
        return GridStudy(f1, f1, math.nan, FS * spread, "oscillating")
    r21, r32 = h2 / h1, h3 / h2
    if abs(e32 / e21) <= math.log(r32) / math.log(r21):
        # f = f_ext + C h^p with p > 0 has |e32/e21| = r21^p (r32^p - 1)/(r21^p - 1) > ln r32 / ln r21: the
        # differences do not shrink on refinement (Celik's |ln| would still return an order for them)
        spread = max(abs(e21), abs(f3 - f1)) / scale
        return GridStudy(f1, f1, math.nan, FS * spread, "diverging")
    p = _order(e21, e32, r21, r32)
    if not (math.isfinite(p) and p > 0):
        return GridStudy(f1, f1, math.nan, FS * max(abs(e21), abs(f3 - f1)) / scale, "not asymptotic")
    rp = r21**p
    f_ext = (rp * f1 - f2) / (rp - 1.0)
    gci = FS * abs(e21 / scale) / (rp - 1.0)
    status = "asymptotic"
    if expected_order is not None and not (0.5 * expected_order <= p <= 2.0 * expected_order):
        status = "not asymptotic"
    return GridStudy(f1, f_ext, p, gci, status)
