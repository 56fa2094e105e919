"""Command-line entry point of the workbench: ``python -m scripts <command>``.

Commands:
    list                 the cases in ``cases/`` and what each compares
    validate CASE...     load and check case files (exit 2 on the first bad one)
    run CASE...          run cases, writing ``results/<case>/`` (metrics.json, pressure.csv, plots, VTK)
    report               the summary ``results/report.md`` and ``results/report.html``
    ci                   every case at its coarsest level; ``results/ci_report.md``; exit 1 on a violation

Exit codes: 0 success; 1 a run failed or a tolerance was violated; 2 bad input (case file or arguments),
reported as one line naming the field and the allowed range, before anything is written.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

__all__ = ["main"]

RESULTS = Path("results")


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors and exit code 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        print(f"error: {message} (see --help)", file=sys.stderr)
        raise SystemExit(2)


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="python -m scripts", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    sub.add_parser("list", help="list the cases")
    v = sub.add_parser("validate", help="validate case files")
    v.add_argument("cases", nargs="+", metavar="CASE")
    r = sub.add_parser("run", help="run cases")
    r.add_argument("cases", nargs="+", metavar="CASE", help="case names or paths to .toml files")
    r.add_argument("--h-contact", type=float, default=None, help="override h_c as a fraction of the half-width")
    r.add_argument("--ci", action="store_true", help="run at the case's ci_level")
    r.add_argument("--out", type=Path, default=RESULTS, help="results folder (default: results)")
    rep = sub.add_parser("report", help="write results/report.md and results/report.html")
    rep.add_argument("--out", type=Path, default=RESULTS)
    c = sub.add_parser("ci", help="run every case at its coarsest level and check tolerances")
    c.add_argument("--out", type=Path, default=RESULTS)
    return p


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; returns the exit code."""
    args = _parser().parse_args(argv)
    from cases import CaseError, case_names, load_case

    try:
        if args.command == "list":
            for name in case_names():
                case = load_case(name)
                preds = ", ".join(case.analytic.predictions) or "-"
                print(f"{name:22s} runs={len(case.runs())}  compares: {preds}\n{'':22s} {case.description}")
            return 0
        if args.command == "validate":
            for name in args.cases:
                case = load_case(name)
                print(f"{case.path.name}: ok ({len(case.runs())} run(s))")
            return 0
        if args.command == "run":
            if args.h_contact is not None and not 0 < args.h_contact <= 1:
                raise CaseError(f"--h-contact = {args.h_contact} is out of range; allowed: 0 < h_contact <= 1")
            cases = [load_case(name) for name in args.cases]  # validate all before running any
            from scripts.preflight import preflight

            for case in cases:
                preflight(case)
            from scripts.run_case import run_case

            ok = True
            for case in cases:
                metrics = run_case(case, out_root=args.out, h_contact=args.h_contact, ci=args.ci)
                ok &= bool(metrics is None or metrics.get("pass", False))
            return 0 if ok else 1
        if args.command == "report":
            from scripts.summary import write_summary

            write_summary(args.out)
            return 0
        if args.command == "ci":
            from scripts.ci import run_ci

            return run_ci(args.out)
    except CaseError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    return 2


if __name__ == "__main__":
    sys.exit(main())
