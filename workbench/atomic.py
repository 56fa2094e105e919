"""Atomic file output: write to a temporary file in the same folder, then rename.

An interrupted run never leaves a half-written file, and the previous results stay intact. Every folder made
here carries the workbench's marker (:mod:`workbench.owned`), and :func:`atomic_dir` replaces only a folder that
carries it. The swap (and the repair of a swap a killed process left half done) holds an exclusive lock on the
parent folder, so concurrent commands writing the same folder replace it one after the other.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from workbench import interrupt
from workbench.owned import check_dir, check_root_file, is_owned, locked, make_dirs, mark, record_root_files

__all__ = ["atomic_dir", "atomic_path", "strict_json", "write_json", "write_root_text", "write_text"]


@contextlib.contextmanager
def atomic_path(path: str | Path, *, suffix: str | None = None) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; on success rename it onto ``path``.

    Args:
        path: The final file path.
        suffix: Suffix of the temporary file (defaults to the final suffix, so writers that dispatch on
            the extension, like matplotlib's ``savefig``, still work).
    """
    path = Path(path)
    make_dirs(path.parent)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=suffix or path.suffix, dir=path.parent)
    os.close(fd)
    tmp = Path(tmp)
    os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; results are ordinary files
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def write_text(path: str | Path, text: str) -> None:
    """Write ``text`` to ``path`` atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(text)


def write_root_text(root: str | Path, name: str, text: str) -> Path:
    """Write ``root/name`` (a file at the top of an output folder, e.g. ``report.md``) atomically, after
    :func:`workbench.owned.check_root_file` (only a file the workbench wrote is overwritten) and recording it in
    ``root``'s marker."""
    root = Path(root)
    make_dirs(root)
    check_root_file(root, name)
    record_root_files(root, [name])
    write_text(root / name, text)
    return root / name


def write_json(path: str | Path, data: Any) -> None:
    """Write ``data`` as indented, strict JSON to ``path`` atomically.

    NaN and +-Infinity are not JSON: they are written as ``null``, and a dict gets a ``non_finite`` field naming
    each such value (``{"errors.p_max": "NaN"}``), so strict parsers read every file the workbench writes.
    """
    found: dict[str, str] = {}
    clean = strict_json(data, found=found)
    if found and isinstance(clean, dict):
        clean["non_finite"] = found
    write_text(path, json.dumps(clean, indent=2, default=_json_default, allow_nan=False) + "\n")


def strict_json(obj: Any, *, found: dict[str, str] | None = None, where: str = "") -> Any:
    """``obj`` with every non-finite float replaced by None (recorded in ``found`` as dotted path -> text)."""
    import math

    import numpy as np

    if isinstance(obj, np.ndarray):
        obj = obj.tolist()
    elif isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float):
        if math.isfinite(obj):
            return obj
        if found is not None:
            found[where or "."] = "NaN" if math.isnan(obj) else ("Infinity" if obj > 0 else "-Infinity")
        return None
    if isinstance(obj, dict):
        return {k: strict_json(v, found=found, where=f"{where}.{k}" if where else str(k)) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [strict_json(v, found=found, where=f"{where}[{i}]") for i, v in enumerate(obj)]
    return obj


def _json_default(obj: Any) -> Any:
    import numpy as np

    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


@contextlib.contextmanager
def atomic_dir(path: str | Path, *, kind: str = "case") -> Iterator[Path]:
    """Yield a fresh staging folder (with the marker of ``kind``); on success it replaces ``path`` as a whole.

    The old folder is kept until the new one is complete, so an interrupted run (an exception,
    SIGINT) leaves the previous results of the case intact. ``path`` must not exist or be a workbench folder
    of the same ``kind`` (else :class:`workbench.paths.OutputError`, before anything is written). A signal that
    arrives while the new folder is swapped in is held back until the swap and the removal of the old folder are
    done; the interrupt line then says that the new results are in place (:func:`workbench.interrupt.replaced`).
    """
    path = Path(path)
    check_dir(path, kinds=(kind,))
    make_dirs(path.parent)
    with locked(path.parent):  # another process's swap in this folder is never seen half done
        _restore_interrupted_swap(path)
        _clear_stale_staging(path)
    stage = _new_staging(path, kind=kind)
    try:
        yield stage
        old = path.with_name(f".{path.name}.old.{os.getpid()}")
        # The swap is two renames: a SIGINT/SIGTERM is held back until both are done and the old folder is removed,
        # so a signal never leaves the case without its folder (a kill -9 there is repaired by the next run:
        # _restore_interrupted_swap), and its line says the new results are in place.
        with interrupt.held(), locked(path.parent):  # one swap at a time in this folder (concurrent commands)
            check_dir(path, kinds=(kind,))  # still the workbench's (never replace what appeared meanwhile)
            had_old = path.exists()
            if had_old:
                os.replace(path, old)
            os.replace(stage, path)
            interrupt.replaced(path)  # a signal held back until here finds the new results in place
            if had_old:
                shutil.rmtree(old, ignore_errors=True)
    finally:
        if stage.exists():
            shutil.rmtree(stage, ignore_errors=True)


def _new_staging(path: Path, *, kind: str) -> Path:
    """A new staging folder ``.<name>.staging.<pid>.<random>`` beside ``path`` that carries its marker from the
    moment it has that name (made as ``.<name>.new.<pid>.<random>``, marked, then renamed), so a folder of that
    pattern without the marker is never the workbench's."""
    tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.new.{os.getpid()}.", dir=path.parent))
    try:
        os.chmod(tmp, 0o777 & ~_umask())  # mkdtemp makes 0700; a results folder is an ordinary one (umask)
        mark(tmp, kind=kind)
        stage = tmp.with_name(f".{path.name}.staging.{tmp.name[len(f'.{path.name}.new.'):]}")
        os.rename(tmp, stage)  # the name is new (pid and mkdtemp's random part): nothing is replaced
        return stage
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)


def _umask() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return umask


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _clear_stale_staging(path: Path) -> None:
    """Remove the staging folders ``.<name>.staging.<pid>.*`` (and ``.<name>.new.<pid>.*``) of runs that were killed
    (SIGKILL, power loss): their process is gone, so nothing will ever finish them. A live process's staging folder
    is left alone, and so is every folder without the workbench's marker (a user's folder that only matches the
    pattern: a staging folder carries its marker from the moment it has that name, :func:`_new_staging`)."""
    for st in [*path.parent.glob(f".{path.name}.staging.*"), *path.parent.glob(f".{path.name}.new.*")]:
        pid = st.name[len(f".{path.name}."):].split(".", 2)[1]
        if st.is_dir() and not st.is_symlink() and pid.isdigit() and not _alive(int(pid)) and is_owned(st):
            shutil.rmtree(st, ignore_errors=True)


def _restore_interrupted_swap(path: Path) -> None:
    """A previous run killed between the two renames of :func:`atomic_dir` left ``.<name>.old.<pid>`` and no
    ``<name>``: put the previous results back."""
    if path.exists() or path.is_symlink():
        for old in path.parent.glob(f".{path.name}.old.*"):  # left by a process that died after the swap
            pid = old.name.rsplit(".", 1)[-1]
            if pid.isdigit() and not _alive(int(pid)) and is_owned(old):
                shutil.rmtree(old, ignore_errors=True)
        return
    olds = sorted((p for p in path.parent.glob(f".{path.name}.old.*") if is_owned(p)),
                  key=lambda p: p.stat().st_mtime)
    if olds:
        os.replace(olds[-1], path)
