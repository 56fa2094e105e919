"""Read a gmsh ``.msh`` file into dolfinx quietly (named physical groups, MPI-distributed)."""

from __future__ import annotations

import dolfinx_solver  # noqa: F401

import signal
from pathlib import Path

__all__ = ["read_mesh"]


def read_mesh(path: str | Path, comm):
    """``dolfinx.io.gmsh.read_from_msh`` with gmsh's terminal output off.

    Returns:
        dolfinx ``MeshData(mesh, cell_tags, facet_tags, ..., physical_groups)``; rank 0 reads the file.
    """
    import gmsh
    from dolfinx.io import gmsh as gmsh_io

    previous = signal.getsignal(signal.SIGINT)
    if not gmsh.isInitialized():
        from meshes._session import initialize

        initialize()  # nothing written in the home folder
    gmsh.option.setNumber("General.Terminal", 0)
    data = gmsh_io.read_from_msh(str(path), comm, 0, gdim=2)
    # gmsh.initialize() installs the default SIGINT action; restore the handler that was there (the command
    # line's, workbench.interrupt), so Ctrl-C raises and the case runner cleans its staging folder.
    signal.signal(signal.SIGINT, previous if previous is not None else signal.default_int_handler)
    return data
