"""What every scene's benchmark builder shares: the registry, the grouping of a case's runs into benchmarks, the
finished mesh (compact, facets oriented, written as one ``.msh``) and its statistics.

A builder is ``part(case, runs, *, level, mesh_cache, folder, stem) -> Exported``: the runs of one geometry (the
runs of a case that differ only in the workbench's own discretisation choices share one benchmark), its mesh
written as ``<folder>/<stem>.msh``. :func:`build` calls it once per geometry: a case with one geometry (13 of the
14) gets one benchmark in ``folder``; one with several (``wedge``: theta = pi/20 and pi/5, each its own indenter)
one per geometry, each in ``folder/<run label folder>/`` (its files named after it), so that every folder holds
one model a code runs as it is (a Kratos ``ProjectParameters.json`` names one ``.mdpa``).

Mesh conventions (the contract with the deck writers, :mod:`workbench.external.writers`): 3-node triangles,
counter-clockwise; every facet ``(i, j)`` runs with its body on its left (its outward normal is the direction
``j - i`` turned by -90 degrees); no node that no cell uses. Units mm.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

import numpy as np

from cases.schema import Case, Run, label_folder
from workbench.external.benchmark import Benchmark
from workbench.external.mesh_model import MeshModel, write_msh

__all__ = ["Exported", "BUILDERS", "register_builder", "build", "finish", "band_model", "mesh_stats",
           "DISCRETISATION_FIELDS"]

# [geometry] fields that are the workbench's discretisation choices, not the problem: runs differing only there
# (patch_test's mortar and node-to-segment runs) are one benchmark
DISCRETISATION_FIELDS = ("pairing", "convection")


class Exported(NamedTuple):
    """One benchmark as exported: the record, its mesh (arrays), the folder its files go to, and statistics
    (``cells``, ``nodes``, per-group counts, ``build_s``: the time to build it, mesh and band included)."""

    benchmark: Benchmark
    model: MeshModel
    folder: Path
    stats: dict


Builder = Callable[..., Exported]
BUILDERS: dict[str, Builder] = {}


def register_builder(scene: str, builder: Builder) -> Builder:
    """Register the benchmark builder of a scene (the ``[geometry] scene`` name)."""
    BUILDERS[scene] = builder
    return builder


def _problem(run: Run):
    """What makes two runs the same problem: the geometry without the workbench's discretisation choices, the
    elastic constants (a finite run's hyperelastic law is a property of its run) and the loading."""
    g = run.geometry
    defaults = {f.name: f.default for f in dataclasses.fields(g) if f.name in DISCRETISATION_FIELDS}
    bodies = tuple((b.name, b.E, b.nu) for b in run.bodies)  # a finite run's hyperelastic model is its Run's
    return dataclasses.replace(g, **defaults), (run.material.E, run.material.nu), bodies, run.loading


def groups(runs: tuple[Run, ...]) -> list[tuple[Run, ...]]:
    """The runs grouped by problem (:func:`_problem`), in the case's order."""
    out: dict = {}
    for run in runs:
        out.setdefault(_problem(run), []).append(run)
    return [tuple(v) for v in out.values()]


def build(case: Case, *, level: float, mesh_cache: Path, folder: Path) -> tuple[Exported, ...]:
    """The benchmarks of ``case`` at ``level`` (the case's ``h_contact`` fraction), their files written under
    ``folder`` (see the module docstring). ValueError (one line) for a case its scene's builder cannot export."""
    runs = case.runs(h_contact=level)
    scene = runs[0].geometry.scene
    if scene not in BUILDERS:
        raise ValueError(f"case {case.name}: scene {scene!r} has no benchmark builder; known: {sorted(BUILDERS)}")
    parts = groups(runs)
    out = []
    for part in parts:
        sub = folder if len(parts) == 1 else folder / label_folder(part[0].label)
        stem = case.name if len(parts) == 1 else f"{case.name}_{label_folder(part[0].label)}"
        sub.mkdir(parents=True, exist_ok=True)
        t0 = time.perf_counter()
        exp = BUILDERS[scene](case, part, level=level, mesh_cache=mesh_cache, folder=sub,
                              stem=f"{stem}_h{level:g}")
        out.append(exp._replace(stats={**exp.stats, "build_s": time.perf_counter() - t0}))
    return tuple(out)


def finish(model: MeshModel) -> MeshModel:
    """The model without unused nodes and with every facet oriented with its body on its left (the triangle that
    holds the facet's two nodes is counter-clockwise, :func:`workbench.external.mesh_model.read_msh`)."""
    used = np.unique(np.concatenate([c[:, :3].reshape(-1) for c in model.cells.values()]))
    new = np.full(len(model.nodes), -1, dtype=int)
    new[used] = np.arange(len(used))
    cells = {k: new[v] for k, v in model.cells.items()}
    edge_dir: dict[tuple[int, int], int] = {}
    for tri in cells.values():
        for a, b in ((0, 1), (1, 2), (2, 0)):
            for i, j in zip(tri[:, a], tri[:, b], strict=True):
                edge_dir[(int(i), int(j))] = 1
    facets = {}
    for name, rows in model.facets.items():
        rows = new[rows[:, :2]]
        if (rows < 0).any():
            raise ValueError(f"facet group {name!r} has a node no cell uses")
        flip = np.array([(int(i), int(j)) not in edge_dir for i, j in rows], dtype=bool)
        if any((int(j), int(i)) not in edge_dir for i, j in rows[flip]):
            raise ValueError(f"facet group {name!r}: a facet is no edge of any cell")
        rows[flip] = rows[flip][:, ::-1]
        facets[name] = rows
    return MeshModel(model.nodes[used], cells, facets)


def band_model(band, *, cells: str = "indenter", facets: str = "indenter_contact") -> MeshModel:
    """A :class:`meshes.rigid_band.RigidBand` as a mesh model: its cells and its contact facets as named groups."""
    return MeshModel(band.nodes, {cells: band.triangles}, {facets: band.surface})


def mesh_stats(model: MeshModel) -> dict:
    """Counts of a finished model: nodes, cells, and per group."""
    return {"nodes": int(len(model.nodes)), "cells": int(sum(len(c) for c in model.cells.values())),
            "groups": {**{k: {"dim": 2, "cells": int(len(v))} for k, v in model.cells.items()},
                       **{k: {"dim": 1, "facets": int(len(v))} for k, v in model.facets.items()}}}


def write_model(model: MeshModel, folder: Path, stem: str) -> Path:
    """The finished model as ``<folder>/<stem>.msh`` (gmsh 4.1, named physical groups)."""
    return write_msh(model, folder / f"{stem}.msh")
