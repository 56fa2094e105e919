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
import stat
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


_SHA: dict[tuple, str] = {}  # (path, size, mtime_ns, inode, ctime_ns) -> sha256: a file is hashed again when it changes
CHECKOUT = Path(__file__).resolve().parents[1]
START_DIR = Path.cwd().resolve()  # the working directory pytest was started in


def jit_cache_folders() -> set[str]:
    """The checkout's top-level folders that hold a JIT cache the user put there: ``$XDG_CACHE_HOME`` (dolfinx's
    FFCx cache ``<it>/fenics``) and ``$WORKBENCH_JIT_CACHE`` (the studies' workers), e.g. a fresh clone tested with
    ``XDG_CACHE_HOME=$clone/.c make test``. dolfinx writes compiled forms there on a cold cache: the user's
    cache, not an output of the workbench."""
    out = set()
    for given in (os.environ.get("XDG_CACHE_HOME"), os.environ.get("WORKBENCH_JIT_CACHE")):
        if given:
            folder = Path(given).expanduser().resolve()
            if CHECKOUT in folder.parents:
                out.add(folder.relative_to(CHECKOUT).parts[0])
    return out


SKIP = {".git", ".venv", "__pycache__", ".pytest_cache", ".ruff_cache", ".hypothesis", ".mypy_cache",
        *jit_cache_folders()}


def _sha(path: str, st: os.stat_result) -> str:
    key = (path, st.st_size, st.st_mtime_ns, st.st_ino, st.st_ctime_ns)
    if key not in _SHA:
        with open(path, "rb") as fh:
            _SHA[key] = hashlib.sha256(fh.read()).hexdigest()
    return _SHA[key]


def tree(root: Path, *, skip: frozenset[str] = frozenset(), depth: int | None = None) -> dict[str, str]:
    """relative path -> sha256 (files), 'dir', 'link -> target' (symlinks, never followed) or 'special <mode>' (a
    FIFO, a device, a socket: never opened) of everything under
    ``root`` (folders named in ``skip`` are listed, not entered; with ``depth``, only that many levels)."""
    out: dict[str, str] = {}

    def walk(folder: str, prefix: str) -> None:
        try:
            entries = list(os.scandir(folder))
        except OSError:
            return
        for e in entries:
            rel = prefix + e.name
            try:
                if e.is_symlink():
                    out[rel] = "link -> " + os.readlink(e.path)
                elif e.is_dir():
                    out[rel] = "dir"
                    if e.name not in skip and (depth is None or rel.count(os.sep) + 1 < depth):
                        walk(e.path, rel + os.sep)
                else:
                    st = e.stat(follow_symlinks=False)
                    # a FIFO, a device or a socket is never opened (opening a FIFO blocks until a writer comes)
                    out[rel] = _sha(e.path, st) if stat.S_ISREG(st.st_mode) else f"special {stat.S_IFMT(st.st_mode):o}"
            except OSError as exc:  # e.g. removed while walking
                out[rel] = f"unreadable: {exc.strerror}"

    walk(str(root), "")
    return out


def snapshot(sandbox: Path) -> dict[str, str]:
    """The sandbox as absolute path -> content (see :func:`tree`)."""
    prefix = str(sandbox).rstrip(os.sep) + os.sep
    return {prefix + rel: v for rel, v in tree(sandbox).items()}


def _shared(folder: Path) -> bool:
    """``folder`` holds the temporary folder or is the home folder or the file system's root: other programs write
    there while the tests run."""
    import tempfile

    tmp = Path(tempfile.gettempdir()).resolve()
    return folder == tmp or folder in tmp.parents or folder == Path.home().resolve() or folder == Path("/")


def _outside() -> dict[str, str]:
    caches = jit_cache_folders()  # in SKIP: not entered; left out entirely (a cold cache's folder appears)
    out = {str(CHECKOUT / rel): v for rel, v in tree(CHECKOUT, skip=SKIP).items()
           if rel.split(os.sep)[0] not in caches}
    # the working directory pytest started in, its top level (inside the checkout: already in its snapshot; a
    # shared folder such as /tmp changes under other programs, so the fuzz tests run inside their sandboxes)
    if not (START_DIR == CHECKOUT or CHECKOUT in START_DIR.parents or _shared(START_DIR)):
        out |= {str(START_DIR / rel): v for rel, v in tree(START_DIR, skip=SKIP, depth=1).items()}
    return out


_OUTSIDE: dict[str, str] = {}


def outside_changes(*, reset: bool = False) -> set[str]:
    """What changed in the checkout (its files and ``results/``, without .git, the venv and caches) and in the
    working directory pytest was started in (its top level; not when it is a shared folder such as /tmp) since the
    first call in this process (paths and SHA-256). Nothing a fuzz example runs may change them, so one snapshot
    taken first serves every example; ``reset`` takes it again (each fuzz module, before its first example)."""
    now = _outside()
    if reset or not _OUTSIDE:
        _OUTSIDE.clear()
        _OUTSIDE.update(now)
    return changed(_OUTSIDE, now)


def changed(before: dict, after: dict) -> set[str]:
    """Paths added, removed or modified between two :func:`tree` snapshots."""
    return {k for k in before.keys() | after.keys() if before.get(k) != after.get(k)}


def one_error_line(err: str) -> bool:
    """Exactly one line on stderr, starting with ``error:`` (no traceback, nothing else)."""
    lines = err.splitlines()
    return len(lines) == 1 and lines[0].startswith("error: ")


def ownership(root: Path) -> dict:
    """What of the output folder ``root`` is the workbench's: whether ``root`` exists, its top-level folders that
    carry the workbench's marker (kind included), and the top-level files its marker lists."""
    from workbench.owned import is_owned, read_marker, root_files

    root = Path(root)
    try:
        exists = root.is_dir() and not root.is_symlink()
    except OSError:  # e.g. a name too long for the file system
        exists = False
    folders = {}
    if exists:
        for p in root.iterdir():
            if not p.is_symlink() and is_owned(p):
                folders[p.name] = read_marker(p).get("kind")
    existed = {p.name for p in root.iterdir()} if exists else set()
    return {"exists": exists, "folders": folders, "files": root_files(root) if exists else set(), "existed": existed}


def owned_change(path: str | Path, root: Path, before: dict, after: dict) -> bool:
    """Whether a change at ``path`` lies in a part of the output folder ``root`` that the workbench owned before
    the run (or that did not exist) and owns after it: ``root`` itself when it was created, its marker, a
    top-level folder with the workbench's marker, or a top-level file its marker lists. ``before``, ``after``:
    :func:`ownership` of ``root`` before and after the run; ``existed``: the names at the top of ``root`` before."""
    from workbench.owned import MARKER

    root, path = Path(root).resolve(), Path(path)
    if path == root:
        return not before["exists"]
    if root not in path.parents:
        return False
    rel = path.relative_to(root).parts
    name = rel[0]
    if name == MARKER:
        return True
    existed = before["existed"]
    if len(rel) == 1 and name not in after["folders"] and name not in before["folders"]:  # a top-level file
        return name in after["files"] and (name not in existed or name in before["files"])
    if name.startswith(".") and (".staging." in name or ".old." in name):  # a case folder being swapped
        return name not in existed
    return name in after["folders"] and (name not in existed or before["folders"].get(name) == after["folders"][name])
