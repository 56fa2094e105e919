"""Convergence study (issue "Error against run time"): error against ndofs and WARM wall time.

Run: ``python -m scripts.convergence`` (``make convergence``) -> ``results/convergence/`` with
``convergence.json`` (everything), ``convergence.csv`` (one row per case x method x degree x level),
``report.md`` and, from :mod:`scripts.convergence_plot`, ``error_vs_time.png`` and ``error_vs_ndofs.png``.
All files are written atomically. Computing lives here; plotting reads the JSON.

Study: for ``hertz_cylinder`` and ``wedge_convective``, every contact element size ``h_c`` of ``levels``
(fractions of the classical half-width) x method {penalty, nitsche} x Lagrange degree {1, 2}; everything else
is the case file (penalty kappa0 = 1e3, Nitsche gamma0 = 10, block W = H = 40 a, mesh growth 1.3). Each run is
solved once to warm the JIT and file caches (its time is kept as ``cold_s``), then ``repeats`` more identical
times; ``time_s`` is the median of those warm solver times (``fem.solver`` load stepping only, no meshing).

Errors (relative, dimensionless; :mod:`scripts.compare` defines p_max, half_width, rms, load_balance):
    hertz:  p_max, half_width, rms = RMS(p - p_H)/p0 over |x| <= 1.05 max(a_fem, a) (trapezoid over the
            samples), l2 = the same mean with the Gauss weights of the contact facets
            (:func:`l2_pressure_error`).
    wedge:  half_width, rms, l2 of the ``small`` run (p_ref = P/(2b), the mean pressure), and b_over_b0 =
            |(b/b0)_fem - (b/b0)_converged| / (b/b0)_converged from the small/convective pair
            (:func:`scripts.case_checks.fem_b_over_b0`); its time is that of the pair (``time_pair_s``).

Observed rates: least-squares slope of log(error) against log(h_c) and against log(ndofs) over the finest
three levels (:func:`fit_rate`): error ~ h^slope_h, error ~ ndofs^slope_ndofs.
"""

from __future__ import annotations

import argparse
import csv
import io
import math
import statistics
import sys
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
    "fit_rate",
    "l2_pressure_error",
    "main",
    "observed_rates",
    "run_study",
    "to_csv",
    "to_markdown",
]

OUT_DIR = Path("results") / "convergence"
CASES = ("hertz_cylinder", "wedge_convective")
DEFAULT_LEVELS = (0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625, 0.003125)
METHODS = ("penalty", "nitsche")
DEGREES = (1, 2)
N_FINEST = 3
RMS_TARGET = 0.005  # issue: cheapest configuration with RMS/p_ref <= 0.5 %
# error metrics of each case (row keys), and which time column they are plotted against
METRICS = {
    "hertz_cylinder": ("p_max", "half_width", "rms", "l2"),
    "wedge_convective": ("b_over_b0", "half_width", "rms", "l2"),
}
TIME_OF = {"b_over_b0": "time_pair_s"}  # default "time_s"
# model-floor diagnostics at the finest level (Nitsche): geometry overrides applied to the case's runs
FLOOR_VARIANTS = {
    "hertz_cylinder": {"case (W = H = 40 a, circle)": {},
                       "W = H = 320 a, circle": {"width_factor": 320.0, "height_factor": 320.0},
                       "W = H = 320 a, parabola": {"width_factor": 320.0, "height_factor": 320.0,
                                                   "indenter": "parabola"}},
    "wedge_convective": {"case (W = H = 40 b0)": {},
                         "W = H = 320 b0": {"width_factor": 320.0, "height_factor": 320.0}},
}


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
    |x_q| <= 1.05 max(a_fem, a) (the band of :func:`scripts.compare.rms_error`), w_q = Gauss weight times
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
    outcome: Any       # the last scripts.scene_block.BlockOutcome
    cold_s: float      # solver time of the warm-up solve (s)
    warm_s: list       # solver times of the repeated identical solves (s)
    spread: float      # max relative change of the rms error across the solves (determinism check)


def _timed_run(run, *, name: str, repeats: int, comm, progress: Callable[[str], None]) -> _Timed:
    """Warm-up solve, then ``repeats`` identical solves; returns the last outcome and the times."""
    from scripts.scene_block import run_block

    quiet = lambda s: None  # noqa: E731
    first = run_block(run, name=name, stage=None, comm=comm, progress=quiet)
    cold = first.metrics["wall_time_s"]
    rms0 = first.metrics["errors"]["rms"]
    warm, spread, last = [], 0.0, first
    for _ in range(repeats):
        last = run_block(run, name=name, stage=None, comm=comm, progress=quiet)
        warm.append(last.metrics["wall_time_s"])
        spread = max(spread, abs(last.metrics["errors"]["rms"] - rms0) / max(abs(rms0), 1e-300))
    return _Timed(last, cold, warm, spread)


def _configure(run, *, method: str, degree: int, geometry: dict | None = None):
    """The run with another contact method, Lagrange degree and (optionally) geometry overrides."""
    return replace(run, solver=replace(run.solver, method=method),
                   discretisation=replace(run.discretisation, degree=degree),
                   geometry=replace(run.geometry, **(geometry or {})))


def _row(case_name: str, method: str, degree: int, level: float, timed: dict[str, _Timed]) -> dict:
    """One CSV/JSON row from the timed runs of one configuration."""
    from scripts.case_checks import convective_theory, fem_b_over_b0

    main_label = "small" if "small" in timed else "base"
    t = timed[main_label]
    o, m = t.outcome, t.outcome.metrics
    row = {
        "case": case_name, "method": method, "degree": degree, "h_contact": level,
        "h_mm": level * float(o.theory.half_width), "ndofs": m["ndofs"], "cells": m["mesh"].get("cells"),
        "time_s": statistics.median(t.warm_s), "cold_s": t.cold_s,
        "time_pair_s": sum(statistics.median(x.warm_s) for x in timed.values()),
        "newton_iterations": int(sum(m["newton_iterations"])),
        "repeat_spread": max(x.spread for x in timed.values()),
        "p_max": m["errors"].get("p_max", math.nan), "half_width": m["errors"]["half_width"],
        "rms": m["errors"]["rms"],
        "l2": l2_pressure_error(o.result.samples, o.theory, half_width_fem=m["patch_half_width"]),
        "load_balance": max(x.outcome.metrics["errors"]["load_balance"] for x in timed.values()),
        "b_over_b0": math.nan, "b_over_b0_fem": math.nan, "b_over_b0_theory": math.nan,
    }
    if {"small", "convective"} <= set(timed):
        conv = timed["convective"].outcome
        ratio = fem_b_over_b0(o, conv)
        exact = convective_theory(conv).b_over_b0_converged
        row.update(b_over_b0_fem=ratio, b_over_b0_theory=exact, b_over_b0=abs(ratio - exact) / exact)
    return row


def observed_rates(rows: list[dict], *, metrics: dict[str, Sequence[str]] = METRICS,
                   n_finest: int = N_FINEST) -> list[dict]:
    """Fitted slopes per case x method x degree x metric, against h_c and against ndofs.

    Rows of one configuration are ordered coarse to fine (h_c decreasing). A metric with a non-finite or zero
    error on a fitted level gets ``None`` slopes and the reason in ``note``.
    """
    out = []
    keys = sorted({(r["case"], r["method"], r["degree"]) for r in rows})
    for case, method, degree in keys:
        sel = sorted((r for r in rows if (r["case"], r["method"], r["degree"]) == (case, method, degree)),
                     key=lambda r: -r["h_contact"])
        h = [r["h_contact"] for r in sel]
        n = [r["ndofs"] for r in sel]
        for metric in metrics.get(case, ()):
            err = [r[metric] for r in sel]
            rec = {"case": case, "method": method, "degree": degree, "metric": metric,
                   "levels": h[-n_finest:], "slope_h": None, "slope_ndofs": None, "note": ""}
            try:
                fh, fn = fit_rate(h, err, n_finest=n_finest), fit_rate(n, err, n_finest=n_finest)
                rec.update(slope_h=fh.slope, slope_ndofs=fn.slope, max_residual_h=fh.max_residual)
            except ValueError as exc:
                rec["note"] = str(exc)
            out.append(rec)
    return out


def cheapest(rows: list[dict], *, metric: str = "rms", target: float = RMS_TARGET) -> dict[str, dict | None]:
    """Per case, the row with the smallest warm time among those with ``row[metric] <= target``."""
    out = {}
    for case in sorted({r["case"] for r in rows}):
        ok = [r for r in rows if r["case"] == case and r[metric] is not None and r[metric] <= target]
        out[case] = min(ok, key=lambda r: r["time_s"]) if ok else None
    return out


def _floors(case, level: float, *, comm, progress) -> list[dict]:
    """Model-floor diagnostics: Nitsche P1/P2 at the finest level with bigger blocks / a parabola."""
    from scripts.scene_block import run_block

    out = []
    for label, geo in FLOOR_VARIANTS.get(case.name, {}).items():
        for degree in DEGREES:
            run = case.runs(h_contact=level)[0]  # the small (or base) run
            o = run_block(_configure(run, method="nitsche", degree=degree, geometry=geo), name=case.name,
                          stage=None, comm=comm, progress=lambda s: None)
            e = o.metrics["errors"]
            rec = {"case": case.name, "variant": label, "degree": degree, "h_contact": level,
                   "ndofs": o.metrics["ndofs"], "p_max": e.get("p_max", math.nan),
                   "half_width": e["half_width"], "rms": e["rms"],
                   "l2": l2_pressure_error(o.result.samples, o.theory,
                                           half_width_fem=o.metrics["patch_half_width"])}
            progress(f"floor {case.name} [{label}] P{degree}: rms {rec['rms']:.3e} p_max {rec['p_max']:.3e} "
                     f"half_width {rec['half_width']:.3e}")
            out.append(rec)
    return out


def run_study(*, cases: Sequence[str] = CASES, levels: Sequence[float] = DEFAULT_LEVELS, repeats: int = 3,
              floors: bool = True, progress: Callable[[str], None] = print) -> dict:
    """Run the whole study and return the JSON-ready data (no files written).

    Args:
        cases: Case names (block scenes).
        levels: h_c fractions of the classical half-width, coarse to fine, each in (0, 1].
        repeats: Timed warm solves per run after the warm-up solve, >= 1 (the median is kept).
        floors: Also run the model-floor diagnostics at the finest level.
        progress: One-line status output.
    """
    import dolfinx_solver  # noqa: F401  (before mpi4py/dolfinx)

    import time

    from mpi4py import MPI

    from cases import load_case

    levels = [float(v) for v in levels]
    if len(levels) < N_FINEST or any(not 0 < v <= 1 for v in levels) or np.any(np.diff(levels) >= 0):
        raise ValueError(f"levels must be >= {N_FINEST} strictly decreasing values in (0, 1], got {levels}")
    if int(repeats) != repeats or repeats < 1:
        raise ValueError(f"repeats must be an integer >= 1, got {repeats!r}")
    loaded = [load_case(c) for c in cases]  # validate all before running any
    comm = MPI.COMM_WORLD
    t0 = time.perf_counter()
    rows, floor_rows = [], []
    for case in loaded:
        for method in METHODS:
            for degree in DEGREES:
                for level in levels:
                    timed = {run.label: _timed_run(_configure(run, method=method, degree=degree),
                                                   name=case.name, repeats=repeats, comm=comm, progress=progress)
                             for run in case.runs(h_contact=level)}
                    row = _row(case.name, method, degree, level, timed)
                    rows.append(row)
                    progress(f"{case.name} {method} P{degree} h_c={level:g}: ndofs {row['ndofs']}, warm "
                             f"{row['time_s']:.3f} s (cold {row['cold_s']:.2f} s), rms {row['rms']:.3e}, "
                             f"half_width {row['half_width']:.3e}, p_max {row['p_max']:.3e}, "
                             f"b/b0 {row['b_over_b0']:.3e}")
        if floors:
            floor_rows += _floors(case, levels[-1], comm=comm, progress=progress)
    return {
        "description": "error against ndofs and warm solver time; see scripts/convergence.py",
        "levels": levels, "repeats": repeats, "n_finest": N_FINEST, "metrics": METRICS, "time_of": TIME_OF,
        "rms_target": RMS_TARGET, "rows": rows, "rates": observed_rates(rows),
        "cheapest_rms": cheapest(rows), "floors": floor_rows, "study_wall_time_s": time.perf_counter() - t0,
    }


CSV_COLUMNS = ("case", "method", "degree", "h_contact", "h_mm", "ndofs", "cells", "time_s", "cold_s",
               "time_pair_s", "newton_iterations", "p_max", "half_width", "rms", "l2", "b_over_b0",
               "b_over_b0_fem", "b_over_b0_theory", "load_balance", "repeat_spread")


def to_csv(rows: list[dict]) -> str:
    """CSV text, one row per case x method x degree x level (columns :data:`CSV_COLUMNS`)."""
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=CSV_COLUMNS, extrasaction="ignore", lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: (f"{v:.8g}" if isinstance(v, float) else v) for k, v in r.items()})
    return buf.getvalue()


def _e(v) -> str:
    return "-" if v is None or (isinstance(v, float) and not math.isfinite(v)) else f"{v:.2e}"


def _s(v) -> str:
    return "-" if v is None else f"{v:+.2f}"


def to_markdown(data: dict, *, discussion: str = "") -> str:
    """The tables of ``report.md`` (errors, fitted slopes, cheapest configuration, floors) + a discussion."""
    lines = ["# Convergence study: error against run time", "",
             f"Levels h_c/a = {', '.join(f'{v:g}' for v in data['levels'])}; times are WARM solver times: "
             f"each run was solved once to warm the JIT cache, then {data['repeats']} more identical times, and "
             f"the median is reported (cold = the first solve). Whole study: {data['study_wall_time_s']:.0f} s "
             "(serial, 1 process). Slopes: least squares of log(error) against log(h_c) and log(ndofs) over "
             f"the finest {data['n_finest']} levels.", ""]
    for case in sorted({r["case"] for r in data["rows"]}):
        mets = data["metrics"][case]
        lines += [f"## {case}", "", "| method | P | h_c/a | ndofs | warm s | cold s | "
                  + " | ".join(mets) + " | Newton its |", "|---" * (6 + len(mets) + 1) + "|"]
        for r in (r for r in data["rows"] if r["case"] == case):
            t = r["time_pair_s"] if case.startswith("wedge") else r["time_s"]
            lines.append(f"| {r['method']} | {r['degree']} | {r['h_contact']:g} | {r['ndofs']} | {t:.3f} | "
                         f"{r['cold_s']:.2f} | " + " | ".join(_e(r[m]) for m in mets)
                         + f" | {r['newton_iterations']} |")
        if case.startswith("wedge"):
            lines += ["", "Wedge times are those of the small + convective pair (b/b0 needs both); "
                      "half_width, rms and l2 are of the small run alone (relative to the mean pressure P/(2b))."]
        lines += ["", f"Fitted slopes (finest {data['n_finest']} levels): vs h_c / vs ndofs", "",
                  "| method | P | " + " | ".join(mets) + " |", "|---" * (2 + len(mets)) + "|"]
        for method, degree in sorted({(r["method"], r["degree"]) for r in data["rows"] if r["case"] == case}):
            cells = []
            for m in mets:
                f = next(x for x in data["rates"] if (x["case"], x["method"], x["degree"], x["metric"])
                         == (case, method, degree, m))
                cells.append(f"{_s(f['slope_h'])} / {_s(f['slope_ndofs'])}")
            lines.append(f"| {method} | {degree} | " + " | ".join(cells) + " |")
        best = data["cheapest_rms"].get(case)
        found = (f"{best['method']} P{best['degree']} h_c/a = {best['h_contact']:g} ({best['ndofs']} dofs, "
                 f"warm {best['time_s']:.3f} s, rms {best['rms']:.2e})" if best else "none reached it")
        lines += ["", f"Cheapest configuration with rms <= {data['rms_target']:.1%}: {found}", ""]
    if data.get("floors"):
        lines += ["## Model floors (Nitsche, finest level)", "",
                  "| case | variant | P | ndofs | p_max | half_width | rms | l2 |", "|---" * 8 + "|"]
        for f in data["floors"]:
            lines.append(f"| {f['case']} | {f['variant']} | {f['degree']} | {f['ndofs']} | "
                         f"{_e(f['p_max'])} | {_e(f['half_width'])} | {_e(f['rms'])} | {_e(f['l2'])} |")
        lines.append("")
    if discussion:
        lines += [discussion.strip(), ""]
    return "\n".join(lines)


def _finite_or_none(obj: Any) -> Any:
    """Replace NaN/inf by None recursively (strict JSON)."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _finite_or_none(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_finite_or_none(v) for v in obj]
    return obj


def discussion(data: dict) -> str:
    """Discussion section of the report (placeholder until measured)."""
    return ""


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
    p.add_argument("--no-floors", action="store_true", help="skip the model-floor diagnostics")
    p.add_argument("--no-plot", action="store_true", help="skip the plots")
    p.add_argument("--out", type=Path, default=OUT_DIR, help="output folder (default: %(default)s)")
    p.add_argument("--replot", action="store_true", help="only rewrite report.md and plots from the JSON")
    args = p.parse_args(argv)
    try:
        if args.replot:
            import json

            data = json.loads((args.out / "convergence.json").read_text())
        else:
            data = run_study(cases=args.cases, levels=args.levels, repeats=args.repeats,
                             floors=not args.no_floors, progress=lambda s: print(s, flush=True))
        write_outputs(data, out_dir=args.out, plot=not args.no_plot)
    except ValueError as exc:  # includes cases.CaseError
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(f"wrote {args.out}/convergence.json, convergence.csv, report.md" + ("" if args.no_plot else
                                                                             ", error_vs_time.png"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
