"""Mesh fingerprint: a small record that says whether two meshes are the same mesh.

Written into ``mesh.json`` (``stats["fingerprint"]``) and into every run of ``metrics.json``
(``runs[i]["mesh_fingerprint"]``), so that a later comparison of two results can name a mesh difference.
"""

from __future__ import annotations

import hashlib
from typing import NamedTuple

import numpy as np

__all__ = ["MeshFingerprint", "mesh_fingerprint", "COORD_REL"]

COORD_REL = 1e-9  # coordinates are hashed on a grid of COORD_REL times the body size


class MeshFingerprint(NamedTuple):
    """Identity of a mesh.

    Attributes:
        n_nodes: nodes of the triangles (gmsh's free geometry points, e.g. B-spline control points, left out).
        n_cells: triangles.
        facets: number of 1D elements per physical group name (dimension-1 groups only).
        coords_sha256: SHA-256 (16 hex digits) of the coordinates of those nodes rounded to COORD_REL x
            ``body_size`` (in gmsh's node order) and of the triangle connectivity.
        gmsh_input_sha256: SHA-256 (16 hex digits) of the builder's options and of every float handed to gmsh
            (:class:`meshes.portable.GmshInputs`).
        perturb: relative perturbation amplitude of the gmsh inputs (``WORKBENCH_MESH_PERTURB``; 0: none).
        geometry_source: ``frozen`` (concave control points from :mod:`meshes.frozen`), ``rounded`` (run-time
            values on the portable grid) or ``parameters`` (block: computed from rounded parameters).

    Identity fields only: the smallest distance of a rounded input to its rounding midpoint (a diagnostic that
    itself varies in the last bits between machines) is ``stats["gmsh_input_rounding_margin"]``.
    """

    n_nodes: int
    n_cells: int
    facets: dict
    coords_sha256: str
    gmsh_input_sha256: str
    perturb: float
    geometry_source: str


def mesh_fingerprint(*, points: np.ndarray, triangles: np.ndarray, facets: dict, body_size: float,
                     gmsh_input_sha256: str, perturb: float, geometry_source: str) -> MeshFingerprint:
    """The fingerprint of a mesh from its nodes (n, 2 or 3), triangles (m, 3) and facet counts by group."""
    q = COORD_REL * float(body_size)
    tri = np.asarray(triangles, dtype=np.int64)
    used, local = np.unique(tri, return_inverse=True)
    ip = np.rint(np.asarray(points, dtype=float)[used, :2] / q).astype("<i8")
    h = hashlib.sha256(ip.tobytes())
    h.update(local.reshape(tri.shape).astype("<i8").tobytes())
    return MeshFingerprint(n_nodes=int(len(used)), n_cells=int(len(tri)),
                           facets={k: int(v) for k, v in sorted(facets.items())},
                           coords_sha256=h.hexdigest()[:16], gmsh_input_sha256=gmsh_input_sha256,
                           perturb=float(perturb), geometry_source=geometry_source)
