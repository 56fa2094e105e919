"""A block case as a CalculiX/Abaqus ``.inp`` deck (2D plane strain, frictionless penalty contact).

The deck (units mm, N, MPa; thickness 1 mm, so forces are N per mm of thickness):

* the block: the case's gmsh mesh, 2nd-order triangles as ``CPE6`` (gmsh and Abaqus number the six nodes the
  same way; a clockwise triangle is reversed), ``*SOLID SECTION`` with thickness 1; linear elastic ``E, nu``;
* supports: bottom (``clamped``) u = 0; a half model's symmetry edge (x = 0) u_x = 0; the sides free;
* the rigid circle: one layer of ``CPE8`` quadrilaterals between radius R and R - t around the circle's lowest
  point (a band over |x| <= ``band`` a), every node moved by the same prescribed displacement (u_x = 0,
  u_y = -d): a rigid surface without a ``*RIGID BODY`` (the elastic band carries no strain); the load is the
  band's reaction (``*NODE FILE RF``/``*NODE PRINT`` of the set ``CYL``), so the external load is measured, and the
  score evaluates the theory at it. ``d`` is the approach estimate ``P/(pi E*) (2 ln(2H/a) - nu/(1-nu))``
  (Johnson's relative approach of a point at depth H) at the case's target load;
* contact: ``*CONTACT PAIR, TYPE=SURFACE TO SURFACE``, slave the block's ``contact`` edges, master the band's
  outer edges; frictionless (no ``*FRICTION``); ``*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR`` with the
  penalty slope ``K = kappa E / h_c`` (MPa/mm);
* output: ``*NODE FILE U, RF``, ``*CONTACT FILE CSTR, CDIS``, ``*CONTACT PRINT CSTR``, ``*NODE PRINT RF``.

Face labels of 2D elements in ``*SURFACE, TYPE=ELEMENT``: S1 = nodes 1-2, S2 = 2-3, S3 = 3-1 (S4 = 4-1 for
quadrilaterals), as in the CalculiX 2.20 manual's element face tables.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

__all__ = ["BlockMeshData", "read_block_msh", "inp_deck", "approach_estimate"]


class BlockMeshData(NamedTuple):
    """The block mesh read from gmsh: nodes (n, 2) mm, 6-node triangles (m, 6) 0-based, edges of the named
    1D groups (k, 3) 0-based (corner, corner, midside)."""

    nodes: np.ndarray
    triangles: np.ndarray
    edges: dict


def read_block_msh(path) -> BlockMeshData:
    """Nodes, quadratic triangles and the named line groups of a gmsh 4.1 block mesh (``meshes/block.py``)."""
    import gmsh

    initialised = gmsh.isInitialized()
    if not initialised:
        from meshes._session import initialize

        initialize()  # nothing written in the home folder
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(path))
        tags, coords, _ = gmsh.model.mesh.getNodes()
        order = np.argsort(tags)
        tags, xyz = tags[order], coords.reshape(-1, 3)[order]
        index = {int(t): i for i, t in enumerate(tags)}
        tri, lin = [], {}
        for t, _tags, conn in zip(*gmsh.model.mesh.getElements(2), strict=True):
            if t not in (2, 9):
                raise ValueError(f"{path}: element type {t}; allowed: 3- or 6-node triangles")
            tri.append(np.array([index[int(n)] for n in conn], dtype=int).reshape(-1, 3 if t == 2 else 6))
        for dim, ptag in gmsh.model.getPhysicalGroups(1):
            name = gmsh.model.getPhysicalName(dim, ptag)
            rows = []
            for ent in gmsh.model.getEntitiesForPhysicalGroup(dim, ptag):
                for t, _tags, conn in zip(*gmsh.model.mesh.getElements(1, ent), strict=True):
                    if t not in (1, 8):
                        raise ValueError(f"{path}: line element type {t}; allowed: 2- or 3-node lines")
                    rows.append(np.array([index[int(n)] for n in conn], dtype=int).reshape(-1, 2 if t == 1 else 3))
            lin[name] = np.concatenate(rows) if rows else np.zeros((0, 2), dtype=int)
    finally:
        gmsh.clear()
        if not initialised:
            gmsh.finalize()
    return _quadratic(xyz[:, :2].copy(), np.concatenate(tri), lin)


def _quadratic(nodes: np.ndarray, tri: np.ndarray, lines: dict) -> BlockMeshData:
    """6-node triangles and 3-node edges: a linear mesh (the workbench's meshes are straight-sided; the FEM's
    degree 2 is the function space) gets a node at the middle of every edge."""
    if tri.shape[1] == 6:
        return BlockMeshData(nodes, tri, lines)
    mid, extra = {}, []
    def middle(i, j):
        key = (min(i, j), max(i, j))
        if key not in mid:
            mid[key] = len(nodes) + len(extra)
            extra.append(0.5 * (nodes[i] + nodes[j]))
        return mid[key]
    tri6 = np.array([[a, b, c, middle(a, b), middle(b, c), middle(c, a)] for a, b, c in tri], dtype=int)
    edges = {name: np.array([[i, j, middle(i, j)] for i, j in rows[:, :2]], dtype=int).reshape(-1, 3)
             for name, rows in lines.items()}
    return BlockMeshData(np.vstack([nodes, np.array(extra).reshape(-1, 2)]), tri6, edges)


def approach_estimate(*, P: float, E_star: float, nu: float, a: float, depth: float) -> float:
    """Approach (mm) of a rigid cylinder on a half-plane relative to a point at ``depth`` (Johnson, Contact
    Mechanics eq. 5.37 form): ``P/(pi E*) (2 ln(2 depth/a) - nu/(1-nu))``. An estimate for the displacement
    control of the deck; the load actually carried is measured."""
    return P / (math.pi * E_star) * (2.0 * math.log(2.0 * depth / a) - nu / (1.0 - nu))


def _num(v) -> str:
    """A float in at most 20 characters (CalculiX reads a field of up to 20): the shortest text that reads back
    to the same double, else 13 significant digits."""
    text = repr(float(v))
    return text if len(text) <= 20 else f"{float(v):.13g}"


def _lines(ids, per: int = 16) -> list[str]:
    ids = [int(i) for i in ids]
    return [", ".join(str(i) for i in ids[k:k + per]) for k in range(0, len(ids), per)]


def inp_deck(mesh: BlockMeshData, *, E: float, nu: float, R: float, a: float, d: float, h_contact: float,
             half_model: bool, kappa: float = 50.0, band: float = 2.5, title: str = "") -> str:
    """The ``.inp`` text (see the module docstring). ``h_contact`` (mm) sets the band's element size and the
    penalty slope; ``a`` (mm) the band's extent."""
    nodes, tri = mesh.nodes, mesh.triangles.copy()
    # counter-clockwise triangles (positive area)
    p = nodes[tri[:, :3]]
    area = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1])
    cw = area < 0
    tri[cw] = tri[cw][:, [0, 2, 1, 5, 4, 3]]
    nn = len(nodes)
    out = ["*HEADING", title or "contact workbench export", "** units: mm, N, MPa; plane strain, thickness 1 mm",
           "*NODE, NSET=NBLOCK"]
    out += [f"{i + 1}, {_num(x)}, {_num(y)}" for i, (x, y) in enumerate(nodes)]
    # the rigid band: CPE8, corners counter-clockwise, face 1-2 on radius R (the master surface)
    xmax = band * a
    n_el = max(2, int(math.ceil(xmax / h_contact)))
    t = max(h_contact, 0.02 * R)
    th_max = math.asin(min(1.0, xmax / R))
    th = np.linspace(0.0 if half_model else -th_max, th_max, (n_el if half_model else 2 * n_el) * 2 + 1)
    ring = {}
    k = nn
    for r_i, r in enumerate((R, R - 0.5 * t, R - t)):
        for j, s in enumerate(th):
            if r_i == 1 and j % 2 == 1:
                continue
            k += 1
            ring[(r_i, j)] = k
            out.append(f"{k}, {_num(r * math.sin(s))}, {_num(R - r * math.cos(s))}")
    out.append("*ELEMENT, TYPE=CPE6, ELSET=BLOCK")
    out += [f"{e + 1}, " + ", ".join(str(n + 1) for n in row) for e, row in enumerate(tri)]
    out.append("*ELEMENT, TYPE=CPE8, ELSET=CYL")
    e0 = len(tri)
    cyl = []
    for m in range(0, len(th) - 1, 2):
        n1, n2 = ring[(0, m)], ring[(0, m + 2)]          # on radius R, increasing angle (left to right below)
        n3, n4 = ring[(2, m + 2)], ring[(2, m)]          # on radius R - t
        n5, n6, n7, n8 = ring[(0, m + 1)], ring[(1, m + 2)], ring[(2, m + 1)], ring[(1, m)]
        e0 += 1
        cyl.append(e0)
        out.append(f"{e0}, {n1}, {n2}, {n3}, {n4}, {n5}, {n6}, {n7}, {n8}")
    out.append("*NSET, NSET=CYL")
    out += _lines(sorted(ring.values()))
    # slave surface: the block's contact edges, as element faces
    faces = {}
    for e, row in enumerate(tri):
        for f, (i, j) in enumerate(((0, 1), (1, 2), (2, 0))):
            faces[frozenset((row[i], row[j]))] = (e + 1, f + 1)
    out.append("*SURFACE, NAME=SBLOCK, TYPE=ELEMENT")
    for edge in mesh.edges["contact"]:
        e, f = faces[frozenset((edge[0], edge[1]))]
        out.append(f"{e}, S{f}")
    out.append("*SURFACE, NAME=MCYL, TYPE=ELEMENT")
    out += [f"{e}, S1" for e in cyl]

    def nset(name, group):
        ids = np.unique(mesh.edges[group].reshape(-1)) + 1
        return [f"*NSET, NSET={name}", *_lines(ids)]

    out += nset("BOTTOM", "clamped")
    out += nset("SCONTACT", "contact")
    if half_model:
        out += nset("SYMM", "symmetry")
    out += ["*MATERIAL, NAME=BLOCKMAT", "*ELASTIC", f"{_num(E)}, {_num(nu)}",
            "*MATERIAL, NAME=RIGIDMAT", "*ELASTIC", f"{_num(E * 1e3)}, {_num(nu)}",
            "*SOLID SECTION, ELSET=BLOCK, MATERIAL=BLOCKMAT", "1.", "*SOLID SECTION, ELSET=CYL, MATERIAL=RIGIDMAT",
            "1.",
            "*SURFACE INTERACTION, NAME=SI", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
            f"{_num(kappa * E / h_contact)}, 0., ",
            "*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE", "SBLOCK, MCYL",
            "*BOUNDARY", "BOTTOM, 1, 2, 0."]
    if half_model:
        out.append("SYMM, 1, 1, 0.")
    out += ["*STEP, INC=200", "*STATIC", "0.1, 1., 1e-6, 0.25", "*BOUNDARY", "CYL, 1, 1, 0.", f"CYL, 2, 2, {_num(-d)}",
            "*NODE FILE", "U, RF", "*EL FILE", "S", "*CONTACT FILE", "CSTR, CDIS", "*NODE PRINT, NSET=CYL, TOTALS=ONLY",
            "RF", "*CONTACT PRINT", "CSTR", "*END STEP", ""]
    return "\n".join(out)
