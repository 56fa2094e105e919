"""Log-log rate fits shared by the studies: one least-squares line in one place.

``fit_rate`` is the convergence rate of an error against a mesh measure (scikit-fem style: the slope of
log(error) against log(h) over the finest levels); ``fit_exponent`` is the cost exponent of a time against
the problem size (``t = c ndofs^k``), the same fit read the other way round. Pure numpy, no dolfinx.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

__all__ = ["N_FINEST", "ExponentFit", "RateFit", "fit_exponent", "fit_rate"]

N_FINEST = 3  # rates are fitted over the finest three levels (STYLE.md, example 7)


class RateFit(NamedTuple):
    """Least-squares line log(err) = intercept + slope log(x) over the finest points.

    Attributes:
        slope: Observed rate (err ~ x^slope): > 0 against h, < 0 against ndofs.
        intercept: Natural-log intercept.
        n_points: Number of points fitted.
        max_residual: Largest |log err - fit| over the fitted points (0 for an exact power law).
    """

    slope: float
    intercept: float
    n_points: int
    max_residual: float


def fit_rate(x: Sequence[float], err: Sequence[float], *, n_finest: int = N_FINEST) -> RateFit:
    """Slope of log(err) against log(x) fitted over the last ``n_finest`` points (scikit-fem style).

    Args:
        x: Mesh measure of each level, ordered coarse to fine (h_c decreasing or ndofs increasing), > 0.
        err: Error of each level (> 0 and finite on the fitted levels).
        n_finest: Number of finest levels fitted, >= 2.

    Raises:
        ValueError: Mismatched or too short inputs, non-monotone x, or a non-positive/non-finite value.
    """
    x, err = np.asarray(x, dtype=float), np.asarray(err, dtype=float)
    if int(n_finest) != n_finest or n_finest < 2:
        raise ValueError(f"n_finest must be an integer >= 2, got {n_finest!r}")
    if x.ndim != 1 or x.shape != err.shape:
        raise ValueError(f"x and err must be 1D of equal length, got shapes {x.shape} and {err.shape}")
    if x.size < n_finest:
        raise ValueError(f"x has {x.size} levels; need at least n_finest = {n_finest}")
    xs, es = x[-n_finest:], err[-n_finest:]
    if not np.all(np.isfinite(xs) & (xs > 0)):
        raise ValueError(f"x must be finite and > 0 on the fitted levels, got {xs.tolist()}")
    dx = np.diff(xs)
    if not (np.all(dx > 0) or np.all(dx < 0)):
        raise ValueError(f"x must be strictly monotone (coarse to fine), got {xs.tolist()}")
    if not np.all(np.isfinite(es) & (es > 0)):
        raise ValueError(f"err must be finite and > 0 on the fitted levels, got {es.tolist()}")
    lx, le = np.log(xs), np.log(es)
    slope, intercept = np.polyfit(lx, le, 1)
    resid = float(np.max(np.abs(le - (intercept + slope * lx))))
    return RateFit(float(slope), float(intercept), int(n_finest), resid)


class ExponentFit(NamedTuple):
    """Power law ``t = c ndofs^exponent`` fitted by least squares in log-log.

    Attributes:
        exponent: fitted exponent (1 = linear cost).
        prefactor: c (s).
        n_points: number of sizes fitted.
        max_residual: largest |log t - fit| over the fitted sizes.
    """

    exponent: float
    prefactor: float
    n_points: int
    max_residual: float


def fit_exponent(ndofs: Sequence[float], times: Sequence[float], *, n_last: int | None = None) -> ExponentFit:
    """Fit ``t = c ndofs^k`` over the ``n_last`` largest sizes (all by default), with :func:`fit_rate`.

    Args:
        ndofs: sizes, strictly increasing, > 0.
        times: times (s), > 0.
        n_last: number of largest sizes fitted, >= 2 (default: all).

    Raises:
        ValueError: fewer than two sizes, non-increasing sizes or a non-positive value.
    """
    n = np.asarray(ndofs, dtype=float)
    if n.ndim != 1 or n.size < 2:
        raise ValueError(f"ndofs must hold >= 2 sizes, got {n.size}")
    if not np.all(np.diff(n) > 0):
        raise ValueError(f"ndofs must be strictly increasing, got {n.tolist()}")
    f = fit_rate(n, times, n_finest=n.size if n_last is None else n_last)
    return ExponentFit(f.slope, float(math.exp(f.intercept)), f.n_points, f.max_residual)
