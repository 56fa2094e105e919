"""Triangle-mesh quality statistics and their JSON record (``results/<case>/mesh.json``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from meshes.cache import atomic_write_json

__all__ = ["triangle_angles", "mesh_quality", "write_mesh_stats"]


def triangle_angles(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Interior angles (deg) of each triangle, shape (m, 3), by the law of cosines."""
    p = points[:, :2][triangles]  # (m, 3, 2)
    e = np.stack([p[:, 2] - p[:, 1], p[:, 0] - p[:, 2], p[:, 1] - p[:, 0]], axis=1)  # edge opposite vertex i
    l2 = (e**2).sum(axis=2)
    ang = np.empty_like(l2)
    for i in range(3):
        j, k = (i + 1) % 3, (i + 2) % 3
        c = (l2[:, j] + l2[:, k] - l2[:, i]) / (2.0 * np.sqrt(l2[:, j] * l2[:, k]))
        ang[:, i] = np.degrees(np.arccos(np.clip(c, -1.0, 1.0)))
    return ang


def mesh_quality(points: np.ndarray, triangles: np.ndarray, contact_edges: np.ndarray | None = None,
                 contact_window=None) -> dict:
    """Quality statistics of a linear triangle mesh.

    Args:
        points: (n, 2 or 3) node coordinates (mm).
        triangles: (m, 3) vertex indices (corner nodes).
        contact_edges: (k, 2) vertex indices of the contact boundary edges.
        contact_window: callable (k, 2) midpoints -> bool mask of the edges inside the predicted contact
            zone (e.g. |x| <= a); None = all contact edges.

    Returns:
        dict with ``n_cells``, ``n_nodes`` (aliases ``cells``, ``nodes``), ``min_angle_deg``,
        ``max_aspect_ratio`` (circumradius / (2 inradius), 1 for equilateral), ``h_max`` / ``h_min`` (all
        edges), and for the contact edges
        ``n_contact_edges``, ``contact_h_max`` (over the window), ``contact_h_min``,
        ``n_contact_edges_window``.
    """
    pts = np.asarray(points, dtype=float)[:, :2]
    tri = np.asarray(triangles, dtype=np.int64)
    ang = triangle_angles(pts, tri)
    p = pts[tri]
    la = np.linalg.norm(p[:, 1] - p[:, 2], axis=1)
    lb = np.linalg.norm(p[:, 2] - p[:, 0], axis=1)
    lc = np.linalg.norm(p[:, 0] - p[:, 1], axis=1)
    u, v = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    area = 0.5 * np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
    s = 0.5 * (la + lb + lc)
    r_in = area / s
    r_circ = la * lb * lc / (4.0 * area)
    stats = {
        "n_cells": int(len(tri)),
        "n_nodes": int(len(np.unique(tri))),
        "cells": int(len(tri)),  # alias of n_cells
        "nodes": int(len(np.unique(tri))),  # alias of n_nodes
        "min_angle_deg": float(ang.min()),
        "max_angle_deg": float(ang.max()),
        "max_aspect_ratio": float((r_circ / (2.0 * r_in)).max()),
        "h_max": float(np.max([la.max(), lb.max(), lc.max()])),
        "h_min": float(np.min([la.min(), lb.min(), lc.min()])),
    }
    if contact_edges is not None and len(contact_edges):
        ce = np.asarray(contact_edges, dtype=np.int64)
        lengths = np.linalg.norm(pts[ce[:, 0]] - pts[ce[:, 1]], axis=1)
        mid = 0.5 * (pts[ce[:, 0]] + pts[ce[:, 1]])
        mask = np.ones(len(ce), dtype=bool) if contact_window is None else np.asarray(contact_window(mid))
        stats["n_contact_edges"] = int(len(ce))
        stats["n_contact_edges_window"] = int(mask.sum())
        stats["contact_h_max"] = float(lengths[mask].max()) if mask.any() else float("nan")
        stats["contact_h_min"] = float(lengths.min())
    return stats


def write_mesh_stats(stats: dict, out_dir) -> Path:
    """Write ``stats`` to ``<out_dir>/mesh.json`` atomically (tmp + os.replace) and return the path."""
    return atomic_write_json(Path(out_dir) / "mesh.json", stats)
