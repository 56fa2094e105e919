"""``workbench external ccx CASE [--levels N] [--out DIR]``: export, run CalculiX on each level, score.

Levels: the case's ``levels`` (h_c / a) from its ``ci_level`` downwards, ``N`` of them (default 3). Per level
``<out>/external_ccx_<case>/h<H>/`` holds the exported deck and CalculiX's files (``.frd``, ``.dat``, ``.sta``,
``ccx.log``); the load is the rigid band's reaction (the ``.dat``'s last ``total force`` of set CYL, doubled for a
half model); the level size h is the exported h_c (exact, ``h_source`` "export level"). The score of all
levels goes to ``<out>/external_ccx_<case>/score/`` (:mod:`workbench.external.score`), with the workbench's own
``<out>/<case>/pressure.csv`` drawn beside it when a ``workbench run`` left one there. Without ``ccx`` on
the PATH: one line, exit 2, nothing written (``make external`` installs Debian's ``calculix-ccx``).
"""

from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys
from pathlib import Path

__all__ = ["main", "ccx_executable", "run_ccx", "dat_total_force", "CcxError"]

CCX_TIMEOUT_S = 1800


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
    from workbench.external.export import ExportError, export_case, supported
    from workbench.external.frd import read_frd_result
    from workbench.external.results import ResultError, read_csv_result
    from workbench.external.score import ScoreError, level_measures, score_levels, write_score
    from workbench.paths import OutputError, check_output_folder, default_paths
    from workbench.scenes.block_theory import block_theory

    args = _parser().parse_args(argv)
    try:
        root = default_paths(None).root if args.out is None else check_output_folder(args.out)
        case = load_case(args.case)
        supported(case)
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
    folder = Path(root) / f"external_ccx_{case.name}"
    try:
        with atomic_dir(folder) as stage:
            results = []
            for lv in levels:
                sub = stage / f"h{lv:g}"
                sub.mkdir()
                (inp,) = export_case(case.name, fmt="inp", h_contact=lv, folder=sub,
                                     mesh_cache=Path(root) / "mesh_cache")
                print(f"ccx {case.name} h_c/a = {lv:g}: {inp.name}", flush=True)
                run_ccx(inp, exe=exe)
                run = case.runs(h_contact=lv)[0]
                half = 2.0 if run.geometry.half_model else 1.0
                load = -dat_total_force(inp.with_suffix(".dat")) * half
                ld = run.loading
                a = (block_theory(run.geometry, run.material, P=ld.P) if ld.P is not None
                     else block_theory(run.geometry, run.material, half_width=ld.half_width)).half_width
                results.append(read_frd_result(inp.with_suffix(".frd"), load=load, h=lv * a))
            score = score_levels(case.name, results)
            for lvl in score["levels"]:
                lvl["h_source"] = "export level (h_c of the exported mesh)"
            own = Path(root) / case.name / "pressure.csv"  # the workbench's own run in the same --out, if any
            fem = read_csv_result(own) if own.is_file() else None
            if fem is not None:
                score["fem_level"] = level_measures(fem, geometry=run.geometry, material=run.material)
            write_score(score, results, stage / "score", fem=fem)
    except (CcxError, ResultError, ScoreError, ExportError, subprocess.TimeoutExpired) as exc:
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    print(f"external ccx {case.name}: {len(levels)} level(s) -> {folder}")
    print(score["verdict"])
    return 0
