"""The export formats: format name -> writer (a registry the deck writers register into).

Every exported benchmark has its mesh (``msh``: gmsh 4.1, written when the benchmark is built) and its JSON spec
(``json``, :mod:`workbench.external.spec`); a deck format adds the input files of one code:

* ``inp``: CalculiX/Abaqus (``workbench.external.inp`` registers it);
* ``mdpa``: Kratos Multiphysics, ``.mdpa`` + ``ProjectParameters.json`` + ``StructuralMaterials.json``
  (``workbench.external.mdpa`` registers it).

A deck writer is a :class:`DeckWriter`: ``write(exported, *, approach=None) -> list[Path]`` writes its files into
``exported.folder`` (named after the mesh's stem) and returns them; ``cannot(case) -> str | None`` says, before
anything is built, why it cannot model a case (None: it can). :func:`writer_for` imports the format's module (which
calls :func:`register_writer` on import) and returns its writer, or raises :class:`FormatError` (one line) when the
format has none.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

__all__ = ["DeckWriter", "FormatError", "FORMATS", "DECK_MODULES", "WRITERS", "register_writer", "writer_for",
           "deck_formats"]

FORMATS = ("msh", "json", "inp", "mdpa")  # every format `workbench export --format` names (and "all")
DECK_MODULES = {"inp": "workbench.external.inp", "mdpa": "workbench.external.mdpa"}


class FormatError(ValueError):
    """A format without a writer, or a writer that cannot model the case (one line)."""


class DeckWriter(NamedTuple):
    """The writer of one deck format.

    Attributes:
        fmt: the format's name (``--format``).
        what: one line: the code and its files.
        write: ``write(exported, *, approach=None) -> list[Path]``: the files written into ``exported.folder``
            (``approach``: the prescribed approach d (mm) of a displacement-driven deck, None for the writer's own).
        cannot: ``cannot(case) -> str | None``: why the writer cannot model the case (:class:`cases.schema.Case`),
            None when it can.
    """

    fmt: str
    what: str
    write: Callable[..., list[Path]]
    cannot: Callable[..., str | None] = lambda case: None  # noqa: ARG005


WRITERS: dict[str, DeckWriter] = {}


def register_writer(writer: DeckWriter) -> DeckWriter:
    """Register (or replace) the writer of ``writer.fmt``."""
    if writer.fmt not in DECK_MODULES:
        raise ValueError(f"deck format {writer.fmt!r}; allowed: {', '.join(DECK_MODULES)} (add it to DECK_MODULES)")
    WRITERS[writer.fmt] = writer
    return writer


def writer_for(fmt: str) -> DeckWriter:
    """The writer of a deck format, after importing its module; FormatError if there is none."""
    if fmt not in DECK_MODULES:
        raise FormatError(f"--format {fmt!r}; allowed: {', '.join(FORMATS)}, all")
    module = DECK_MODULES[fmt]
    try:
        importlib.import_module(module)
    except ModuleNotFoundError as exc:
        if exc.name != module:
            raise
    if fmt not in WRITERS:
        raise FormatError(f"--format {fmt}: its writer ({module}) is not installed in this checkout yet; "
                          f"allowed now: msh, json{''.join(', ' + f for f in WRITERS)}")
    return WRITERS[fmt]


def deck_formats(fmt: str, case) -> tuple[list[DeckWriter], list[str]]:
    """The deck writers ``--format fmt`` asks for on ``case`` and, for ``all``, the lines naming the formats left out
    (no writer yet, or it cannot model the case). A named format that cannot be written is a FormatError."""
    if fmt in ("msh", "json"):
        return [], []
    if fmt != "all":
        w = writer_for(fmt)
        why = w.cannot(case)
        if why:
            raise FormatError(f"--format {fmt} cannot model case {case.name}: {why}")
        return [w], []
    out, skipped = [], []
    for name in DECK_MODULES:
        try:
            w = writer_for(name)
        except FormatError as exc:
            skipped.append(f"{name}: not written ({exc})")
            continue
        why = w.cannot(case)
        if why:
            skipped.append(f"{name}: not written ({why})")
        else:
            out.append(w)
    return out, skipped
