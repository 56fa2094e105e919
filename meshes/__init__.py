"""gmsh mesh builders for the elastic body (rigid bodies are curves and are never meshed).

Public API: :func:`meshes.block.build_block_mesh`, :func:`meshes.concave.build_concave_mesh`,
:class:`meshes.cache.MeshFiles`, :func:`meshes.quality.mesh_quality`, :func:`meshes.quality.write_mesh_stats`,
:class:`meshes.fingerprint.MeshFingerprint` (``stats["fingerprint"]``); every float handed to gmsh goes through
:class:`meshes.portable.GmshInputs` (rounded so the mesh is a function of the case; ``WORKBENCH_MESH_PERTURB``).
Physical-group names (``contact``, ``clamped``, ``sides``, ``symmetry``, ``body``) are the contract.
"""

from meshes.block import build_block_mesh
from meshes.cache import DEFAULT_CACHE_DIR, MeshFiles
from meshes.quality import mesh_quality, write_mesh_stats

__all__ = ["build_block_mesh", "build_concave_mesh", "MeshFiles", "DEFAULT_CACHE_DIR", "mesh_quality",
           "write_mesh_stats"]


def __getattr__(name):  # lazy: the concave builder imports the analytic designs
    if name == "build_concave_mesh":
        from meshes.concave import build_concave_mesh

        return build_concave_mesh
    raise AttributeError(name)
