"""Reading an external code's contact pressure along the contact surface (csv), with strict one-line errors.

A csv result has a header naming its columns (any order, extra columns ignored):

* the position along the contact surface, mm, reference (material) configuration: ``x_mm`` (or ``X_mm``,
  ``s_mm``, ``coordinate_mm``, ``x``);
* optionally the second reference coordinate ``y_mm`` (``Y_mm`` beside ``X_mm``): a curved contact surface (the
  concave scenes: the score projects (x, y) onto the case's concave curve and measures along its arc length);
* the contact pressure, MPa, compression positive, per unit REFERENCE length of the surface (a finite-strain code's
  pressure per deformed length times the surface stretch): ``p_MPa`` (or ``p_fem_MPa``, ``pressure_MPa``, ``p``);
* optionally the load per unit thickness of the full body at the row's step, N/mm: ``P_N_per_mm`` (or ``P``), the
  same on every row of one (run, step, body);
* optionally the level's element size on the contact surface, mm: ``h_mm`` (or ``h``), the same on every row of one
  (run, step, body);
* optionally ``weight_mm``: each sample's quadrature weight (mm; else trapezoid weights), and ``q_MPa``: the
  pressure argument (p = [q]_+; else q = p), as the workbench's own ``vtk/<run>/contact_surface.csv`` has them;
* optionally ``run`` (the run's label, :func:`workbench.external.scorers.runs.benchmark_runs`), ``step`` (the index
  0, 1, ... of the reported load or displacement in the case's schedule) and ``body`` (the body whose surface the
  row samples): a file may hold several runs, steps and bodies; each (run, step, body) is one group of samples.

What the columns may hold is checked here (a name, a whole number >= 0); whether a run label, step or body is the
case's is checked by the scorer (:mod:`workbench.external.scorers`), which knows the case. Samples of one group at
one position are merged, the largest pressure kept, as the frd and vtu readers do
(:func:`workbench.external.result_files.merge_coincident`; the count is ``ExternalResult.merged``).

Half models: a group whose samples all lie at x >= 0 is a half model with its symmetry plane at x = 0 when the
case is symmetric about it; the scorer mirrors it (:func:`mirror_half`: a sample at x = 0 once, a given load counts
both halves). :func:`read_csv_result` (one group, the issue-26 reader) mirrors at once. The file is opened as
:func:`workbench.external.result_files.open_result` says (a regular file of at most 256 MB, never a FIFO or a
device), and at most a million rows are read. Units: mm, N/mm, MPa.
"""

from __future__ import annotations

import csv
import io
import math
import re
from pathlib import Path
from typing import NamedTuple

import numpy as np

from workbench.external.result_files import MAX_SAMPLES, ResultError, merge_coincident, open_result, shown

__all__ = ["ExternalResult", "ResultError", "read_csv_result", "read_csv_groups", "make_result", "mirror_half",
           "group_name", "label_shown", "POSITION", "PRESSURE", "LOAD", "SIZE", "MAX_GROUPS"]

POSITION = ("X_mm", "s_mm", "x_mm", "coordinate_mm", "x")  # X_mm first: the workbench's contact_surface.csv
# has both X_mm (reference) and x_mm (current)
SECOND = {"X_mm": "Y_mm", "x_mm": "y_mm", "x": "y"}  # the second reference coordinate beside each position column
PRESSURE = ("p_MPa", "p_fem_MPa", "pressure_MPa", "p")
LOAD = ("P_N_per_mm", "P")
SIZE = ("h_mm", "h")
WEIGHT = ("weight_mm",)
ARGUMENT = ("q_MPa",)
MAX_GROUPS = 1000
"""(run, step, body) groups of one file at most (the largest case schedule has 6 steps)."""
_STEP = re.compile(r"[0-9]{1,6}")
_LABEL = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.()\[\]/+=-]{0,39}")  # a run label (theta=pi/20) or body name


def label_shown(text: str) -> str:
    """A run label or body name from a file as it may appear in an error line (else a placeholder)."""
    return text if _LABEL.fullmatch(text) else "<not a name>"


class ExternalResult(NamedTuple):
    """One group of samples (one run, step and body) of one mesh level, sorted by ``x``.

    Attributes:
        path: The file it came from.
        x: (n,) position along the contact surface (mm, reference configuration).
        p: (n,) contact pressure (MPa, >= 0 compression, per reference length).
        load: Full-body load per unit thickness from the file (N/mm), or None.
        h: Element size on the contact surface from the file (mm), or None.
        half: The samples were a half model (x >= 0), mirrored here.
        weight, q: (n,) quadrature weights (mm) and pressure argument (MPa) when the file gives them.
        configuration: ``"reference"`` (x is the material position; csv) or ``"current"`` (x = X + u, where
            the code's pressure is force per deformed length: CalculiX's CPRESS).
        merged: Samples dropped because another one had the same position (the largest pressure kept).
        run, step, body: the group's run label, step index and body name from the file (None: not given).
        y: (n,) the second reference coordinate (mm) of a curved surface, or None.
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
    run: str | None = None
    step: int | None = None
    body: str | None = None
    y: np.ndarray | None = None


def group_name(res: ExternalResult) -> str:
    """``run=..., step=..., body=...`` of a group (the parts the file gives), for error lines."""
    parts = [f"{k}={v}" for k, v in (("run", res.run), ("step", res.step), ("body", res.body)) if v is not None]
    return ", ".join(parts) if parts else "its samples"


def _pick(header: list[str], names: tuple[str, ...]) -> str | None:
    return next((n for n in names if n in header), None)


def _numbers(values: list[str], *, what: str, where: str, lines: list[int]) -> np.ndarray:
    """The column ``what`` as floats; ResultError naming the first line that is not a number (not its text)."""
    out = np.empty(len(values))
    for i, v in enumerate(values):
        try:
            out[i] = float(v)
        except ValueError:
            raise ResultError(f"{where}: line {lines[i]}: the {what} value is not a number; allowed: a number") \
                from None
    return out


def _constant(arr: np.ndarray, *, what: str, where: str) -> float:
    if not np.all(np.isfinite(arr)):
        raise ResultError(f"{where}: column {what} has NaN or infinite values; allowed: finite numbers")
    if not np.all(arr > 0):
        raise ResultError(f"{where}: column {what} = {arr.min():.6g} <= 0; allowed: > 0")
    if arr.max() - arr.min() > 1e-12 * arr.max():
        raise ResultError(f"{where}: column {what} varies between rows ({arr.min():.6g} .. {arr.max():.6g}); "
                          "allowed: one value per (run, step, body)")
    return float(arr[0])


def _rows(path: str | Path, where: str) -> list[list[str]]:
    rows = []
    with open_result(path, where=where) as fh:
        reader = csv.reader(io.TextIOWrapper(fh, encoding="utf-8", newline=""))
        try:
            for row in reader:
                if len(rows) > MAX_SAMPLES:
                    raise ResultError(f"{where}: more than {MAX_SAMPLES} rows; allowed: at most {MAX_SAMPLES} "
                                      "samples of one mesh level")
                rows.append((reader.line_num, row))
        except csv.Error as exc:
            raise ResultError(f"{where}: line {reader.line_num} is not csv ({' '.join(str(exc).split())[:80]})") \
                from None
        except UnicodeDecodeError as exc:
            raise ResultError(f"{where}: not UTF-8 text (byte 0x{exc.object[exc.start]:02x} near line "
                              f"{reader.line_num + 1}); allowed: a csv text file") from None
        except OSError as exc:
            raise ResultError(f"{where}: cannot be read ({exc.strerror or exc})") from None
    return [(n, r) for n, r in rows if r and any(c.strip() for c in r)]


def _labels(col: dict, lines: list[int], *, where: str) -> tuple[list, list, list]:
    """The run, step and body of every row (None where the file has no such column), checked as names / whole
    numbers."""
    out = []
    for key in ("run", "step", "body"):
        if key not in col:
            out.append([None] * len(lines))
            continue
        values = col[key]
        for i, v in enumerate(values):
            ok = bool((_STEP if key == "step" else _LABEL).fullmatch(v))
            if not ok:
                allowed = "a whole number >= 0 (the index of the reported step)" if key == "step" else \
                    "a name (letters, digits, _.()[]/+-=, at most 40 characters)"
                raise ResultError(f"{where}: line {lines[i]}: the {key} value {label_shown(v)!r} is not allowed; "
                                  f"allowed: {allowed}")
        out.append([int(v) for v in values] if key == "step" else values)
    return out[0], out[1], out[2]


def read_csv_groups(path: str | Path) -> list[ExternalResult]:
    """Every (run, step, body) group of one level's csv, in the order the file first names them, NOT mirrored
    (the scorer mirrors where the case is symmetric: :func:`mirror_half`).

    Raises:
        ResultError: missing file or columns, non-numeric/NaN values, a negative pressure, load or size <= 0 or
            varying inside a group, a run/body that is not a name or a step that is not a whole number, a group
            with fewer than two distinct positions or no positive pressure, more than :data:`MAX_GROUPS` groups.
    """
    where = str(path)
    rows = _rows(path, where)
    if not rows:
        raise ResultError(f"{where}: the file is empty; allowed: a csv with a header row")
    header = [c.strip() for c in rows[0][1]]
    xcol, pcol = _pick(header, POSITION), _pick(header, PRESSURE)
    if xcol is None or pcol is None:
        missing = [f"one of {'/'.join(names)}" for col, names in ((xcol, POSITION), (pcol, PRESSURE)) if col is None]
        fields = ",".join(shown(c) for c in header[:8]) + (",..." if len(header) > 8 else "")
        raise ResultError(f"{where}: missing column {' and '.join(missing)} (header fields: {fields[:160]})")
    body = rows[1:]
    bad = [n for n, r in body if len(r) != len(header)]
    if bad:
        raise ResultError(f"{where}: line {bad[0]} has a different number of fields than the header")
    lines = [n for n, _ in body]
    col = {name: [r[i].strip() for _, r in body] for i, name in enumerate(header)}
    x = _numbers(col[xcol], what=xcol, where=where, lines=lines)
    p = _numbers(col[pcol], what=pcol, where=where, lines=lines)
    ycol = SECOND.get(xcol) if SECOND.get(xcol) in header else None
    y = _numbers(col[ycol], what=ycol, where=where, lines=lines) if ycol else None
    for name, arr in ((xcol, x), (pcol, p), (ycol, y)):
        if arr is not None and not np.all(np.isfinite(arr)):
            raise ResultError(f"{where}: column {name} has NaN or infinite values at line "
                              f"{lines[int(np.flatnonzero(~np.isfinite(arr))[0])]}; allowed: finite numbers")
    if p.size and p.min() < 0:
        raise ResultError(f"{where}: column {pcol} has a negative pressure {p.min():.6g} MPa at line "
                          f"{lines[int(np.argmin(p))]}; allowed: >= 0 (compression positive)")
    lcol, hcol = _pick(header, LOAD), _pick(header, SIZE)
    load = _numbers(col[lcol], what=lcol, where=where, lines=lines) if lcol else None
    size = _numbers(col[hcol], what=hcol, where=where, lines=lines) if hcol else None
    extra = {}
    for key, names in (("weight", WEIGHT), ("q", ARGUMENT)):
        name = _pick(header, names)
        if name:
            arr = _numbers(col[name], what=name, where=where, lines=lines)
            if not np.all(np.isfinite(arr)) or (key == "weight" and arr.min() < 0):
                raise ResultError(f"{where}: column {name} has NaN, infinite or negative values; allowed: finite"
                                  + (" >= 0" if key == "weight" else ""))
            extra[key] = arr
    runs, steps, bodies = _labels(col, lines, where=where)
    keys = list(zip(runs, steps, bodies, strict=True))
    order = list(dict.fromkeys(keys))
    if len(order) > MAX_GROUPS:
        raise ResultError(f"{where}: {len(order)} (run, step, body) groups; allowed: at most {MAX_GROUPS}")
    if not order:
        raise ResultError(f"{where}: 0 distinct sample position(s); allowed: at least 2")
    index = {k: i for i, k in enumerate(order)}
    gid = np.array([index[k] for k in keys], dtype=int)
    out = []
    for i, (run, step, bod) in enumerate(order):
        sel = gid == i
        label = group_name(ExternalResult(where, x, p, None, None, False, run=run, step=step, body=bod))
        here = where if len(order) == 1 else f"{where} ({label})"
        xs = x[sel]
        if np.unique(xs if y is None else np.column_stack([xs, y[sel]]), axis=0).shape[0] < 2:
            raise ResultError(f"{here}: {np.unique(xs).size} distinct sample position(s); allowed: at least 2")
        if not np.any(p[sel] > 0):
            raise ResultError(f"{here}: no positive pressure (no contact); allowed: a pressure > 0 somewhere")
        g_load = _constant(load[sel], what=lcol, where=here) if lcol else None
        g_h = _constant(size[sel], what=hcol, where=here) if hcol else None
        out.append(make_result(where, xs, p[sel], load=g_load, h=g_h, mirror=False, run=run, step=step, body=bod,
                               y=None if y is None else y[sel], **{k: v[sel] for k, v in extra.items()}))
    return out


def read_csv_result(path: str | Path) -> ExternalResult:
    """Read one level's csv holding one (run, step, body) group, mirrored where it is a half model (issue 26).

    Raises:
        ResultError: as :func:`read_csv_groups`, and a file holding several runs, steps or bodies.
    """
    groups = read_csv_groups(path)
    if len(groups) > 1:
        runs = sorted({g.run for g in groups if g.run is not None})
        what = (f"{len(runs)} runs ({', '.join(runs)[:80]})" if len(runs) > 1
                else f"{len(groups)} (run, step, body) groups")
        raise ResultError(f"{path}: holds {what}; allowed: one run per file")
    return mirror_half(groups[0])


def make_result(where: str, x: np.ndarray, p: np.ndarray, *, load: float | None, h: float | None,
                configuration: str = "reference", weight: np.ndarray | None = None,
                q: np.ndarray | None = None, merged: int = 0, mirror: bool = True, run: str | None = None,
                step: int | None = None, body: str | None = None, y: np.ndarray | None = None) -> ExternalResult:
    """Sort by x, merge samples at one position (the largest pressure kept; ``merged`` adds to the count of a
    reader that merged before) and, with ``mirror``, mirror a half model (:func:`mirror_half`)."""
    x = np.asarray(x, dtype=float)
    scale = max(1.0, float(np.max(np.abs(x)))) if x.size else 1.0
    if y is not None:
        y = np.asarray(y, dtype=float)
        scale = max(scale, float(np.max(np.abs(y))) if y.size else 1.0)
    merged_arrays = merge_coincident(x, np.asarray(p, dtype=float),
                                     None if weight is None else np.asarray(weight, dtype=float),
                                     None if q is None else np.asarray(q, dtype=float), scale=scale, y=y)
    if y is None:
        x, p, weight, q, more = merged_arrays
    else:
        x, p, weight, q, y, more = merged_arrays
    res = ExternalResult(where, x, p, load, h, False, configuration, weight, q, merged + more, run, step, body, y)
    return mirror_half(res) if mirror else res


def mirror_half(res: ExternalResult) -> ExternalResult:
    """A half model (samples all at x >= 0 of a case symmetric about x = 0) mirrored to the full body: a sample at
    x = 0 once, weights, arguments and y mirrored with it; anything else unchanged (the caller knows the case is
    symmetric)."""
    x = res.x
    if res.half or not x.size:
        return res
    tol = 1e-12 * max(1.0, float(np.max(np.abs(x))))
    if not x[0] >= -tol:
        return res
    keep = x > tol
    x = np.concatenate([-x[keep][::-1], x])
    p, weight, q, y = (np.concatenate([a[keep][::-1], a]) if a is not None else None
                       for a in (res.p, res.weight, res.q, res.y))
    return res._replace(x=x, p=p, weight=weight, q=q, y=y, half=True)


def positive(value: float, *, what: str) -> float:
    """``value`` if finite and > 0 (an option), else ResultError naming it."""
    if not (math.isfinite(value) and value > 0):
        raise ResultError(f"{what} = {value!r}; allowed: a finite number > 0")
    return value
