"""Convergence study (issue "Error against run time"): error against ndofs and WARM wall time.

Run: ``python -m scripts.convergence`` (``make convergence``) -> ``results/convergence/`` with
``convergence.json`` (everything), ``convergence.csv`` (one row per case x series x method x degree x level),
``report.md`` and, from :mod:`scripts.convergence_plot`, ``error_vs_time.png`` and ``error_vs_ndofs.png``.
All files are written atomically. Computing lives here; plotting reads the JSON.

Study: for ``hertz_cylinder`` and ``wedge_convective``, every contact element size ``h_c`` of ``levels``
(fractions of the classical half-width) x method {penalty, nitsche} x Lagrange degree {1, 2}, in two series:
``case`` (the case file as it is: kappa0 = 1e3, gamma0 = 10, block W = H = 40 a) and ``ideal`` (the same with
the model floors removed: block W = H = 640 a, and a parabola instead of the circle for Hertz). Each run is
solved once to warm the JIT and file caches (``cold_s``), then ``repeats`` more identical times; ``time_s`` is
the median of those warm solver times (``fem.solver`` load stepping only, no meshing).

Errors (relative, dimensionless; formulas in :mod:`scripts.compare` and :mod:`scripts.case_checks`):
    p_max, half_width, rms (RMS(p - p_th)/p_ref over |x| <= 1.05 max(a_fem, a), trapezoid over the samples)
    and l2 (the same mean with the contact-facet Gauss weights, :func:`l2_pressure_error`); p_ref = p0 (Hertz)
    or P/(2b) (wedge). Wedge: those of the ``small`` run, plus the case-level b_over_b0 (FEM b/b0 against the
    converged Ciavarella-Hills value) and rms_convective (convective run against the converged theory), both
    timed by the small + convective pair (``time_pair_s``).

Observed rates: least-squares slope of log(error) against log(h_c) and against log(ndofs) over the finest
three levels (:func:`fit_rate`): error ~ h^slope_h, error ~ ndofs^slope_ndofs.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import math
import statistics
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from scripts.atomic import write_json, write_text

__all__ = [
    "CASES",
    "DEFAULT_LEVELS",
    "METRICS",
    "RateFit",
    "cheapest",
    "discussion",
    "fit_rate",
    "l2_pressure_error",
    "main",
    "observed_rates",
    "run_study",
    "to_csv",
    "to_markdown",
    "write_outputs",
]

OUT_DIR = Path("results") / "convergence"
CASES = ("hertz_cylinder", "wedge_convective")
DEFAULT_LEVELS = (0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625, 0.003125)
METHODS = ("penalty", "nitsche")
DEGREES = (1, 2)
N_FINEST = 3
RMS_TARGET = 0.005  # issue: cheapest configuration with RMS/p_ref <= 0.5 %
METRICS = {  # error columns per case (row keys)
    "hertz_cylinder": ("p_max", "half_width", "rms", "l2"),
    "wedge_convective": ("b_over_b0", "rms_convective", "half_width", "rms", "l2"),
}
TIME_OF = {"b_over_b0": "time_pair_s", "rms_convective": "time_pair_s"}  # default "time_s"
BIG = {"width_factor": 640.0, "height_factor": 640.0}
SERIES = {  # geometry overrides of each series
    "hertz_cylinder": {"case": {}, "ideal": {**BIG, "indenter": "parabola"}},
    "wedge_convective": {"case": {}, "ideal": BIG},
}
FLOORS = {  # finest-level decomposition of the model floors (Nitsche P2)
    "hertz_cylinder": {"case (W = H = 40 a, circle)": {}, "W = H = 640 a, circle": BIG,
                       "W = H = 640 a, parabola": {**BIG, "indenter": "parabola"}},
    "wedge_convective": {"case (W = H = 40 b0)": {}, "W = H = 160 b0": {"width_factor": 160.0,
                                                                       "height_factor": 160.0},
                         "W = H = 640 b0": BIG},
}
KAPPA0_SWEEP = (1e2, 1e3, 1e4, 1e5)
KAPPA0_LEVEL = 0.0125
GROWTH_PROBE = {"case": "hertz_cylinder", "series": "ideal", "growth": 1.1, "degrees": (1, 2),
                "levels": (0.025, 0.0125, 0.00625, 0.003125)}  # the mesh builder's default growth is 1.3


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


def l2_pressure_error(samples, theory, *, half_width_fem: float) -> float:
    """Gauss-quadrature L2 mean of the pressure error on the patch, relative to the reference pressure.

    l2 = sqrt( sum_q w_q (p_q - p_th(x_q))^2 / sum_q w_q ) / p_ref over the contact-facet Gauss points with
    |x_q| <= 1.05 max(a_fem, a) (the band of :func:`scripts.compare.rms_error`); w_q = Gauss weight times
    facet length (mm). These are the points where the discrete contact law holds.

    Args:
        samples: :class:`fem.postprocess.SurfaceSamples` (``s``, ``p``, ``weight``); a half model's samples.
        theory: :class:`scripts.compare.BlockTheory` at the measured load (``pressure``, ``half_width``,
            ``p_ref``).
        half_width_fem: FEM half-width of the patch (mm).
    """
    s, p, w = np.asarray(samples.s), np.asarray(samples.p), np.asarray(samples.weight)
    band = max(half_width_fem, theory.half_width) if math.isfinite(half_width_fem) else theory.half_width
    p_th = theory.pressure(s)
    keep = (np.abs(s) <= 1.05 * band) & np.isfinite(p_th)
    if not np.any(keep):
        return math.nan
    d2 = (p[keep] - p_th[keep]) ** 2
    return float(math.sqrt(np.sum(w[keep] * d2) / np.sum(w[keep])) / theory.p_ref)


class _Timed(NamedTuple):
    outcome: Any       # the last scripts.outcome.Outcome
    cold_s: float      # solver time of the first solve (s)
    warm_s: list       # solver times of the repeated identical solves (s); [cold_s] when repeats = 0
    spread: float      # max relative change of the FEM half-width across the solves (determinism check)


def _timed_run(run, *, name: str, repeats: int, comm) -> _Timed:
    """First (warm-up) solve, then ``repeats`` identical solves; returns the last outcome and the times."""
    from scripts.scene_block import run_block

    def solve():
        return run_block(run, name=name, stage=None, comm=comm, progress=lambda s: None)

    first = last = solve()
    a0, warm, spread = first.metrics["patch_half_width"], [], 0.0
    for _ in range(repeats):
        last = solve()
        warm.append(last.metrics["wall_time_s"])
        spread = max(spread, abs(last.metrics["patch_half_width"] - a0) / abs(a0))
    return _Timed(last, first.metrics["wall_time_s"], warm or [first.metrics["wall_time_s"]], spread)


def _configure(run, *, method: str, degree: int, geometry: dict, kappa0: float | None = None):
    """The run with another contact method, Lagrange degree, geometry overrides and penalty factor."""
    solver = replace(run.solver, method=method, **({} if kappa0 is None else {"kappa0": kappa0}))
    return replace(run, solver=solver, discretisation=replace(run.discretisation, degree=degree),
                   geometry=replace(run.geometry, **geometry))


def _measure(case, *, series: str, method: str, degree: int, level: float, repeats: int, comm,
             kappa0: float | None = None) -> dict:
    """One configuration: every run of the case, timed; returns its CSV/JSON row (NaN errors on failure)."""
    from scripts.case_checks import case_level_comparisons

    geometry = {**SERIES.get(case.name, {}), **FLOORS.get(case.name, {})}.get(series, {})
    row = {"case": case.name, "series": series, "method": method, "degree": degree, "h_contact": level,
           "kappa0": kappa0 if kappa0 is not None else case.solver.kappa0, "failed": ""}
    row.update({k: math.nan for k in ("p_max", "half_width", "rms", "l2", "b_over_b0", "b_over_b0_fem",
                                      "b_over_b0_theory", "rms_convective", "load_balance", "time_s",
                                      "cold_s", "time_pair_s", "cold_pair_s", "h_mm")})
    row.update(ndofs=0, cells=0, newton_iterations=0, repeat_spread=0.0, warnings="")
    try:
        timed = {run.label: _timed_run(_configure(run, method=method, degree=degree, geometry=geometry,
                                                  kappa0=kappa0), name=case.name, repeats=repeats, comm=comm)
                 for run in case.runs(h_contact=level)}
    except RuntimeError as exc:  # fem.solver.ContactSolveError: record, keep the study going
        row["failed"] = str(exc).splitlines()[0]
        return row
    t = timed.get("small", timed.get("base", next(iter(timed.values()))))
    o, m = t.outcome, t.outcome.metrics
    row.update(
        h_mm=level * float(o.theory.half_width), ndofs=m["ndofs"], cells=m["mesh"].get("cells", 0),
        time_s=statistics.median(t.warm_s), cold_s=t.cold_s,
        time_pair_s=sum(statistics.median(x.warm_s) for x in timed.values()),
        cold_pair_s=sum(x.cold_s for x in timed.values()),
        warnings="; ".join(sorted({w.split(":")[0] for x in timed.values()
                                   for w in getattr(x.outcome.result, "warnings", ())})),
        newton_iterations=int(sum(m["newton_iterations"])),
        repeat_spread=max(x.spread for x in timed.values()),
        p_max=m["errors"].get("p_max", math.nan), half_width=m["errors"]["half_width"],
        rms=m["errors"]["rms"],
        l2=l2_pressure_error(o.result.samples, o.theory, half_width_fem=m["patch_half_width"]),
        load_balance=max(x.outcome.metrics["errors"]["load_balance"] for x in timed.values()),
    )
    if len(timed) > 1:
        cmp = case_level_comparisons(case, [x.outcome for x in timed.values()])
        row.update(b_over_b0=float(cmp.errors.get("b_over_b0", math.nan)),
                   rms_convective=float(cmp.errors.get("rms_convective", math.nan)),
                   b_over_b0_fem=float(cmp.analytic.get("b_over_b0_fem", math.nan)),
                   b_over_b0_theory=float(cmp.analytic.get("b_over_b0_converged", math.nan)))
    return row


def _growth_probe(case, *, comm, say) -> list[dict]:
    """Nitsche on the ``ideal`` Hertz geometry with a finer mesh grading (``GROWTH_PROBE["growth"]``).

    The study refines h_c only; the element size away from the contact zone grows by the builder's fixed
    factor 1.3 per element. :func:`scripts.scene_block.run_block` does not expose that factor, so this
    diagnostic patches the builder's default for its own calls (``unittest.mock.patch``) and checks that the
    patch changed the mesh (``note``).
    """
    import functools
    from unittest import mock

    import meshes.block

    g, out = GROWTH_PROBE, []
    original = meshes.block.build_block_mesh
    for degree in g["degrees"]:
        for level in g["levels"]:
            with mock.patch.object(meshes.block, "build_block_mesh",
                                   functools.partial(original, growth=g["growth"])):
                row = _measure(case, series=g["series"], method="nitsche", degree=degree, level=level,
                               repeats=0, comm=comm)
            out.append({**row, "series": f"{g['series']}, growth {g['growth']:g}", "growth": g["growth"]})
            say(out[-1])
    return out


def _group(rows: list[dict], *keys: str) -> dict[tuple, list[dict]]:
    out: dict[tuple, list[dict]] = {}
    for r in rows:
        out.setdefault(tuple(r[k] for k in keys), []).append(r)
    return out


def observed_rates(rows: list[dict], *, metrics: dict[str, Sequence[str]] = METRICS,
                   n_finest: int = N_FINEST) -> list[dict]:
    """Fitted slopes per case x series x method x degree x metric, against h_c and against ndofs.

    Rows of one configuration are sorted coarse to fine (h_c decreasing). A metric with a non-finite or zero
    error on a fitted level gets ``None`` slopes and the reason in ``note``.
    """
    out = []
    groups = _group(rows, "case", "series", "method", "degree")
    for (case, series, method, degree), sel in sorted(groups.items()):
        sel = sorted(sel, key=lambda r: -r["h_contact"])
        h, n = [r["h_contact"] for r in sel], [r["ndofs"] for r in sel]
        for metric in metrics.get(case, ()):
            err = [math.nan if r[metric] is None else r[metric] for r in sel]
            rec = {"case": case, "series": series, "method": method, "degree": degree, "metric": metric,
                   "levels": h[-n_finest:], "slope_h": None, "slope_ndofs": None, "note": ""}
            try:
                fh, fn = fit_rate(h, err, n_finest=n_finest), fit_rate(n, err, n_finest=n_finest)
                rec.update(slope_h=fh.slope, slope_ndofs=fn.slope, max_residual_h=fh.max_residual)
            except ValueError as exc:
                rec["note"] = str(exc)
            out.append(rec)
    return out


def cheapest(rows: list[dict], *, metric: str = "rms", target: float = RMS_TARGET) -> dict[str, dict | None]:
    """Per ``case/series``, the row with the smallest warm time among those with ``row[metric] <= target``."""
    out = {}
    for (case, series), sel in sorted(_group(rows, "case", "series").items()):
        ok = [r for r in sel if r[metric] is not None and r[metric] <= target]
        out[f"{case}/{series}"] = min(ok, key=lambda r: r["time_s"]) if ok else None
    return out


def run_study(*, cases: Sequence[str] = CASES, levels: Sequence[float] = DEFAULT_LEVELS, repeats: int = 3,
              diagnostics: bool = True, progress: Callable[[str], None] = print) -> dict:
    """Run the whole study and return the JSON-ready data (no files written).

    Args:
        cases: Case names (block scenes).
        levels: h_c fractions of the classical half-width, coarse to fine, each in (0, 1].
        repeats: Timed warm solves per run after the warm-up solve, >= 1 (the median is kept).
        diagnostics: Also run the model-floor decomposition (finest level) and the penalty kappa0 sweep.
        progress: One-line status output.
    """
    import dolfinx_solver  # noqa: F401  (before mpi4py/dolfinx)

    from mpi4py import MPI

    from cases import load_case

    levels = [float(v) for v in levels]
    if len(levels) < N_FINEST or any(not 0 < v <= 1 for v in levels) or np.any(np.diff(levels) >= 0):
        raise ValueError(f"levels must be >= {N_FINEST} strictly decreasing values in (0, 1], got {levels}")
    if int(repeats) != repeats or repeats < 1:
        raise ValueError(f"repeats must be an integer >= 1, got {repeats!r}")
    loaded = [load_case(c) for c in cases]  # validate all before running any
    comm, t0 = MPI.COMM_WORLD, time.perf_counter()

    def say(r: dict) -> None:
        extra = f" kappa0={r['kappa0']:g}" if r["series"] == "kappa0 sweep" else ""
        progress(f"{r['case']} [{r['series']}] {r['method']} P{r['degree']} h_c={r['h_contact']:g}{extra}: "
                 + (f"FAILED {r['failed']}" if r["failed"] else
                    f"ndofs {r['ndofs']}, warm {r['time_s']:.3f} s (cold {r['cold_s']:.2f} s), "
                    f"rms {r['rms']:.2e}, half_width {r['half_width']:.2e}, p_max {r['p_max']:.2e}, "
                    f"b/b0 {r['b_over_b0']:.2e}"))

    rows, floors, sweep, growth = [], [], [], []
    for case in loaded:
        for series in SERIES.get(case.name, {"case": {}}):
            for method in METHODS:
                for degree in DEGREES:
                    for level in levels:
                        rows.append(_measure(case, series=series, method=method, degree=degree, level=level,
                                             repeats=repeats, comm=comm))
                        say(rows[-1])
        if not diagnostics:
            continue
        for label in FLOORS.get(case.name, {}):
            floors.append(_measure(case, series=label, method="nitsche", degree=2, level=levels[-1],
                                   repeats=0, comm=comm))
            say(floors[-1])
        for degree in DEGREES:
            for kappa0 in KAPPA0_SWEEP:
                r = _measure(case, series="case", method="penalty", degree=degree, level=KAPPA0_LEVEL,
                             repeats=0, comm=comm, kappa0=kappa0)
                sweep.append({**r, "series": "kappa0 sweep"})
                say(sweep[-1])
        if case.name == GROWTH_PROBE["case"]:
            growth = _growth_probe(case, comm=comm, say=say)
    return {
        "description": "error against ndofs and warm solver time; see scripts/convergence.py",
        "levels": levels, "repeats": repeats, "n_finest": N_FINEST, "metrics": METRICS, "time_of": TIME_OF,
        "series": SERIES, "rms_target": RMS_TARGET, "rows": rows, "rates": observed_rates(rows),
        "cheapest_rms": cheapest(rows), "floors": floors, "kappa0_sweep": sweep, "growth_probe": growth,
        "growth_rates": observed_rates(growth), "growth_setting": GROWTH_PROBE,
        "study_wall_time_s": time.perf_counter() - t0,
    }


CSV_COLUMNS = ("case", "series", "method", "degree", "h_contact", "h_mm", "ndofs", "cells", "time_s",
               "cold_s", "time_pair_s", "newton_iterations", "p_max", "half_width", "rms", "l2", "b_over_b0",
               "rms_convective", "b_over_b0_fem", "b_over_b0_theory", "load_balance", "repeat_spread",
               "warnings", "failed")


def to_csv(rows: list[dict]) -> str:
    """CSV text, one row per case x series x method x degree x level (columns :data:`CSV_COLUMNS`)."""
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=CSV_COLUMNS, extrasaction="ignore", lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: (f"{v:.8g}" if isinstance(v, float) else v) for k, v in r.items()})
    return buf.getvalue()


def _e(v) -> str:
    return "-" if v is None or (isinstance(v, float) and not math.isfinite(v)) else f"{v:.2e}"


def _t(v) -> str:
    return "-" if v is None or (isinstance(v, float) and not math.isfinite(v)) else f"{v:.3f}"


def _status(r: dict) -> str:
    if not r["failed"]:
        return "ok"
    return "diverged (SNES max iterations)" if "DIVERGED_MAX_IT" in r["failed"] else r["failed"][:80]


def _s(v) -> str:
    return "-" if v is None else f"{v:+.2f}"


def to_markdown(data: dict, *, discussion: str = "") -> str:
    """``report.md``: error tables, fitted slopes, cheapest configuration, diagnostics, discussion."""
    lines = ["# Convergence study: error against run time", "",
             f"Levels h_c/a = {', '.join(f'{v:g}' for v in data['levels'])}. Times are WARM solver times: "
             f"each run was solved once to warm the JIT cache, then {data['repeats']} more identical times; "
             "the median is reported (cold = the first solve in the process). Whole study: "
             f"{data['study_wall_time_s']:.0f} s (serial, one process). Slopes: least squares of log(error) "
             f"against log(h_c) / log(ndofs) over the finest {data['n_finest']} levels.", ""]
    for (case, series), sel in _group(data["rows"], "case", "series").items():
        mets = data["metrics"][case]
        tcol, ccol = ("time_pair_s", "cold_pair_s") if case.startswith("wedge") else ("time_s", "cold_s")
        overrides = data["series"][case][series] or "none"
        lines += [f"## {case}, series `{series}` (geometry overrides {overrides})", "",
                  "| method | P | h_c/a | ndofs | warm s | cold s | " + " | ".join(mets)
                  + " | Newton its | solver warnings |", "|---" * (8 + len(mets)) + "|"]
        for r in sel:
            lines.append(f"| {r['method']} | {r['degree']} | {r['h_contact']:g} | {r['ndofs']} | "
                         f"{_t(r[tcol])} | {_t(r[ccol])} | " + " | ".join(_e(r[m]) for m in mets)
                         + f" | {r['newton_iterations']} | {r['warnings'] or '-'} |"
                         + (f" {_status(r)}" if r["failed"] else ""))
        if case.startswith("wedge"):
            lines += ["", "Wedge times: the small + convective pair (b/b0 needs both); half_width, rms and "
                      "l2: the small run against the classical wedge (p_ref = P/(2b))."]
        lines += ["", f"Fitted slopes, finest {data['n_finest']} levels (vs h_c / vs ndofs):", "",
                  "| method | P | " + " | ".join(mets) + " |", "|---" * (2 + len(mets)) + "|"]
        rates = {(x["method"], x["degree"], x["metric"]): x for x in data["rates"]
                 if (x["case"], x["series"]) == (case, series)}
        for method, degree in sorted({(r["method"], r["degree"]) for r in sel}):
            fits = [rates[method, degree, m] for m in mets]
            cells = [f"{_s(f['slope_h'])} / {_s(f['slope_ndofs'])}" for f in fits]
            lines.append(f"| {method} | {degree} | " + " | ".join(cells) + " |")
        best = data["cheapest_rms"].get(f"{case}/{series}")
        found = (f"{best['method']} P{best['degree']} h_c/a = {best['h_contact']:g} ({best['ndofs']} dofs, "
                 f"warm {best['time_s']:.3f} s, rms {best['rms']:.2e})" if best else "none reached it")
        lines += ["", f"Cheapest configuration with rms <= {data['rms_target']:.1%}: {found}", ""]
    if data.get("floors"):
        lines += ["## Model floors (Nitsche P2, finest level)", "",
                  "| case | variant | ndofs | p_max | half_width | rms | l2 | b_over_b0 | rms_convective |",
                  "|---" * 9 + "|"]
        for f in data["floors"]:
            lines.append(f"| {f['case']} | {f['series']} | {f['ndofs']} | " + " | ".join(
                _e(f[k]) for k in ("p_max", "half_width", "rms", "l2", "b_over_b0", "rms_convective")) + " |")
        lines.append("")
    if data.get("kappa0_sweep"):
        lines += [f"## Penalty factor sweep (case geometry, h_c/a = {KAPPA0_LEVEL:g})", "",
                  "| case | P | kappa0 | p_max | half_width | rms | b_over_b0 | Newton its | status |",
                  "|---" * 9 + "|"]
        for f in data["kappa0_sweep"]:
            lines.append(f"| {f['case']} | {f['degree']} | {f['kappa0']:g} | " + " | ".join(
                _e(f[k]) for k in ("p_max", "half_width", "rms", "b_over_b0"))
                + f" | {f['newton_iterations']} | {_status(f)} |")
        lines.append("")
    if data.get("growth_probe"):
        g = data["growth_setting"]
        base = {(r["degree"], r["h_contact"]): r for r in data["rows"]
                if (r["case"], r["series"], r["method"]) == (g["case"], g["series"], "nitsche")}
        lines += [f"## Mesh grading probe ({g['case']}, series `{g['series']}`, Nitsche)", "",
                  "Element growth factor 1.3 (builder default, used by the whole study) against "
                  f"{g['growth']:g} (unmarked columns).", "",
                  "| P | h_c/a | ndofs 1.3 | ndofs | rms 1.3 | rms | p_max 1.3 | p_max | half_width 1.3 | "
                  "half_width |", "|---" * 10 + "|"]
        for r in data["growth_probe"]:
            b0 = base.get((r["degree"], r["h_contact"]), {})
            lines.append(f"| {r['degree']} | {r['h_contact']:g} | {b0.get('ndofs', '-')} | {r['ndofs']} | "
                         + " | ".join(f"{_e(b0.get(k))} | {_e(r[k])}" for k in ("rms", "p_max", "half_width"))
                         + " |")
        lines += ["", "Slopes vs h_c over the finest 3 probe levels: " + "; ".join(
            f"P{x['degree']} {x['metric']} {_s(x['slope_h'])}" for x in data["growth_rates"]
            if x["metric"] in ("rms", "half_width")), ""]
    if discussion:
        lines += [discussion.strip(), ""]
    return "\n".join(lines)


def _find(rows: list[dict], **match) -> dict | None:
    """The row matching every ``key=value`` (finest h_c when ``h_contact`` is not given), or None."""
    sel = [r for r in rows if all(r.get(k) == v for k, v in match.items()) and not r.get("failed")]
    return min(sel, key=lambda r: r["h_contact"]) if sel else None


def _slope(data: dict, case: str, series: str, method: str, degree: int, metric: str) -> float | None:
    for x in data["rates"]:
        if (x["case"], x["series"], x["method"], x["degree"], x["metric"]) == (case, series, method, degree,
                                                                              metric):
            return x["slope_h"]
    return None


def _load(name: str):
    """The case record, or None when it cannot be loaded (the report must still be written)."""
    from cases import CaseError, load_case

    try:
        return load_case(name)
    except (CaseError, FileNotFoundError):
        return None


def discussion(data: dict) -> str:
    """The discussion of ``report.md``: every number in it is read from ``data`` (nothing typed in)."""
    rows, out = data["rows"], ["## Discussion", ""]
    hz, wd = "hertz_cylinder", "wedge_convective"
    n2 = sorted((r for r in rows if (r["case"], r["series"], r["method"], r["degree"])
                 == (hz, "case", "nitsche", 2) and not r["failed"]), key=lambda r: -r["h_contact"])
    if len(n2) >= N_FINEST:
        tfit = fit_rate([r["ndofs"] for r in n2], [r["time_s"] for r in n2])
        out += ["**Run time.** Warm and cold solver times differ little once the FFCx disk cache holds the "
                "forms (the JIT cost falls on the first solve of a form in a fresh cache only). The Hertz "
                f"Nitsche P2 warm time grows like ndofs^{tfit.slope:.2f} over the finest levels "
                f"({n2[-1]['ndofs']} dofs: {n2[-1]['time_s']:.3f} s); the wedge pair costs more because "
                "the force-controlled wedge runs need several times more Newton iterations (column Newton "
                "its).", ""]
    fl = {f["series"]: f for f in data.get("floors", []) if f["case"] == hz}
    c, b_, p_ = (fl.get(k) for k in ("case (W = H = 40 a, circle)", "W = H = 640 a, circle",
                                       "W = H = 640 a, parabola"))
    if c and b_ and p_:
        out += ["**Hertz, case series: the errors stop at model floors, not at a method limit.** At the "
                f"finest level Nitsche P2 has p_max {c['p_max']:.1e}, rms {c['rms']:.1e}. A block 16 times "
                f"larger (W = H = 640 a) lowers them to {b_['p_max']:.1e} / {b_['rms']:.1e} (finite clamped "
                "block), and the Hertz parabola instead of the exact circle (a/R = 0.05) to "
                f"{p_['p_max']:.1e} / {p_['rms']:.1e}. The finest-three slopes of the case series are "
                "therefore ~0: they measure the distance between the modelled scene and half-plane Hertz "
                "theory, which no mesh removes.", ""]
    gp = data.get("growth_probe", [])
    if gp:
        g = data["growth_setting"]
        f1, f2 = _find(gp, degree=1), _find(gp, degree=2)
        key = {"case": g["case"], "series": g["series"], "method": "nitsche"}
        b1 = _find(rows, **key, degree=1, h_contact=f1["h_contact"]) if f1 else None
        b2 = _find(rows, **key, degree=2, h_contact=f2["h_contact"]) if f2 else None
        rs = {(x["degree"], x["metric"]): x["slope_h"] for x in data.get("growth_rates", [])}
        if f1 and f2 and b1 and b2:
            out += ["**Hertz, ideal series: the mesh grading limits the rate.** Only h_c is refined; away "
                    "from the contact zone the element size grows by the mesh builder's fixed factor 1.3 per "
                    "element, so the elements at a distance ~a from the patch never shrink. Nitsche P1 "
                    f"stagnates near rms {b1['rms']:.1e} (slope "
                    f"{_s(_slope(data, hz, 'ideal', 'nitsche', 1, 'rms'))}) and P2 flattens at rms "
                    f"{b2['rms']:.1e}, p_max {b2['p_max']:.1e} (slope "
                    f"{_s(_slope(data, hz, 'ideal', 'nitsche', 2, 'rms'))}). With growth {g['growth']:g} at "
                    f"the same h_c = {f2['h_contact']:g}: P1 rms {f1['rms']:.1e}, P2 rms {f2['rms']:.1e}, "
                    f"p_max {f2['p_max']:.1e} (slopes vs h_c: P1 rms {_s(rs.get((1, 'rms')))}, P2 rms "
                    f"{_s(rs.get((2, 'rms')))}, P2 half_width {_s(rs.get((2, 'half_width')))}), for "
                    f"{f2['ndofs']} instead of {b2['ndofs']} dofs. A study meant to show asymptotic rates "
                    "must refine the grading with h_c (growth - 1 proportional to h_c). The next limit is "
                    "the square-root edge of the Hertz pressure, p ~ sqrt(a - |x|): its best L2 "
                    "approximation error is O(h) whatever the degree, and the half-width error depends on "
                    "where the edge falls between Gauss points (hence non-monotone sequences).", ""]
    sw = [r for r in data.get("kappa0_sweep", []) if r["case"] == hz and r["degree"] == 2]
    if sw:
        txt = ", ".join(f"kappa0 = {r['kappa0']:g}: " + ("diverged" if r["failed"] else
                                                         f"p_max {r['p_max']:.1e}, rms {r['rms']:.1e}")
                        for r in sw)
        nit = _find(rows, case=hz, series="case", method="nitsche", degree=2, h_contact=KAPPA0_LEVEL)
        ref = f"; Nitsche at the same level: p_max {nit['p_max']:.1e}, rms {nit['rms']:.1e}" if nit else ""
        pen_warn = sum(1 for r in rows if r["method"] == "penalty" and "oscillation" in r.get("warnings", ""))
        n_pen = sum(1 for r in rows if r["method"] == "penalty")
        pen = _find(rows, case=hz, series="case", method="penalty", degree=2, h_contact=KAPPA0_LEVEL)
        ratio = (f"{pen['rms'] / nit['rms']:.1f} times Nitsche's" if pen and nit else "above Nitsche's")
        failed = [f"{r['kappa0']:g}" for r in data["kappa0_sweep"] if r["failed"]]
        fails = (f" Penalty runs with kappa0 in {{{', '.join(sorted(set(failed), key=float))}}} did not "
                 "converge within the solver's cut-backs (table above)." if failed else "")
        out += ["**Penalty (kappa = kappa0 E / h).** Its consistency error (a penetration p/kappa, i.e. an "
                "elastic layer of compliance h/(kappa0 E)) falls with kappa0, but the pressure read from "
                "kappa [-g]_+ at the Gauss points zig-zags between neighbouring points with an amplitude "
                f"that GROWS with kappa0 (Hertz P2, h_c = {KAPPA0_LEVEL:g}: {txt}{ref}). No kappa0 makes the "
                f"penalty error vanish: at the case's kappa0 = 1e3 its rms is {ratio}.{fails} The "
                f"solver flags the zig-zag (\"pressure oscillation\") in {pen_warn} of the {n_pen} penalty "
                "rows.", ""]
    w = [r for r in rows if r["case"] == wd and r["series"] == "case" and not r["failed"]
         and r["b_over_b0_fem"] is not None and math.isfinite(r["b_over_b0_fem"])]
    fw = {f["series"]: f for f in data.get("floors", []) if f["case"] == wd}
    if w:
        fine = [r for r in w if r["h_contact"] == min(x["h_contact"] for x in w)]
        vals = [r["b_over_b0_fem"] for r in fine]
        theory = fine[0]["b_over_b0_theory"]
        gap, spread = abs(1.0 - statistics.mean(vals) / theory), (max(vals) - min(vals)) / theory
        block = ("Block size at the finest level (Nitsche P2), b/b0 error: "
                 + ", ".join(f"{f['b_over_b0']:.1e} ({k})" for k, f in fw.items()) + ". ") if fw else ""
        tol = next((c.tolerances.get("b_over_b0") for c in [_load(wd)] if c is not None), None)
        n2w = next((r for r in fine if (r["method"], r["degree"]) == ("nitsche", 2)), None)
        verdict = ("" if tol is None or n2w is None else
                   f"Nitsche P2 at the finest level: b/b0 error {n2w['b_over_b0']:.2%}, so the case's "
                   f"acceptance ({tol:.0%}) is "
                   + ("met, by a margin set by the block size. " if n2w["b_over_b0"] <= tol else "NOT met. "))
        wslopes = [x["slope_h"] for x in data["rates"] if (x["case"], x["series"], x["metric"])
                   == (wd, "case", "rms") and x["slope_h"] is not None]
        out += [f"**Wedge.** The small-run rms slopes lie in {min(wslopes):+.2f} .. {max(wslopes):+.2f} "
                f"(Nitsche P2 {_s(_slope(data, wd, 'case', 'nitsche', 2, 'rms'))}): the classical wedge "
                "pressure is log-singular at the apex, p ~ (E* m / pi) arccosh(b/|x|), and the L2 error of a "
                "polynomial on the apex element of size h is O(h^(1/2) log h); the apex refinement (h_c/4) "
                "lowers the constant, not the rate. b/b0: at the finest level every method gives FEM b/b0 = "
                f"{min(vals):.4f} to {max(vals):.4f} (spread {spread:.2%}) against the converged theory "
                f"{theory:.4f}: a {gap:.2%} gap. {block}{verdict}rms_convective (convective run against the "
                "converged pressure) levels off too (tables): besides the block size, its floor is "
                "the linear interpolation of the log-singular theoretical pressure from the 801-point "
                "output grid of analytic.convective.solve in scripts/case_checks.py (a one-off check "
                "on the finest ideal Nitsche P2 run with an 8001-point grid gave a value about 5 "
                "times smaller); it is not a discretisation error.", ""]
    found = []
    for key, r in data["cheapest_rms"].items():
        case, series = key.split("/")
        if r:
            found.append(f"{key}: {r['method']} P{r['degree']} at h_c/a = {r['h_contact']:g} ({r['ndofs']} "
                         f"dofs, {r['time_s']:.3f} s warm, rms {r['rms']:.1e})")
            continue
        cand = _find(rows, case=case, series=series, method="nitsche", degree=2)
        sl = _slope(data, case, series, "nitsche", 2, "rms")
        if cand and sl and sl > 0:
            h_need = cand["h_contact"] * (data["rms_target"] / cand["rms"]) ** (1.0 / sl)
            found.append(f"{key}: none within the levels; Nitsche P2 reaches rms {cand['rms']:.1e} at "
                         f"h_c/a = {cand['h_contact']:g} and its slope {sl:+.2f} extrapolates to h_c/a ~ "
                         f"{h_need:.1e}")
        else:
            found.append(f"{key}: none within the levels")
    out += [f"**Cheapest configuration with rms <= {data['rms_target']:.1%}.** " + "; ".join(found) + ".", ""]
    return "\n".join(out)


def _finite_or_none(obj: Any) -> Any:
    """Replace NaN/inf by None recursively (strict JSON)."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _finite_or_none(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_finite_or_none(v) for v in obj]
    return obj


def write_outputs(data: dict, *, out_dir: Path = OUT_DIR, plot: bool = True) -> None:
    """Write convergence.json, convergence.csv, report.md (and the plots) atomically."""
    write_json(out_dir / "convergence.json", _finite_or_none(data))
    write_text(out_dir / "convergence.csv", to_csv(data["rows"]))
    write_text(out_dir / "report.md", to_markdown(data, discussion=discussion(data)))
    if plot:
        from scripts.convergence_plot import plot_study

        plot_study(data, out_dir=out_dir)


def main(argv: list[str] | None = None) -> int:
    """CLI: run the study and write ``results/convergence/``; exit 2 on bad arguments."""
    p = argparse.ArgumentParser(prog="python -m scripts.convergence", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--cases", nargs="+", default=list(CASES), help="block cases (default: %(default)s)")
    p.add_argument("--levels", nargs="+", type=float, default=list(DEFAULT_LEVELS),
                   help="h_c fractions, coarse to fine (default: %(default)s)")
    p.add_argument("--repeats", type=int, default=3, help="timed warm solves per run (default: 3)")
    p.add_argument("--no-diagnostics", action="store_true", help="skip the model floors and the kappa0 sweep")
    p.add_argument("--no-plot", action="store_true", help="skip the plots")
    p.add_argument("--out", type=Path, default=OUT_DIR, help="output folder (default: %(default)s)")
    p.add_argument("--rewrite", action="store_true", help="only rewrite report.md and plots from the JSON")
    args = p.parse_args(argv)
    try:
        if args.rewrite:
            data = json.loads((args.out / "convergence.json").read_text())
        else:
            data = run_study(cases=args.cases, levels=args.levels, repeats=args.repeats,
                             diagnostics=not args.no_diagnostics, progress=lambda s: print(s, flush=True))
    except (ValueError, FileNotFoundError) as exc:  # includes cases.CaseError
        print(f"error: {exc}", file=sys.stderr)
        return 2
    write_outputs(data, out_dir=args.out, plot=not args.no_plot)
    print(f"wrote {args.out}/convergence.json, convergence.csv, report.md"
          + ("" if args.no_plot else ", error_vs_time.png, error_vs_ndofs.png"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
