"""Exact integrals of the half-plane kernels against the bounded Chebyshev pressure basis (numpy only).

A pressure on the patch |x - c| < b is written, with x = c + b t, t = cos(phi), as the bounded series

    p(x) = sqrt(1 - t^2) sum_{n >= 0} alpha_n U_n(t) = sum_n alpha_n sin((n + 1) phi)        (|t| < 1)

(U_n Chebyshev of the second kind: bounded, vanishing like a square root at both ends; n = 0 is Hertz's
semi-ellipse). Everything below follows from one classical expansion (u = cos theta, w = t + sign(t) sqrt(t^2-1)
for |t| > 1, w = exp(i phi) for |t| <= 1):

    ln|t - cos theta| = ln(|w| / 2) - 2 sum_{m >= 1} Re(w^-m) cos(m theta) / m,

so that lambda_m(t) := (1/pi) int_{-1}^{1} ln|t - u| T_m(u) / sqrt(1 - u^2) du is
    |t| <= 1:  lambda_0 = -ln 2,              lambda_m = -T_m(t) / m;
    |t| > 1:   lambda_0 = -ln 2 - ln|z|,      lambda_m = -z^m / m,     z = t - sign(t) sqrt(t^2 - 1) = 1/w,
and its t-derivative (the Cauchy kernel) lambda'_0 = 0, lambda'_m = -U_{m-1}(t) inside, and
lambda'_m = sign(t) z^m / sqrt(t^2 - 1) (m >= 0) outside. With sqrt(1-u^2) U_n(u) = (T_n(u) - T_{n+2}(u)) /
(2 sqrt(1 - u^2)):

    (1/pi) int_{-1}^{1} sqrt(1 - u^2) U_n(u) ln|t - u| du = (lambda_n(t) - lambda_{n+2}(t)) / 2    =: Lambda_n(t)
    (1/pi) PV int_{-1}^{1} sqrt(1 - u^2) U_n(u) / (t - u) du = Lambda'_n(t)      (= T_{n+1}(t) for |t| < 1)

and the load int p dx = (pi/2) b alpha_0. Every integral is exact (no quadrature): the Hertz distribution
(alpha = (alpha_0, 0, ...)) is represented with no discretisation error. Tested against adaptive quadrature in
``tests/test_interacting_patches.py``.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["cauchy_matrix", "chebyshev_coefficients", "gauss_chebyshev_nodes", "log_matrix", "series_pressure"]


def gauss_chebyshev_nodes(n: int) -> tuple[np.ndarray, np.ndarray]:
    """The n Gauss-Chebyshev angles theta_i = pi (i + 1/2)/n and nodes t_i = cos(theta_i), t decreasing."""
    theta = math.pi * (np.arange(n) + 0.5) / n
    return theta, np.cos(theta)


def chebyshev_coefficients(n: int) -> np.ndarray:
    """(n, n) matrix C with f_m = sum_i C[m, i] F(t_i): the Chebyshev (first kind) coefficients of the degree
    n - 1 interpolant of F at the Gauss-Chebyshev nodes (discrete cosine transform, f_0 halved)."""
    theta, _ = gauss_chebyshev_nodes(n)
    C = (2.0 / n) * np.cos(np.multiply.outer(np.arange(n), theta))
    C[0] *= 0.5
    return C


def _lambda(t: np.ndarray, m_max: int, *, derivative: bool) -> np.ndarray:
    """lambda_m(t) (or lambda'_m(t)) for m = 0 .. m_max, shape t.shape + (m_max + 1,) (module docstring)."""
    t = np.asarray(t, dtype=float)
    m = np.arange(m_max + 1)
    out = np.empty(t.shape + (m_max + 1,))
    inside = np.abs(t) <= 1.0
    ti = t[inside]
    phi = np.arccos(np.clip(ti, -1.0, 1.0))
    if derivative:
        with np.errstate(divide="ignore", invalid="ignore"):
            s = np.sin(phi)
            u = np.sin(np.multiply.outer(phi, m)) / s[:, None]  # U_{m-1}(t) = sin(m phi)/sin(phi)
        out[inside] = -u
        out[inside, 0] = 0.0
    else:
        with np.errstate(divide="ignore"):
            val = -np.cos(np.multiply.outer(phi, m)) / np.where(m == 0, 1, m)
        val[:, 0] = -math.log(2.0)
        out[inside] = val
    to = t[~inside]
    if to.size:
        sg = np.sign(to)
        root = np.sqrt(to * to - 1.0)
        z = sg / (np.abs(to) + root)  # = t - sign(t) sqrt(t^2 - 1), without the cancellation at large |t|
        zm = z[:, None] ** m
        if derivative:
            out[~inside] = (sg / root)[:, None] * zm
        else:
            val = -zm / np.where(m == 0, 1, m)
            with np.errstate(divide="ignore"):  # |t| = inf (a degenerate iterate of a root search): lambda_0 = -inf
                val[:, 0] = -math.log(2.0) - np.log(np.abs(z))
            out[~inside] = val
    return out


def log_matrix(t: np.ndarray, n_terms: int) -> np.ndarray:
    """Lambda_n(t) = (1/pi) int sqrt(1-u^2) U_n(u) ln|t - u| du, n = 0 .. n_terms - 1, shape t.shape + (n_terms,)."""
    lam = _lambda(t, n_terms + 1, derivative=False)
    return 0.5 * (lam[..., :n_terms] - lam[..., 2:n_terms + 2])


def cauchy_matrix(t: np.ndarray, n_terms: int) -> np.ndarray:
    """Lambda'_n(t) = (1/pi) PV int sqrt(1-u^2) U_n(u) / (t - u) du, n = 0 .. n_terms - 1 (= T_{n+1}(t) inside)."""
    lam = _lambda(t, n_terms + 1, derivative=True)
    return 0.5 * (lam[..., :n_terms] - lam[..., 2:n_terms + 2])


def series_pressure(t: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """sqrt(1 - t^2) sum_n alpha_n U_n(t) = sum_n alpha_n sin((n + 1) phi) for |t| < 1, 0 outside."""
    t = np.asarray(t, dtype=float)
    phi = np.arccos(np.clip(t, -1.0, 1.0))
    val = np.sin(np.multiply.outer(phi, np.arange(1, alpha.size + 1))) @ alpha
    return np.where(np.abs(t) < 1.0, val, 0.0)
