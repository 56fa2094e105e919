"""``workbench external ccx CASE [--levels N] [--out DIR]``: export, run CalculiX on each level, score.

The output folder, ``external_ccx_<case>/`` and the mesh cache pass the guard every command that writes uses
(:func:`workbench.paths.checked_paths`, :func:`workbench.owned.check_dir`), before ccx is looked for.

Levels: the case's ``levels`` (h_c / a) from its ``ci_level`` downwards, ``N`` of them (default 3). Per level
``<out>/external_ccx_<case>/h<H>/`` holds the exported deck and CalculiX's files (``.frd``, ``.dat``, ``.sta``,
``ccx.log``); the load is the rigid band's reaction (the ``.dat``'s last ``total force`` of set CYL, doubled for a
half model); the level size h is the exported h_c (exact, ``h_source`` "export level"). The score of all
levels goes to ``<out>/external_ccx_<case>/score/`` (:mod:`workbench.external.score`), with the workbench's own
``<out>/<case>/pressure.csv`` drawn beside it when a ``workbench run`` left one there. Without ``ccx`` on
the PATH: one line, exit 2, nothing written (``make external`` installs Debian's ``calculix-ccx``).

Load calibration: the deck is displacement driven, and the approach estimate
(:func:`workbench.external.inp.approach_estimate`) carried 11 % less than the case's target load on
hertz_cylinder. When the measured load is more than ``LOAD_RTOL`` (0.5 %) off the target, ccx runs again with
the approach corrected (by the 2D approach law first, then by the secant through the last two runs), at most
``MAX_RUNS`` runs per level. The last run is scored, at its measured load either way; ``score.json`` keeps
every run's (d, P) per level under ``load_calibration``.
"""

from __future__ import annotations

import argparse
import math
import re
import shutil
import subprocess
import sys
from pathlib import Path

__all__ = ["main", "ccx_executable", "run_ccx", "dat_total_force", "deck_approach", "calibrated_level", "CcxError"]

CCX_TIMEOUT_S = 1800
LOAD_RTOL = 0.005  # relative distance of the measured load from the case's target that ends the calibration
MAX_RUNS = 4  # ccx runs per level at most (the first one and three secant corrections)


class CcxError(RuntimeError):
    """CalculiX missing or failed (one line)."""


def ccx_executable() -> str:
    """The path of ``ccx``, or CcxError."""
    exe = shutil.which("ccx")
    if exe is None:
        raise CcxError("ccx (CalculiX) is not installed or not on PATH; install it with `make external` "
                       "(Debian package calculix-ccx)")
    return exe


def run_ccx(inp: Path, *, exe: str) -> None:
    """Run ``ccx -i <stem>`` in the deck's folder (log in ``ccx.log``); CcxError if it fails."""
    with open(inp.parent / "ccx.log", "w") as log:
        proc = subprocess.run([exe, "-i", inp.stem], cwd=inp.parent, stdout=log, stderr=subprocess.STDOUT,
                              timeout=CCX_TIMEOUT_S, env={"OMP_NUM_THREADS": "1", "PATH": "/usr/bin:/bin"})
    text = (inp.parent / "ccx.log").read_text(errors="replace")
    if proc.returncode != 0 or "Job finished" not in text or "*ERROR" in text:
        first = next((ln.strip() for ln in text.splitlines() if "*ERROR" in ln), f"exit code {proc.returncode}")
        raise CcxError(f"ccx failed on {inp}: {first} (see {inp.parent / 'ccx.log'})")


def dat_total_force(dat: Path, *, component: int = 1) -> float:
    """The last ``total force`` printed in a CalculiX ``.dat`` (component 0, 1, 2 = x, y, z)."""
    text = dat.read_text(errors="replace")
    hits = list(re.finditer(r"total force[^\n]*\n\s*\n\s*(\S+)\s+(\S+)\s+(\S+)", text))
    if not hits:
        raise CcxError(f"{dat}: no 'total force' (*NODE PRINT, TOTALS=ONLY) in the .dat")
    return float(hits[-1].group(1 + component))


def deck_approach(inp: Path) -> float:
    """The prescribed approach d (mm, > 0 downwards) of an exported deck (its ``CYL, 2, 2, -d`` line)."""
    hit = re.search(r"^CYL, 2, 2, (\S+)$", inp.read_text(), flags=re.MULTILINE)
    if hit is None:
        raise CcxError(f"{inp}: no prescribed approach (CYL, 2, 2, -d) in the deck")
    return -float(hit.group(1))


def calibrated_level(case_name: str, level: float, folder: Path, *, exe: str, mesh_cache: Path, target: float,
                     half: float, log_term: float) -> tuple[Path, float, list[dict]]:
    """Export and run one level, re-running with a corrected approach until the load is within ``LOAD_RTOL`` of
    ``target`` (N/mm) or ``MAX_RUNS`` runs are done. The first correction follows the 2D approach law
    ``d ~ P (f_t - ln(P/P_t))``, ``f_t = log_term = 2 ln(2 H/a) - nu/(1 - nu)`` at the target (a ~ sqrt(P)),
    later ones the secant through the last two runs. Returns the deck, the last load (N/mm) and every run's
    ``{"d": mm, "P": N/mm}``."""
    from workbench.external.export import export_case

    runs, d = [], None
    for _ in range(MAX_RUNS):
        (inp,) = export_case(case_name, fmt="inp", h_contact=level, folder=folder, mesh_cache=mesh_cache, approach=d)
        used = deck_approach(inp)
        run_ccx(inp, exe=exe)
        load = -dat_total_force(inp.with_suffix(".dat")) * half
        runs.append({"d": used, "P": load})
        print(f"  d = {used:.6g} mm: P = {load:.6g} N/mm ({load / target - 1:+.2%} from the target)", flush=True)
        if abs(load / target - 1.0) <= LOAD_RTOL or not load > 0:
            break
        if len(runs) == 1:
            d = used * target * log_term / (load * (log_term - math.log(load / target)))
        else:
            (d0, p0), (d1, p1) = ((r["d"], r["P"]) for r in runs[-2:])
            d = d1 + (target - p1) * (d1 - d0) / (p1 - p0) if p1 != p0 else d1 * target / p1
    return inp, load, runs


def _parser() -> argparse.ArgumentParser:
    from workbench.cli import _Parser

    p = _Parser(prog="workbench external", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("code", choices=("ccx",))
    p.add_argument("case", metavar="CASE")
    p.add_argument("--levels", type=int, default=3, help="number of mesh levels from the case's ci_level down")
    p.add_argument("--out", default=None, help="output folder (default: results/ of this checkout)")
    return p


def main(argv: list[str] | None = None) -> int:
    """``workbench external ccx`` (exit 0 scored, 2 bad input or ccx missing/failed)."""
    import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
    from cases import CaseError, load_case
    from workbench.atomic import atomic_dir
    from workbench.external.export import ExportError, supported
    from workbench.external.frd import read_frd_result
    from workbench.external.results import ResultError, read_csv_result
    from workbench.external.score import ScoreError, level_measures, score_levels, write_score
    from workbench.owned import check_dir, ensure_dir
    from workbench.paths import OutputError, checked_paths
    from workbench.scenes.block_theory import block_theory

    args = _parser().parse_args(argv)
    try:
        paths = checked_paths(args.out)  # the output folder's guard, whichever way it was given
        case = load_case(args.case)
        supported(case)
        folder = paths.command("external_ccx_", case.name)
        check_dir(folder, kinds=("external",))
        check_dir(paths.mesh_cache, kinds=("mesh_cache",))
        disc = case.runs()[0].discretisation
        start = disc.ci_level or disc.h_contact
        available = [lv for lv in sorted(disc.levels, reverse=True) if lv <= start]
        if not 1 <= args.levels <= len(available):
            raise CcxError(f"--levels {args.levels}; allowed: 1 to {len(available)} (the case's levels from "
                           f"ci_level {start:g} down)")
        exe = ccx_executable()  # after the arguments: a bad value is named even where ccx is missing
    except (CcxError, CaseError, OutputError, ExportError) as exc:
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    levels = available[:args.levels]
    from workbench import interrupt

    interrupt.stage(f"running CalculiX on {case.name} (writing {folder.name})")
    try:
        with atomic_dir(folder, kind="external") as stage:
            ensure_dir(paths.mesh_cache, kind="mesh_cache", kinds=("mesh_cache",))
            results, calibration = [], []
            for lv in levels:
                sub = stage / f"h{lv:g}"
                sub.mkdir()
                run = case.runs(h_contact=lv)[0]
                half = 2.0 if run.geometry.half_model else 1.0
                ld = run.loading
                target = (block_theory(run.geometry, run.material, P=ld.P) if ld.P is not None
                          else block_theory(run.geometry, run.material, half_width=ld.half_width))
                print(f"ccx {case.name} h_c/a = {lv:g} (target load {target.P:.6g} N/mm)", flush=True)
                nu = run.material.nu
                log_term = 2.0 * math.log(2.0 * run.geometry.height_factor) - nu / (1.0 - nu)
                inp, load, runs = calibrated_level(case.name, lv, sub, exe=exe, mesh_cache=paths.mesh_cache,
                                                   target=target.P, half=half, log_term=log_term)
                calibration.append({"target_P": target.P, "rtol": LOAD_RTOL, "runs": runs,
                                    "within_rtol": abs(load / target.P - 1.0) <= LOAD_RTOL})
                results.append(read_frd_result(inp.with_suffix(".frd"), load=load, h=lv * target.half_width))
            score = score_levels(case.name, results)
            for lvl, cal in zip(score["levels"], calibration, strict=True):
                lvl["h_source"] = "export level (h_c of the exported mesh)"
                lvl["load_calibration"] = cal
            try:  # the workbench's own run in the same output folder, if any (never through a symlink out of it)
                own = paths.case(case.name) / "pressure.csv"
            except OutputError:
                own = None
            fem = read_csv_result(own) if own is not None and own.is_file() and not own.is_symlink() else None
            if fem is not None:
                score["fem_level"] = level_measures(fem, geometry=run.geometry, material=run.material)
            write_score(score, results, stage / "score", fem=fem)
    except (CcxError, ResultError, ScoreError, ExportError, CaseError, subprocess.TimeoutExpired) as exc:
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    print(f"external ccx {case.name}: {len(levels)} level(s) -> {folder}")
    print(score.get("headline", ""))
    print(score["verdict"])
    return 0
