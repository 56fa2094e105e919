"""Forms compile once per structure, never per value (issue 34).

Requirement: every number a case or a study varies (E, nu, the obstacle's radius or wedge angle, kappa0, gamma0,
the load) enters the UFL forms as a dolfinx Constant (:mod:`fem.coefficients`), so that a second run of a case
with other values compiles no new FFCx module. Measured on a new machine before: a copy of ``hertz_cylinder``
with only E changed took 14.4 s warm against 4.0 s, nearly all of it the compiler.

Each check runs the real command line twice in one temporary, initially empty ``XDG_CACHE_HOME`` (the FFCx cache
``<XDG_CACHE_HOME>/fenics``) and counts the compiled modules (``.so`` files) the second run adds: 0.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

# case -> (field, factor) changes of its case file: every number the forms used to hold as a float
CHANGES = {
    "hertz_augmented_lagrangian": (("E", 0.7), ("nu", 0.9), ("radius", 1.2), ("kappa0", 3.0), ("half_width", 0.9)),
    "wedge": (("E", 0.7), ("nu", 0.9), ("half_width", 0.9), ("gamma0", 2.0)),
}


def _changed(case: str, folder: Path) -> Path:
    text = (ROOT / "cases" / f"{case}.toml").read_text(encoding="utf-8")
    for field, factor in CHANGES[case]:
        def scaled(m, factor=factor):
            return f"{m.group(1)}{float(m.group(2)) * factor!r}"

        text, n = re.subn(rf"(?m)^({field}\s*=\s*)([0-9.eE+-]+)", scaled, text)
        if n == 0:  # a solver parameter the case leaves at its default: set it
            default = {"kappa0": 1e3, "gamma0": 10.0}[field]
            text, n = re.subn(r"(?m)^(\[solver\]\n)", rf"\g<1>{field} = {default * factor!r}\n", text)
        assert n, (case, field)
    text = re.sub(r'(?m)^(name\s*=\s*)"[^"]*"', rf'\g<1>"{case}_changed"', text, count=1)
    path = folder / f"{case}_changed.toml"
    path.write_text(text, encoding="utf-8")
    return path


def _modules(cache: Path) -> set[str]:
    folder = cache / "fenics"
    return {p.name for p in folder.glob("*.so")} if folder.is_dir() else set()


def _run(case: str, out: Path, cache: Path, *, codes=(0,)) -> None:
    env = os.environ | {"XDG_CACHE_HOME": str(cache), "OMP_NUM_THREADS": "1"}
    cp = subprocess.run([sys.executable, "-m", "workbench", "run", case, "--ci", "--no-pictures", "--out", str(out)],
                        env=env, capture_output=True, text=True, timeout=600, cwd=out.parent)
    assert cp.returncode in codes, cp.stderr[-2000:]


@pytest.mark.parametrize("case", sorted(CHANGES))
def test_other_values_compile_no_new_module(case, tmp_path):
    cache = tmp_path / "xdg"
    cache.mkdir()
    out = tmp_path / "out"
    _run(case, out, cache)
    first = _modules(cache)
    assert first, "the first run compiled nothing: the cache was not the temporary one"
    changed = _changed(case, tmp_path)
    assert changed.read_text() != (ROOT / "cases" / f"{case}.toml").read_text()
    _run(str(changed), out, cache, codes=(0, 1))  # solved and written; its own tolerances are not the point
    assert _modules(cache) == first, sorted(_modules(cache) - first)
