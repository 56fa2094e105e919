"""Shared build pipeline: cache lookup -> gmsh build -> .msh + stats (+ XDMF) -> MeshFiles."""

from __future__ import annotations

import json
import os
import time
from collections.abc import Callable

from meshes._child import run_in_child
from meshes._session import gmsh_model
from meshes.cache import MeshFiles, atomic_write_json, cache_key, cache_paths, make_cache_dir
from meshes.fingerprint import mesh_fingerprint
from meshes.output import extract_model, msh_to_xdmf, write_msh
from meshes.portable import GmshInputs
from meshes.quality import mesh_quality, write_mesh_stats

__all__ = ["build_cached", "BUILDER_VERSION"]

BUILDER_VERSION = 3  # bump to invalidate every cached mesh when a builder changes


def build_cached(*, kind: str, params: dict, name: str, out_dir, make: Callable, inputs: GmshInputs,
                 body_size: float, geometry_source: str, write_xdmf: bool = True, stats_dir=None, comm=None,
                 extra_stats: Callable | None = None) -> MeshFiles:
    """Build (or reuse) one mesh.

    Args:
        kind: builder name (part of the hash).
        params: every parameter that changes the mesh (hashed, with the digest of ``inputs``).
        name: file stem.
        out_dir: cache directory.
        make: ``make(gmsh) -> (contact_curve_tags, contact_window, physical_groups)``; builds geometry, size
            fields and the 2D mesh in the current gmsh model from the values already taken from ``inputs``.
        inputs: :class:`meshes.portable.GmshInputs` holding every float handed to gmsh (rounded, perturbed);
            its digest and perturbation amplitude are part of the cache key and of the fingerprint.
        body_size: size of the body (mm), the scale of the fingerprint's coordinate grid.
        geometry_source: recorded in the fingerprint (``frozen``, ``rounded``, ``parameters``).
        write_xdmf: also write XDMF via dolfinx.
        stats_dir: when given, also write ``<stats_dir>/mesh.json``.
        comm: optional MPI communicator: only rank 0 builds, the result is broadcast.
        extra_stats: ``extra_stats(points, triangles, contact_edges) -> dict`` merged into the stats.
    """
    if comm is not None and comm.size > 1:
        result = None
        if comm.rank == 0:
            result = build_cached(kind=kind, params=params, name=name, out_dir=out_dir, make=make,
                                  inputs=inputs, body_size=body_size, geometry_source=geometry_source,
                                  write_xdmf=write_xdmf, stats_dir=stats_dir, comm=None,
                                  extra_stats=extra_stats)
        return comm.bcast(result, root=0)
    params = {**params, "gmsh_input_floats_sha256": inputs.digest(), "perturb": inputs.perturb}
    input_sha = cache_key({"kind": kind, **params})  # every float handed to gmsh and every option of the builder
    make_cache_dir(out_dir)  # with the workbench's marker (a folder that exists is left as it is)
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
                facets = {g: _facet_count(gmsh, tag) for g, (dim, tag) in groups.items() if dim == 1}
                write_msh(gmsh, paths["msh"])
            st = mesh_quality(points, tri, edges, window)
            if extra_stats is not None:
                st.update(extra_stats(points, tri, edges))
            fp = mesh_fingerprint(points=points, triangles=tri, facets=facets, body_size=body_size,
                                  gmsh_input_sha256=input_sha, perturb=inputs.perturb,
                                  geometry_source=geometry_source)
            st["fingerprint"] = fp._asdict()
            return st, groups

        try:  # in a child process: a signal stops gmsh at once (see meshes._child)
            stats, groups = run_in_child(build)
        finally:
            for tmp in paths["msh"].parent.glob(f".{paths['msh'].stem}.*.tmp.msh"):
                if not _pid_alive(tmp.name.rsplit(".", 3)[-3]):  # left by a killed child
                    tmp.unlink(missing_ok=True)
        t_mesh = time.perf_counter() - t0
        stats.update(kind=kind, key=key, params=params, mesh_time_s=t_mesh,
                     gmsh_input_rounding_margin=inputs.margin,
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


def _facet_count(gmsh, tag: int) -> int:
    """Number of 1D elements on the entities of the dimension-1 physical group ``tag``."""
    n = 0
    for c in gmsh.model.getEntitiesForPhysicalGroup(1, tag):
        _, etags, _ = gmsh.model.mesh.getElements(1, int(c))
        n += sum(len(t) for t in etags)
    return n


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
