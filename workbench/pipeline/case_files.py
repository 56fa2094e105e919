"""The data files of a case, written from its runs' outcomes: ``pressure.csv`` and ``series.json``.

These are the only files made from live Python objects besides ``metrics.json``; the case report
(:func:`workbench.reports.case_report.write_case_report`) is drawn from the saved JSON alone.

``pressure.csv``: one row per surface point of every series: ``run`` (series label), ``coordinate_mm``,
``p_fem_MPa``, ``sigma_nn_MPa``, then ``p_<prediction>_MPa`` for every analytic prediction of any series
(empty where a series has no such prediction or its value is not finite), then ``weight_mm`` (each sample's
quadrature weight: ``sum(weight_mm * p_fem_MPa)`` is the load the samples carry, full body) and ``q_MPa`` (the
contact law's argument, ``p = [q]_+``: its zero crossings are the edges), empty where the scene gives none. Numbers
have 10 significant digits, the weights 17 (the load they sum to is then exact to round-off).

``series.json``: ``{"series": [...]}``, one record per pressure curve (one plot panel) with ``label``,
``x`` (mm), ``p`` (MPa), ``sigma_nn`` (MPa), ``predictions`` (name -> MPa at ``x``), ``xlabel`` and
``xlim`` (mm). Arrays are JSON lists at full double precision; NaN and infinities are written as ``null``.
"""

from __future__ import annotations

import csv
import io
import json
import math
from pathlib import Path

import numpy as np

from workbench.atomic import write_text

__all__ = ["pressure_csv", "series_json", "series_records", "write_case_files"]


def _slug(name: str) -> str:
    return "_".join("".join(c if c.isalnum() else " " for c in name.lower()).split())


def _series(outcomes) -> list:
    return [sr for o in outcomes for sr in o.series]


def pressure_csv(outcomes) -> str:
    """The text of ``pressure.csv`` (see the module docstring)."""
    series = _series(outcomes)
    names = list(dict.fromkeys(k for sr in series for k in sr.predictions))
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(["run", "coordinate_mm", "p_fem_MPa", "sigma_nn_MPa", *[f"p_{_slug(n)}_MPa" for n in names],
                "weight_mm", "q_MPa"])
    for sr in series:
        for i in range(len(sr.x)):
            row = [sr.label, f"{sr.x[i]:.10g}", f"{sr.p[i]:.10g}", f"{sr.sigma_nn[i]:.10g}"]
            for v in [sr.predictions.get(n) for n in names] + [sr.weight, sr.q]:
                row.append("" if v is None or not np.isfinite(v[i]) else f"{v[i]:.17g}" if v is sr.weight
                           else f"{v[i]:.10g}")
            w.writerow(row)
    return buf.getvalue()


def _floats(values) -> list[float | None] | None:
    """A 1D array as a JSON list: Python floats, ``None`` for NaN and infinities."""
    if values is None:
        return None
    arr = np.asarray(values, dtype=float)
    if arr.ndim != 1:
        raise ValueError(f"a pressure series must be one-dimensional, got shape {arr.shape}")
    return [v if math.isfinite(v) else None for v in arr.tolist()]


def series_records(outcomes) -> list[dict]:
    """The pressure series of every run as JSON-ready records (see the module docstring)."""
    out = []
    for sr in _series(outcomes):
        x = _floats(sr.x)
        rec = {"label": str(sr.label), "x": x, "p": _floats(sr.p), "sigma_nn": _floats(sr.sigma_nn),
               "predictions": {str(k): _floats(v) for k, v in sr.predictions.items()},
               "xlabel": str(sr.xlabel), "xlim": None if sr.xlim is None else _floats(sr.xlim)}
        for key, arr in (("p", rec["p"]), ("sigma_nn", rec["sigma_nn"]), *rec["predictions"].items()):
            if arr is not None and len(arr) != len(x):
                raise ValueError(f"series {sr.label!r}: {key} has {len(arr)} values for {len(x)} points")
        out.append(rec)
    return out


def series_json(outcomes) -> str:
    """The text of ``series.json``: strict JSON (no NaN), one series per line."""
    lines = [json.dumps(rec, allow_nan=False) for rec in series_records(outcomes)]
    return '{"series": [\n' + ",\n".join(lines) + "\n]}\n"


def write_case_files(outcomes, folder: Path) -> None:
    """Write ``pressure.csv`` and ``series.json`` of a case into ``folder`` (atomically, file by file)."""
    folder = Path(folder)
    write_text(folder / "pressure.csv", pressure_csv(outcomes))
    write_text(folder / "series.json", series_json(outcomes))
