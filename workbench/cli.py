"""The workbench's one command: ``workbench <subcommand>`` (also ``python -m workbench``).

Subcommands:
    list                 the cases in ``cases/`` and what each compares
    validate CASE...     load and check case files (exit 2 on the first bad one)
    run CASE...          run cases, writing ``<out>/<case>/`` (metrics.json, pressure.csv, plots, VTK);
                         ``--no-pictures``: the fast path for scripts (same numbers, no PNG, no
                         matplotlib/pyvista start-up; ``workbench report`` draws the pictures later)
    mesh CASE            build (or reuse) the meshes of a case's runs and print their statistics
    report               the summary ``<out>/report.md`` and ``<out>/report.html``
    ci                   every case at its coarsest level; ``<out>/ci_report.md``; exit 1 on a violation
                         (``--no-pictures`` as for ``run``)
    convergence          study: error against run time over refinement levels (``<out>/convergence/``)
    stability            study: stiff and extreme cases (``<out>/stability/``)
    bench                study: performance (``<out>/bench/``)
    convective-table     b/b0 of the convective theory against the paper's figures (``<out>/analytic/``)
    validity             study: where the half-plane theories hold, model by model (``<out>/validity/``)
    concave-map          study: where Hertz superposition holds over the concave design family
                         (``<out>/concave_map/``; ``--tiny``: the machinery on 2 designs x 2 loads)
    score CASE RESULT... an external code's pressures (csv|frd, one file per mesh level) against the case's
                         theory with the workbench's measures (``<out>/score_<case>/``)
    export CASE          every case as a benchmark another code runs: mesh, JSON spec, decks (--format
                         msh|json|inp|mdpa|all, --level H... | --levels N; ``<out>/export_<case>/h<level>/``)
    external ccx CASE    export, run CalculiX on each level, score (``<out>/external_ccx_<case>/``)
    external kratos CASE export, run Kratos (its own venv, ``make external``) on each level, score
                         (``<out>/external_kratos_<case>/``)
    external workbench CASE  the workbench's own solver run and scored as an external code is
                         (``<out>/external_workbench_<case>/``)
    external compare [CASE...]  the workbench, CalculiX and Kratos side by side on the same levels, scored alike,
                         the verdict first (``<out>/external_compare/``; ``--add NAME=FOLDER``: a code of yours)
    forcelaw DESIGN      P(d), patch positions and sizes of a design from the interacting-patch model, csv/json
                         and a numpy evaluator (``<out>/forcelaw_<design>/``; :mod:`workbench.forcelaw_command`)

``<out>`` is ``--out`` (default: ``results/`` of this checkout, or ``$WORKBENCH_RESULTS``); nothing depends on
the working directory. A study's own options follow its name (``workbench convergence --help``).

Exit codes: 0 success; 1 a run failed or a tolerance was violated (or the disk filled: named, previous results
intact); 2 bad input (case file, arguments or an unusable ``--out``, or a folder or file in the way that the
workbench did not write: :mod:`workbench.owned`), reported as one line naming the field and the allowed range,
before anything is written; 130 interrupted by SIGINT, 143 by SIGTERM, at any stage (one line naming the stage;
previous results intact, staging removed: :mod:`workbench.interrupt`).
"""

from __future__ import annotations

import argparse
import importlib
import signal
import sys
from pathlib import Path

from workbench.owned import check_dir, check_run_outputs, ensure_dir
from workbench.paths import check_output_folder, checked_paths

__all__ = ["main", "STUDIES", "EXTERNAL", "TOOLS"]

# subcommand -> module with ``main(argv) -> int`` (the study's own options follow the subcommand)
STUDIES = {
    "convergence": "workbench.studies.convergence",
    "stability": "workbench.studies.stability",
    "bench": "workbench.studies.bench",
    "convective-table": "workbench.studies.convective_table",
    "validity": "workbench.studies.validity",
    "concave-map": "workbench.studies.concave_map",
}
# external codes (issue 26): subcommand -> module with ``main(argv) -> int``, own options too
EXTERNAL = {
    "score": "workbench.external.score",
    "export": "workbench.external.export",
    "external": "workbench.external.codes",
}
# tools: subcommand -> module with ``main(argv) -> int``, own options too
TOOLS = {"forcelaw": "workbench.forcelaw_command"}
OWN_OPTIONS = {**STUDIES, **EXTERNAL, **TOOLS}


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


# study -> its folder under the output folder (the default of its --out)
STUDY_FOLDERS = {"convergence": "convergence", "stability": "stability", "bench": "bench",
                 "convective-table": "analytic", "validity": "validity",
                 "concave-map": "concave_map"}


def _check_study_folders(study: str, given: dict[str, str]) -> None:
    """A study writes into its folder and the mesh cache: each the workbench's own or new (issue 23)."""
    paths = checked_paths(None) if "--out" not in given or "--mesh-cache" not in given else None
    out = Path(given["--out"]).expanduser() if "--out" in given else paths.study(STUDY_FOLDERS[study])
    check_dir(out)
    if study != "convective-table":
        check_dir(Path(given["--mesh-cache"]).expanduser() if "--mesh-cache" in given else paths.mesh_cache,
                  kinds=("mesh_cache",))


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
    r.add_argument("--dry-run", action="store_true",
                   help="check everything a run checks before meshing (cases, sizes, memory), then stop")
    r.add_argument("--no-pictures", action="store_true",
                   help="fast path for scripts: the same metrics.json and data files, a text report, no PNG "
                        "(no pressure plot, budget plot or pyvista renders; `workbench report` draws them later)")
    m = sub.add_parser("mesh", help="build the meshes of a case and print their statistics")
    m.add_argument("case", metavar="CASE")
    m.add_argument("--h-contact", type=float, default=None, help="h_c as a fraction of the half-width")
    m.add_argument("--json", action="store_true", help="print the statistics as JSON")
    m.add_argument("--out", type=_folder, default=None, help="output folder (mesh cache and <case>/mesh.json)")
    rep = sub.add_parser("report", help="write <out>/report.md and <out>/report.html")
    rep.add_argument("--out", type=_folder, default=None)
    c = sub.add_parser("ci", help="run every case at its coarsest level and check tolerances")
    c.add_argument("--out", type=_folder, default=None)
    c.add_argument("--no-pictures", action="store_true", help="run every case with `run --no-pictures`")
    for name, module in OWN_OPTIONS.items():
        kind = "external code" if name in EXTERNAL else "tool" if name in TOOLS else "study"
        st = sub.add_parser(name, help=f"{kind} ({module}); its options follow", add_help=False)
        st.add_argument("study_args", nargs=argparse.REMAINDER)
    return p


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; returns the exit code (SIGINT -> 130, SIGTERM -> 143 at any stage, the exit included: one line,
    the previous results intact; :mod:`workbench.interrupt`). The program itself (``argv`` None) ends through
    :func:`workbench.fast_exit.finish`: without the interpreter's teardown where nothing can be lost, and with a
    signal that arrives during its exit reported in one line."""
    if argv is not None:
        return _guarded_main(argv)
    import atexit

    from workbench.fast_exit import at_teardown, finish

    atexit.register(at_teardown)  # registered first, so it runs after every other atexit handler
    code = _guarded_main(None)
    return finish(code, sys.argv[1] if len(sys.argv) > 1 else None)


def _guarded_main(argv: list[str] | None) -> int:
    """:func:`main` with the signal handling of :mod:`workbench.interrupt` around :func:`_main`."""
    import os
    import threading

    from workbench import interrupt

    # PETSc would install its own SIGTERM/SIGINT handlers (an MPI_Abort, no clean-up): keep Python's.
    if "-no_signal_handler" not in os.environ.get("PETSC_OPTIONS", ""):
        os.environ["PETSC_OPTIONS"] = (os.environ.get("PETSC_OPTIONS", "") + " -no_signal_handler").strip()
    if threading.current_thread() is not threading.main_thread():
        return _main(argv)
    previous = interrupt.install()
    interrupt.stage("start-up")
    try:
        try:
            interrupt.check()  # a signal that came while the program started (interrupt.early)
            code = _main(argv)
        except SystemExit as exc:
            if argv is not None or interrupt.received() is not None:
                raise
            code = _system_exit_code(exc)  # the program: its exit goes through the same end as a return
        interrupt.test_point("work-done")
        if argv is None:  # the program: its work is over; a signal from now on is reported by its exit
            interrupt.stage("the exit")
            interrupt.work_done()
        return code
    except BaseException as exc:  # noqa: BLE001 - after a signal, whatever native code made of it is an interrupt
        signum = interrupt.received()
        if signum is None and not isinstance(exc, KeyboardInterrupt):
            raise
        signum = signum or signal.SIGINT
        if argv is None:
            interrupt.work_done()
        print(interrupt.message(signum), file=sys.stderr)
        interrupt.reported()
        return interrupt.exit_code(signum)
    finally:
        if argv is not None:
            interrupt.restore(previous)


def _system_exit_code(exc: SystemExit) -> int:
    """The exit code of a ``SystemExit`` (its text, if it carries one, printed as Python would)."""
    if exc.code is None or isinstance(exc.code, int):
        return int(exc.code or 0)
    print(exc.code, file=sys.stderr)
    return 1


def _main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
    from cases import CaseError, case_names, load_case
    from meshes.portable import perturb_amplitude

    try:  # the mesh perturbation hook (portability emulation): a bad value stops every command before any work
        perturb_amplitude()
    except ValueError as exc:
        print(f"error: {_one_line(exc)}", file=sys.stderr)
        return 2

    from workbench import interrupt

    if argv and argv[0] in OWN_OPTIONS:  # the study parses its own options (``workbench convergence --help``)
        interrupt.stage(f"workbench {argv[0]}")
        try:
            for opt, folder in _study_out_options(argv[1:]):
                if not folder.strip():
                    raise CaseError(f"{opt}: an empty folder name is not allowed; allowed: a folder path")
                check_output_folder(folder, option=opt)
            if argv[0] in STUDIES:  # an external-code command writes through atomic_dir (owned folders only)
                _check_study_folders(argv[0], dict(_study_out_options(argv[1:])))
            return int(importlib.import_module(OWN_OPTIONS[argv[0]]).main(argv[1:]) or 0)
        except CaseError as exc:
            print(f"error: {_one_line(exc)}", file=sys.stderr)
            return 2
    args = _parser().parse_args(argv)
    interrupt.stage(f"workbench {args.command}")  # the command's own stages follow (meshing, the Newton solve, ...)

    try:
        paths = checked_paths(args.out) if args.command in ("run", "mesh", "report", "ci") else None
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
            from workbench.pipeline.preflight import preflight
            from workbench.pipeline.size_estimate import check_case_fits

            for name in args.cases:
                case = load_case(name)
                preflight(case)  # what `run` checks before meshing, `validate` checks too
                check_case_fits(case)
                print(f"{case.path.name}: ok ({len(case.runs())} run(s))")
            return 0
        if args.command == "run":
            if args.h_contact is not None and not 0 < args.h_contact <= 1:
                raise CaseError(f"--h-contact = {args.h_contact} is out of range; allowed: 0 < h_contact <= 1")
            cases = [load_case(name) for name in args.cases]  # validate all before running any
            from workbench.pipeline.preflight import preflight
            from workbench.pipeline.size_estimate import check_case_fits

            for case in cases:
                preflight(case)
                check_case_fits(case, h_contact=args.h_contact, ci=args.ci)  # before anything is meshed
            for case in cases:
                paths.case(case.name)  # inside the output folder (the case name is a slug: never fails)
            check_run_outputs(paths, cases)  # only the workbench's own folders are replaced (issue 23)
            if args.dry_run:
                for case in cases:
                    print(f"{case.path.name}: would run {len(case.runs())} run(s)")
                return 0
            from workbench.pipeline.run_case import run_case

            ok = True
            for case in cases:
                try:
                    metrics = run_case(case, paths=paths, h_contact=args.h_contact, ci=args.ci,
                                       pictures=not args.no_pictures)
                except OSError as exc:  # e.g. ENOSPC: the staging folder is removed, the previous results stay
                    where = f" ({_one_line(exc.filename)})" if getattr(exc, "filename", None) else ""
                    print(f"error: case {case.name} failed: cannot write the results: "
                          f"{_one_line(exc.strerror or exc)}{where}; previous results left intact", file=sys.stderr)
                    return 1
                ok &= bool(metrics is None or metrics.get("pass", False))
            return 0 if ok else 1
        if args.command == "report":
            from workbench.reports.summary import check_summary_writes, write_summary

            check_summary_writes(paths.root)  # nothing over a file or into a folder the workbench did not write
            write_summary(paths.root)
            return 0
        if args.command == "mesh":
            return _mesh(args, paths, load_case)
        if args.command == "ci":
            from workbench.pipeline.ci import check_ci_writes, run_ci

            check_ci_writes(paths)
            return run_ci(paths, pictures=not args.no_pictures)
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
    from workbench.pipeline.size_estimate import check_run_fits

    for run in case.runs(h_contact=args.h_contact):
        check_run_fits(run, where=f"{case.path.name}: [{run.label}]",
                       field="--h-contact" if args.h_contact is not None else "discretisation.h_contact")
    check_run_outputs(paths, [case])
    ensure_dir(paths.case(case.name), kind="case")
    ensure_dir(paths.mesh_cache, kind="mesh_cache")
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
