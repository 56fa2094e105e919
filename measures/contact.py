"""Measures of a sampled contact pressure (numpy only; no dolfinx): patches, edges, moments, RMS.

The one definition of each measure, shared by the FEM pipeline (:mod:`fem.postprocess`, the block and
concave scenes, the error budget) and the scorer of external results (:mod:`workbench.external.score`), so a
pressure scored from a file and the same pressure inside the solver give the same numbers.

Conventions (units: mm, N/mm, MPa): pressure p >= 0 compressive; ``q`` is the pressure argument
(``p = [q]_+``; the contact law's argument inside the FEM, ``q = p`` for an external pressure) whose zero
crossings locate the contact edges; ``s`` is the surface coordinate (the material abscissa X1 on a block top);
``weight`` is the quadrature weight of a sample (mm), so ``sum(weight * p)`` is the load carried.

Half models: samples live on x >= 0; :func:`find_patches` mirrors patches touching ``s = 0`` (full-body centre,
half-width, peak) and doubles their load when ``half=True``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

__all__ = ["SurfaceSamples", "Patch", "contact_edges", "find_patches", "moment_half_width", "rms_error",
           "trapezoid_weights"]


class SurfaceSamples(NamedTuple):
    """Samples at the facet quadrature points of Gamma_c, gathered and sorted by ``s``.

    Attributes:
        s: (n,) surface coordinate (mm): material abscissa X1.
        X: (n, 2) material position (mm).
        x: (n, 2) current position X + u (mm).
        p: (n,) contact pressure from the contact law (MPa, >= 0).
        q: (n,) pressure argument, p = [q]_+ (MPa).
        sigma_nn: (n,) stress-based pressure -n_c . sigma n_b (MPa).
        gap: (n,) gap g(u) (mm, > 0 open).
        weight: (n,) quadrature weight times facet length (mm): sum(weight * p) = int p ds on the model.
    """

    s: np.ndarray
    X: np.ndarray
    x: np.ndarray
    p: np.ndarray
    q: np.ndarray
    sigma_nn: np.ndarray
    gap: np.ndarray
    weight: np.ndarray


class Patch(NamedTuple):
    """A connected contact region (full-body quantities; mm, MPa, N/mm)."""

    center: float
    half_width: float
    p_max: float
    P: float


def _edge(s_in2, s_in1, q_in2, q_in1, s_out, q_out):
    """Edge between the last active sample (s_in1) and the first inactive one (s_out).

    Square-root edge model: near a smooth incomplete-contact edge ``p ~ sqrt(dist)``, so ``q^2`` is linear; it is
    extrapolated from the two outermost active samples. Falls back to the linear zero crossing of q when the
    extrapolation leaves ``[s_in1, s_out]`` or there is one active sample only.
    """
    linear = s_in1 + (s_out - s_in1) * q_in1 / (q_in1 - q_out)
    if s_in2 is None or not q_in2 > q_in1:
        return linear
    e = s_in1 + (s_in1 - s_in2) * q_in1**2 / (q_in2**2 - q_in1**2)
    lo, hi = min(s_in1, s_out), max(s_in1, s_out)
    return e if lo <= e <= hi else linear


def contact_edges(s: np.ndarray, q: np.ndarray) -> list[tuple[float, float, int, int]]:
    """Active runs (q > 0) with edges at the zero crossing of the pressure argument between samples.

    Edges use the square-root edge model (see :func:`_edge`). Returns a list of (left edge, right edge, first
    index, last index); an edge at the end of the sample range is the end sample's coordinate.
    """
    active = q > 0.0
    runs = []
    i, n = 0, len(s)
    while i < n:
        if not active[i]:
            i += 1
            continue
        j = i
        while j + 1 < n and active[j + 1]:
            j += 1
        two = j > i
        left = s[i] if i == 0 else _edge(s[i + 1] if two else None, s[i], q[i + 1] if two else None, q[i],
                                         s[i - 1], q[i - 1])
        right = s[j] if j == n - 1 else _edge(s[j - 1] if two else None, s[j], q[j - 1] if two else None, q[j],
                                              s[j + 1], q[j + 1])
        runs.append((float(left), float(right), i, j))
        i = j + 1
    return runs


def find_patches(samples: SurfaceSamples, *, half: bool = False) -> list[Patch]:
    """Connected contact regions, full-body quantities (a half model's patch at s = 0 is mirrored).

    For ``half=True`` a patch whose active run starts at the first sample (s ~ 0) is mirrored: centre 0,
    half-width = its right edge, load doubled; other patches are reported once (their mirror images are
    implied) with their own load.
    """
    patches = []
    for left, right, i, j in contact_edges(samples.s, samples.q):
        P = float(np.sum(samples.weight[i:j + 1] * samples.p[i:j + 1]))
        p_max = float(np.max(samples.p[i:j + 1]))
        if half and i == 0:
            patches.append(Patch(center=0.0, half_width=right, p_max=p_max, P=2.0 * P))
        else:
            patches.append(Patch(center=0.5 * (left + right), half_width=0.5 * (right - left), p_max=p_max, P=P))
    return patches


def moment_half_width(x: np.ndarray, p: np.ndarray, weight: np.ndarray, *, center: float | None = None) -> float:
    """sqrt(M2/M0) of the sampled pressure ``p`` (MPa) at ``x`` (mm) with quadrature ``weight`` (mm).

    A half model (samples x >= 0, symmetric about x = 0) passes ``center=0.0``: M2/M0 of the half is that of
    the full body. Otherwise the centroid c = M1/M0 is used.
    """
    w = np.asarray(weight) * np.asarray(p)
    M0 = float(np.sum(w))
    if not M0 > 0:
        return math.nan
    c = float(np.sum(w * x)) / M0 if center is None else center
    return math.sqrt(float(np.sum(w * (x - c) ** 2)) / M0)



def rms_error(x: np.ndarray, p: np.ndarray, p_th: np.ndarray, *, center: float, half_width: float,
              p_ref: float) -> float:
    """sqrt(mean over the sampled patch region of (p - p_th)^2) / p_ref (trapezoidal mean in x).

    Non-finite theory values (the wedge apex) are dropped.
    """
    order = np.argsort(x)
    x, p, p_th = x[order], p[order], p_th[order]
    keep = (np.abs(x - center) <= 1.05 * half_width) & np.isfinite(p_th)
    x, d2 = x[keep], (p[keep] - p_th[keep]) ** 2
    if x.size < 2 or x[-1] <= x[0]:
        return math.nan
    return float(math.sqrt(np.trapezoid(d2, x) / (x[-1] - x[0])) / p_ref)


def trapezoid_weights(x: np.ndarray) -> np.ndarray:
    """Trapezoid-rule weights (mm) of samples at sorted abscissae ``x`` (mm): ``sum(w * f)`` = the trapezoid
    integral of f over [x[0], x[-1]] (for samples of an external code, which gives no quadrature weights)."""
    x = np.asarray(x, dtype=float)
    w = np.zeros_like(x)
    if x.size >= 2:
        dx = np.diff(x)
        w[:-1] += 0.5 * dx
        w[1:] += 0.5 * dx
    return w
