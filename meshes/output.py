"""Extract a finished gmsh model (nodes, triangles, contact edges), write ``.msh`` 4.1 and XDMF."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

__all__ = ["extract_model", "write_msh", "msh_to_xdmf"]


def extract_model(gmsh, *, contact_curves) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return (points (n, 3), triangles (m, 3) as row indices, contact edges (k, 2) as row indices)."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    points = coords.reshape(-1, 3)
    index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    etypes, _, enodes = gmsh.model.mesh.getElements(2)
    tri = [index[np.asarray(n, dtype=np.int64)].reshape(-1, 3) for t, n in zip(etypes, enodes, strict=True)
           if t == 2]
    edges = []
    for c in contact_curves:
        et, _, en = gmsh.model.mesh.getElements(1, c)
        edges += [index[np.asarray(n, dtype=np.int64)].reshape(-1, 2) for t, n in zip(et, en, strict=True)
                  if t == 1]
    return points, np.concatenate(tri), np.concatenate(edges) if edges else np.zeros((0, 2), dtype=np.int64)


def write_msh(gmsh, path) -> Path:
    """Write the current gmsh model as MSH 4.1 (physical groups only) atomically."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.SaveAll", 0)
    tmp = path.with_name(f".{path.stem}.{os.getpid()}.tmp.msh")
    gmsh.write(str(tmp))
    os.replace(tmp, path)
    return path


def msh_to_xdmf(msh, xdmf) -> Path:
    """Convert ``msh`` to XDMF (mesh + ``facet_tags`` + ``cell_tags``) with dolfinx on COMM_SELF.

    The tag values are gmsh physical tags; their names are stored by the caller in the stats JSON
    (``physical_groups``: name -> [dim, tag]).
    """
    import dolfinx_solver  # noqa: F401  (must precede dolfinx / petsc4py)

    from dolfinx.io import XDMFFile
    from dolfinx.io import gmsh as dgmsh
    from mpi4py import MPI

    from meshes._session import gmsh_model

    xdmf = Path(xdmf)
    # same as dgmsh.read_from_msh, but quiet and without finalising a gmsh session we did not open
    with gmsh_model("xdmf") as gmsh:
        gmsh.merge(str(msh))
        data = dgmsh.model_to_mesh(gmsh.model, MPI.COMM_SELF, 0, gdim=2)
    tmp = xdmf.with_name(f".{xdmf.stem}.{os.getpid()}.tmp.xdmf")
    data.mesh.name = "mesh"
    with XDMFFile(MPI.COMM_SELF, str(tmp), "w") as f:
        f.write_mesh(data.mesh)
        if data.facet_tags is not None:
            data.facet_tags.name = "facet_tags"
            f.write_meshtags(data.facet_tags, data.mesh.geometry)
        if data.cell_tags is not None:
            data.cell_tags.name = "cell_tags"
            f.write_meshtags(data.cell_tags, data.mesh.geometry)
    # the .h5 companion is referenced by name from the .xdmf: rename both
    os.replace(tmp.with_suffix(".h5"), xdmf.with_suffix(".h5"))
    text = tmp.read_text().replace(tmp.with_suffix(".h5").name, xdmf.with_suffix(".h5").name)
    tmp.unlink()
    tmp2 = xdmf.with_name(f".{xdmf.stem}.{os.getpid()}.tmp2")
    tmp2.write_text(text)
    os.replace(tmp2, xdmf)
    return xdmf
