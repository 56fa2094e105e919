"""Least-squares semi-elliptical (Hertz-shaped) fit of a sampled contact pressure.

Model: p(s) ~ pm sqrt(max(1 - ((s - c)/a)^2, 0)) with centre c, half-width a and peak pm
(mm, MPa; s is any coordinate along the surface, e.g. the arc length of the close-to-conformal paper).

Measure of misfit (the close-to-conformal paper's measure, "the ratio of the RMS [of the difference
between the distributions] and the maximum pressure"):
    rms         = sqrt(mean over the patch samples of (p_i - fit(s_i))^2)
    rms_over_p0 = rms / max_i p_i
where the *patch samples* are those inside the fitted patch |s_i - c| <= a OR carrying pressure p_i > 0
(the union, so a pressure outside the fitted ellipse and an ellipse over unloaded samples both count).
Samples far outside both are excluded: they would only dilute the RMS. The caller passes the samples
of ONE patch (window them first when several patches exist).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy import optimize

from analytic.hertz import hertz_pressure

__all__ = ["EllipticalFit", "fit_elliptical", "initial_guess"]


class EllipticalFit(NamedTuple):
    """Result of :func:`fit_elliptical` (mm, MPa).

    Attributes:
        center: Fitted centre c.
        half_width: Fitted half-width a (full patch size 2a).
        p_max: Fitted peak pm.
        rms: RMS of (p - fit) over the patch samples (MPa).
        rms_over_p0: rms / max(p) (dimensionless; the paper's measure).
        n_samples: Number of patch samples in the RMS.
    """

    center: float
    half_width: float
    p_max: float
    rms: float
    rms_over_p0: float
    n_samples: int


class _Guess(NamedTuple):
    center: float
    half_width: float
    p_max: float


def initial_guess(s: np.ndarray, p: np.ndarray) -> _Guess:
    """Moments of the sampled pressure: for a semi-ellipse, int p = pi pm a / 2, mean = c, variance = a^2/4."""
    s, p = _check(s, p)
    from scipy import integrate  # imported here: a run that never integrates skips its ~20 ms import

    q = np.clip(p, 0.0, None)
    m0 = integrate.trapezoid(q, s)
    if not m0 > 0.0:
        raise ValueError("p out of range: need a positive pressure integral over the samples")
    c = integrate.trapezoid(q * s, s) / m0
    var = integrate.trapezoid(q * (s - c) ** 2, s) / m0
    a = 2.0 * math.sqrt(max(var, 0.0))
    if not a > 0.0:
        a = max(np.ptp(s[q > 0.0]) / 2.0, np.min(np.diff(s)))
    return _Guess(c, a, 2.0 * m0 / (math.pi * a))


def _check(s: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    s = np.asarray(s, dtype=float).ravel()
    p = np.asarray(p, dtype=float).ravel()
    if s.size != p.size or s.size < 4:
        raise ValueError(f"s, p sizes = {s.size}, {p.size} out of range: need equal sizes >= 4")
    if not (np.all(np.isfinite(s)) and np.all(np.isfinite(p))):
        raise ValueError("s, p out of range: need finite values")
    order = np.argsort(s, kind="stable")
    return s[order], p[order]


def fit_elliptical(s: np.ndarray, p: np.ndarray) -> EllipticalFit:
    """Fit pm sqrt(1 - ((s - c)/a)^2)_+ to samples (s_i, p_i) by least squares (all samples weighted equally).

    Args:
        s: Sample positions (mm), any order.
        p: Pressures (MPa, compression positive) at ``s``.

    Returns:
        :class:`EllipticalFit`; on exact semi-elliptical data the parameters are recovered to round-off.
    """
    s, p = _check(s, p)
    g = initial_guess(s, p)

    def model(x: np.ndarray) -> np.ndarray:
        return hertz_pressure(s, a=x[1], p0=x[2], center=x[0])

    def residual(x: np.ndarray) -> np.ndarray:
        return model(x) - p

    def jac(x: np.ndarray) -> np.ndarray:
        c, a, pm = x
        z = (s - c) / a
        q = np.sqrt(np.clip(1.0 - z * z, 0.0, None))
        inside = q > 0.0
        dq = np.zeros_like(s)
        dq[inside] = 1.0 / q[inside]
        return np.column_stack((pm * z / a * dq, pm * z * z / a * dq, q))

    scale = np.array([g.half_width, g.half_width, g.p_max])
    res = optimize.least_squares(
        residual,
        np.array(g),
        jac=jac,
        x_scale=scale,
        method="lm",
        xtol=1e-15,
        ftol=1e-15,
        gtol=1e-15,
        max_nfev=2000,
    )
    c, a, pm = (float(v) for v in res.x)
    a = abs(a)
    diff = hertz_pressure(s, a=a, p0=pm, center=c) - p
    patch = (np.abs(s - c) <= a) | (p > 0.0)
    rms = float(np.sqrt(np.mean(diff[patch] ** 2)))
    pmax = float(np.max(p))
    return EllipticalFit(
        center=c,
        half_width=a,
        p_max=pm,
        rms=rms,
        rms_over_p0=rms / pmax if pmax > 0.0 else math.inf,
        n_samples=int(patch.sum()),
    )
