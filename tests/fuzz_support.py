"""Shared pieces of the fuzz tests (tests/test_fuzz_cases.py, tests/test_fuzz_cli.py): hypothesis profiles, a
tiny TOML writer, and the file-tree snapshots that prove nothing was written outside the output folder.

Profiles (``HYPOTHESIS_PROFILE``): ``ci`` (the default, ``make test``: the example counts of each test add up to
at least 1000), ``fuzz`` (``make fuzz``: ten times as many). Both are derandomized in CI (a failure reproduces)
and keep no example database (nothing is written into the checkout).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
from pathlib import Path

from hypothesis import HealthCheck, settings

SCALE = 10 if os.environ.get("HYPOTHESIS_PROFILE") == "fuzz" else 1
_COMMON = dict(deadline=None, database=None, suppress_health_check=[HealthCheck.too_slow,
                                                                   HealthCheck.function_scoped_fixture])
settings.register_profile("ci", derandomize=True, **_COMMON)
settings.register_profile("fuzz", derandomize=False, **_COMMON)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


def examples(n: int) -> settings:
    """``n`` examples under ``make test``, ``10 n`` under ``make fuzz``."""
    return settings(max_examples=n * SCALE)


def toml_value(v) -> str:
    """One TOML value (strings via JSON escapes; nan/inf as TOML writes them)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return _toml_string(v)
    if isinstance(v, list | tuple):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_toml_string(str(k))} = {toml_value(x)}" for k, x in v.items()) + " }"
    raise TypeError(type(v))


def _toml_string(text: str) -> str:
    """A TOML basic string: JSON escapes for control characters, non-ASCII written as UTF-8."""
    return json.dumps(text, ensure_ascii=False).replace("\x7f", "\\u007f")


def to_toml(doc: dict) -> str:
    """A case document: top-level tables (dict values), arrays of tables (``variant``: list of dicts)."""
    lines = []
    for name, table in doc.items():
        if isinstance(table, dict):
            lines.append(f"[{_toml_string(name)}]")
            lines += [f"{_toml_string(str(k))} = {toml_value(v)}" for k, v in table.items()]
        elif isinstance(table, list) and all(isinstance(t, dict) for t in table):
            for t in table:
                lines.append(f"[[{_toml_string(name)}]]")
                lines += [f"{_toml_string(str(k))} = {toml_value(v)}" for k, v in t.items()]
        else:
            lines.insert(0, f"{_toml_string(name)} = {toml_value(table)}")
    return "\n".join(lines) + "\n"


def tree(root: Path) -> dict[str, str]:
    """relative path -> sha256 (files) or 'dir' of everything under ``root``."""
    out = {}
    for dirpath, dirnames, filenames in os.walk(root):
        for d in dirnames:
            out[os.path.relpath(os.path.join(dirpath, d), root)] = "dir"
        for f in filenames:
            p = os.path.join(dirpath, f)
            with open(p, "rb") as fh:
                out[os.path.relpath(p, root)] = hashlib.sha256(fh.read()).hexdigest()
    return out


def changed(before: dict, after: dict) -> set[str]:
    """Paths added, removed or modified between two :func:`tree` snapshots."""
    return {k for k in before.keys() | after.keys() if before.get(k) != after.get(k)}


def one_error_line(err: str) -> bool:
    """Exactly one non-empty stderr line, an ``error:`` line, and no traceback."""
    lines = [ln for ln in err.splitlines() if ln.strip()]
    return len(lines) == 1 and "error" in lines[0] and "Traceback" not in err
