"""A small reader of VTK XML ``.vtu`` / ``.vtp`` files (and a ``.pvd``'s last dataset): points and one point
field, for ``workbench score --format vtu --field NAME``.

Our own for the same reason as :mod:`workbench.external.frd` (no VTK/meshio in the environment). Supported
encodings: ``format="ascii"`` and inline ``format="binary"`` (base64), raw or ``vtkZLibDataCompressor``, with
``header_type`` UInt32 or UInt64, as dolfinx and ParaView write them; ``appended`` data is refused in one line.
The contact surface is found as in the .frd: the points on the block top Y = 0 (reference configuration),
coincident points merged by their largest value. A ``P_N_per_mm`` FieldData value (the workbench writes it) is
taken as the load. Units: mm, MPa.
"""

from __future__ import annotations

import base64
import math
import xml.etree.ElementTree as ET
import zlib
from pathlib import Path

import numpy as np

from workbench.external.results import ExternalResult, ResultError, make_result

__all__ = ["read_vtk_result"]

_TYPES = {"Float64": "<f8", "Float32": "<f4", "Int64": "<i8", "Int32": "<i4", "UInt64": "<u8", "UInt32": "<u4",
          "Int8": "<i1", "UInt8": "<u1"}


def _array(el, *, root, where: str) -> np.ndarray:
    fmt = el.get("format", "ascii")
    dtype = _TYPES.get(el.get("type", ""))
    if dtype is None:
        raise ResultError(f"{where}: DataArray {el.get('Name')} has type {el.get('type')}; allowed: "
                          f"{', '.join(_TYPES)}")
    text = (el.text or "").strip()
    if fmt == "ascii":
        return np.array(text.split(), dtype=float)
    if fmt != "binary":
        raise ResultError(f"{where}: DataArray {el.get('Name')} format {fmt!r}; allowed: ascii, binary (inline)")
    head_t = "<u8" if root.get("header_type", "UInt32") == "UInt64" else "<u4"
    hsize = np.dtype(head_t).itemsize
    if root.get("compressor"):
        first = base64.b64decode(text[:4 * math.ceil(3 * hsize / 3)])
        nblocks = int(np.frombuffer(first[:hsize], dtype=head_t)[0])
        hlen = 4 * math.ceil((3 + nblocks) * hsize / 3)
        header = np.frombuffer(base64.b64decode(text[:hlen])[:(3 + nblocks) * hsize], dtype=head_t)
        raw = base64.b64decode(text[hlen:])
        out, pos = [], 0
        for size in header[3:]:
            out.append(zlib.decompress(raw[pos:pos + int(size)]))
            pos += int(size)
        data = b"".join(out)
    else:
        blob = base64.b64decode(text)
        n = int(np.frombuffer(blob[:hsize], dtype=head_t)[0])
        data = blob[hsize:hsize + n]
    return np.frombuffer(data, dtype=dtype).astype(float)


def _dataset_file(path: Path) -> Path:
    """A .pvd's last dataset (the last time step), else the file itself."""
    if path.suffix != ".pvd":
        return path
    root = ET.parse(path).getroot()
    sets = root.findall(".//DataSet")
    if not sets:
        raise ResultError(f"{path}: a .pvd without DataSet entries")
    return path.parent / sets[-1].get("file")


def read_vtk_result(path: str | Path, *, field: str = "p_MPa", load: float | None = None,
                    h: float | None = None) -> ExternalResult:
    """One level's pressure from the point field ``field`` of a .vtu/.vtp/.pvd (see the module docstring)."""
    where = str(path)
    try:
        f = _dataset_file(Path(path))
        root = ET.parse(f).getroot()
    except (OSError, ET.ParseError) as exc:
        raise ResultError(f"{where}: not a readable VTK XML file ({exc.__class__.__name__}: {exc})") from None
    try:
        piece = root.find(".//Piece")
        pts_el = piece.find("./Points/DataArray") if piece is not None else None
        if pts_el is None:
            raise ResultError(f"{where}: no Piece/Points; allowed: a VTK XML UnstructuredGrid or PolyData")
        pts = _array(pts_el, root=root, where=where).reshape(-1, int(pts_el.get("NumberOfComponents", "3")))
        arrays = {el.get("Name"): el for el in piece.findall("./PointData/DataArray")}
        if field not in arrays:
            raise ResultError(f"{where}: no point field {field!r} (fields: {', '.join(arrays)[:120]}); give --field")
        vals = _array(arrays[field], root=root, where=where)
        if load is None:
            for el in root.findall(".//FieldData/DataArray"):
                if el.get("Name") == "P_N_per_mm":
                    load = float(_array(el, root=root, where=where)[0])
    except (ValueError, zlib.error, TypeError, AttributeError) as exc:
        raise ResultError(f"{where}: corrupt VTK data ({exc.__class__.__name__}: {exc})") from None
    if vals.size != pts.shape[0]:
        raise ResultError(f"{where}: field {field!r} has {vals.size} values for {pts.shape[0]} points "
                          "(a vector field?); allowed: a scalar point field")
    if not (np.all(np.isfinite(vals)) and np.all(np.isfinite(pts))):
        raise ResultError(f"{where}: NaN or infinite values in the points or {field!r}")
    scale = float(np.max(np.abs(pts[:, :2]))) or 1.0
    top = np.abs(pts[:, 1]) <= 1e-9 * scale
    if top.sum() < 2:
        raise ResultError(f"{where}: {int(top.sum())} point(s) on the contact surface Y = 0; the surface does not "
                          "match the case (block top at y = 0)")
    x, p = pts[top, 0], vals[top]
    order = np.lexsort((-p, x))
    x, p = x[order], p[order]
    first = np.ones(x.size, dtype=bool)
    first[1:] = np.diff(x) > 1e-12 * scale
    x, p = x[first], p[first]
    if p.min() < 0 or not np.any(p > 0):
        raise ResultError(f"{where}: field {field!r} on the surface is negative or nowhere positive; allowed: "
                          "a contact pressure >= 0, compression positive")
    if load is not None and not load > 0:
        raise ResultError(f"{where}: load P_N_per_mm = {load:g} <= 0; allowed: > 0")
    return make_result(where, x, p, load=load, h=h)
