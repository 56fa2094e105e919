"""Convergence study (issue "Error against run time"): error against ndofs and WARM wall time.

Run: ``workbench convergence [options]`` -> ``<results>/convergence/``: convergence.json (the config and every
row), convergence.csv (one row per case x series x method x degree x level) and, from the JSON, report.md
(:mod:`workbench.studies.convergence_report`) and error_vs_time/ndofs.png
(:mod:`workbench.studies.convergence_plot`); atomic. What is run is :class:`ConvergenceConfig`.

Study: for ``hertz_cylinder`` and ``wedge_convective``, method {penalty, nitsche} x Lagrange degree {1, 2} x
contact element size ``h_c`` (fraction of the classical half-width a or b0), in two series:

* ``case``: the case file as it is (kappa0 = 1e3, gamma0 = 10, mesh growth 1.3, Hertz block 40 a with the
  exact circle, wedge block 160 b0), refined in h_c only (``levels``). Its errors stop at the model floors
  (finite block, circle against parabola) and at the fixed far-field grading.
* ``ideal``: the model floors removed (block 640 a, Hertz parabola) AND the grading refined with h_c,
  growth = 1 + ``growth_per_h`` h_c (:func:`ideal_growth`), so that the whole size field
  h(d) = h_c a + (growth - 1) d scales with h_c: a genuine h-refinement family (``ideal_levels``).

Each run goes through the case pipeline (:func:`workbench.pipeline.run_case.run_one`: its scene's mesh, the
wiring's solve, its scene's comparison) once to warm the JIT and file caches (``cold_s``), then ``repeats``
more identical times; ``time_s`` is the median of those warm solver times (``fem.solver`` load stepping only,
no meshing). A case's runs are judged together by its scene (``scene_for(run).judge``: b/b0).

Errors (relative, dimensionless; formulas in :mod:`workbench.scenes.block_theory` and
:mod:`workbench.scenes.convective`):
    p_max, half_width, rms (RMS(p - p_th)/p_ref over |x| <= 1.05 max(a_fem, a), trapezoid over the samples),
    l2 (the same mean with the contact-facet Gauss weights, :func:`l2_pressure_error`) and, Hertz only,
    l2_inner (the same on |x| <= 0.8 a, away from the square-root edges); p_ref = p0 (Hertz) or P/(2b)
    (wedge). Wedge: those of the ``small`` run, plus the case-level b_over_b0 (FEM b/b0 against the
    converged Ciavarella-Hills value) and rms_convective (convective run against the converged theory), both
    timed by the small + convective pair (``time_pair_s``).

Observed rates: least-squares slope of log(error) against log(h_c) and against log(ndofs) over the finest
three levels (:func:`workbench.studies.rates.fit_rate`), judged against ``expected_rates`` +- ``rate_band``
(:func:`judge_rates`).
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
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from workbench.atomic import write_json, write_text
from workbench.owned import ensure_dir
from workbench.studies.config import to_json
from workbench.studies.convergence_config import ConvergenceConfig
from workbench.studies.executor import (
    ExecutorChoice,
    add_executor_options,
    executor_from_args,
    run_points,
    worker_summary,
)
from workbench.studies.rates import fit_rate
from workbench.studies.scene_point import run_failure

__all__ = ["ConvergenceConfig", "Point", "cheapest", "ideal_growth", "judge_rates", "l2_pressure_error", "main",
           "observed_rates", "points", "run_convergence_point", "run_study", "to_csv", "write_outputs"]

_DEFAULT = ConvergenceConfig()


def ideal_growth(h_contact: float, *, config: ConvergenceConfig = _DEFAULT) -> float:
    """Mesh growth of the ideal series: 1 + growth_per_h h_c, so the size field scales with h_c.

    Args:
        h_contact: Contact element size as a fraction of the half-width, in [0.025, 0.5] by default (so that
            the growth stays in the case schema's range [1.05, 2]).
        config: The study's config (growth_per_h, growth_range).
    """
    return config.ideal_growth(h_contact)


def l2_pressure_error(samples, theory, *, half_width_fem: float, x_max: float | None = None) -> float:
    """Gauss-quadrature L2 mean of the pressure error on the patch, relative to the reference pressure.

    l2 = sqrt( sum_q w_q (p_q - p_th(x_q))^2 / sum_q w_q ) / p_ref over the contact-facet Gauss points with
    |x_q| <= 1.05 max(a_fem, a) (the band of :func:`workbench.scenes.block_theory.rms_error`), or |x_q| <= x_max when
    given; w_q = Gauss weight times facet length (mm). These are the points where the discrete contact law
    holds.

    Args:
        samples: :class:`fem.postprocess.SurfaceSamples` (``s``, ``p``, ``weight``); a half model's samples.
        theory: :class:`workbench.scenes.block_theory.BlockTheory` at the measured load (``pressure``, ``half_width``,
            ``p_ref``).
        half_width_fem: FEM half-width of the patch (mm).
        x_max: Optional band half-length (mm), > 0, replacing the default band.
    """
    s, p, w = np.asarray(samples.s), np.asarray(samples.p), np.asarray(samples.weight)
    if x_max is not None and not x_max > 0:
        raise ValueError(f"x_max must be > 0 (mm), got {x_max}")
    band = max(half_width_fem, theory.half_width) if math.isfinite(half_width_fem) else theory.half_width
    lim = 1.05 * band if x_max is None else x_max
    p_th = theory.pressure(s)
    keep = (np.abs(s) <= lim) & np.isfinite(p_th)
    if not np.any(keep):
        return math.nan
    d2 = (p[keep] - p_th[keep]) ** 2
    return float(math.sqrt(np.sum(w[keep] * d2) / np.sum(w[keep])) / theory.p_ref)


class _Timed(NamedTuple):
    outcome: Any       # the last workbench.scenes.base.Outcome
    cold_s: float      # solver time of the first solve (s)
    warm_s: list       # solver times of the repeated identical solves (s); [cold_s] when repeats = 0
    spread: float      # max relative change of the FEM half-width across the solves (determinism check)


def _timed_run(run, *, name: str, repeats: int, comm, mesh_cache: Path) -> _Timed:
    """First (warm-up) solve, then ``repeats`` identical solves; returns the last outcome and the times."""
    from workbench.pipeline.run_case import run_one

    def solve():
        return run_one(run, name=name, mesh_cache=mesh_cache, comm=comm, progress=lambda s: None)

    first = last = solve()
    a0, warm, spread = first.metrics["patch_half_width"], [], 0.0
    for _ in range(repeats):
        last = solve()
        warm.append(last.metrics["wall_time_s"])
        spread = max(spread, abs(last.metrics["patch_half_width"] - a0) / abs(a0))
    return _Timed(last, first.metrics["wall_time_s"], warm or [first.metrics["wall_time_s"]], spread)


def _configure(run, *, method: str, degree: int, geometry: dict, growth: float | None,
               kappa0: float | None = None):
    """The run with another contact method, degree, mesh growth, geometry overrides and penalty factor."""
    solver = replace(run.solver, method=method, **({} if kappa0 is None else {"kappa0": kappa0}))
    disc = replace(run.discretisation, degree=degree, **({} if growth is None else {"growth": growth}))
    return replace(run, solver=solver, discretisation=disc, geometry=replace(run.geometry, **geometry))


def _measure(case, cfg: ConvergenceConfig, *, series: str, geometry: dict, method: str, degree: int, level: float,
             repeats: int, comm, growth: float | None = None, kappa0: float | None = None) -> dict:
    """One configuration: every run of the case, timed; returns its CSV/JSON row (NaN errors on failure)."""
    from workbench.scenes import scene_for

    row = {"case": case.name, "series": series, "method": method, "degree": degree, "h_contact": level,
           "growth": growth if growth is not None else case.discretisation.growth,
           "kappa0": kappa0 if kappa0 is not None else case.solver.kappa0, "failed": ""}
    row.update({k: math.nan for k in ("p_max", "half_width", "rms", "l2", "l2_inner", "b_over_b0",
                                      "b_over_b0_fem", "b_over_b0_theory", "rms_convective", "load_balance",
                                      "time_s", "cold_s", "time_pair_s", "cold_pair_s", "h_mm")})
    row.update(ndofs=0, cells=0, newton_iterations=0, repeat_spread=0.0, warnings="")
    try:
        timed = {run.label: _timed_run(_configure(run, method=method, degree=degree, geometry=geometry,
                                                  growth=growth, kappa0=kappa0),
                                       name=case.name, repeats=repeats, comm=comm, mesh_cache=cfg.cache_dir)
                 for run in case.runs(h_contact=level)}
    except RuntimeError as exc:  # fem.solver.ContactSolveError: record (named), keep the study going
        row["failed"] = run_failure(exc)
        return row
    t = timed.get("small", timed.get("base", next(iter(timed.values()))))
    o, m = t.outcome, t.outcome.metrics
    smp, a_fem = o.result.samples, m["patch_half_width"]
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
        rms=m["errors"]["rms"], l2=l2_pressure_error(smp, o.theory, half_width_fem=a_fem),
        load_balance=max(x.outcome.metrics["errors"]["load_balance"] for x in timed.values()),
    )
    if o.theory.kind != "wedge":  # the wedge pressure is log-singular at x = 0: no smooth inner band
        row["l2_inner"] = l2_pressure_error(smp, o.theory, half_width_fem=a_fem,
                                            x_max=cfg.inner * float(o.theory.half_width))
    if len(timed) > 1:
        outcomes = [x.outcome for x in timed.values()]
        cmp = scene_for(outcomes[0].run).judge(case, outcomes)
        row.update(b_over_b0=float(cmp.errors.get("b_over_b0", math.nan)),
                   rms_convective=float(cmp.errors.get("rms_convective", math.nan)),
                   b_over_b0_fem=float(cmp.analytic.get("b_over_b0_fem", math.nan)),
                   b_over_b0_theory=float(cmp.analytic.get("b_over_b0_converged", math.nan)))
    return row


def _group(rows: list[dict], *keys: str) -> dict[tuple, list[dict]]:
    out: dict[tuple, list[dict]] = {}
    for r in rows:
        out.setdefault(tuple(r[k] for k in keys), []).append(r)
    return out


def observed_rates(rows: list[dict], *, metrics: dict[str, Sequence[str]] = _DEFAULT.metrics,
                   n_finest: int = _DEFAULT.n_finest) -> list[dict]:
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
            err = [math.nan if r.get(metric) is None else r[metric] for r in sel]
            rec = {"case": case, "series": series, "method": method, "degree": degree, "metric": metric,
                   "levels": h[-n_finest:], "slope_h": None, "slope_ndofs": None, "note": ""}
            try:
                fh, fn = fit_rate(h, err, n_finest=n_finest), fit_rate(n, err, n_finest=n_finest)
                rec.update(slope_h=fh.slope, slope_ndofs=fn.slope, max_residual_h=fh.max_residual)
            except ValueError as exc:
                rec["note"] = str(exc)
            out.append(rec)
    return out


def judge_rates(rates: list[dict], *, expected: dict[str, dict[str, float]] = _DEFAULT.expected_rates,
                band: float = _DEFAULT.rate_band) -> list[dict]:
    """Each rate record with ``expected`` (slope against h_c, or None) and ``verdict``.

    verdict: ``"within"`` when |slope_h - expected| <= band, ``"outside"`` otherwise, ``"no fit"`` when the
    slope could not be fitted, ``""`` when no rate is expected for that case/series/metric.
    """
    if not band > 0:
        raise ValueError(f"band must be > 0, got {band}")
    out = []
    for r in rates:
        exp = expected.get(f"{r['case']}/{r['series']}", {}).get(r["metric"])
        if exp is None:
            verdict = ""
        elif r["slope_h"] is None:
            verdict = "no fit"
        else:
            verdict = "within" if abs(r["slope_h"] - exp) <= band else "outside"
        out.append({**r, "expected": exp, "verdict": verdict})
    return out


def _extension_rates(rows: list[dict], ext: list[dict], cfg: ConvergenceConfig) -> list[dict]:
    """Rates of the ideal series refitted with the extension level (its finest levels), judged."""
    if not ext:
        return []
    case, series = cfg.extension["case"], cfg.extension["series"]
    label = f"{series} + extension"
    sel = [{**r, "series": label} for r in rows if (r["case"], r["series"]) == (case, series)] + ext
    return judge_rates(observed_rates(sel, metrics=cfg.metrics, n_finest=cfg.n_finest),
                       expected={f"{case}/{label}": cfg.expected_rates[f"{case}/{series}"]}, band=cfg.rate_band)


def cheapest(rows: list[dict], *, metric: str = "rms", target: float = _DEFAULT.rms_target) -> dict[str, dict | None]:
    """Per ``case/series``, the row with the smallest warm time among those with ``row[metric] <= target``."""
    out = {}
    for (case, series), sel in sorted(_group(rows, "case", "series").items()):
        ok = [r for r in sel if r[metric] is not None and r[metric] <= target]
        out[f"{case}/{series}"] = min(ok, key=lambda r: r["time_s"]) if ok else None
    return out


@dataclass(frozen=True)
class Point:
    """One configuration of the study for the shared runner (:func:`workbench.studies.executor.run_points`).

    Attributes:
        group: Where its row goes: ``rows``, ``floors``, ``kappa0_sweep``, ``grading_probe``, ``extension`` or
            ``perturbed``.  section: Its entry of ``section_wall_time_s``.  relabel: The row's ``series`` when it
            differs from the measured series (e.g. ``kappa0 sweep``).
        case, series, geometry, method, degree, level, repeats, growth, kappa0: :func:`_measure`'s arguments.
        cfg: The study's config.
    """

    group: str
    section: str
    case: str
    series: str
    geometry: dict
    method: str
    degree: int
    level: float
    repeats: int
    cfg: ConvergenceConfig
    growth: float | None = None
    kappa0: float | None = None
    relabel: str | None = None


_CASES: dict = {}


def run_convergence_point(point: Point) -> dict:
    """The study's point function (module level: sent to the workers by name): :func:`_measure` on
    ``MPI.COMM_SELF``, its row tagged with ``group`` and ``section``."""
    from mpi4py import MPI

    import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
    from cases import load_case

    if point.case not in _CASES:
        _CASES[point.case] = load_case(point.case)
    row = _measure(_CASES[point.case], point.cfg, series=point.series, geometry=point.geometry, method=point.method,
                   degree=point.degree, level=point.level, repeats=point.repeats, comm=MPI.COMM_SELF,
                   growth=point.growth, kappa0=point.kappa0)
    if point.relabel is not None:
        row["series"] = point.relabel
    return row | {"group": point.group, "section": point.section}


def points(cfg: ConvergenceConfig) -> list[Point]:
    """Every configuration of the study, in report order: the case and ideal series of each case, then (with
    ``cfg.diagnostics``) its model floors, kappa0 sweep, grading probe, extension and perturbed levels."""
    series_levels = {"case": [float(v) for v in cfg.levels], "ideal": [float(v) for v in cfg.ideal_levels]}
    out = []
    for name in cfg.cases:
        for series, geometry in cfg.series.get(name, {"case": {}}).items():
            for method in cfg.methods:
                for degree in cfg.degrees:
                    for level in series_levels[series]:
                        growth = cfg.ideal_growth(level) if series == "ideal" else None
                        out.append(Point("rows", f"{name}/{series}", name, series, geometry, method, degree, level,
                                         cfg.repeats, cfg, growth=growth))
        if not cfg.diagnostics:
            continue
        diag = f"{name}/diagnostics"
        for label, geometry in cfg.floors.get(name, {}).items():
            out.append(Point("floors", diag, name, label, geometry, "nitsche", 2, series_levels["case"][-1], 0, cfg))
        for degree in cfg.degrees:
            for kappa0 in cfg.kappa0_sweep:
                out.append(Point("kappa0_sweep", diag, name, "case", {}, "penalty", degree, cfg.kappa0_level, 0, cfg,
                                 kappa0=kappa0, relabel="kappa0 sweep"))
        if name == cfg.grading_probe["case"]:
            g = cfg.grading_probe
            for degree in g["degrees"]:
                for level in series_levels["ideal"][-cfg.n_finest:]:
                    out.append(Point("grading_probe", diag, name, g["series"], cfg.series[name][g["series"]],
                                     "nitsche", degree, level, 0, cfg, relabel=f"{g['series']}, fixed growth"))
        if name == cfg.extension["case"]:
            lvl, series = cfg.extension["level"], cfg.extension["series"]
            geometry = cfg.series[name][series]
            for method in cfg.methods:
                for degree in cfg.degrees:
                    out.append(Point("extension", diag, name, series, geometry, method, degree, lvl, 0, cfg,
                                     growth=1.0 + cfg.growth_per_h * lvl, relabel=f"{series} + extension"))
            for h in cfg.extension["perturbed"]:
                out.append(Point("perturbed", diag, name, series, geometry, "nitsche", 2, h, 0, cfg,
                                 growth=1.0 + cfg.growth_per_h * h, relabel=f"{series}, h_c perturbed"))
    return out


def run_study(cfg: ConvergenceConfig | None = None, *, executor: ExecutorChoice | None = None,
              progress: Callable[[str], None] = print) -> dict:
    """Run the whole study of ``cfg`` (default :class:`ConvergenceConfig`) on ``executor`` (default: in this
    process, one configuration after the other: the published warm times) and return the JSON-ready data (no
    files written).

    The case series at ``cfg.levels``, the ideal series at ``cfg.ideal_levels`` (timed ``cfg.repeats`` times
    after a warm-up), and with ``cfg.diagnostics`` the model-floor decomposition (finest case level), the
    penalty kappa0 sweep, the grading probe (ideal geometry, fixed growth) and the extension level. Each
    configuration is one point (:func:`points`); ``section_wall_time_s`` sums its points' wall times.
    """
    from cases import load_case
    from workbench.studies.reference import measure_reference

    cfg = ConvergenceConfig() if cfg is None else cfg
    executor = ExecutorChoice() if executor is None else executor
    ensure_dir(cfg.cache_dir, kind="mesh_cache", kinds=("mesh_cache",))  # the workbench's own, or refused
    series_levels = {"case": [float(v) for v in cfg.levels], "ideal": [float(v) for v in cfg.ideal_levels]}
    repeats, n_finest = cfg.repeats, cfg.n_finest
    for c in cfg.cases:  # validate all before running any
        load_case(c)
    t0 = time.perf_counter()

    def say(_i: int, _n: int, r: dict) -> None:
        extra = f" kappa0={r['kappa0']:g}" if r["series"] == "kappa0 sweep" else ""
        progress(f"[{time.perf_counter() - t0:6.0f} s] {r['case']} [{r['series']}] {r['method']} "
                 f"P{r['degree']} h_c={r['h_contact']:g} growth={r['growth']:g}{extra}: "
                 + (f"FAILED {r['failed']}" if r["failed"] else
                    f"ndofs {r['ndofs']}, warm {r['time_s']:.3f} s (cold {r['cold_s']:.2f} s), "
                    f"rms {r['rms']:.2e}, half_width {r['half_width']:.2e}, p_max {r['p_max']:.2e}, "
                    f"b/b0 {r['b_over_b0']:.2e}"))

    done = run_points(run_convergence_point, points(cfg), executor=executor, progress=say)
    groups: dict = {g: [] for g in ("rows", "floors", "kappa0_sweep", "grading_probe", "extension", "perturbed")}
    section_s: dict = {}
    for r in done:
        groups[r["group"]].append(r)
        section_s[r["section"]] = section_s.get(r["section"], 0.0) + r["worker"]["wall_s"]
    rows, probe, ext = groups["rows"], groups["grading_probe"], groups["extension"]
    return {
        "description": "error against ndofs and warm solver time; see workbench/studies/convergence.py",
        "config": to_json(cfg),
        "levels": series_levels, "repeats": repeats, "n_finest": n_finest, "metrics": cfg.metrics,
        "time_of": cfg.time_of, "series": cfg.series, "growth_per_h": cfg.growth_per_h, "inner": cfg.inner,
        "rms_target": cfg.rms_target, "rate_band": cfg.rate_band, "expected_rates": cfg.expected_rates,
        "rows": rows, "rates": judge_rates(observed_rates(rows, metrics=cfg.metrics, n_finest=n_finest),
                                           expected=cfg.expected_rates, band=cfg.rate_band),
        "cheapest_rms": cheapest(rows, target=cfg.rms_target),
        "floors": groups["floors"], "kappa0_sweep": groups["kappa0_sweep"], "kappa0_level": cfg.kappa0_level,
        "grading_probe": probe, "grading_rates": observed_rates(probe, metrics=cfg.metrics, n_finest=n_finest),
        "extension": ext, "perturbed": groups["perturbed"], "extension_rates": _extension_rates(rows, ext, cfg),
        "extension_setting": cfg.extension,
        "section_wall_time_s": section_s, "study_wall_time_s": time.perf_counter() - t0,
        "executor": executor.kind, "workers": executor.workers, "where": worker_summary(done),
        "reference": measure_reference(executor=executor, mesh_cache=cfg.cache_dir),
    }


CSV_COLUMNS = ("case", "series", "method", "degree", "h_contact", "growth", "h_mm", "ndofs", "cells",
               "time_s", "cold_s", "time_pair_s", "newton_iterations", "p_max", "half_width", "rms", "l2",
               "l2_inner", "b_over_b0", "rms_convective", "b_over_b0_fem", "b_over_b0_theory", "load_balance",
               "repeat_spread", "warnings", "failed")


def to_csv(rows: list[dict]) -> str:
    """CSV text, one row per case x series x method x degree x level (columns :data:`CSV_COLUMNS`)."""
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=CSV_COLUMNS, extrasaction="ignore", lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: (f"{v:.8g}" if isinstance(v, float) else v) for k, v in r.items()})
    return buf.getvalue()


def _finite_or_none(obj: Any) -> Any:
    """Replace NaN/inf by None recursively (strict JSON)."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _finite_or_none(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_finite_or_none(v) for v in obj]
    return obj


def write_outputs(data: dict, *, out_dir: Path, plot: bool = True) -> None:
    """Write convergence.json, convergence.csv, report.md (and the plots) atomically."""
    data = _finite_or_none(data)
    write_json(out_dir / "convergence.json", data)
    write_text(out_dir / "convergence.csv", to_csv(data["rows"]))
    from workbench.studies.convergence_report import to_markdown  # after the data files: a report bug loses nothing

    write_text(out_dir / "report.md", to_markdown(data))
    if plot:
        from workbench.studies.convergence_plot import plot_study

        plot_study(data, out_dir=out_dir)


def main(argv: list[str] | None = None) -> int:
    """CLI ``workbench convergence [options]``: run the study and write ``<results>/convergence/``; exit 2 on bad
    arguments."""
    d = _DEFAULT
    p = argparse.ArgumentParser(prog="workbench convergence", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--cases", nargs="+", default=list(d.cases), help="block cases (default: %(default)s)")
    p.add_argument("--levels", nargs="+", type=float, default=list(d.levels),
                   help="h_c fractions of the case series, coarse to fine (default: %(default)s)")
    p.add_argument("--ideal-levels", nargs="+", type=float, default=list(d.ideal_levels),
                   help="h_c fractions of the ideal series, in [0.025, 0.5] (default: %(default)s)")
    p.add_argument("--repeats", type=int, default=d.repeats,
                   help="timed warm solves per run (default: %(default)s)")
    p.add_argument("--no-diagnostics", action="store_true",
                   help="skip the model floors, the kappa0 sweep and the grading probe")
    p.add_argument("--no-plot", action="store_true", help="skip the plots")
    p.add_argument("--out", type=Path, default=None, help="output folder (default: <results>/convergence)")
    p.add_argument("--mesh-cache", type=Path, default=None, help="mesh cache (default: <results>/mesh_cache)")
    p.add_argument("--rewrite", action="store_true", help="only rewrite report.md and plots from the JSON")
    add_executor_options(p, workers=1)
    args = p.parse_args(argv)
    try:
        executor = executor_from_args(args)
        cfg = ConvergenceConfig(cases=tuple(args.cases), levels=tuple(args.levels),
                                ideal_levels=tuple(args.ideal_levels), repeats=args.repeats,
                                diagnostics=not args.no_diagnostics, plot=not args.no_plot, out=args.out,
                                mesh_cache=args.mesh_cache)
        if args.rewrite:
            data = json.loads((cfg.out_dir / "convergence.json").read_text())
        else:
            from workbench.pipeline.size_estimate import check_levels_fit

            check_levels_fit(cfg.cases, cfg.levels, study="convergence", field="--levels")  # before any mesh
            data = run_study(cfg, executor=executor, progress=lambda s: print(s, flush=True))
    except (ValueError, FileNotFoundError) as exc:  # includes cases.CaseError
        print(f"error: {exc}", file=sys.stderr)
        return 2
    write_outputs(data, out_dir=cfg.out_dir, plot=cfg.plot)
    print(f"wrote {cfg.out_dir}/convergence.json, convergence.csv, report.md"
          + ("" if not cfg.plot else ", error_vs_time.png, error_vs_ndofs.png"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
