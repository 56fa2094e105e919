"""A contact surface's nodes in order along it (numpy only).

A surface is a 1D facet group of a :class:`workbench.external.mesh_model.MeshModel`: 2-node or 3-node lines
(corner, corner[, middle]). :func:`surface_chain` walks the facets from one end to the other and returns the node
indices in order (corner, middle, corner, middle, ..., corner): one open chain, starting at the end with the
smaller x (then smaller y). :func:`is_horizontal` tells a straight horizontal surface (every block top and
two-body interface of the cases: a result reports X only) from a curved one (the concave scenes: X and Y). Units
mm.
"""

from __future__ import annotations

import numpy as np

__all__ = ["surface_chain", "is_horizontal"]


def surface_chain(model, group: str) -> np.ndarray:
    """The node indices (0-based) of facet group ``group`` in order along it (module docstring).

    Raises:
        ValueError: the group is empty, branches, is closed or has several pieces.
    """
    lines = np.asarray(model.facets[group])
    if lines.size == 0:
        raise ValueError(f"surface {group!r} has no facets")
    neighbours: dict[int, list[tuple[int, int | None]]] = {}
    for row in lines:
        a, b = int(row[0]), int(row[1])
        mid = int(row[2]) if row.shape[0] > 2 else None
        neighbours.setdefault(a, []).append((b, mid))
        neighbours.setdefault(b, []).append((a, mid))
    if any(len(v) > 2 for v in neighbours.values()):
        raise ValueError(f"surface {group!r} branches (a node with three facets); allowed: one open chain")
    ends = [n for n, v in neighbours.items() if len(v) == 1]
    if len(ends) != 2:
        raise ValueError(f"surface {group!r} is closed or in {len(ends) // 2} pieces; allowed: one open chain")
    start = min(ends, key=lambda n: (model.nodes[n, 0], model.nodes[n, 1]))
    chain, prev, cur = [start], None, start
    while True:
        step = next(((n, m) for n, m in neighbours[cur] if n != prev), None)
        if step is None or (prev is not None and len(neighbours[cur]) == 1):
            break
        nxt, mid = step
        if mid is not None:
            chain.append(mid)
        chain.append(nxt)
        prev, cur = cur, nxt
        if len(neighbours[cur]) == 1:
            break
    if len(chain) != len(set(chain)) or (len(chain) - 1) // (2 if lines.shape[1] > 2 else 1) != len(lines):
        raise ValueError(f"surface {group!r} is not one open chain of its {len(lines)} facets")
    return np.array(chain, dtype=int)


def is_horizontal(points: np.ndarray) -> bool:
    """Whether the points (n, 2) lie on one horizontal line (to 1e-9 of their extent)."""
    extent = float(np.ptp(points[:, 0])) or 1.0
    return bool(np.ptp(points[:, 1]) <= 1e-9 * extent)
