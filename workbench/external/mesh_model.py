"""A benchmark's mesh as plain arrays: nodes, the cells of each body, the facets of each surface (numpy only).

:func:`read_msh` reads a gmsh ``.msh`` (4.1, linear or quadratic triangles and lines) with its named physical
groups; :meth:`MeshModel.merge` adds another body's mesh (a rigid indenter's band) with its own nodes;
:func:`write_msh` writes a model back as a gmsh ``.msh`` with the same groups; :meth:`MeshModel.quadratic` gives
6-node triangles and 3-node facets (a node at the middle of every straight edge) for a code whose elements are
quadratic. Node indices are 0-based. Units mm.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["MeshModel", "read_msh", "write_msh"]


@dataclass(frozen=True)
class MeshModel:
    """Nodes (n, 2) mm; ``cells``: 2D group name -> (m, 3 or 6) triangles (counter-clockwise corners first);
    ``facets``: 1D group name -> (k, 2 or 3) lines (corner, corner[, middle])."""

    nodes: np.ndarray
    cells: dict
    facets: dict

    @property
    def order(self) -> int:
        """1 for 3-node triangles, 2 for 6-node ones."""
        first = next(iter(self.cells.values()))
        return 1 if first.shape[1] == 3 else 2

    def merge(self, other: MeshModel) -> MeshModel:
        """This model and ``other`` in one (``other``'s nodes appended, its indices shifted; its groups must have
        names of their own)."""
        if other.order != self.order:
            raise ValueError("merge: both meshes must have the same element order")
        clash = (set(self.cells) & set(other.cells)) | (set(self.facets) & set(other.facets))
        if clash:
            raise ValueError(f"merge: groups of both meshes share the names {sorted(clash)}")
        n = len(self.nodes)
        return MeshModel(np.vstack([self.nodes, other.nodes]),
                         {**self.cells, **{k: v + n for k, v in other.cells.items()}},
                         {**self.facets, **{k: v + n for k, v in other.facets.items()}})

    def quadratic(self) -> MeshModel:
        """6-node triangles and 3-node facets: a node at the middle of every edge (the meshes are straight-sided)."""
        if self.order == 2:
            return self
        nodes = [*self.nodes]
        middle: dict[tuple[int, int], int] = {}

        def mid(i: int, j: int) -> int:
            key = (min(i, j), max(i, j))
            if key not in middle:
                middle[key] = len(nodes)
                nodes.append(0.5 * (self.nodes[i] + self.nodes[j]))
            return middle[key]

        cells = {k: np.array([[a, b, c, mid(a, b), mid(b, c), mid(c, a)] for a, b, c in tri], dtype=int).reshape(-1, 6)
                 for k, tri in self.cells.items()}
        facets = {k: np.array([[i, j, mid(i, j)] for i, j in lines[:, :2]], dtype=int).reshape(-1, 3)
                  for k, lines in self.facets.items()}
        return MeshModel(np.asarray(nodes, dtype=float).reshape(-1, 2), cells, facets)

    def group_nodes(self, name: str) -> np.ndarray:
        """The sorted node indices of a cell or facet group."""
        rows = self.cells[name] if name in self.cells else self.facets[name]
        return np.unique(rows.reshape(-1))


def _ccw(nodes: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Triangles with counter-clockwise corners (positive area); 6-node ones keep their edge nodes' order."""
    p = nodes[tri[:, :3]]
    area = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1])
    out = tri.copy()
    cw = area < 0
    out[cw] = tri[cw][:, [0, 2, 1]] if tri.shape[1] == 3 else tri[cw][:, [0, 2, 1, 5, 4, 3]]
    return out


_TRI = {2: 3, 9: 6}
_LINE = {1: 2, 8: 3}


def read_msh(path: str | Path) -> MeshModel:
    """The nodes, the named 2D groups' triangles and the named 1D groups' lines of a gmsh ``.msh`` file."""
    import gmsh

    from meshes._session import initialize

    initialised = gmsh.isInitialized()
    if not initialised:
        initialize()  # nothing written in the home folder (meshes._session)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(path))
        tags, coords, _ = gmsh.model.mesh.getNodes()
        order = np.argsort(tags)
        tags, xyz = tags[order], coords.reshape(-1, 3)[order]
        index = np.full(int(tags.max()) + 1 if tags.size else 1, -1, dtype=int)
        index[tags.astype(int)] = np.arange(tags.size)
        cells, facets = {}, {}
        for dim, ptag in gmsh.model.getPhysicalGroups():
            name = gmsh.model.getPhysicalName(dim, ptag) or f"group_{dim}_{ptag}"
            kinds = _TRI if dim == 2 else _LINE if dim == 1 else None
            if kinds is None:
                continue
            rows = []
            for ent in gmsh.model.getEntitiesForPhysicalGroup(dim, ptag):
                for etype, _etags, conn in zip(*gmsh.model.mesh.getElements(dim, ent), strict=True):
                    if etype not in kinds:
                        raise ValueError(f"{path}: element type {etype} in group {name!r}; allowed: linear or "
                                         "quadratic triangles and lines")
                    rows.append(index[np.asarray(conn, dtype=int)].reshape(-1, kinds[etype]))
            block = np.concatenate(rows) if rows else np.zeros((0, 3 if dim == 2 else 2), dtype=int)
            (cells if dim == 2 else facets)[name] = block
    finally:
        gmsh.clear()
        if not initialised:
            gmsh.finalize()
    nodes = xyz[:, :2].copy()
    return MeshModel(nodes, {k: _ccw(nodes, v) for k, v in cells.items()}, facets)


def write_msh(model: MeshModel, path: str | Path) -> Path:
    """``model`` as a gmsh 4.1 ``.msh`` (one discrete entity per group, its physical group of the same name)."""
    import gmsh

    from meshes._session import initialize

    path = Path(path)
    initialised = gmsh.isInitialized()
    if not initialised:
        initialize()  # nothing written in the home folder (meshes._session)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add(path.stem)
        node_tags = np.arange(1, len(model.nodes) + 1)
        xyz = np.column_stack([model.nodes, np.zeros(len(model.nodes))]).reshape(-1)
        anchor = gmsh.model.addDiscreteEntity(2)
        gmsh.model.mesh.addNodes(2, anchor, node_tags, xyz)
        next_element = 1
        for dim, groups, types in ((2, model.cells, {3: 2, 6: 9}), (1, model.facets, {2: 1, 3: 8})):
            for name, rows in groups.items():
                ent = anchor if (dim == 2 and name == next(iter(model.cells))) else gmsh.model.addDiscreteEntity(dim)
                etags = np.arange(next_element, next_element + len(rows))
                next_element += len(rows)
                gmsh.model.mesh.addElementsByType(ent, types[rows.shape[1]], etags, (rows + 1).reshape(-1))
                gmsh.model.setPhysicalName(dim, gmsh.model.addPhysicalGroup(dim, [ent]), name)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(str(path))
    finally:
        gmsh.clear()
        if not initialised:
            gmsh.finalize()
    return path
