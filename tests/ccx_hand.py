"""Hand computations for the independent CalculiX models (tests/ccx_independent*.py), sharing no code with the
workbench: a small .frd parser and the measures written out from their definitions.

* :func:`parse_frd`: node coordinates and the last block of every result name of an ASCII .frd (short format:
  ``-1`` records, the node number in columns 4-13, then 12-character fields);
* :func:`reference_pressure`: CPRESS (a force per current length) times the surface stretch d(X + u1)/dX by central
  differences (one-sided at the ends): a force per reference length, on a flat surface y = 0;
* :func:`mirror`, :func:`trapezoid`, :func:`edge`, :func:`moment_half_width`, :func:`rms`: a half model mirrored
  about x = 0, the trapezoid rule, the square-root edge model (q^2 linear through the two outermost loaded
  samples, extrapolated to zero, else the linear zero crossing), 2 sqrt(M2/M0), and the RMS of p - p_th over
  |x| <= 1.05 w (trapezoid mean, non-finite theory values dropped) over p_ref.

Units mm, N/mm, MPa.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

__all__ = ["parse_frd", "reference_pressure", "mirror", "trapezoid", "edge", "moment_half_width", "rms",
           "write_csv"]


def parse_frd(path: Path) -> tuple[dict, dict]:
    """({node: (x, y)}, {name: {node: [values]}}) of the LAST block of every result name."""
    coords, blocks = {}, {}
    name, cur, in_nodes = None, None, False
    for line in path.read_text().splitlines():
        if line.startswith("    2C"):
            in_nodes = True
        elif line.startswith(" -4"):
            name, cur = line.split()[1], {}
        elif line.startswith(" -1") and (in_nodes or cur is not None):
            node = int(line[3:13])
            vals = [float(line[13 + 12 * k:25 + 12 * k]) for k in range((len(line) - 13) // 12)]
            if in_nodes:
                coords[node] = (vals[0], vals[1])
            else:
                cur[node] = vals
        elif line.startswith(" -3"):
            if cur is not None:
                blocks[name] = cur
            in_nodes, name, cur = False, None, None
    return coords, blocks


def reference_pressure(coords: dict, blocks: dict, nodes: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """(X, p) at the given surface nodes (left to right on y = 0): p = CPRESS d(X + u1)/dX."""
    X = np.array([coords[n][0] for n in nodes])
    u1 = np.array([blocks["DISP"][n][0] for n in nodes])
    cp = np.array([blocks["CONTACT"].get(n, [0.0] * 4)[3] for n in nodes])  # COPEN, CSLIP1, CSLIP2, CPRESS
    x = X + u1
    stretch = np.empty_like(X)
    stretch[1:-1] = (x[2:] - x[:-2]) / (X[2:] - X[:-2])
    stretch[0] = (x[1] - x[0]) / (X[1] - X[0])
    stretch[-1] = (x[-1] - x[-2]) / (X[-1] - X[-2])
    return X, cp * stretch


def mirror(x: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A half model's samples (x >= 0, one at x = 0) mirrored to the full body."""
    return np.concatenate([-x[:0:-1], x]), np.concatenate([p[:0:-1], p])


def trapezoid(x: np.ndarray, f: np.ndarray) -> float:
    return float(sum(0.5 * (f[i] + f[i + 1]) * (x[i + 1] - x[i]) for i in range(len(x) - 1)))


def edge(x: np.ndarray, p: np.ndarray) -> float:
    """The right edge of the loaded run of samples (x ascending) by the square-root edge model."""
    k = int(np.flatnonzero(p > 0)[-1])
    q1, q2 = p[k], p[k - 1]
    linear = x[k] + (x[k + 1] - x[k]) * q1 / (q1 - p[k + 1])
    if not q2 > q1:
        return float(linear)
    e = x[k] + (x[k] - x[k - 1]) * q1**2 / (q2**2 - q1**2)
    return float(e if x[k] <= e <= x[k + 1] else linear)


def moment_half_width(x: np.ndarray, p: np.ndarray) -> float:
    """2 sqrt(M2/M0) about x = 0 (trapezoid rule)."""
    return 2.0 * math.sqrt(trapezoid(x, p * x * x) / trapezoid(x, p))


def rms(x: np.ndarray, p: np.ndarray, p_th: np.ndarray, *, width: float, p_ref: float) -> float:
    keep = (np.abs(x) <= 1.05 * width) & np.isfinite(p_th)
    xs, d2 = x[keep], (p[keep] - p_th[keep]) ** 2
    return math.sqrt(trapezoid(xs, d2) / (xs[-1] - xs[0])) / p_ref


def write_csv(path: Path, rows: list[dict]) -> Path:
    """Rows (dicts with the same keys) as a csv, floats with repr."""
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        for r in rows:
            w.writerow({k: repr(v) if isinstance(v, float) else v for k, v in r.items()})
    return path
