"""Parameter-hash cache for meshes: a rerun with the same parameters does not remesh.

Files of one mesh: ``<cache_dir>/<name>-<key>.{msh,xdmf,h5,json}``; the key is the first 16 hex digits of
the SHA-256 of the canonical JSON of all build parameters (plus the builder version).
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path
from typing import NamedTuple

__all__ = ["MeshFiles", "cache_key", "cache_paths", "atomic_write_json", "make_cache_dir", "DEFAULT_CACHE_DIR"]

# The default of the standalone builders and `python -m meshes`: results/mesh_cache of this checkout, whatever the
# working directory (the workbench passes its own output folder's cache).
DEFAULT_CACHE_DIR = Path(__file__).resolve().parent.parent / "results" / "mesh_cache"


class MeshFiles(NamedTuple):
    """Result of a mesh build.

    Attributes:
        msh: path of the gmsh 4.1 ``.msh`` file.
        xdmf: path of the XDMF file (mesh + ``facet_tags`` + ``cell_tags``), or None when not written.
        stats: quality statistics (see :func:`meshes.quality.mesh_quality`) plus ``physical_groups``.
        key: parameter hash.
        cached: True when the files were reused from the cache.
    """

    msh: Path
    xdmf: Path | None
    stats: dict
    key: str
    cached: bool


def _canonical(obj):
    if isinstance(obj, dict):
        return {str(k): _canonical(v) for k, v in sorted(obj.items())}
    if isinstance(obj, (list, tuple)):
        return [_canonical(v) for v in obj]
    if isinstance(obj, float):
        return repr(obj)
    if hasattr(obj, "tolist"):
        return _canonical(obj.tolist())
    return obj


def cache_key(params: dict) -> str:
    """SHA-256 (16 hex digits) of the canonical JSON of ``params`` (floats by repr, keys sorted)."""
    text = json.dumps(_canonical(params), sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def cache_paths(cache_dir, name: str, key: str) -> dict[str, Path]:
    """Paths of the cached files of one mesh: ``<name>-<key>.<ext>``. The extension is appended, not put in
    place of a suffix: ``Path.with_suffix`` took a name with a dot (``cyl_0.05``) for a suffix and dropped the
    key with it, so a mesh of other parameters under that name was served from the cache."""
    folder, stem = Path(cache_dir), f"{name}-{key}"
    return {ext: folder / f"{stem}.{ext}" for ext in ("msh", "xdmf", "h5", "json")}


def make_cache_dir(cache_dir) -> Path:
    """Create a missing cache folder with the workbench's ownership marker ``.workbench-owned`` (kind
    ``mesh_cache``; the format of :mod:`workbench.owned`, which this layer cannot import), so the workbench
    later recognises the folder as its own. A folder that exists is left as it is (the workbench checks it)."""
    import datetime

    cache_dir = Path(cache_dir)
    if cache_dir.exists() or cache_dir.is_symlink():
        return cache_dir
    import shutil
    import tempfile

    cache_dir.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{cache_dir.name[:40]}.new.", dir=cache_dir.parent))
    try:  # the folder appears with its marker in one rename (a concurrent build never sees it without)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o777 & ~umask)
        now = datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")
        atomic_write_json(tmp / ".workbench-owned", {"tool": "contact-workbench", "kind": "mesh_cache",
                                                     "created": now})
        try:
            os.rename(tmp, cache_dir)
        except OSError:  # a concurrent build made it meanwhile
            if not cache_dir.is_dir():
                raise
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)
    return cache_dir


def atomic_write_json(path, data: dict) -> Path:
    """Write JSON to ``path`` atomically (temporary file in the same directory + os.replace)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")
    os.replace(tmp, path)
    return path
