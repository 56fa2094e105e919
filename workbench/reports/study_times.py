"""The summary's table of study times (issue 27, point 4): each study's wall time, how it ran, its JIT retries,
and its ratio to the reference solve measured in the same run (:mod:`workbench.studies.reference`), then the
total, then the issue's own total (:data:`ISSUE_TOTAL`: ``make run`` plus convergence, stability and bench, against
:data:`ISSUE_TARGET_S`), naming what is missing from it. Reads only the studies' JSON files and the cases'
``metrics.json`` (their ``wall_time_s`` and file times); a study not run yet is listed as such.
"""

from __future__ import annotations

import json
from pathlib import Path

__all__ = ["ISSUE_TARGET_S", "ISSUE_TOTAL", "STUDY_JSONS", "make_run_time", "study_times", "study_times_markdown"]

# study -> (its JSON below the output folder, where the wall time is, where the summary record is)
STUDY_JSONS = {
    "convergence": ("convergence/convergence.json", ("study_wall_time_s",), ()),
    "stability": ("stability/stability.json", ("summary", "wall_time_s"), ("summary",)),
    "validity": ("validity/validity.json", ("summary", "wall_time_s"), ("summary",)),
    "bench": ("bench/bench.json", ("bench_wall_time_s",), ()),
    "convective-table": ("analytic/convective.json", ("wall_time_s",), ()),
}


ISSUE_TOTAL = ("convergence", "stability", "bench")
"""The studies that issue 27 (point 4) times together with ``make run``."""
ISSUE_TARGET_S = 600.0
"""Issue 27: ``make run`` plus those studies under 10 minutes on 2 cores on a quiet machine (s)."""


def _get(d: dict, keys) -> object:
    for k in keys:
        if not isinstance(d, dict):
            return None
        d = d.get(k)
    return d


def study_times(results: Path) -> dict[str, dict | None]:
    """Per study: ``{"wall_s", "executor", "workers", "jit_retries", "reference_s"}`` (None: not run yet)."""
    out: dict[str, dict | None] = {}
    for study, (rel, wall_key, rec_key) in STUDY_JSONS.items():
        f = Path(results) / rel
        try:
            data = json.loads(f.read_text())
        except (OSError, ValueError):
            out[study] = None
            continue
        rec = _get(data, rec_key) if rec_key else data
        rec = rec if isinstance(rec, dict) else {}
        ref = rec.get("reference") or {}
        where = rec.get("where") or {}
        out[study] = {"wall_s": _get(data, wall_key), "executor": rec.get("executor"), "workers": rec.get("workers"),
                      "jit_retries": rec.get("jit_retries", where.get("jit_retries")),
                      "reference_s": ref.get("solve_s")}
    return out


def _cases_time(results: Path) -> tuple[float, int]:
    """Summed whole-case wall time (s) of the cases' metrics, and how many cases."""
    total, n = 0.0, 0
    for f in sorted(Path(results).glob("*/metrics.json")):
        try:
            t = json.loads(f.read_text()).get("wall_time_s")
        except (OSError, ValueError):
            continue
        if isinstance(t, int | float):
            total, n = total + float(t), n + 1
    return total, n


def make_run_time(results: Path) -> tuple[float, str] | None:
    """The wall time of ``make run``'s cases (s) and how it was found, or None when no case has run.

    From the cases' ``metrics.json``: each case started ``wall_time_s`` before its file was written, so the span
    from the first start to the last file is the elapsed time of cases run together (``make run`` runs two at once;
    the span leaves out each process's start-up before its case and the summary report after the last). When that
    span is longer than the summed case times, the cases were not run together (idle gaps): the sum is used.
    """
    spans, total = [], 0.0
    for f in sorted(Path(results).glob("*/metrics.json")):
        try:
            t = json.loads(f.read_text()).get("wall_time_s")
            mtime = f.stat().st_mtime
        except (OSError, ValueError):
            continue
        if isinstance(t, int | float):
            spans.append((mtime - float(t), mtime))
            total += float(t)
    if not spans:
        return None
    span = max(e for _, e in spans) - min(s for s, _ in spans)
    if span <= total:
        return span, f"{len(spans)} cases, first start to last metrics.json"
    return total, f"{len(spans)} cases run at different times: their summed wall times"


def _issue_total(results: Path, times: dict[str, dict | None]) -> list[str]:
    """One line: ``make run`` + :data:`ISSUE_TOTAL` against :data:`ISSUE_TARGET_S`, or what is missing."""
    parts, missing = [], []
    run = make_run_time(results)
    if run is None:
        missing.append("`make run` (no case metrics)")
    else:
        parts.append((f"`make run` {run[0]:.0f} s ({run[1]})", run[0]))
    for study in ISSUE_TOTAL:
        t = times.get(study)
        if t is None or not isinstance(t.get("wall_s"), int | float):
            missing.append(study)
        else:
            parts.append((f"{study} {t['wall_s']:.0f} s", float(t["wall_s"])))
    total = sum(v for _, v in parts)
    what = " + ".join(text for text, _ in parts) or "nothing measured yet"
    if missing:
        return [f"**`make run` + {' + '.join(ISSUE_TOTAL)}: incomplete**, not run yet: {', '.join(missing)} "
                f"(measured so far: {total:.0f} s = {what}).", ""]
    ok = total <= ISSUE_TARGET_S
    return [f"**`make run` + {' + '.join(ISSUE_TOTAL)}: {total:.0f} s ({total / 60:.1f} min)** = {what}; the "
            f"issue's target, under {ISSUE_TARGET_S / 60:.0f} min on 2 cores on a quiet machine: "
            f"{'met' if ok else 'NOT met'} here (on a loaded machine compare the reference-solve ratios above).", ""]


def study_times_markdown(results: Path) -> list[str]:
    """The ``## Study times`` section of the summary."""
    times = study_times(results)
    lines = ["## Study times", "",
             "Wall time of each study's last run (s), how it ran, its JIT retries (0 expected: every worker "
             "compiles into its own cache) and the same time in reference solves (hertz_cylinder at its default "
             "level, warm, measured in that study's run: on a loaded machine compare these ratios).", "",
             "| study | wall time (s) | executor | JIT retries | in reference solves |", "|---|---|---|---|---|"]
    total = 0.0
    cases_s, n_cases = _cases_time(results)
    if n_cases:
        total += cases_s
        lines.append(f"| cases (`make run`: summed wall times of {n_cases} cases) | {cases_s:.0f} | - | - | - |")
    for study, t in times.items():
        if t is None or not isinstance(t.get("wall_s"), int | float):
            lines.append(f"| {study} | not run yet | | | |")
            continue
        total += t["wall_s"]
        how = f"{t['executor']}, {t['workers']} worker(s)" if t.get("executor") else "in one process"
        retries = "-" if t.get("jit_retries") is None else str(t["jit_retries"])
        ratio = f"{t['wall_s'] / t['reference_s']:.0f}" if t.get("reference_s") else "-"
        lines.append(f"| {study} | {t['wall_s']:.0f} | {how} | {retries} | {ratio} |")
    lines += [f"| **total** | **{total:.0f}** | | | |", ""]
    return lines + _issue_total(results, times)
