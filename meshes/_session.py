"""A clean gmsh session: initialise if needed, quiet terminal, a fresh model, finalise only what we opened.

gmsh is global state: ``dolfinx.io.gmsh.read_from_msh`` itself calls ``gmsh.initialize()`` and
``gmsh.finalize()``, so builders never keep gmsh alive between calls.
"""

from __future__ import annotations

import contextlib
import itertools

import gmsh

__all__ = ["gmsh_model"]

_counter = itertools.count()


@contextlib.contextmanager
def gmsh_model(name: str):
    """Yield the ``gmsh`` module with a fresh current model named ``name`` (removed/finalised on exit)."""
    opened = not gmsh.isInitialized()
    if opened:
        gmsh.initialize(interruptible=False)
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.Verbosity", 1)
    model_name = f"{name}_{next(_counter)}"
    gmsh.model.add(model_name)
    try:
        yield gmsh
    finally:
        try:
            gmsh.model.setCurrent(model_name)
            gmsh.model.remove()
        except Exception:  # noqa: BLE001 - best effort cleanup of a failed build
            pass
        if opened:
            gmsh.finalize()
