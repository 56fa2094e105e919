"""VTK XML files that ParaView reads as they are meant (pure numpy, no VTK library needed).

* :func:`write_vtu`: an unstructured grid of linear triangles with point data, named components and field
  data (``TimeValue`` and any scalars, e.g. the rigid displacement ``d_mm`` and the load ``P_N_per_mm``).
* :func:`write_vtp`: poly data of one or more polylines with point data and field data.
* :func:`write_pvd`: a collection that lists one file per time step (ParaView's time series).

Arrays are written zlib-compressed and base64-encoded (binary, 64-bit headers): small files, exact values.
Component names follow ParaView's conventions: a 3-vector ``X Y Z``; a symmetric tensor as 6 components
``XX YY ZZ XY YZ XZ`` (the order ParaView reads a 6-component array in, e.g. for *Tensor Glyph*).
"""

from __future__ import annotations

import base64
import zlib
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

__all__ = ["SYM_TENSOR_COMPONENTS", "VECTOR_COMPONENTS", "write_pvd", "write_vtp", "write_vtu"]

VECTOR_COMPONENTS = ("X", "Y", "Z")
SYM_TENSOR_COMPONENTS = ("XX", "YY", "ZZ", "XY", "YZ", "XZ")
_VTK_TRIANGLE = 5
_VTK_POLY_LINE = 4
_TYPES = {np.dtype(np.float64): "Float64", np.dtype(np.int64): "Int64", np.dtype(np.uint8): "UInt8"}


def quoteattr(data: str) -> str:
    """``data`` as a quoted XML attribute value: the same text as ``xml.sax.saxutils.quoteattr`` (``& < >`` and
    newline, carriage return and tab escaped; single quotes around a value that holds a double quote but no single
    one, else double quotes with ``&quot;``), without importing ``xml.sax`` (it pulls in ``urllib.request``, http
    and ssl: ~9 ms of every run's start-up)."""
    data = data.replace("&", "&amp;").replace(">", "&gt;").replace("<", "&lt;")
    data = data.replace("\n", "&#10;").replace("\r", "&#13;").replace("\t", "&#9;")
    if '"' not in data:
        return f'"{data}"'
    if "'" not in data:
        return f"'{data}'"
    return '"' + data.replace('"', "&quot;") + '"'


def _array(name: str | None, values, *, components: Sequence[str] | None = None, tuples: bool = False) -> str:
    arr = np.ascontiguousarray(values)
    if arr.dtype.kind == "f":
        arr = arr.astype(np.float64)
    elif arr.dtype != np.uint8:
        arr = arr.astype(np.int64)
    ncomp = 1 if arr.ndim == 1 else arr.shape[1]
    raw = arr.tobytes()
    # one zlib block: header (blocks, block size, last block size, compressed size), then the data,
    # each base64-encoded on its own (the layout VTK's zlib compressor reads inline)
    comp = zlib.compress(raw, 6)
    header = np.array([1, len(raw), len(raw), len(comp)], dtype=np.uint64).tobytes()
    data = (base64.b64encode(header) + base64.b64encode(comp)).decode("ascii")
    attrs = f'type="{_TYPES[arr.dtype]}"'
    if name is not None:
        attrs += f" Name={quoteattr(name)}"
    attrs += f' NumberOfComponents="{ncomp}"'
    if tuples:  # field data arrays must say how many tuples they hold
        attrs += f' NumberOfTuples="{len(arr)}"'
    if components:
        if len(components) != ncomp:
            raise ValueError(f"{name}: {len(components)} component names for {ncomp} components")
        attrs += "".join(f' ComponentName{i}={quoteattr(c)}' for i, c in enumerate(components))
    if arr.ndim == 2 and arr.dtype.kind == "f":
        attrs += f' RangeMin="{np.min(arr) if arr.size else 0:.17g}" RangeMax="{np.max(arr) if arr.size else 0:.17g}"'
    return f'<DataArray {attrs} format="binary">{data}</DataArray>'


def _field_data(field: Mapping[str, float]) -> list[str]:
    if not field:
        return []
    arrays = [_array(k, np.atleast_1d(np.asarray(v, dtype=float)), tuples=True) for k, v in field.items()]
    return ["<FieldData>", *arrays, "</FieldData>"]


def _point_data(point_data: Mapping[str, tuple]) -> list[str]:
    """``name -> array`` or ``name -> (array, component names)``."""
    out = ["<PointData>"]
    for name, spec in point_data.items():
        values, comps = spec if isinstance(spec, tuple) else (spec, None)
        out.append(_array(name, values, components=comps))
    return [*out, "</PointData>"]


def _header(kind: str) -> list[str]:
    return ['<?xml version="1.0"?>',
            f'<VTKFile type="{kind}" version="1.0" byte_order="LittleEndian" header_type="UInt64" '
            'compressor="vtkZLibDataCompressor">']


def _points3(points) -> np.ndarray:
    pts = np.asarray(points, dtype=float)
    return np.column_stack([pts, np.zeros(len(pts))]) if pts.shape[1] == 2 else pts


def write_vtu(path: Path, *, points, triangles, point_data: Mapping[str, tuple],
              field: Mapping[str, float] | None = None) -> Path:
    """Write a grid of linear triangles.

    Args:
        path: The ``.vtu`` file.
        points: (n, 2) or (n, 3) coordinates (mm).
        triangles: (m, 3) point indices, counter-clockwise.
        point_data: name -> (n, k) values, or name -> ((n, k) values, k component names).
        field: Field data: name -> number (e.g. ``TimeValue``, ``d_mm``, ``P_N_per_mm``).
    """
    pts, tri = _points3(points), np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    lines = [*_header("UnstructuredGrid"), "<UnstructuredGrid>", *_field_data(field or {}),
             f'<Piece NumberOfPoints="{len(pts)}" NumberOfCells="{len(tri)}">', *_point_data(point_data),
             "<Points>", _array("Points", pts), "</Points>", "<Cells>",
             _array("connectivity", tri.ravel()), _array("offsets", 3 * np.arange(1, len(tri) + 1)),
             _array("types", np.full(len(tri), _VTK_TRIANGLE, dtype=np.uint8)), "</Cells>", "</Piece>",
             "</UnstructuredGrid>", "</VTKFile>"]
    Path(path).write_text("\n".join(lines) + "\n")
    return Path(path)


def write_vtp(path: Path, *, points, polylines: Sequence[Sequence[int]], point_data: Mapping[str, tuple],
              field: Mapping[str, float] | None = None) -> Path:
    """Write polylines (each a list of point indices, in order along the line) with point data."""
    pts = _points3(points)
    conn = np.concatenate([np.asarray(pl, dtype=np.int64) for pl in polylines]) if polylines else np.zeros(0, int)
    offs = np.cumsum([len(pl) for pl in polylines]).astype(np.int64)
    lines = [*_header("PolyData"), "<PolyData>", *_field_data(field or {}),
             f'<Piece NumberOfPoints="{len(pts)}" NumberOfVerts="0" NumberOfLines="{len(polylines)}" '
             'NumberOfStrips="0" NumberOfPolys="0">', *_point_data(point_data),
             "<Points>", _array("Points", pts), "</Points>", "<Lines>", _array("connectivity", conn),
             _array("offsets", offs), "</Lines>", "</Piece>", "</PolyData>", "</VTKFile>"]
    Path(path).write_text("\n".join(lines) + "\n")
    return Path(path)


def write_pvd(path: Path, entries: Sequence[tuple[float, str]]) -> Path:
    """A ParaView collection: ``entries`` are (time, file name relative to the .pvd)."""
    lines = ['<?xml version="1.0"?>', '<VTKFile type="Collection" version="1.0" byte_order="LittleEndian">',
             "<Collection>"]
    lines += [f'<DataSet timestep="{t:.17g}" part="0" file={quoteattr(f)}/>' for t, f in entries]
    lines += ["</Collection>", "</VTKFile>"]
    Path(path).write_text("\n".join(lines) + "\n")
    return Path(path)
