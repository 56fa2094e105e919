"""Evaluate a force-law table written by ``workbench forcelaw`` (pure numpy; copy this one file into your code).

The table (``forcelaw.json``) holds, for one particle/concavity design, the vertical load per unit thickness
P (N/mm) at the particle's displacement d (mm along its path, from the design's position; first touch at
``d_touch``), and the contact patches (centre x, half-width b in mm, peak pressure p0 in MPa, load share). It is
valid from first touch to the last row only: that range is the interacting-patch model's analytic validity limit
(see the table's ``note``), and :meth:`ForceLaw.load` refuses beyond it rather than extrapolate.

Interpolation: P(d) by the monotone piecewise-cubic Hermite interpolant of Fritsch and Carlson (it keeps P
monotone and C1, so the contact stiffness dP/dd is continuous); the patches linearly, slot by slot (a slot that
is empty at either neighbouring row gives nan). Units: mm, N/mm, MPa.

    law = ForceLaw.from_json("forcelaw.json")
    P = law.load(d)             # N/mm, 0 before first touch
    k = law.stiffness(d)        # N/mm per mm
"""

from __future__ import annotations

import json

import numpy as np

__all__ = ["ForceLaw"]


class ForceLaw:
    """P(d) and the patches of one design, from the rows of its table (d increasing, P[0] = 0 at first touch)."""

    def __init__(self, d, P, patches=None):
        self.d = np.asarray(d, dtype=float)
        self.P = np.asarray(P, dtype=float)
        if self.d.ndim != 1 or self.d.size < 2 or self.d.shape != self.P.shape or np.any(np.diff(self.d) <= 0):
            raise ValueError("d, P out of range: need two equal-length rows of at least 2 values, d increasing")
        self.patches = patches  # list (per row) of lists of (x, b, p0, share), or None
        self.slopes = _pchip_slopes(self.d, self.P)

    @classmethod
    def from_json(cls, path) -> ForceLaw:
        with open(path, encoding="utf-8") as f:
            table = json.load(f)
        rows = table["rows"]
        return cls([r["d_mm"] for r in rows], [r["P_N_per_mm"] for r in rows],
                   [[(p["x_mm"], p["b_mm"], p["p0_MPa"], p["share"]) for p in r["patches"]] for r in rows])

    @property
    def d_touch(self) -> float:
        return float(self.d[0])

    @property
    def d_max(self) -> float:
        return float(self.d[-1])

    def _interval(self, d):
        d = np.asarray(d, dtype=float)
        if np.any(d > self.d_max) or np.any(~np.isfinite(d)):
            raise ValueError(f"d out of range: need d <= {self.d_max:.6g} mm (the table's validity limit)")
        i = np.clip(np.searchsorted(self.d, d, side="right") - 1, 0, self.d.size - 2)
        return d, i

    def load(self, d):
        """P (N/mm) at d (mm): 0 before first touch, the Hermite interpolant up to the last row, refused beyond."""
        d, i = self._interval(d)
        h = self.d[i + 1] - self.d[i]
        t = (d - self.d[i]) / h
        h00, h10, h01, h11 = 2 * t**3 - 3 * t**2 + 1, t**3 - 2 * t**2 + t, -2 * t**3 + 3 * t**2, t**3 - t**2
        P = h00 * self.P[i] + h10 * h * self.slopes[i] + h01 * self.P[i + 1] + h11 * h * self.slopes[i + 1]
        return np.where(d <= self.d_touch, 0.0, P)

    def stiffness(self, d):
        """dP/dd (N/mm per mm) at d: 0 before first touch."""
        d, i = self._interval(d)
        h = self.d[i + 1] - self.d[i]
        t = (d - self.d[i]) / h
        d00, d10, d01, d11 = 6 * t**2 - 6 * t, 3 * t**2 - 4 * t + 1, -6 * t**2 + 6 * t, 3 * t**2 - 2 * t
        k = (d00 * self.P[i] + d01 * self.P[i + 1]) / h + d10 * self.slopes[i] + d11 * self.slopes[i + 1]
        return np.where(d <= self.d_touch, 0.0, k)

    def patch_table(self, d: float):
        """[(x, b, p0, share), ...] at d, each slot linearly interpolated (nan where a neighbour lacks it)."""
        if self.patches is None:
            raise ValueError("patches out of range: this table has no patches")
        dd, i = self._interval(float(d))
        i = int(i)
        w = float((dd - self.d[i]) / (self.d[i + 1] - self.d[i]))
        a, b = self.patches[i], self.patches[i + 1]
        out = []
        for k in range(max(len(a), len(b))):
            if k < len(a) and k < len(b):
                out.append(tuple((1 - w) * u + w * v for u, v in zip(a[k], b[k], strict=True)))
            else:
                out.append((np.nan,) * 4)
        return out


def _pchip_slopes(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Fritsch-Carlson slopes (the monotone Hermite interpolant; scipy's PchipInterpolator chooses the same)."""
    h = np.diff(x)
    delta = np.diff(y) / h
    m = np.zeros_like(y)
    if x.size == 2:
        return np.full_like(y, delta[0])
    w1, w2 = 2 * h[1:] + h[:-1], h[1:] + 2 * h[:-1]
    with np.errstate(divide="ignore", invalid="ignore"):
        harm = (w1 + w2) / (w1 / delta[:-1] + w2 / delta[1:])
    same = np.sign(delta[:-1]) * np.sign(delta[1:]) > 0
    m[1:-1] = np.where(same, harm, 0.0)
    m[0] = _end_slope(h[0], h[1], delta[0], delta[1])
    m[-1] = _end_slope(h[-1], h[-2], delta[-1], delta[-2])
    return m


def _end_slope(h0, h1, d0, d1):
    s = ((2 * h0 + h1) * d0 - h0 * d1) / (h0 + h1)
    if np.sign(s) != np.sign(d0):
        return 0.0
    if np.sign(d0) != np.sign(d1) and abs(s) > abs(3 * d0):
        return 3 * d0
    return s
