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
    validity             study: where the half-plane theories hold, model by model (``<out>/validity/``)
    score CASE RESULT... an external code's pressures (csv|frd, one file per mesh level) against the case's
                         theory with the workbench's measures (``<out>/score_<case>/``)
    export CASE          the case as a benchmark: --format msh|json|inp (``<out>/export_<case>/``)
    external ccx CASE    export, run CalculiX on each level, score (``<out>/external_ccx_<case>/``)

``<out>`` is ``--out`` (default: ``results/`` of this checkout, or ``$WORKBENCH_RESULTS``); nothing depends on
the working directory. A study's own options follow its name (``workbench convergence --help``).

Exit codes: 0 success; 1 a run failed or a tolerance was violated (or the disk filled: named, previous results
intact); 2 bad input (case file, arguments or an unusable ``--out``), reported as one line naming the field and
the allowed range, before anything is written; 130 interrupted (SIGINT or SIGTERM: previous results intact).
"""

from __future__ import annotations

import argparse
import importlib
import signal
import sys
from pathlib import Path

from workbench.paths import check_output_folder, default_paths

__all__ = ["main", "STUDIES", "EXTERNAL"]

# subcommand -> module with ``main(argv) -> int`` (the study's own options follow the subcommand)
STUDIES = {
    "convergence": "workbench.studies.convergence",
    "stability": "workbench.studies.stability",
    "bench": "workbench.studies.bench",
    "convective-table": "workbench.studies.convective_table",
    "validity": "workbench.studies.validity",
}
# external codes (issue 26): subcommand -> module with ``main(argv) -> int``, own options too
EXTERNAL = {
    "score": "workbench.external.score",
    "export": "workbench.external.export",
    "external": "workbench.external.ccx",
}
OWN_OPTIONS = {**STUDIES, **EXTERNAL}


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors and exit code 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        print(f"error: {_one_line(message)} (see --help)", file=sys.stderr)
        raise SystemExit(2)


MAX_MESSAGE = 400  # characters of an error line (values inside are already cut by the case schema)


def _one_line(message: str) -> str:
    """``message`` on one line, cut to MAX_MESSAGE characters."""
    text = " ".join(str(message).split())
    return text if len(text) <= MAX_MESSAGE else text[:MAX_MESSAGE - 3] + "..."


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised like Ctrl-C so the same clean-up runs (staging removed, previous results intact)."""


def _on_sigterm(signum, frame) -> None:
    raise Terminated()


def _study_out_options(argv: list[str]) -> list[tuple[str, str]]:
    """The ``--out`` and ``--mesh-cache`` folders given to a study (checked before it starts)."""
    out = []
    for i, a in enumerate(argv):
        for opt in ("--out", "--mesh-cache"):
            if a == opt and i + 1 < len(argv):
                out.append((opt, argv[i + 1]))
            elif a.startswith(opt + "="):
                out.append((opt, a.split("=", 1)[1]))
    return out


def _folder(text: str) -> Path:
    """An output folder argument (an empty one would silently mean the working directory)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("an empty folder name is not allowed; allowed: a folder path")
    return Path(text)


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
    r.add_argument("--out", type=_folder, default=None, help="output folder (default: results/ of this checkout)")
    m = sub.add_parser("mesh", help="build the meshes of a case and print their statistics")
    m.add_argument("case", metavar="CASE")
    m.add_argument("--h-contact", type=float, default=None, help="h_c as a fraction of the half-width")
    m.add_argument("--json", action="store_true", help="print the statistics as JSON")
    m.add_argument("--out", type=_folder, default=None, help="output folder (mesh cache and <case>/mesh.json)")
    rep = sub.add_parser("report", help="write <out>/report.md and <out>/report.html")
    rep.add_argument("--out", type=_folder, default=None)
    c = sub.add_parser("ci", help="run every case at its coarsest level and check tolerances")
    c.add_argument("--out", type=_folder, default=None)
    for name, module in OWN_OPTIONS.items():
        kind = "external code" if name in EXTERNAL else "study"
        st = sub.add_parser(name, help=f"{kind} ({module}); its options follow", add_help=False)
        st.add_argument("study_args", nargs=argparse.REMAINDER)
    return p


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; returns the exit code (SIGTERM is handled like Ctrl-C while it runs: exit 130, the previous
    results intact)."""
    import os
    import threading

    # PETSc would install its own SIGTERM/SIGINT handlers (an MPI_Abort, no clean-up): keep Python's.
    if "-no_signal_handler" not in os.environ.get("PETSC_OPTIONS", ""):
        os.environ["PETSC_OPTIONS"] = (os.environ.get("PETSC_OPTIONS", "") + " -no_signal_handler").strip()
    if threading.current_thread() is not threading.main_thread():
        return _main(argv)
    previous = signal.signal(signal.SIGTERM, _on_sigterm)
    try:
        return _main(argv)
    except KeyboardInterrupt:
        print("interrupted: nothing more written; previous results left intact", file=sys.stderr)
        return 130
    finally:
        signal.signal(signal.SIGTERM, previous)
        if argv is None:  # the program itself: its work is done, a signal now would only garble the exit code
            signal.signal(signal.SIGINT, signal.SIG_IGN)
            signal.signal(signal.SIGTERM, signal.SIG_IGN)


def _main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    from cases import CaseError, case_names, load_case
    from meshes.portable import perturb_amplitude

    try:  # the mesh perturbation hook (portability emulation): a bad value stops every command before any work
        perturb_amplitude()
    except ValueError as exc:
        print(f"error: {_one_line(exc)}", file=sys.stderr)
        return 2

    if argv and argv[0] in OWN_OPTIONS:  # the study parses its own options (``workbench convergence --help``)
        try:
            for opt, folder in _study_out_options(argv[1:]):
                if not folder.strip():
                    raise CaseError(f"{opt}: an empty folder name is not allowed; allowed: a folder path")
                check_output_folder(folder, option=opt)
            return int(importlib.import_module(OWN_OPTIONS[argv[0]]).main(argv[1:]) or 0)
        except CaseError as exc:
            print(f"error: {_one_line(exc)}", file=sys.stderr)
            return 2
    args = _parser().parse_args(argv)

    try:
        paths = default_paths(args.out) if hasattr(args, "out") else None
        if args.command in ("run", "mesh", "report", "ci"):
            check_output_folder(paths.root, option="--out" if args.out is not None else "output folder")
    except CaseError as exc:
        print(f"error: {_one_line(exc)}", file=sys.stderr)
        return 2

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
            for case in cases:
                paths.case(case.name)  # inside the output folder (the case name is a slug: never fails)
            from workbench.pipeline.run_case import run_case

            ok = True
            for case in cases:
                try:
                    metrics = run_case(case, paths=paths, h_contact=args.h_contact, ci=args.ci)
                except OSError as exc:  # e.g. ENOSPC: the staging folder is removed, the previous results stay
                    where = f" ({_one_line(exc.filename)})" if getattr(exc, "filename", None) else ""
                    print(f"error: case {case.name} failed: cannot write the results: "
                          f"{_one_line(exc.strerror or exc)}{where}; previous results left intact", file=sys.stderr)
                    return 1
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
        print(f"error: {_one_line(exc)}", file=sys.stderr)
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
