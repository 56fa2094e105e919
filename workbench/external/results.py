"""Reading an external code's contact pressure along the contact surface (csv), with strict one-line errors.

A csv result has a header naming its columns (any order, extra columns ignored):

* the position along the contact surface, mm, reference (material) configuration: ``x_mm`` (or ``s_mm``,
  ``coordinate_mm``, ``x``);
* the contact pressure, MPa, compression positive: ``p_MPa`` (or ``p_fem_MPa``, ``pressure_MPa``, ``p``);
* optionally the load per unit thickness of the full body, N/mm: ``P_N_per_mm`` (or ``P``), the same on every row;
* optionally the level's element size on the contact surface, mm: ``h_mm`` (or ``h``), the same on every row;
* optionally ``weight_mm``: each sample's quadrature weight (mm; else trapezoid weights), and ``q_MPa``: the
  pressure argument (p = [q]_+; else q = p), as the workbench's own ``vtk/<run>/contact_surface.csv`` has them;
* optionally ``run``: a file with several runs (the workbench's own ``pressure.csv``) must hold exactly one.

Samples all at x >= 0 are a half model with its symmetry plane at x = 0: they are mirrored to the full body
(a sample at x = 0 once), and a given load counts both halves. Samples at one position are merged, the largest
pressure kept, as the frd and vtu readers do (:func:`workbench.external.result_files.merge_coincident`; the
count is ``ExternalResult.merged``). The file is opened as :func:`workbench.external.result_files.open_result`
says (a regular file of at most 256 MB, never a FIFO or a device), and at most a million rows are read.
Units: mm, N/mm, MPa.
"""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path
from typing import NamedTuple

import numpy as np

from workbench.external.result_files import MAX_SAMPLES, ResultError, merge_coincident, open_result, shown

__all__ = ["ExternalResult", "ResultError", "read_csv_result", "make_result", "POSITION", "PRESSURE", "LOAD", "SIZE"]

POSITION = ("X_mm", "s_mm", "x_mm", "coordinate_mm", "x")  # X_mm first: the workbench's contact_surface.csv
# has both X_mm (reference) and x_mm (current)
PRESSURE = ("p_MPa", "p_fem_MPa", "pressure_MPa", "p")
LOAD = ("P_N_per_mm", "P")
SIZE = ("h_mm", "h")
WEIGHT = ("weight_mm",)
ARGUMENT = ("q_MPa",)


class ExternalResult(NamedTuple):
    """One mesh level of an external code, mirrored to the full body and sorted by ``x``.

    Attributes:
        path: The file it came from.
        x: (n,) position along the contact surface (mm, reference configuration).
        p: (n,) contact pressure (MPa, >= 0 compression).
        load: Full-body load per unit thickness from the file (N/mm), or None.
        h: Element size on the contact surface from the file (mm), or None.
        half: The file held a half model (x >= 0), mirrored here.
        weight, q: (n,) quadrature weights (mm) and pressure argument (MPa) when the file gives them.
        configuration: ``"reference"`` (x is the material position; csv) or ``"current"`` (x = X + u, where
            the code's pressure is force per deformed length: CalculiX's CPRESS).
        merged: Samples dropped because another one had the same position (the largest pressure kept).
    """

    path: str
    x: np.ndarray
    p: np.ndarray
    load: float | None
    h: float | None
    half: bool
    configuration: str = "reference"
    weight: np.ndarray | None = None
    q: np.ndarray | None = None
    merged: int = 0


def _pick(header: list[str], names: tuple[str, ...]) -> str | None:
    return next((n for n in names if n in header), None)


def _numbers(values: list[str], *, what: str, where: str) -> np.ndarray:
    """The column ``what`` as floats; ResultError naming the first line that is not a number (not its text)."""
    out = np.empty(len(values))
    for i, v in enumerate(values):
        try:
            out[i] = float(v)
        except ValueError:
            raise ResultError(f"{where}: line {i + 2}: the {what} value is not a number; allowed: a number") from None
    return out


def _constant(values: list[str], *, what: str, where: str) -> float:
    arr = _numbers(values, what=what, where=where)
    if not np.all(np.isfinite(arr)):
        raise ResultError(f"{where}: column {what} has NaN or infinite values; allowed: finite numbers")
    if not np.all(arr > 0):
        raise ResultError(f"{where}: column {what} = {arr.min():.6g} <= 0; allowed: > 0")
    if arr.max() - arr.min() > 1e-12 * arr.max():
        raise ResultError(f"{where}: column {what} varies between rows ({arr.min():.6g} .. {arr.max():.6g}); "
                          "allowed: one value for the whole file")
    return float(arr[0])


def read_csv_result(path: str | Path) -> ExternalResult:
    """Read one level's csv (see the module docstring).

    Raises:
        ResultError: missing file or columns, non-numeric/NaN values, a negative pressure, load or size <= 0,
            fewer than two distinct positions, no positive pressure, several runs.
    """
    where = str(path)
    rows = []
    with open_result(path, where=where) as fh:
        reader = csv.reader(io.TextIOWrapper(fh, encoding="utf-8", newline=""))
        try:
            for row in reader:
                if len(rows) > MAX_SAMPLES:
                    raise ResultError(f"{where}: more than {MAX_SAMPLES} rows; allowed: at most {MAX_SAMPLES} "
                                      "samples of one mesh level")
                rows.append(row)
        except csv.Error as exc:
            raise ResultError(f"{where}: line {reader.line_num} is not csv ({' '.join(str(exc).split())[:80]})") \
                from None
        except UnicodeDecodeError as exc:
            raise ResultError(f"{where}: not UTF-8 text (byte 0x{exc.object[exc.start]:02x} near line "
                              f"{reader.line_num + 1}); allowed: a csv text file") from None
        except OSError as exc:
            raise ResultError(f"{where}: cannot be read ({exc.strerror or exc})") from None
    rows = [r for r in rows if r and any(c.strip() for c in r)]
    if not rows:
        raise ResultError(f"{where}: the file is empty; allowed: a csv with a header row")
    header = [c.strip() for c in rows[0]]
    xcol, pcol = _pick(header, POSITION), _pick(header, PRESSURE)
    if xcol is None or pcol is None:
        missing = [f"one of {'/'.join(names)}" for col, names in ((xcol, POSITION), (pcol, PRESSURE)) if col is None]
        fields = ",".join(shown(c) for c in header[:8]) + (",..." if len(header) > 8 else "")
        raise ResultError(f"{where}: missing column {' and '.join(missing)} (header fields: {fields[:160]})")
    body = rows[1:]
    bad = [i + 2 for i, r in enumerate(body) if len(r) != len(header)]
    if bad:
        raise ResultError(f"{where}: line {bad[0]} has a different number of fields than the header")
    col = {name: [r[i].strip() for r in body] for i, name in enumerate(header)}
    if "run" in col and len(set(col["run"])) > 1:
        runs = ", ".join(shown(r) for r in sorted(set(col["run"]))[:6])
        raise ResultError(f"{where}: holds {len(set(col['run']))} runs ({runs[:80]}); allowed: one run per file")
    x = _numbers(col[xcol], what=xcol, where=where)
    p = _numbers(col[pcol], what=pcol, where=where)
    for name, arr in ((xcol, x), (pcol, p)):
        if not np.all(np.isfinite(arr)):
            raise ResultError(f"{where}: column {name} has NaN or infinite values at line "
                              f"{int(np.flatnonzero(~np.isfinite(arr))[0]) + 2}; allowed: finite numbers")
    if p.size and p.min() < 0:
        raise ResultError(f"{where}: column {pcol} has a negative pressure {p.min():.6g} MPa at line "
                          f"{int(np.argmin(p)) + 2}; allowed: >= 0 (compression positive)")
    if np.unique(x).size < 2:
        raise ResultError(f"{where}: {np.unique(x).size} distinct sample position(s); allowed: at least 2")
    if not np.any(p > 0):
        raise ResultError(f"{where}: no positive pressure (no contact); allowed: a pressure > 0 somewhere")
    lcol, hcol = _pick(header, LOAD), _pick(header, SIZE)
    load = _constant(col[lcol], what=lcol, where=where) if lcol else None
    h = _constant(col[hcol], what=hcol, where=where) if hcol else None
    extra = {}
    for key, names in (("weight", WEIGHT), ("q", ARGUMENT)):
        name = _pick(header, names)
        if name:
            arr = _numbers(col[name], what=name, where=where)
            if not np.all(np.isfinite(arr)) or (key == "weight" and arr.min() < 0):
                raise ResultError(f"{where}: column {name} has NaN, infinite or negative values; allowed: finite"
                                  + (" >= 0" if key == "weight" else ""))
            extra[key] = arr
    return make_result(where, x, p, load=load, h=h, **extra)


def make_result(where: str, x: np.ndarray, p: np.ndarray, *, load: float | None, h: float | None,
                configuration: str = "reference", weight: np.ndarray | None = None,
                q: np.ndarray | None = None, merged: int = 0) -> ExternalResult:
    """Sort by x, merge samples at one position (the largest pressure kept; ``merged`` adds to the count of a
    reader that merged before), and mirror a half model (samples all at x >= 0) to the full body (a sample at
    x = 0 once, weights and arguments mirrored with it)."""
    x = np.asarray(x, dtype=float)
    scale = max(1.0, float(np.max(np.abs(x)))) if x.size else 1.0
    x, p, weight, q, more = merge_coincident(x, np.asarray(p, dtype=float),
                                             None if weight is None else np.asarray(weight, dtype=float),
                                             None if q is None else np.asarray(q, dtype=float), scale=scale)
    arrays = [p, weight, q]
    tol = 1e-12 * scale
    half = bool(x[0] >= -tol)
    if half:
        keep = x > tol
        x = np.concatenate([-x[keep][::-1], x])
        arrays = [np.concatenate([a[keep][::-1], a]) if a is not None else None for a in arrays]
    p, weight, q = arrays
    return ExternalResult(where, x, p, load, h, half, configuration, weight, q, merged + more)


def positive(value: float, *, what: str) -> float:
    """``value`` if finite and > 0 (an option), else ResultError naming it."""
    if not (math.isfinite(value) and value > 0):
        raise ResultError(f"{what} = {value!r}; allowed: a finite number > 0")
    return value
