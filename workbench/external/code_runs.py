"""What every ``workbench external <code>`` command shares: its options, the guard before anything is written, the
mesh levels it runs and the score of a geometry's levels.

Options: ``<code> CASE [--levels N] [--out DIR]`` (and ``--time-limit S`` where the code takes one). The guard
(:func:`open_command`): the time limit, the output folder (:func:`workbench.paths.checked_paths`), the case, the levels,
the code's folder ``external_<code>_<case>/`` and the mesh cache (:func:`workbench.owned.check_dir`), each refused in
one line before anything is written.

Levels: the case's first ``n`` from its ``ci_level`` down (:func:`workbench.external.export.level_sequence`, the levels
``workbench export --levels n`` writes: the case's list, continued by halving). Score: the result files of one
geometry, one per level, read and scored exactly as ``workbench score`` does (:mod:`workbench.external.score`).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import NamedTuple

__all__ = ["Opened", "code_parser", "open_command", "code_levels", "score_geometry", "score_all", "print_summary",
           "first_error",
           "timed_job"]


class Opened(NamedTuple):
    """A command past its guard: the output paths, the loaded case, its levels and the code's folder."""

    paths: object
    case: object
    levels: list[float]
    folder: Path


def code_parser(code: str, description: str, *, time_limit: float | None = None) -> argparse.ArgumentParser:
    """The options of ``workbench external <code>`` (module docstring)."""
    from workbench.cli import _Parser

    p = _Parser(prog=f"workbench external {code}", description=description,
                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("code", choices=(code,))
    p.add_argument("case", metavar="CASE")
    p.add_argument("--levels", type=int, default=3, help="number of mesh levels from the case's ci_level down")
    p.add_argument("--out", default=None, help="output folder (default: results/ of this checkout)")
    if time_limit is not None:
        p.add_argument("--time-limit", type=float, default=time_limit, help="seconds per level")
    return p


def open_command(code: str, args, *, error) -> Opened:
    """The guard of ``workbench external <code>`` (module docstring); raises ``error(message)``,
    :class:`cases.CaseError` or :class:`workbench.paths.OutputError` (one line each: the command exits 2)."""
    import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
    from cases import load_case
    from workbench.owned import check_dir
    from workbench.paths import checked_paths

    limit = getattr(args, "time_limit", None)
    if limit is not None and not (math.isfinite(limit) and limit > 0):
        raise error(f"--time-limit {limit!r}; allowed: a number of seconds > 0")
    paths = checked_paths(args.out)  # the output folder's guard, whichever way it was given
    case = load_case(args.case)
    levels = code_levels(case, args.levels, error=error)
    folder = paths.command(f"external_{code}_", case.name)
    check_dir(folder, kinds=("external",))
    check_dir(paths.mesh_cache, kinds=("mesh_cache",))
    return Opened(paths, case, levels, folder)


def code_levels(case, n: int, *, error: type[Exception]) -> list[float]:
    """The case's first ``n`` mesh levels from its ``ci_level`` down; ``error`` (one line) outside 1 .. MAX_LEVELS."""
    from workbench.external.export import MAX_LEVELS, level_sequence

    if not 1 <= n <= MAX_LEVELS:
        d = case.runs()[0].discretisation
        raise error(f"--levels {n}; allowed: 1 to {MAX_LEVELS} (the case's levels from ci_level "
                    f"{d.ci_level or d.h_contact:g} down, halving beyond its list)")
    return list(level_sequence(case)[:n])


def score_geometry(case_name: str, files: list[Path], folder: Path) -> str:
    """Score one geometry's levels (one result csv per level) into ``folder``; the headline, or why it was not
    scored (one line)."""
    from workbench.external.results import ResultError
    from workbench.external.score import ScoreError, read_results, score_levels, write_score

    try:
        results = read_results([str(f) for f in files], fmt="csv")
        score = score_levels(case_name, results)
        write_score(score, results, folder)
    except (ScoreError, ResultError, ValueError) as exc:
        return f"not scored: {' '.join(str(exc).split())[:300]}"
    return score.get("headline") or score.get("verdict", "")


def score_all(case_name: str, results: dict, stage: Path, summary: dict) -> None:
    """Score every (geometry, variant)'s levels (``results``: (geometry key or "", variant or "") -> result files,
    coarse first) into ``<geometry>/score/`` (a variant's ``score_<variant>/``), the headline into ``summary``."""
    for (key, variant), files in results.items():
        name = f"score_{variant}" if variant else "score"
        target = stage / key / name if key else stage / name
        target.parent.mkdir(parents=True, exist_ok=True)
        summary["geometries"][key or case_name][name] = score_geometry(case_name, files, target)


def print_summary(code: str, case_name: str, levels: list[float], folder: Path, summary: dict) -> None:
    """The command's last lines: where it wrote, and every geometry's (and variant's) headline."""
    print(f"external {code} {case_name}: {len(levels)} level(s) -> {folder}")
    for key, entry in summary["geometries"].items():
        for name in [k for k in entry if k.startswith("score")]:
            print(f"{key}{'' if name == 'score' else ' (' + name[6:] + ')'}: {entry[name]}")


def first_error(stderr: str | None) -> str:
    """The first ``error:`` line of a job's stderr (else its last line), without the prefix, at most 300 characters."""
    lines = [ln for ln in (stderr or "").splitlines() if ln.strip()]
    first = next((ln for ln in lines if ln.startswith("error:")), lines[-1] if lines else "")
    return first.removeprefix("error: ")[:300]


def timed_job(argv: list[str], *, record: Path, what: str, error, time_limit: float, env: dict,
              cwd: Path | None = None, log: Path | None = None) -> dict:
    """Run one job process (``argv``; its stdout into ``log`` if given) and read the JSON ``record`` it wrote, with
    the process's wall time added (``process_wall_s``, s). ``error(message)`` (one line naming ``what``) when it
    exceeded ``time_limit`` seconds or failed."""
    import json
    import subprocess
    import time

    t0 = time.perf_counter()
    out = open(log, "w") if log is not None else subprocess.DEVNULL  # noqa: SIM115  (closed below)
    try:
        proc = subprocess.run(argv, cwd=cwd, stdout=out, stderr=subprocess.PIPE, timeout=time_limit, env=env,
                              text=True)
    except subprocess.TimeoutExpired:
        raise error(f"{what} exceeded the time limit of {time_limit:g} s (--time-limit); nothing written") from None
    finally:
        if log is not None:
            out.close()
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        where = f" (log: {log.name})" if log is not None else ""
        raise error(f"{what} failed (exit {proc.returncode}): {first_error(proc.stderr)}{where}")
    data = json.loads(record.read_text())
    data["process_wall_s"] = wall
    return data
