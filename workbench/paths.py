"""One place for every output path of the workbench.

Everything the workbench writes lives under one output folder (``--out``; default ``results/`` beside the
``cases/`` folder of this checkout, or ``$WORKBENCH_RESULTS``), whatever the working directory is:

=====================  ============================================================
``<root>/<case>/``     a case's results (metrics.json, pressure.csv, plots, report, VTK)
``<root>/mesh_cache/`` meshes, keyed by a hash of their build parameters
``<root>/logs/``       the log of a failed case
``<root>/ci/``         ``workbench ci``: every case at its coarsest level
``<root>/<study>/``    a study (convergence, stability, bench) and ``analytic/`` (convective table)
``<root>/score_<case>/``            ``workbench score``; ``export_<case>/``: ``workbench export``;
``<root>/external_ccx_<case>/``     ``workbench external ccx`` (names no case may take: :data:`COMMAND_PREFIXES`)
=====================  ============================================================

Nothing is written outside the output folder: every path handed out here resolves inside ``root`` (a case or
study name that would leave it, or a symlink in its place, raises :class:`OutputError`), and
:func:`check_output_folder` refuses an output folder that is a file, has a missing or unwritable parent, is
read-only, or is ``/``, the home folder, the checkout, above it or in its source (:func:`check_location`), with one
line (exit code 2) before anything is written. Every command that writes takes its output folder from
:func:`checked_paths` (``--out``, else ``$WORKBENCH_RESULTS``, else ``results/``: the same checks whichever way it
came). What may be replaced or overwritten inside it: :mod:`workbench.owned`.
"""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

from cases.schema import CASE_DIR, COMMAND_PREFIXES, MAX_ECHO, CaseError

__all__ = ["COMMAND_PREFIXES", "DEFAULT_ROOT", "PROJECT_ROOT", "OutputError", "OutputPaths", "check_location",
           "check_output_folder", "checked_paths", "default_paths", "root_option", "show"]


class OutputError(CaseError):
    """The output folder cannot be used, or a path would leave it (one line; the CLI exits 2)."""


def show(path, limit: int = MAX_ECHO) -> str:
    """``path`` as text for one-line messages: at most ``limit`` characters, cut in the middle (its start and its
    last component stay readable)."""
    text = str(path)
    if len(text) <= limit:
        return text
    head = limit // 3
    return text[:head] + "..." + text[len(text) - (limit - head - 3):]


_show = show
PROJECT_ROOT = CASE_DIR.parent
"""The checkout (the folder holding ``cases/``, ``fem/``, ...): no output folder may hold it or lie in its source."""


def check_location(root: str | Path, *, option: str = "--out") -> None:
    """Refuse an output folder that is ``/``, the home folder, the checkout, a folder above it, or inside one of
    its source folders (``cases/``, ``fem/``, ``.git`` ...; ``results/`` of the checkout is allowed).

    Raises:
        OutputError: one line naming the option, the folder and why.
    """
    where = Path(root).expanduser().resolve()
    project = PROJECT_ROOT.resolve()
    why = None
    if where == Path(where.anchor):
        why = "is the root of the file system"
    elif where == Path.home().resolve():
        why = "is the home folder"
    elif where == project or where in project.parents:
        why = f"holds the project's source (the checkout {show(project)})"
    elif project in where.parents:
        top = where.relative_to(project).parts[0]
        if top != "results" and (project / top).exists():
            why = f"lies in the project's source folder {show(project / top)}"
    if why:
        raise OutputError(f"{option} {show(root)}: {why}; allowed: a folder of its own, e.g. results/ of the "
                          "checkout (the default) or a new folder elsewhere")


def _writable(folder: Path) -> bool:
    """A file can really be created in ``folder`` (not just ``os.access``: root ignores mode bits but not a
    read-only mount)."""
    try:
        with tempfile.TemporaryFile(dir=folder):
            return True
    except OSError:
        return False


def check_output_folder(root: str | Path, *, option: str = "--out") -> Path:
    """Refuse an output folder that cannot be used, before anything is written.

    Allowed: an existing writable folder, or a new folder whose parent is an existing writable folder; never
    ``/``, the home folder or the checkout's source (:func:`check_location`).

    Raises:
        OutputError: one line naming the option, the folder and what is wrong.
    """
    root = Path(root).expanduser()
    try:
        check_location(root, option=option)
        if root.exists() or root.is_symlink():
            if not root.is_dir():
                raise OutputError(f"{option} {_show(root)}: is not a folder (a file is in the way); "
                                  "allowed: a writable folder, or a new one inside a writable folder")
            if not _writable(root):
                raise OutputError(f"{option} {_show(root)}: the folder is read-only; allowed: a writable folder")
            return root.resolve()
        parent = root.absolute().parent
        if not parent.is_dir():
            raise OutputError(f"{option} {_show(root)}: its parent {_show(parent)} does not exist or is not a "
                              "folder; allowed: a new folder inside an existing writable folder")
        if not _writable(parent):
            raise OutputError(f"{option} {_show(root)}: its parent {_show(parent)} is read-only; allowed: a new "
                              "folder inside an existing writable folder")
    except (OSError, RuntimeError) as exc:  # e.g. a name too long for the file system, a symlink loop
        raise OutputError(f"{option} {_show(root)}: cannot be used: {getattr(exc, 'strerror', None) or exc}") from None
    return root.resolve()

DEFAULT_ROOT = CASE_DIR.parent / "results"


@dataclass(frozen=True)
class OutputPaths:
    """The output folder and everything below it (absolute paths)."""

    root: Path

    def __post_init__(self) -> None:
        object.__setattr__(self, "root", Path(self.root).expanduser().resolve())

    @property
    def mesh_cache(self) -> Path:
        return self.root / "mesh_cache"

    @property
    def logs(self) -> Path:
        return self.root / "logs"

    @property
    def ci(self) -> OutputPaths:
        """The CI tree ``<root>/ci``."""
        return OutputPaths(self.root / "ci")

    def inside(self, path: str | Path) -> Path:
        """``path`` (relative to root, or absolute) resolved, refused unless it lies inside root."""
        if (self.root / path).is_symlink():
            raise OutputError(f"{show(self.root / path, 160)} is a symlink (the workbench follows none out of its "
                              "output folder); nothing was written or deleted: move it away or choose another --out")
        p = (self.root / path).resolve()
        if p == self.root or self.root not in p.parents:
            raise OutputError(f"{_show(path)}: resolves to {_show(p)}, outside the output folder {_show(self.root)}; "
                              "allowed: a name of letters, digits, '_' or '-'")
        return p

    def case(self, name: str) -> Path:
        return self.inside(name)

    def study(self, name: str) -> Path:
        return self.inside(name)

    @property
    def analytic(self) -> Path:
        return self.root / "analytic"

    def command(self, prefix: str, case: str) -> Path:
        """The folder of a command's results for ``case``: ``<root>/<prefix><case>`` (``score_``, ``export_``,
        ``external_ccx_``; prefixes no case name may start with, so a case never replaces them)."""
        if not any(prefix.startswith(p) for p in COMMAND_PREFIXES):
            raise ValueError(f"{prefix!r} is not a command prefix ({', '.join(COMMAND_PREFIXES)})")
        return self.inside(f"{prefix}{case}")


def default_paths(out: str | Path | None = None) -> OutputPaths:
    """``out`` if given, else ``$WORKBENCH_RESULTS``, else ``results/`` of this checkout (not checked: a command
    that writes uses :func:`checked_paths`)."""
    if out is None:
        out = os.environ.get("WORKBENCH_RESULTS") or DEFAULT_ROOT
    return OutputPaths(Path(out))


def root_option(out: str | Path | None) -> str:
    """How the output folder was given, for its error lines: ``--out``, ``WORKBENCH_RESULTS`` or
    ``output folder`` (the default ``results/``)."""
    return "--out" if out is not None else "WORKBENCH_RESULTS" if os.environ.get("WORKBENCH_RESULTS") else \
        "output folder"


def checked_paths(out: str | Path | None = None) -> OutputPaths:
    """The output folder of a command that writes, checked before anything is written: ``out`` (``--out``), else
    ``$WORKBENCH_RESULTS``, else ``results/`` of this checkout, each through :func:`check_output_folder` under the
    name it was given by. The one guard of ``run``, ``mesh``, ``report``, ``ci``, the studies, ``score``,
    ``export`` and ``external``.

    Raises:
        OutputError: one line naming the option (or ``WORKBENCH_RESULTS``), the folder and what is wrong.
    """
    option = root_option(out)
    given = out if out is not None else (os.environ.get("WORKBENCH_RESULTS") or DEFAULT_ROOT)
    if not str(given).strip():
        raise OutputError(f"{option}: an empty folder name is not allowed; allowed: a folder path")
    check_output_folder(given, option=option)
    return OutputPaths(Path(given))
