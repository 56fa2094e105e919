"""``workbench external compare [CASES] [--codes C,..] [--levels N] [--out DIR] [--time-limit S]``: three codes on
the same benchmarks, scored alike, in one report.

For every case (default :data:`DEFAULT_CASES`) and code (default ``workbench,ccx,kratos``), the code's own command
runs first (``workbench external <code> CASE --levels N --out DIR``: the same exported levels, the code's results in
the result schema, scored by the scorer of the case's scene into ``<out>/external_<code>_<case>/``). Then this command
reads what they wrote (``<code>.json`` and every geometry's ``score/score.json``) and writes
``<out>/external_compare/`` (staged, the same guard as every command that writes):

* ``compare.json``: per case, geometry and code (:class:`CodeRow`): the main quantity (the study the scene's verdict
  reads first: :meth:`SceneScorer.main_key`), its value per level, the extrapolated value and its GCI band, the
  difference to the theory, the models of the workbench's hierarchy whose band holds it (or none, and why), the
  process wall time per level and the time to reach 1 % and 0.1 % (:func:`time_to_reach`);
* ``report.md`` / ``report.html`` (:mod:`workbench.reports.compare_report`), the verdict first;
* ``error_time_<case>.png``: the main quantity's error against the process wall time, one line per code.

The error of a level is ``|v - R| / |R|`` with R the theory the scorer holds the main quantity against (a quantity
whose theory is 0, the patch test's uniformity, is already relative: ``|v|``); without a theory, R is the
workbench's extrapolated value (said in the report). A process wall time is what a user waits for one level: the
interpreter, the code's imports, (the workbench:) the FFCx compilation of any form not yet in the JIT cache, meshing
or reading the mesh, the solve, and (CalculiX, force control) every calibration run of the load. Codes run one after
another on one core each (one thread).

A code of your own joins with ``--add NAME=FOLDER``: FOLDER is what ``workbench export CASE --levels N --out FOLDER``
wrote, with your code's ``result.csv`` (the result schema, :data:`workbench.external.benchmark.RESULT_COLUMNS`) put
beside each level's deck, ``FOLDER/export_<case>/h<H>/[<geometry>/]result.csv``, and optionally its process wall
time in seconds in ``wall_s.txt`` beside it (without it, no time to reach is given). Its levels are scored alike into
``external_compare/<NAME>_<case>/`` and it is one more row. A missing or malformed file: one line, exit 2, nothing
written, before any code runs.

A code not installed: one line, exit 2, nothing written (``make external`` installs CalculiX and the Kratos venv).
A code that cannot model a case is a row that says why. Exit 0; 1 when a code's run failed (its row says which).
Units mm, N/mm, MPa, s.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path
from typing import NamedTuple

__all__ = ["DEFAULT_CASES", "CODES", "CodeRow", "Added", "time_to_reach", "level_errors", "collect", "added_levels",
           "main"]

DEFAULT_CASES = ("hertz_cylinder", "wedge", "patch_test", "elastic_cylinder_dissimilar", "close_to_conformal")
CODES = {"workbench": "the workbench", "ccx": "CalculiX 2.20", "kratos": "Kratos 10.4.4"}
TARGETS = (1e-2, 1e-3)  # the errors whose time is reported (1 %, 0.1 %)


class Reach(NamedTuple):
    """The time to reach an error: ``seconds`` (None: not reached on these levels) and how it was found
    (``level`` i: a level's own time; ``interpolated``: log-log between two levels; ``not reached``)."""

    target: float
    seconds: float | None
    how: str


class CodeRow(NamedTuple):
    """One code on one geometry of a case (module docstring). Units: the quantity's own (mostly a ratio), s."""

    case: str
    geometry: str
    code: str
    status: str  # "scored", "not scored: ...", "cannot model: ...", "failed: ..."
    quantity: str | None = None
    label: str | None = None
    h: tuple[float, ...] = ()  # coarse first
    values: tuple[float, ...] = ()
    wall_s: tuple[float, ...] = ()
    extrapolated: float | None = None
    band: float | None = None
    status_study: str | None = None
    theory: float | None = None
    theory_name: str | None = None
    reference: str | None = None
    errors: tuple[float, ...] = ()
    deviation: float | None = None
    models: tuple[str, ...] = ()
    models_why: str = ""
    reach: tuple[Reach, ...] = ()
    headline: str = ""


def level_errors(values, *, reference: float) -> tuple[float, ...]:
    """Each level's error ``|v - R| / |R|`` (``|v|`` when R = 0: the quantity is already relative)."""
    if reference == 0.0:
        return tuple(abs(v) for v in values)
    return tuple(abs(v - reference) / abs(reference) for v in values)


def time_to_reach(wall_s, errors, target: float) -> Reach:
    """The process wall time at which the error reaches ``target``, from levels coarse first: the shortest of the
    times of the levels at or below it (a level's own time) and, where the error fell onto the target from the level
    above the first of them, the log-log interpolation between the two; else not reached. (A level's time need not
    grow with refinement: CalculiX's first level carries the load calibration's extra runs.)"""
    best = Reach(target, None, "not reached")
    for i, (t, e) in enumerate(zip(wall_s, errors, strict=True)):
        if not (math.isfinite(e) and e <= target):
            continue
        if best.seconds is None and i > 0:
            t0, e0 = wall_s[i - 1], errors[i - 1]
            if e0 > e > 0.0 and t > t0 > 0.0:
                s = (math.log(target) - math.log(e0)) / (math.log(e) - math.log(e0))
                best = Reach(target, math.exp(math.log(t0) + s * (math.log(t) - math.log(t0))), "interpolated")
        if best.seconds is None or t < best.seconds:
            best = Reach(target, t, f"level {i}")
    return best


def _models(score: dict) -> tuple[tuple[str, ...], str]:
    """The models whose band holds the main value, else why none are named."""
    match = score.get("models")
    if score.get("plausibility"):
        return (), "no verdict: " + score["plausibility"][0]
    if match is None:
        return (), "no model bands saved for this case (make model-bands)"
    inside = tuple(r["model"] for r in match["models"] if r["contains"])
    if inside:
        return inside, ""
    near = min(match["models"], key=lambda r: abs(r["distance"]))
    return (), (f"none: outside every model's band; nearest {near['model']} at {near['distance']:+.3g} "
                f"(uncertainty +-{match['uncertainty']:.2g})")


def _row(case: str, geometry: str, code: str, summary_levels: list, score: dict, *, reference=None) -> CodeRow:
    main = score.get("main")
    st = (score.get("studies") or {}).get(main) if main else None
    if not st:
        return CodeRow(case, geometry, code, "not scored: " + (score.get("headline") or "no main study"))
    order = sorted(range(len(st["h"])), key=lambda i: -st["h"][i])  # coarse first
    h = tuple(st["h"][i] for i in order)
    values = tuple(st["ratios"][i] for i in order)
    wall = tuple(lv["process_wall_s"] for lv in summary_levels)
    theory = st.get("theory")
    if theory is not None and math.isfinite(theory):
        ref, ref_name = theory, st.get("theory_name") or "the theory"
    elif reference is not None:
        ref, ref_name = reference, "the workbench's extrapolated value (no theory)"
    else:
        ref, ref_name = st["extrapolated"], "its own extrapolated value (no theory)"
    errors = level_errors(values, reference=ref)
    reach = tuple(time_to_reach(wall, errors, t) for t in TARGETS) if len(wall) == len(errors) else ()
    models, why = _models(score)
    return CodeRow(case, geometry, code, "scored", main, st.get("label"), h, values, wall, st.get("extrapolated"),
                   st.get("band"), st.get("status"), theory, st.get("theory_name"), ref_name, errors,
                   st.get("deviation"), models, why, reach, score.get("headline", ""))


def _cannot(code: str, case) -> str | None:
    """Why ``code`` cannot model ``case`` at all (None: it models at least one of its runs)."""
    if code == "workbench":
        return None
    from workbench.external.writers import writer_for

    return writer_for("inp" if code == "ccx" else "mdpa").cannot(case)


def collect(out: Path, case, code: str, *, ran: int | None, reference: float | None = None) -> list[CodeRow]:
    """The rows of one code on one case from what its command wrote under ``out``."""
    folder = out / f"external_{code}_{case.name}"
    summary_file = folder / f"{code}.json"
    if not summary_file.is_file():
        why = f"failed: exit {ran}" if ran else "failed: no summary written"
        return [CodeRow(case.name, case.name, code, why)]
    summary = json.loads(summary_file.read_text())
    rows = []
    for key, entry in summary["geometries"].items():
        sub = folder if key == case.name else folder / key
        score_file = sub / "score" / "score.json"
        if not score_file.is_file():
            rows.append(CodeRow(case.name, key, code, str(entry.get("score") or "not scored")))
            continue
        rows.append(_row(case.name, key, code, entry["levels"], json.loads(score_file.read_text()),
                         reference=reference))
    return rows


class Added(NamedTuple):
    """A code of the user's (``--add NAME=FOLDER``): its name and the export folder holding its results."""

    name: str
    folder: Path


class AddedLevels(NamedTuple):
    """One geometry of a case in an added code's folder: the result file per level (coarse first) and the process
    wall times (s; None where ``wall_s.txt`` is missing)."""

    geometry: str
    files: tuple[Path, ...]
    wall_s: tuple[float | None, ...]


def parse_added(specs: list[str]) -> list[Added]:
    """The ``--add`` options; CompareError (one line) for a bad name or a folder that is not one."""
    import re

    out = []
    for spec in specs:
        name, sep, folder = spec.partition("=")
        if not sep or not re.fullmatch(r"[a-z][a-z0-9_-]{0,19}", name) or name in CODES \
                or any(a.name == name for a in out):
            raise CompareError(f"--add {spec[:60]!r}; allowed: NAME=FOLDER, NAME of 1-20 lower-case letters, digits, "
                               f"_ or - (starting with a letter), distinct and none of {', '.join(CODES)}")
        path = Path(folder)
        if not path.is_dir():
            raise CompareError(f"--add {name}: {folder[:120]!r} is not a folder; allowed: the --out folder of "
                               "workbench export CASE --levels N, with your result.csv beside each level's deck")
        out.append(Added(name, path))
    return out


def added_levels(added: Added, case, levels: list[float]) -> list[AddedLevels]:
    """Every geometry's result files and wall times of an added code (module docstring); CompareError (one line)
    for a missing file or a wall time that is not a positive number."""
    from cases.schema import label_folder
    from workbench.external.benchmarks.base import groups

    parts = groups(case.runs(h_contact=levels[0]))
    keys = [""] if len(parts) == 1 else [label_folder(p[0].label) for p in parts]
    out = []
    for key in keys:
        files, walls = [], []
        for lv in levels:
            where = added.folder / f"export_{case.name}" / f"h{lv:g}" / key
            f = where / "result.csv"
            if not f.is_file() or f.is_symlink():
                raise CompareError(f"--add {added.name}: {f} is missing (or not a regular file); allowed: one "
                                   f"result.csv per level and geometry, export_{case.name}/h<H>/[<geometry>/]"
                                   "result.csv as workbench export lays the levels out")
            files.append(f)
            w = where / "wall_s.txt"
            if w.is_file() and not w.is_symlink():
                text = w.read_text(errors="replace")[:40].strip()
                try:
                    value = float(text)
                except ValueError:
                    value = math.nan
                if not (math.isfinite(value) and 0.0 < value < 1e7):
                    raise CompareError(f"--add {added.name}: {w} holds {text[:20]!r}; allowed: one number of "
                                       "seconds, > 0")
                walls.append(value)
            else:
                walls.append(None)
        out.append(AddedLevels(key or case.name, tuple(files), tuple(walls)))
    return out


def _check_codes(codes: list[str]) -> None:
    from workbench.external.ccx import ccx_executable
    from workbench.external.kratos import kratos_python

    for c in codes:
        if c == "ccx":
            ccx_executable()
        elif c == "kratos":
            kratos_python()


class CompareError(RuntimeError):
    """Bad input: one line, exit 2."""


def _parser() -> argparse.ArgumentParser:
    from workbench.cli import _Parser

    p = _Parser(prog="workbench external compare", description=__doc__,
                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("code", choices=("compare",))
    p.add_argument("cases", metavar="CASE", nargs="*", help=f"default: {' '.join(DEFAULT_CASES)}")
    p.add_argument("--codes", default=",".join(CODES), help=f"comma-separated, of: {','.join(CODES)}")
    p.add_argument("--levels", type=int, default=3, help="number of mesh levels from each case's ci_level down")
    p.add_argument("--out", default=None, help="output folder (default: results/ of this checkout)")
    p.add_argument("--time-limit", type=float, default=1800.0, help="seconds per level and code")
    p.add_argument("--add", action="append", default=[], metavar="NAME=FOLDER",
                   help="a code of your own: the workbench export folder with its result.csv per level (repeatable)")
    return p


def main(argv: list[str] | None = None) -> int:
    """``workbench external compare`` (exit 0 all ran, 1 a code's run failed, 2 bad input or a code missing)."""
    import workbench.scenes  # noqa: F401
    from cases import CaseError, load_case
    from workbench import interrupt
    from workbench.atomic import atomic_dir, write_json
    from workbench.external.ccx import CcxError
    from workbench.external.code_runs import code_levels
    from workbench.external.codes import CODES as COMMANDS
    from workbench.external.kratos import KratosError
    from workbench.external.results import ResultError
    from workbench.owned import check_dir
    from workbench.paths import OutputError, checked_paths

    args = _parser().parse_args(argv)
    try:
        codes = [c.strip() for c in args.codes.split(",") if c.strip()]
        bad = [c for c in codes if c not in CODES]
        added = parse_added(args.add)
        if bad or (not codes and not added) or len(set(codes)) != len(codes):
            raise CompareError(f"--codes {args.codes[:60]!r}; allowed: distinct names of {', '.join(CODES)}")
        if not (math.isfinite(args.time_limit) and args.time_limit > 0):
            raise CompareError(f"--time-limit {args.time_limit!r}; allowed: a number of seconds > 0")
        paths = checked_paths(args.out)
        cases = [load_case(n) for n in (args.cases or DEFAULT_CASES)]
        levels = {case.name: code_levels(case, args.levels, error=CompareError) for case in cases}
        mine = {(a.name, case.name): added_levels(a, case, levels[case.name]) for a in added for case in cases}
        _read_added(mine)
        folder = paths.command("external_", "compare")
        check_dir(folder, kinds=("external",))
        check_dir(paths.mesh_cache, kinds=("mesh_cache",))
        for case in cases:
            for c in codes:
                check_dir(paths.command(f"external_{c}_", case.name), kinds=("external",))
        _check_codes(codes)
    except (CompareError, CaseError, OutputError, CcxError, KratosError, ResultError) as exc:
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    import importlib

    from workbench.reports.compare_report import write_compare_report

    interrupt.stage("comparing codes (writing external_compare)")
    rows: list[CodeRow] = []
    failed = 0
    for case in cases:
        reference = None
        for c in codes:
            why = _cannot(c, case)
            if why:
                rows.append(CodeRow(case.name, case.name, c, f"cannot model: {why}"))
                continue
            print(f"== {CODES[c]} on {case.name}", flush=True)
            mod = importlib.import_module(COMMANDS[c])
            rc = int(mod.main([c, case.name, "--levels", str(args.levels), "--out", str(paths.root),
                               "--time-limit", f"{args.time_limit!r}"] if c != "ccx" else
                              [c, case.name, "--levels", str(args.levels), "--out", str(paths.root)]) or 0)
            if rc == 2:
                print(f"error: {CODES[c]} refused {case.name} (exit 2, above); nothing written", file=sys.stderr)
                return 2
            failed += rc != 0
            got = collect(paths.root, case, c, ran=rc, reference=reference)
            if c == "workbench" and got and got[0].extrapolated is not None and got[0].theory is None:
                reference = got[0].extrapolated
            rows.extend(got)
    with atomic_dir(folder, kind="external") as stage:
        rows = _with_added(rows, mine, stage)
        data = {"codes": {c: CODES[c] for c in codes} | {a.name: f"{a.name} (added: {a.folder})" for a in added},
                "levels": args.levels, "targets": list(TARGETS), "rows": [_as_json(r) for r in rows]}
        write_json(stage / "compare.json", data)
        write_compare_report(data, stage)
    print(f"external compare: {len(cases)} case(s), {len(codes)} code(s) -> {folder}")
    for line in _verdict_lines(rows):
        print(line)
    return 1 if failed else 0


def _read_added(mine: dict) -> None:
    """Read every added result once before any code runs: a malformed file is one line (ResultError), exit 2."""
    from workbench.external.score import read_results

    for geos in mine.values():
        for g in geos:
            read_results([str(f) for f in g.files], fmt="csv")


def _with_added(rows: list[CodeRow], mine: dict, stage: Path) -> list[CodeRow]:
    """The rows with every added code's, each geometry scored into ``<stage>/<name>_<case>/`` and placed after the
    case's other rows."""
    from workbench.external.code_runs import score_geometry

    out = list(rows)
    for (name, case), geos in mine.items():
        for g in geos:
            target = stage / f"{name}_{case}" / ("" if g.geometry == case else g.geometry) / "score"
            target.parent.mkdir(parents=True, exist_ok=True)
            headline = score_geometry(case, list(g.files), target)
            f = target / "score.json"
            if not f.is_file():
                row = CodeRow(case, g.geometry, name, headline)
            else:
                walls = [{"process_wall_s": w} for w in g.wall_s] if all(w is not None for w in g.wall_s) else []
                row = _row(case, g.geometry, name, walls, json.loads(f.read_text()))
            last = max((i for i, r in enumerate(out) if r.case == case), default=len(out) - 1)
            out.insert(last + 1, row)
    return out


def _as_json(r: CodeRow) -> dict:
    d = r._asdict()
    d["reach"] = [x._asdict() for x in r.reach]
    return d


def _verdict_lines(rows: list[CodeRow]) -> list[str]:
    from workbench.reports.compare_report import verdict_lines

    return verdict_lines([_as_json(r) for r in rows])
