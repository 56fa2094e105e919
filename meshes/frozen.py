"""Frozen control points of the shipped concave designs: the B-spline gmsh meshes is data, not a computation.

:mod:`analytic.designs` builds each concave curve at run time (curvature integration, a least-squares
B-spline fit through OpenBLAS); its last bits depend on the machine (OpenBLAS's AVX-512 against its AVX2
kernels moved 44 of the 480 control-point coordinates of ``symmetric`` by up to 4.4e-15 mm, and the CI mesh
from 11800 to 11856 dofs). The control points handed to gmsh are therefore taken from
``meshes/data/concave_<design>.json`` (hex floats, written on the developers' machine) whenever the run-time
points agree with the table within ``SNAP_TOL`` (1e-9 mm, ~1e5 times the machine spread); a design that
changed by more falls back to its run-time points rounded to the length grid (:mod:`meshes.portable`), and the
fingerprint says which (``geometry_source``). Rewrite a table after a deliberate design change with
``python -m meshes freeze DESIGN``.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

__all__ = ["frozen_control_points", "write_frozen", "SNAP_TOL", "DATA_DIR"]

DATA_DIR = Path(__file__).resolve().parent / "data"
SNAP_TOL = 1e-9  # mm


def _path(name: str) -> Path:
    return DATA_DIR / f"concave_{name}.json"


def frozen_control_points(name: str, runtime: np.ndarray) -> np.ndarray | None:
    """The frozen control points of design ``name`` if they exist and agree with ``runtime`` within SNAP_TOL."""
    path = _path(name)
    if not path.exists():
        return None
    data = json.loads(path.read_text())
    cp = np.array([[float.fromhex(x), float.fromhex(y)] for x, y in data["control_points"]])
    rt = np.asarray(runtime, dtype=float)
    if cp.shape != rt.shape or not np.all(np.abs(cp - rt) <= SNAP_TOL):
        return None
    return cp


def write_frozen(name: str, control_points: np.ndarray) -> Path:
    """Write the table of design ``name`` (hex floats, exact)."""
    cp = np.asarray(control_points, dtype=float)
    DATA_DIR.mkdir(parents=True, exist_ok=True)
    rows = ",\n".join(json.dumps([float(x).hex(), float(y).hex()]) for x, y in cp)
    _path(name).write_text(f'{{"design": "{name}",\n "control_points": [\n{rows}\n]}}\n')
    return _path(name)
