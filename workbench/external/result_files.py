"""What every reader of an external result (csv, frd, vtu/vtp/pvd) does before and after it parses, in one place.

* :func:`open_result`: the file is opened without blocking and refused unless it is a regular file (a FIFO, a
  device or a socket is never read: a FIFO would hang the command, ``/dev/zero`` never end) of at most
  :data:`MAX_RESULT_BYTES`; a symlink is followed only to a file in its own folder (``pw.csv -> /etc/passwd`` is
  refused, never read).
* :func:`inside_folder`: a file a result names (a ``.pvd``'s ``DataSet file=``) must lie in the result's folder:
  not absolute, no ``..`` out of it, no symlink out of it.
* :func:`merge_coincident`: samples at one position (within 1e-12 of the surface's extent) are merged into one,
  the largest pressure kept (with its weight and argument), by all three readers alike: CalculiX writes the
  slave and the master node of the first contact point at one position, one of them without CPRESS; a csv that
  repeats a position gets the same rule. How many were merged is recorded (``merged``) and the report says so.
* :func:`shown`: a name from inside a file is echoed in an error line only if it looks like a column or field
  name (never a line of whatever file the path pointed at).
* :func:`parsing`: any other failure of the parser on a malformed file (``ValueError``, ``IndexError``,
  ``OverflowError`` ...) becomes one line naming the file (the command exits 2; never a traceback).

Units: mm, MPa.
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
import stat
import struct
import zlib
from pathlib import Path

import numpy as np

__all__ = ["ResultError", "MAX_RESULT_BYTES", "MAX_SAMPLES", "MAX_POINTS", "open_result", "read_result_bytes",
           "inside_folder", "merge_coincident", "shown", "parsing"]

class ResultError(ValueError):
    """A bad external result file: the message is one line naming the file and the problem."""


MAX_RESULT_BYTES = 256 * 2**20
"""The largest result file read (bytes; checked before reading): a CalculiX .frd of a 2D model with 1e6 nodes
and its CONTACT and DISP blocks is about 150 MB."""
MAX_SAMPLES = 1_000_000
"""Rows of a csv result at most (a contact surface sampled at a million points is no external code's level)."""
MAX_POINTS = 4_000_000
"""Points (nodes) of a .vtu/.vtp or .frd at most: with 3 coordinates and one field, about 130 MB as float64."""

_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_.()\[\]/+-]{0,39}")


def shown(text: str) -> str:
    """``text`` as it may appear in an error line: itself if it looks like a column or field name (letters,
    digits, ``_.()[]/+-``, at most 40 characters), else a placeholder (the file's content is never echoed)."""
    return text if _NAME.fullmatch(text) else "<not a name>"


def _refuse_kind(mode: int, where: str) -> None:
    if not stat.S_ISREG(mode):
        kind = ("a FIFO" if stat.S_ISFIFO(mode) else "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode)
                else "a socket" if stat.S_ISSOCK(mode) else "a folder" if stat.S_ISDIR(mode) else "not a file")
        raise ResultError(f"{where}: is {kind}, not a regular file; allowed: a result file")


def open_result(path: str | Path, *, where: str | None = None, max_bytes: int = MAX_RESULT_BYTES,
                folder: str | Path | None = None):
    """The binary file object of a result file, opened without blocking and checked (see the module docstring).

    Args:
        path: The file.
        where: Its name in error lines (default: ``path``).
        max_bytes: The largest size read (bytes).
        folder: The folder it must resolve into (default: its own folder).

    Raises:
        ResultError: one line: missing, a symlink out of its folder, not a regular file, too large, unreadable.
    """
    path = Path(path)
    where = str(path) if where is None else where
    inside_folder(Path(folder) if folder is not None else path.absolute().parent, path, where=where)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_NOCTTY | getattr(os, "O_CLOEXEC", 0))
    except OSError as exc:
        what = "no such file" if exc.errno == errno.ENOENT else exc.strerror or str(exc)
        raise ResultError(f"{where}: cannot be read ({what})") from None
    try:
        st = os.fstat(fd)
        _refuse_kind(st.st_mode, where)
        if st.st_size > max_bytes:
            raise ResultError(f"{where}: {st.st_size} bytes; allowed: at most {max_bytes} bytes (a result file of one "
                              "mesh level)")
        os.set_blocking(fd, True)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def read_result_bytes(path: str | Path, *, where: str | None = None, max_bytes: int = MAX_RESULT_BYTES,
                      folder: str | Path | None = None) -> bytes:
    """The whole content of a result file (:func:`open_result`), at most ``max_bytes``."""
    where = str(path) if where is None else where
    with open_result(path, where=where, max_bytes=max_bytes, folder=folder) as fh:
        try:
            size = os.fstat(fh.fileno()).st_size  # read() of max_bytes + 1 would allocate that much at once
            data = fh.read(size + 1)
            if len(data) > size:  # it grew while being read
                data += fh.read(max_bytes + 1 - len(data))
        except OSError as exc:
            raise ResultError(f"{where}: cannot be read ({exc.strerror or exc})") from None
    if len(data) > max_bytes:  # it grew while being read
        raise ResultError(f"{where}: more than {max_bytes} bytes; allowed: at most {max_bytes} bytes")
    return data


def inside_folder(folder: Path, path: str | Path, *, where: str, what: str = "file") -> Path:
    """``path`` resolved (symlinks followed), refused unless it lies inside ``folder`` (no ``..`` or symlink out of
    it)."""
    try:
        real_folder = Path(folder).resolve()
        real = Path(path).resolve()
    except (OSError, RuntimeError) as exc:
        raise ResultError(f"{where}: the {what} cannot be resolved ({exc})") from None
    if real_folder not in real.parents:
        raise ResultError(f"{where}: the {what} resolves to {shown_path(real)}, outside the folder "
                          f"{shown_path(real_folder)}; allowed: a {what} inside it (a symlink or '..' out of it is "
                          "not followed)")
    return real


def shown_path(path: Path, limit: int = 120) -> str:
    text = str(path)
    return text if len(text) <= limit else text[:40] + "..." + text[-(limit - 43):]


def merge_coincident(x: np.ndarray, p: np.ndarray, *others: np.ndarray | None, scale: float,
                     y: np.ndarray | None = None):
    """Samples at one position merged into one, the largest pressure kept (see the module docstring).

    Args:
        x, p: positions (mm) and pressures (MPa), any order.
        others: arrays carried along with each sample (weights, arguments, displacements) or None.
        scale: the surface's extent (mm); positions closer than 1e-12 of it are one position.
        y: the second reference coordinate of a curved surface (mm), or None (a flat surface: x alone). Given, two
            samples are one position when both x and y are that close; ``y`` is then the last of ``others``.

    Returns:
        ``(x, p, *others, merged)``: sorted by x (then y), and the number of samples dropped.
    """
    if y is not None:
        others = (*others, y)
    order = np.lexsort((-p, x)) if y is None else np.lexsort((-p, y, x))
    x, p = x[order], p[order]
    others = [o[order] if o is not None else None for o in others]
    first = np.ones(x.size, dtype=bool)
    first[1:] = np.diff(x) > 1e-12 * scale
    if y is not None:
        first[1:] |= np.abs(np.diff(others[-1])) > 1e-12 * scale
    merged = int(x.size - np.count_nonzero(first))
    return (x[first], p[first], *[o[first] if o is not None else None for o in others], merged)


@contextlib.contextmanager
def parsing(where: str):
    """Any failure of a parser on a malformed file, as one line naming the file (see the module docstring)."""
    try:
        yield
    except ResultError:
        raise
    except (ValueError, TypeError, IndexError, KeyError, AttributeError, OverflowError, ZeroDivisionError,
            ArithmeticError, UnicodeError, struct.error, zlib.error, RecursionError, MemoryError) as exc:
        text = " ".join(str(exc).split())[:120]
        raise ResultError(f"{where}: a malformed result file ({exc.__class__.__name__}: {text})") from None
