"""Every case as a benchmark another code can run: one builder per scene, registered by the scene's name.

:func:`build` ``(case, *, level, mesh_cache, folder) -> tuple[Exported, ...]``: the case's
:class:`workbench.external.benchmark.Benchmark` records at one mesh level, one per geometry (the ``wedge`` case has
two), each with its merged mesh (:class:`workbench.external.mesh_model.MeshModel`) written as ONE gmsh ``.msh`` with
named physical groups (:mod:`workbench.external.benchmarks.base`). Scenes: ``block`` (the block mesh + the rigid
indenter as a band), ``concave`` (the concave body + the B-spline particle as a band), ``two_body`` (both elastic
bodies), ``halfplanes`` (the upper body meshed with its real profile). A new scene adds a module with
``part(case, runs, *, level, mesh_cache, folder, stem) -> Exported`` and one line below.
"""

from workbench.external.benchmarks import block, concave, halfplanes, two_body
from workbench.external.benchmarks.base import BUILDERS, Exported, build, register_builder

__all__ = ["BUILDERS", "Exported", "build", "register_builder"]

register_builder("block", block.part)
register_builder("concave", concave.part)
register_builder("two_body", two_body.part)
register_builder("halfplanes", halfplanes.part)
