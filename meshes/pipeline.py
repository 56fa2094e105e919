"""Shared build pipeline: cache lookup -> gmsh build -> .msh + stats (+ XDMF) -> MeshFiles."""

from __future__ import annotations

import json
import os
import time
from collections.abc import Callable

from meshes._child import run_in_child
from meshes._session import gmsh_model
from meshes.cache import MeshFiles, atomic_write_json, cache_key, cache_paths
from meshes.output import extract_model, msh_to_xdmf, write_msh
from meshes.quality import mesh_quality, write_mesh_stats

__all__ = ["build_cached", "BUILDER_VERSION"]

BUILDER_VERSION = 2  # bump to invalidate every cached mesh when a builder changes


def build_cached(*, kind: str, params: dict, name: str, out_dir, make: Callable, write_xdmf: bool = True,
                 stats_dir=None, comm=None, extra_stats: Callable | None = None) -> MeshFiles:
    """Build (or reuse) one mesh.

    Args:
        kind: builder name (part of the hash).
        params: every parameter that changes the mesh (hashed).
        name: file stem.
        out_dir: cache directory.
        make: ``make(gmsh) -> (contact_curve_tags, contact_window, physical_groups)``; builds geometry, size
            fields and the 2D mesh in the current gmsh model.
        write_xdmf: also write XDMF via dolfinx.
        stats_dir: when given, also write ``<stats_dir>/mesh.json``.
        comm: optional MPI communicator: only rank 0 builds, the result is broadcast.
        extra_stats: ``extra_stats(points, triangles, contact_edges) -> dict`` merged into the stats.
    """
    if comm is not None and comm.size > 1:
        result = None
        if comm.rank == 0:
            result = build_cached(kind=kind, params=params, name=name, out_dir=out_dir, make=make,
                                  write_xdmf=write_xdmf, stats_dir=stats_dir, comm=None,
                                  extra_stats=extra_stats)
        return comm.bcast(result, root=0)
    key = cache_key({"kind": kind, "version": BUILDER_VERSION, "write_xdmf": write_xdmf, **params})
    paths = cache_paths(out_dir, name, key)
    have = paths["msh"].exists() and paths["json"].exists()
    if write_xdmf:
        have = have and paths["xdmf"].exists() and paths["h5"].exists()
    if have:
        stats = json.loads(paths["json"].read_text())
        cached = True
    else:
        t0 = time.perf_counter()

        def build(pid: int) -> tuple[dict, dict]:
            with gmsh_model(name) as gmsh:
                contact_curves, window, groups = make(gmsh)
                points, tri, edges = extract_model(gmsh, contact_curves=contact_curves)
                write_msh(gmsh, paths["msh"])
            st = mesh_quality(points, tri, edges, window)
            if extra_stats is not None:
                st.update(extra_stats(points, tri, edges))
            return st, groups

        try:  # in a child process: a signal stops gmsh at once (see meshes._child)
            stats, groups = run_in_child(build)
        finally:
            for tmp in paths["msh"].parent.glob(f".{paths['msh'].stem}.*.tmp.msh"):
                if not _pid_alive(tmp.name.rsplit(".", 3)[-3]):  # left by a killed child
                    tmp.unlink(missing_ok=True)
        t_mesh = time.perf_counter() - t0
        stats.update(kind=kind, key=key, params=params, mesh_time_s=t_mesh,
                     physical_groups={k: list(v) for k, v in groups.items()})
        if write_xdmf:
            t1 = time.perf_counter()
            msh_to_xdmf(paths["msh"], paths["xdmf"])
            stats["xdmf_time_s"] = time.perf_counter() - t1
        atomic_write_json(paths["json"], stats)
        cached = False
    if stats_dir is not None:
        write_mesh_stats(stats, stats_dir)
    return MeshFiles(msh=paths["msh"], xdmf=paths["xdmf"] if write_xdmf else None, stats=stats, key=key,
                     cached=cached)


def _pid_alive(pid: str) -> bool:
    """Whether the process ``pid`` (a string from a file name) still runs (a non-number: treated as alive)."""
    if not pid.isdigit():
        return True
    try:
        os.kill(int(pid), 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True
