"""A clean gmsh session: initialise if needed, quiet terminal, a fresh model, finalise only what we opened.

gmsh is global state: ``dolfinx.io.gmsh.read_from_msh`` itself calls ``gmsh.initialize()`` and
``gmsh.finalize()``, so builders never keep gmsh alive between calls.

:func:`initialize` is the one way the project starts gmsh: the FLTK library linked into gmsh writes its
preferences ``$HOME/.fltk/fltk.org/fltk.prefs`` during ``gmsh.initialize()`` (measured: gmsh 4.15.2, even with
``readConfigFiles=False``), so ``HOME`` points at a temporary folder for that call (removed after it); nothing
is written in the user's home folder.
"""

from __future__ import annotations

import contextlib
import itertools
import os
import shutil
import tempfile

import gmsh

__all__ = ["gmsh_model", "initialize"]

_counter = itertools.count()


def initialize() -> None:
    """``gmsh.initialize`` (not interruptible: the workbench handles signals) without writing in the home folder
    (see the module docstring); a no-op when gmsh is initialised."""
    if gmsh.isInitialized():
        return
    home = os.environ.get("HOME")
    scratch = tempfile.mkdtemp(prefix="gmsh-home-")
    os.environ["HOME"] = scratch
    try:
        gmsh.initialize(interruptible=False)
    finally:
        if home is None:
            os.environ.pop("HOME", None)
        else:
            os.environ["HOME"] = home
        shutil.rmtree(scratch, ignore_errors=True)


@contextlib.contextmanager
def gmsh_model(name: str):
    """Yield the ``gmsh`` module with a fresh current model named ``name`` (removed/finalised on exit)."""
    opened = not gmsh.isInitialized()
    if opened:
        initialize()
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
