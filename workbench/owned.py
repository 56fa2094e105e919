"""What the workbench wrote: the ownership marker ``.workbench-owned`` and the checks that read it.

Every folder the workbench creates carries a marker file ``.workbench-owned`` (small JSON: ``tool``, ``kind``,
``created``; ``kind`` is ``case``, ``mesh_cache``, ``logs``, ``ci``, ``vtk``, a study's name, or ``folder``).
The rules (issue 23):

- A folder is replaced (a case's results) only when it carries the marker of kind ``case``; the workbench
  writes into a folder below the output folder only when it carries a marker or does not exist yet (then it
  creates it, with the marker). A folder without the marker is never touched: :func:`check_dir` refuses it
  with one line (the CLI exits 2) before anything is written.
- A file at the top of the output folder (``report.md``, ``report.html``, ``ci_report.md`` ...) is
  overwritten only when the output folder's marker lists it (``files``): :func:`check_root_file`,
  :func:`record_root_files`. A folder the workbench did not create but wrote such a file into gets a marker
  with ``adopted: true``: it lists the files, and does not make the folder the workbench's.
- A symlink in the place of such a folder or file is refused, never followed out of the output folder.

Results written by a workbench older than these rules carry no marker: they are refused like a user's files
(move them away, or choose another ``--out``).
"""

from __future__ import annotations

import contextlib
import datetime
import json
import os
import shutil
import tempfile
from collections.abc import Iterable
from pathlib import Path

from workbench.paths import OutputError, show

__all__ = ["MARKER", "TOOL", "check_dir", "check_root_file", "check_run_outputs", "ensure_dir", "is_owned", "locked",
           "make_dirs", "mark", "read_marker", "record_root_files", "root_files"]

MARKER = ".workbench-owned"
TOOL = "contact-workbench"
_MAX_MARKER = 1 << 20  # bytes: a marker is a few hundred; anything larger is not ours


def read_marker(folder: str | Path) -> dict | None:
    """The marker of ``folder`` as a dict, or None (no folder, a symlink, no marker, or not the workbench's)."""
    folder = Path(folder)
    f = folder / MARKER
    try:
        if folder.is_symlink() or not folder.is_dir() or f.is_symlink() or not f.is_file():
            return None
        if f.stat().st_size > _MAX_MARKER:
            return None
        data = json.loads(f.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) and data.get("tool") == TOOL else None


def is_owned(folder: str | Path, *, kinds: Iterable[str] | None = None) -> bool:
    """``folder`` was created by the workbench (a marker that is not ``adopted``), of one of ``kinds`` if given."""
    m = read_marker(folder)
    if m is None or m.get("adopted"):
        return False
    return kinds is None or m.get("kind") in set(kinds)


def _write_marker(folder: Path, data: dict) -> None:
    fd, tmp = tempfile.mkstemp(prefix=f"{MARKER}.", dir=folder)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            json.dump(data, fh, indent=1, sort_keys=True)
            fh.write("\n")
        os.chmod(tmp, 0o644)
        os.replace(tmp, folder / MARKER)
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)


def _new_marker(kind: str, *, adopted: bool = False) -> dict:
    now = datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")
    return {"tool": TOOL, "kind": kind, "created": now} | ({"adopted": True} if adopted else {})


def mark(folder: str | Path, *, kind: str) -> None:
    """Give ``folder`` (which the workbench has just created) its marker, unless it has one."""
    folder = Path(folder)
    if read_marker(folder) is None:
        _write_marker(folder, _new_marker(kind))


def make_dirs(folder: str | Path, *, kind: str = "folder") -> Path:
    """Create ``folder`` and its missing parents, each with a marker (``kind`` for ``folder`` itself,
    ``folder`` for the parents); folders that exist are left as they are."""
    folder = Path(folder)
    missing = []
    p = folder
    while not (p.exists() or p.is_symlink()):
        missing.append(p)
        if p.parent == p:
            break
        p = p.parent
    for p in reversed(missing):
        _make_marked(p, kind=kind if p == folder else "folder")
    return folder


def _make_marked(folder: Path, *, kind: str) -> None:
    """Create ``folder`` with its marker in one step (a marked temporary folder renamed into place), so a
    concurrent run never sees it without its marker; if a concurrent run made it first, keep theirs."""
    tmp = Path(tempfile.mkdtemp(prefix=f".{folder.name[:40]}.new.", dir=folder.parent))
    try:
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o777 & ~umask)  # mkdtemp makes 0700; an output folder is an ordinary one
        _write_marker(tmp, _new_marker(kind))
        try:
            os.rename(tmp, folder)  # fails when a concurrent run made it meanwhile (ENOTEMPTY / EEXIST)
        except OSError:
            if not folder.is_dir():
                raise
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)


PATH_ECHO = 160  # characters of a path in these messages (cut in the middle beyond)


def _refuse(path: Path, what: str = "exists and was not written by the workbench") -> OutputError:
    return OutputError(f"{show(path, PATH_ECHO)} {what}; the workbench replaces, deletes or overwrites only what it "
                       f"wrote (a folder with its {MARKER} marker); nothing was written or deleted: move it away "
                       "(results of an older workbench have no marker) or choose another --out")


def check_dir(folder: str | Path, *, kinds: Iterable[str] | None = None) -> None:
    """Refuse ``folder`` unless it does not exist yet or is a workbench folder (of one of ``kinds``).

    Raises:
        OutputError: one line naming the folder (a symlink, a file, or a folder without the marker).
    """
    folder = Path(folder)
    if folder.is_symlink():
        raise _refuse(folder, "is a symlink (the workbench follows none out of its output folder)")
    if not folder.exists():
        return
    if not folder.is_dir():
        raise _refuse(folder, "exists, is not a folder, and was not written by the workbench")
    if not is_owned(folder, kinds=kinds):
        m = read_marker(folder)
        if m is not None and not m.get("adopted") and kinds is not None:
            raise _refuse(folder, f"is a workbench {m.get('kind')!s:.20} folder, not one of: {', '.join(kinds)}")
        raise _refuse(folder)


def ensure_dir(folder: str | Path, *, kind: str, kinds: Iterable[str] | None = None) -> Path:
    """:func:`check_dir`, then create ``folder`` with its marker if it does not exist."""
    check_dir(folder, kinds=kinds)
    return make_dirs(folder, kind=kind)


def root_files(root: str | Path) -> set[str]:
    """The files at the top of ``root`` that the workbench wrote (its marker's ``files``)."""
    m = read_marker(root)
    files = (m or {}).get("files", [])
    return {f for f in files if isinstance(f, str)} if isinstance(files, list) else set()


def check_root_file(root: str | Path, name: str) -> None:
    """Refuse to overwrite ``root/name`` unless it does not exist or the workbench wrote it.

    Raises:
        OutputError: one line naming the file.
    """
    path = Path(root) / name
    if path.is_symlink():
        raise _refuse(path, "is a symlink (the workbench follows none out of its output folder)")
    if path.exists() and (not path.is_file() or name not in root_files(root)):
        raise _refuse(path)


@contextlib.contextmanager
def locked(folder: Path):
    """An exclusive lock on ``folder`` (flock on the folder itself: no lock file left behind)."""
    import fcntl

    fd = os.open(folder, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)


def record_root_files(root: str | Path, names: Iterable[str]) -> None:
    """Add ``names`` to the files of ``root``'s marker (a marker ``adopted: true`` if ``root`` had none)."""
    root = Path(root)
    with locked(root):
        m = read_marker(root) or _new_marker("root", adopted=True)
        m["files"] = sorted(root_files(root) | set(names))
        _write_marker(root, m)


def check_run_outputs(paths, cases) -> None:
    """Before ``workbench run`` (or ``mesh``) writes anything: refuse two cases of one name, a case folder, mesh
    cache or logs folder that is not the workbench's, and a case file inside the folder its results would replace.

    Args:
        paths: The :class:`workbench.paths.OutputPaths` of the run.
        cases: The loaded cases (``name``, ``path``).

    Raises:
        OutputError: one line naming the folder, file or name.
    """
    seen: dict[str, object] = {}
    for case in cases:
        if case.name in seen:
            raise OutputError(f"case name {case.name!r} is given twice ({show(seen[case.name], PATH_ECHO)} "
                              f"and {show(case.path, PATH_ECHO)}); allowed: one case of each name per call (its "
                              "results folder would be replaced by the other's)")
        seen[case.name] = case.path
    check_dir(paths.mesh_cache, kinds=("mesh_cache",))
    check_dir(paths.logs, kinds=("logs",))
    for case in cases:
        folder = paths.case(case.name)
        check_dir(folder, kinds=("case",))
        source = Path(case.path).resolve()
        if folder == source or folder in source.parents:
            raise OutputError(f"case file {show(case.path, PATH_ECHO)} lies inside {show(folder, PATH_ECHO)}, "
                              "the folder its results would replace; allowed: a case file outside its case's results "
                              "folder")
