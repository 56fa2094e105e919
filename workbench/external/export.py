"""``workbench export CASE [--format msh|json|inp|mdpa|all] [--level H [H ...] | --levels N] [--out DIR]``: every
case as a benchmark another code can run, one folder per mesh level.

Per level ``<out>/export_<case>/h<H>/`` (``H`` the case's ``h_contact`` fraction: h_c / a for the block scenes):

* ``<case>_h<H>.msh``: every body in ONE gmsh 4.1 mesh with named physical groups (each body's cells, each contact
  surface, the supports, the symmetry edge, the driven edge), a rigid indenter meshed as a band whose every node
  moves with it (:mod:`workbench.external.benchmarks`);
* ``<case>_h<H>.json``: the spec a person can implement by hand (:mod:`workbench.external.spec`);
* each deck format asked (:mod:`workbench.external.writers`): ``inp`` (CalculiX/Abaqus), ``mdpa`` (Kratos).

The msh and the spec are written whatever ``--format`` says (default ``all``: every deck format whose writer is
installed and can model the case; the others are named on stdout). A case with several geometries (``wedge``: one
indenter per angle) has one sub-folder per geometry in each level folder, ``h<H>/<run label>/``.

Levels: ``--level H ...`` (fractions in (0, 1]); ``--levels N``: the case's first N levels from its ``ci_level`` down
(:func:`level_sequence`); default: the ``ci_level`` (else ``h_contact``). ``--h-contact H`` is ``--level H``'s
former name. Every run of every level passes the size estimate before anything is meshed
(:func:`workbench.pipeline.size_estimate.check_run_fits`).

Safety (issue 35): the output folder, the export folder and the mesh cache pass the guard of ``workbench run``
(:func:`workbench.paths.checked_paths`, :func:`workbench.owned.check_dir`); a bad value is one ``error:`` line naming
the option and the allowed range, exit 2, nothing written; the export is staged and replaces
``export_<case>/`` whole (:func:`workbench.atomic.atomic_dir`), the level folders exported before and not asked for
now kept. No dolfinx is imported. Units: mm, N, MPa.
"""

from __future__ import annotations

import argparse
import math
import shutil
import sys
from pathlib import Path

__all__ = ["export_case", "main", "ExportError", "level_sequence", "supported", "MAX_LEVELS"]

MAX_LEVELS = 6  # --levels N at most (each level halves h: the sixth has 32 times the first's elements per length)


class ExportError(ValueError):
    """Bad input to ``workbench export`` (one line)."""


def level_sequence(case) -> tuple[float, ...]:
    """The case's mesh levels from its ``ci_level`` (else ``h_contact``) down: its ``levels`` (else its
    ``budget_levels``) at or below that level, continued by halving the last one up to MAX_LEVELS levels (the patch
    test's 0.143, 0.0714, then 0.0357)."""
    d = case.runs()[0].discretisation
    start = d.ci_level or d.h_contact
    listed = sorted({lv for lv in (d.levels or d.budget_levels) if lv < start * (1 - 1e-12)}, reverse=True)
    out = [start, *listed]
    while len(out) < MAX_LEVELS:
        out.append(out[-1] / 2.0)
    return tuple(out[:MAX_LEVELS])


def supported(case) -> None:
    """ExportError unless the ``inp`` writer can model the case (``workbench external ccx``'s check)."""
    from workbench.external.writers import writer_for

    why = writer_for("inp").cannot(case)
    if why:
        raise ExportError(f"case {case.name}: {why}")


def _levels(case, args) -> tuple[tuple[float, ...], str]:
    """The levels asked for and the option that named them (for the size estimate's message)."""
    given = args.level if args.level is not None else ([args.h_contact] if args.h_contact is not None else None)
    name = "--level" if args.level is not None else "--h-contact"
    if given is not None and args.levels is not None:
        raise ExportError(f"{name} and --levels together; allowed: one of them")
    if given is not None:
        for h in given:
            if not (math.isfinite(h) and 0 < h <= 1):
                raise ExportError(f"{name} = {h!r}; allowed: 0 < H <= 1 (the element size on the contact as a "
                                  "fraction of the case's contact size)")
        return tuple(dict.fromkeys(given)), name
    if args.levels is not None:
        if not 1 <= args.levels <= MAX_LEVELS:
            raise ExportError(f"--levels {args.levels}; allowed: 1 to {MAX_LEVELS} (the case's levels from its "
                              "ci_level down, halving beyond its list)")
        return level_sequence(case)[:args.levels], "--levels"
    return level_sequence(case)[:1], "discretisation.ci_level"


def export_case(case_name: str, *, fmt: str, h_contact: float, folder: Path, mesh_cache: Path,
                approach: float | None = None) -> list[Path]:
    """Export one level of a case into ``folder`` (which exists): the mesh and the spec of every benchmark, and the
    deck files ``fmt`` asks for (a format, or ``all``). Returns the files of ``fmt`` (``all``: every file written).
    ``approach``: a displacement-driven deck's approach d (mm) instead of its writer's estimate (a calibration)."""
    import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
    from cases import load_case
    from workbench.external.benchmarks import build
    from workbench.external.spec import write_spec
    from workbench.external.writers import deck_formats

    case = load_case(case_name)
    writers, _ = deck_formats(fmt, case)
    out = []
    for exp in build(case, level=h_contact, mesh_cache=mesh_cache, folder=Path(folder)):
        files = {"msh": [exp.benchmark.mesh]}
        for w in writers:
            files[w.fmt] = w.write(exp, approach=approach)
        spec = exp.folder / f"{exp.benchmark.mesh.stem}.json"
        files["json"] = [spec]
        write_spec(exp.benchmark, spec, stats=exp.stats,
                   files={k: [p.name for p in v] for k, v in files.items()})
        out += [p for k, v in files.items() if fmt in (k, "all") for p in v]
    return out


def _parser() -> argparse.ArgumentParser:
    from workbench.cli import _Parser

    p = _Parser(prog="workbench export", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("case", metavar="CASE")
    p.add_argument("--format", default="all", help="msh | json | inp | mdpa | all (default: all; the msh and the "
                                                    "JSON spec are always written)")
    p.add_argument("--level", type=float, nargs="+", default=None, metavar="H",
                   help="mesh levels: h_c as a fraction of the case's contact size")
    p.add_argument("--levels", type=int, default=None, metavar="N", help="the case's first N levels from ci_level down")
    p.add_argument("--h-contact", type=float, default=None, help=argparse.SUPPRESS)  # --level's former name
    p.add_argument("--out", default=None, help="output folder (default: results/ of this checkout)")
    return p


def _copy_levels(old: Path, stage: Path) -> None:
    """The level folders (``h*``) of a previous export, their regular files and folders (never a symlink)."""
    def copy(src: Path, dst: Path) -> None:
        dst.mkdir(exist_ok=True)
        for item in src.iterdir():
            if item.is_symlink():
                continue
            if item.is_dir():
                copy(item, dst / item.name)
            elif item.is_file():
                shutil.copy2(item, dst / item.name)

    if old.is_dir() and not old.is_symlink():
        for level in sorted(old.glob("h*")):
            if level.is_dir() and not level.is_symlink():
                copy(level, stage / level.name)


def main(argv: list[str] | None = None) -> int:
    """``workbench export`` (exit 0 written, 2 bad input, 1 the mesh or the files could not be made: one line)."""
    from cases import CaseError
    from workbench import interrupt
    from workbench.atomic import atomic_dir
    from workbench.external.writers import FORMATS, FormatError, deck_formats
    from workbench.owned import check_dir, ensure_dir
    from workbench.paths import OutputError, checked_paths

    args = _parser().parse_args(argv)
    try:
        paths = checked_paths(args.out)  # the output folder's guard, whichever way it was given
        import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
        from cases import load_case
        from workbench.pipeline.size_estimate import check_run_fits

        case = load_case(args.case)
        if args.format not in (*FORMATS, "all"):
            raise ExportError(f"--format {args.format!r}; allowed: {', '.join(FORMATS)}, all")
        levels, option = _levels(case, args)
        _, skipped = deck_formats(args.format, case)
        for lv in levels:
            for run in case.runs(h_contact=lv):
                check_run_fits(run, where=f"{case.path.name}: [{run.label}]", field=option)
        folder = paths.command("export_", case.name)
        check_dir(folder, kinds=("export",))
        check_dir(paths.mesh_cache, kinds=("mesh_cache",))
    except (ExportError, CaseError, OutputError, FormatError) as exc:
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    interrupt.stage(f"exporting {case.name} (meshing, writing {folder.name})")
    try:
        with atomic_dir(folder, kind="export") as stage:
            _copy_levels(folder, stage)  # the levels exported before stay (re-exported files are replaced)
            ensure_dir(paths.mesh_cache, kind="mesh_cache", kinds=("mesh_cache",))
            written = []
            for lv in levels:
                (stage / f"h{lv:g}").mkdir(exist_ok=True)
                written += export_case(args.case, fmt=args.format, h_contact=lv, folder=stage / f"h{lv:g}",
                                       mesh_cache=paths.mesh_cache)
    except (ExportError, CaseError, FormatError) as exc:  # OutputError among them: the folder changed meanwhile
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        raise  # the command line prints the one line and exits 130 / 143
    except Exception as exc:  # noqa: BLE001 - gmsh (e.g. out of memory), a full disk: one line, nothing written
        first = " ".join(str(exc).split())[:200] or type(exc).__name__
        print(f"error: export {case.name} failed: {type(exc).__name__}: {first}; nothing written (a previous export "
              "left intact)", file=sys.stderr)
        return 1
    for w in written:
        print(folder / w.relative_to(stage))
    for line in skipped:
        print(line)
    return 0
