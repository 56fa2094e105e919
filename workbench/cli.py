"""The workbench's one command: ``workbench <subcommand>`` (also ``python -m workbench``).

Subcommands:
    list                 the cases in ``cases/`` and what each compares
    validate CASE...     load and check case files (exit 2 on the first bad one)
    run CASE...          run cases, writing ``<out>/<case>/`` (metrics.json, pressure.csv, plots, VTK)
    mesh CASE            build (or reuse) the meshes of a case's runs and print their statistics
    report               the summary ``<out>/report.md`` and ``<out>/report.html``
    ci                   every case at its coarsest level; ``<out>/ci_report.md``; exit 1 on a violation
    convergence          study: error against run time over refinement levels (``<out>/convergence/``)
    stability            study: stiff and extreme cases (``<out>/stability/``)
    bench                study: performance (``<out>/bench/``)
    convective-table     b/b0 of the convective theory against the paper's figures (``<out>/analytic/``)

``<out>`` is ``--out`` (default: ``results/`` of this checkout, or ``$WORKBENCH_RESULTS``); nothing depends on
the working directory. A study's own options follow its name (``workbench convergence --help``).

Exit codes: 0 success; 1 a run failed or a tolerance was violated; 2 bad input (case file or arguments),
reported as one line naming the field and the allowed range, before anything is written.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from pathlib import Path

from workbench.paths import default_paths

__all__ = ["main", "STUDIES"]

# subcommand -> module with ``main(argv) -> int`` (the study's own options follow the subcommand)
STUDIES = {
    "convergence": "workbench.studies.convergence",
    "stability": "workbench.studies.stability",
    "bench": "workbench.studies.bench",
    "convective-table": "workbench.studies.convective_table",
}


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors and exit code 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        print(f"error: {message} (see --help)", file=sys.stderr)
        raise SystemExit(2)


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="workbench", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    sub.add_parser("list", help="list the cases")
    v = sub.add_parser("validate", help="validate case files")
    v.add_argument("cases", nargs="+", metavar="CASE")
    r = sub.add_parser("run", help="run cases")
    r.add_argument("cases", nargs="+", metavar="CASE", help="case names or paths to .toml files")
    r.add_argument("--h-contact", type=float, default=None, help="override h_c as a fraction of the half-width")
    r.add_argument("--ci", action="store_true", help="run at the case's ci_level")
    r.add_argument("--out", type=Path, default=None, help="output folder (default: results/ of this checkout)")
    m = sub.add_parser("mesh", help="build the meshes of a case and print their statistics")
    m.add_argument("case", metavar="CASE")
    m.add_argument("--h-contact", type=float, default=None, help="h_c as a fraction of the half-width")
    m.add_argument("--json", action="store_true", help="print the statistics as JSON")
    m.add_argument("--out", type=Path, default=None, help="output folder (mesh cache and <case>/mesh.json)")
    rep = sub.add_parser("report", help="write <out>/report.md and <out>/report.html")
    rep.add_argument("--out", type=Path, default=None)
    c = sub.add_parser("ci", help="run every case at its coarsest level and check tolerances")
    c.add_argument("--out", type=Path, default=None)
    for name, module in STUDIES.items():
        st = sub.add_parser(name, help=f"study ({module}); its options follow", add_help=False)
        st.add_argument("study_args", nargs=argparse.REMAINDER)
    return p


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; returns the exit code."""
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv and argv[0] in STUDIES:  # the study parses its own options (``workbench convergence --help``)
        return int(importlib.import_module(STUDIES[argv[0]]).main(argv[1:]) or 0)
    args = _parser().parse_args(argv)
    from cases import CaseError, case_names, load_case

    paths = default_paths(args.out) if hasattr(args, "out") else None

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
            from workbench.pipeline.preflight import preflight

            for case in cases:
                preflight(case)
            from workbench.pipeline.run_case import run_case

            ok = True
            for case in cases:
                metrics = run_case(case, paths=paths, h_contact=args.h_contact, ci=args.ci)
                ok &= bool(metrics is None or metrics.get("pass", False))
            return 0 if ok else 1
        if args.command == "report":
            from workbench.reports.summary import write_summary

            write_summary(paths.root)
            return 0
        if args.command == "mesh":
            return _mesh(args, paths, load_case)
        if args.command == "ci":
            from workbench.pipeline.ci import run_ci

            return run_ci(paths)
    except CaseError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    return 2


def _mesh(args, paths, load_case) -> int:
    """``workbench mesh CASE``: every run's mesh exactly as the case runs it; statistics to ``<out>/<case>/``."""
    import json

    from mpi4py import MPI

    from cases import CaseError
    from workbench.pipeline.case_mesh import case_meshes

    if args.h_contact is not None and not 0 < args.h_contact <= 1:
        raise CaseError(f"--h-contact = {args.h_contact} is out of range; allowed: 0 < h_contact <= 1")
    case = load_case(args.case)
    try:
        files = case_meshes(case, mesh_cache=paths.mesh_cache, comm=MPI.COMM_WORLD, h_contact=args.h_contact,
                            stats_dir=paths.case(case.name))
    except ValueError as exc:
        raise CaseError(str(exc).splitlines()[0]) from None
    out = {label: {"msh": str(f.msh), "cached": f.cached, **{k: v for k, v in f.stats.items() if k != "params"}}
           for label, f in files.items()}
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    for label, st in out.items():
        print(f"[{label}]")
        for k, v in st.items():
            print(f"  {k:26s} {v:.6g}" if isinstance(v, float) else f"  {k:26s} {v}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
