"""Mutation check (issue 28; ``make mutations``, not part of ``make test``): each mutation below, applied to a
temporary copy of the tree, must make the test suite fail.

The copy is ``git archive HEAD`` plus the uncommitted diff of tracked files (``git diff HEAD``), with ``.venv`` a
symlink to this checkout's venv; the worktree itself is never changed. Each mutation runs
``python -m pytest -x -q`` with the files most likely to catch it first, then the whole ``tests/`` folder, and
reports the first failing test. A mutation no test catches is SURVIVED and the script exits 1.

Usage: ``python tools/mutations.py [NAME ...]`` (default: all; ``--list`` prints the table).
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import NamedTuple

ROOT = Path(__file__).resolve().parents[1]


class Mutation(NamedTuple):
    """One mutation: replace ``old`` (must occur exactly once) by ``new`` in ``file``; ``first`` are the test
    files run first (the expected catchers)."""

    name: str
    file: str
    old: str
    new: str
    first: tuple[str, ...]


MUTATIONS = (
    Mutation("contact term sign (Nitsche)", "fem/methods/nitsche.py",
             "- p / gamma * (theta * sig_n(stress_v) - gamma * ufl.dot(kin.n_c, v))",
             "+ p / gamma * (theta * sig_n(stress_v) - gamma * ufl.dot(kin.n_c, v))",
             ("tests/test_fem_hertz.py", "tests/test_fem_patch.py")),
    Mutation("convective term sign (half-plane)", "fem/contact_forms.py",
             "x1 = X[0] if kinematics == \"small\" else X[0] + u[0]",
             "x1 = X[0] if kinematics == \"small\" else X[0] - u[0]",
             ("tests/test_models_obstacle_wedge.py", "tests/test_fem_wedge.py")),
    Mutation("Hertz width x 1.01", "analytic/hertz.py",
             "return math.sqrt(4.0 * P * R / (math.pi * E_star))",
             "return 1.01 * math.sqrt(4.0 * P * R / (math.pi * E_star))",
             ("tests/test_analytic_hertz.py", "tests/test_fem_hertz.py")),
    Mutation("wedge width x 1.01", "analytic/wedge.py",
             "return _positive(P, \"P\", \"N/mm\") / (_positive(E_star, \"E_star\", \"MPa\") * "
             "_positive(m, \"m\", \"-\"))",
             "return 1.01 * _positive(P, \"P\", \"N/mm\") / (_positive(E_star, \"E_star\", \"MPa\") * "
             "_positive(m, \"m\", \"-\"))",
             ("tests/test_analytic_wedge.py", "tests/test_fem_wedge.py")),
    Mutation("close-to-conformal patch detection (one patch kept)", "workbench/scenes/concave.py",
             "    patches = find_patches(smp)\n",
             "    patches = find_patches(smp)[:1]\n",
             ("tests/test_close_to_conformal_physics.py",)),
    Mutation("superposition sum (last patch only)", "analytic/superposition.py",
             "        p += hertz_pressure(s, a=h.half_width, p0=h.p0, center=c)",
             "        p = hertz_pressure(s, a=h.half_width, p0=h.p0, center=c)",
             ("tests/test_analytic_superposition.py", "tests/test_close_to_conformal_physics.py")),
    Mutation("superposition sum x 1.1", "analytic/superposition.py",
             "        p += hertz_pressure(s, a=h.half_width, p0=h.p0, center=c)",
             "        p += 1.1 * hertz_pressure(s, a=h.half_width, p0=h.p0, center=c)",
             ("tests/test_close_to_conformal_physics.py", "tests/test_analytic_superposition.py")),
    Mutation("exit code 0 on a tolerance FAIL", "workbench/cli.py",
             "            return 0 if ok else 1\n",
             "            return 0\n",
             ("tests/test_readme_promises.py",)),
)


def _copy_tree(dest: Path) -> None:
    """HEAD plus the uncommitted diff of tracked files, into ``dest``; .venv a symlink to this checkout's."""
    archive = subprocess.run(["git", "archive", "HEAD"], cwd=ROOT, capture_output=True, check=True).stdout
    subprocess.run(["tar", "-x", "-C", str(dest)], input=archive, check=True)
    diff = subprocess.run(["git", "diff", "HEAD", "--binary"], cwd=ROOT, capture_output=True, check=True).stdout
    if diff.strip():
        subprocess.run(["git", "apply", "--whitespace=nowarn", "-"], cwd=dest, input=diff, check=True)
    (dest / ".venv").symlink_to((ROOT / ".venv").resolve())


def run_one(m: Mutation, *, timeout: float, files: list[str] | None = None) -> tuple[str, str, float]:
    """(verdict, catcher or reason, wall seconds) of one mutation."""
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="mutation-") as tmp:
        tree = Path(tmp) / "tree"
        tree.mkdir()
        _copy_tree(tree)
        path = tree / m.file
        text = path.read_text()
        if text.count(m.old) != 1:
            return "ERROR", f"the old text occurs {text.count(m.old)} times in {m.file}", 0.0
        path.write_text(text.replace(m.old, m.new))
        env = dict(os.environ, PYTHONPATH=str(tree), OMP_NUM_THREADS="1", WORKBENCH_RESULTS=str(Path(tmp) / "res"))
        # the expected catchers first, then every other test file (explicit paths: pytest keeps their order)
        rest = [f"tests/{f.name}" for f in sorted((tree / "tests").glob("test_*.py"))
                if f"tests/{f.name}" not in m.first]
        order = list(files) if files else [*m.first, *rest]
        cmd = [sys.executable, "-m", "pytest", "-x", "-q", "-rf", "-p", "no:cacheprovider", *order]
        try:
            proc = subprocess.run(cmd, cwd=tree, capture_output=True, text=True, env=env, timeout=timeout)
        except subprocess.TimeoutExpired:
            return "TIMEOUT", f"no failure within {timeout:.0f} s", time.perf_counter() - t0
    dt = time.perf_counter() - t0
    if proc.returncode == 0:
        return "SURVIVED", "every test passed", dt
    failed = re.findall(r"^(?:FAILED|ERROR) (\S+)", proc.stdout, flags=re.M)
    if proc.returncode == 1 and failed:
        return "CAUGHT", failed[0], dt
    return "CAUGHT?", f"pytest exit {proc.returncode}: {proc.stdout.strip().splitlines()[-1:]}", dt


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", help="substrings of mutation names (default: all)")
    ap.add_argument("--list", action="store_true", help="print the table and stop")
    ap.add_argument("--files", nargs="+", default=None, help="run only these test files (which of them catches it)")
    ap.add_argument("--timeout", type=float, default=3600.0, help="seconds per mutation (default 3600)")
    args = ap.parse_args(argv)
    todo = [m for m in MUTATIONS if not args.names or any(n in m.name for n in args.names)]
    if args.list:
        for m in todo:
            print(f"{m.name}: {m.file}: {m.old.strip()!r} -> {m.new.strip()!r} (first: {', '.join(m.first)})")
        return 0
    rows, ok = [], True
    for m in todo:
        verdict, what, dt = run_one(m, timeout=args.timeout, files=args.files)
        ok &= verdict == "CAUGHT"
        rows.append(f"| {m.name} | {m.file} | {verdict} | {what} | {dt:.0f} |")
        print(rows[-1], flush=True)
    print("\n| mutation | file | verdict | first failing test | wall (s) |\n|---|---|---|---|---|")
    print("\n".join(rows))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
