"""``make ci``: every case at its coarsest level (``ci_level``), checked against the case tolerances.

Results go to ``<out>/ci/<case>/`` (the default-resolution results are left alone); the report is
``<out>/ci_report.md``. Exit code 1 on any tolerance violation or failed run.

Which cases: every case of ``cases/``, or the ``cases`` given to :func:`run_ci`, or (for ``workbench ci``) the
case names or ``.toml`` paths in ``$WORKBENCH_CI_CASES`` (separated by spaces or commas), e.g. to run the real
CI path on one small case.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from collections.abc import Sequence

import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
from cases import case_names, load_case
from workbench.atomic import write_root_text
from workbench.owned import check_dir, check_root_file, check_run_outputs, ensure_dir
from workbench.paths import OutputPaths
from workbench.reports.markdown import markdown_to_html

__all__ = ["CI_CASES_ENV", "check_ci_writes", "ci_cases", "run_ci"]

CI_CASES_ENV = "WORKBENCH_CI_CASES"


def check_ci_writes(paths: OutputPaths, cases: Sequence[str] | None = None) -> None:
    """Refuse (:class:`workbench.paths.OutputError`, one line) before ``workbench ci`` writes anything over a file or
    into a folder the workbench did not write: ``ci_report.{md,html}``, ``<out>/ci/`` and every case folder, the
    mesh cache and the logs below it."""
    for name in ("ci_report.md", "ci_report.html"):
        check_root_file(paths.root, name)
    check_dir(paths.ci.root, kinds=("ci",))
    check_run_outputs(paths.ci, [load_case(entry) for entry in ci_cases(cases)])


def ci_cases(cases: Sequence[str] | None = None) -> list[str]:
    """The cases ``workbench ci`` runs: ``cases``, else ``$WORKBENCH_CI_CASES`` (names or .toml paths separated by
    spaces or commas), else every case of ``cases/``."""
    if cases is None:
        text = os.environ.get(CI_CASES_ENV, "")
        cases = [c for c in text.replace(",", " ").split() if c]
    return list(cases) or case_names()


def run_ci(paths: OutputPaths, *, cases: Sequence[str] | None = None, pictures: bool = True) -> int:
    """Run every case (or ``cases``, see :func:`ci_cases`) at its CI level in a subprocess each (a crash of one
    case cannot hide the others); ``pictures=False`` runs each with ``--no-pictures`` (no PNG)."""
    results = paths.root
    ci_root = paths.ci.root
    check_ci_writes(paths, cases)  # refuse before anything runs or is written (issue 23)
    ensure_dir(ci_root, kind="ci", kinds=("ci",))
    rows, ok = [], True
    selected = [(entry, load_case(entry)) for entry in ci_cases(cases)]  # all validated before any runs
    for entry, case in selected:
        name = case.name
        level = case.discretisation.ci_level or case.discretisation.h_contact
        t0 = time.perf_counter()
        cmd = [sys.executable, "-m", "workbench", "run", str(entry), "--ci", "--out", str(ci_root)]
        proc = subprocess.run(cmd + ([] if pictures else ["--no-pictures"]), capture_output=True, text=True)
        dt = time.perf_counter() - t0
        sys.stdout.write(proc.stdout)
        sys.stderr.write(proc.stderr)
        rows.append((name, level, proc.returncode, dt))
    # the metrics of the cases run here (also a case file outside cases/), by case name
    metrics = {name: json.loads(f.read_text()) for name, *_ in rows
               if (f := ci_root / name / "metrics.json").is_file()}
    lines = ["| case | h_c (x half-width) | exit | time (s) | checks | verdict |", "|---|---|---|---|---|---|"]
    failing = []
    for name, level, code, dt in rows:
        m = metrics.get(name)
        if m is None or code not in (0, 1):
            verdict, checks = "FAIL (run failed)", f"see {ci_root}/logs/{name}.log"
        else:
            failed = [k for k, v in m["checks"].items() if not v]
            checks = ", ".join(f"{k} {m['errors'].get(k, float('nan')):.3g} <= {m['tolerances'][k]:.3g}"
                               f"{'' if m['checks'][k] else ' ✗'}" for k in m["checks"]) or "-"
            verdict = "PASS" if (m["pass"] and code == 0) else f"FAIL ({', '.join(failed) or 'exit ' + str(code)})"
        ok &= verdict == "PASS"
        if verdict != "PASS":
            failing.append(f"- FAIL **{name}**: {verdict[len('FAIL ('):-1]}")
        lines.append(f"| {name} | {level} | {code} | {dt:.1f} | {checks} | {verdict} |")
    head = ["# CI report: every case at its coarsest level", "",
            f"**{len(rows) - len(failing)} of {len(rows)} cases PASS** ({'PASS' if ok else 'FAIL'}).", "",
            *failing, *([""] if failing else [])]
    lines = head + lines + ["", f"Overall: **{'PASS' if ok else 'FAIL'}**", ""]
    write_root_text(results, "ci_report.md", "\n".join(lines))
    write_root_text(results, "ci_report.html", markdown_to_html("\n".join(lines), title="CI report"))
    print("\n".join(lines))
    return 0 if ok else 1
