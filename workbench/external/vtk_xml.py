"""A small reader of VTK XML ``.vtu`` / ``.vtp`` files (and a ``.pvd``'s last dataset): points and one point
field, for ``workbench score --format vtu --field NAME``.

Our own for the same reason as :mod:`workbench.external.frd` (no VTK/meshio in the environment). Supported
encodings: ``format="ascii"`` and inline ``format="binary"`` (base64), raw or ``vtkZLibDataCompressor``, with
``header_type`` UInt32 or UInt64, as dolfinx and ParaView write them; ``appended`` data is refused in one line.
The contact surface is found as in the .frd: the points on the block top Y = 0 (reference configuration),
coincident points merged by their largest value. A ``P_N_per_mm`` FieldData value (the workbench writes it) is
taken as the load. Units: mm, MPa.

Before anything is decoded the file passes :func:`workbench.external.result_files.open_result` (a regular file of
at most 256 MB), a file with a DTD (``<!DOCTYPE``, ``<!ENTITY``: entity expansion, external entities) is refused,
and every array's size is checked against what the Piece declares (``NumberOfPoints``, at most 4e6, times its
components): a binary header or a zlib block that declares more is refused before it is inflated (a zlib bomb of
85 KB declaring 64 MB is one line, not 700 MB of memory), and a block is inflated to its declared size at most.
A ``.pvd``'s dataset must lie in the ``.pvd``'s folder (no absolute path, no ``..`` or symlink out of it).
"""

from __future__ import annotations

import base64
import binascii
import math
import xml.etree.ElementTree as ET
import zlib
from pathlib import Path

import numpy as np

from workbench.external.result_files import MAX_POINTS, inside_folder, open_result, parsing, read_result_bytes, shown
from workbench.external.results import ExternalResult, ResultError, make_result

__all__ = ["read_vtk_result"]

_TYPES = {"Float64": "<f8", "Float32": "<f4", "Int64": "<i8", "Int32": "<i4", "UInt64": "<u8", "UInt32": "<u4",
          "Int8": "<i1", "UInt8": "<u1"}


def _b64(text: str, *, where: str) -> bytes:
    try:
        return base64.b64decode(text, validate=False)
    except (binascii.Error, ValueError):
        raise ResultError(f"{where}: corrupt base64 data") from None


def _array(el, *, root, where: str, count: int) -> np.ndarray:
    """The values of a DataArray, exactly ``count`` of them (its declared tuples times components)."""
    name = shown(el.get("Name") or "")
    fmt = el.get("format", "ascii")
    dtype = _TYPES.get(el.get("type", ""))
    if dtype is None:
        raise ResultError(f"{where}: DataArray {name} has type {shown(el.get('type') or '')}; allowed: "
                          f"{', '.join(_TYPES)}")
    text = (el.text or "").strip()
    itemsize = np.dtype(dtype).itemsize
    want = count * itemsize
    if fmt == "ascii":
        parts = text.split(maxsplit=count)
        if len(parts) != count:
            raise ResultError(f"{where}: DataArray {name} has {len(parts) if len(parts) <= count else 'more'} "
                              f"values; allowed: {count} (the Piece's points times the components)")
        return np.array(parts, dtype=float)
    if fmt != "binary":
        raise ResultError(f"{where}: DataArray {name} format {shown(fmt)!r}; allowed: ascii, binary (inline)")
    head_t = "<u8" if root.get("header_type", "UInt32") == "UInt64" else "<u4"
    hsize = np.dtype(head_t).itemsize
    if root.get("compressor"):
        if root.get("compressor") != "vtkZLibDataCompressor":
            raise ResultError(f"{where}: compressor {shown(root.get('compressor'))}; allowed: vtkZLibDataCompressor")
        first = _b64(text[:4 * math.ceil(3 * hsize / 3)], where=where)
        if len(first) < 3 * hsize:
            raise ResultError(f"{where}: DataArray {name}: a truncated compression header")
        nblocks, block, last = (int(v) for v in np.frombuffer(first[:3 * hsize], dtype=head_t))
        if nblocks > max(1, want // max(block, 1) + 1) or nblocks < (1 if want else 0):
            raise ResultError(f"{where}: DataArray {name} declares {nblocks} compressed blocks; allowed: what "
                              f"{count} values need")
        total = (nblocks - 1) * block + (last or block) if nblocks else 0
        if total != want:
            raise ResultError(f"{where}: DataArray {name} declares {total} bytes uncompressed; allowed: {want} "
                              "(the Piece's points times the components); refused before inflating")
        hlen = 4 * math.ceil((3 + nblocks) * hsize / 3)
        header = np.frombuffer(_b64(text[:hlen], where=where)[:(3 + nblocks) * hsize], dtype=head_t)
        if header.size != 3 + nblocks:
            raise ResultError(f"{where}: DataArray {name}: a truncated compression header")
        raw = _b64(text[hlen:], where=where)
        sizes = [int(v) for v in header[3:]]
        if sum(sizes) > len(raw):
            raise ResultError(f"{where}: DataArray {name}: the compressed blocks are shorter than declared")
        out, pos = [], 0
        for k, size in enumerate(sizes):
            expect = block if k < nblocks - 1 or not last else last
            d = zlib.decompressobj()
            piece = d.decompress(raw[pos:pos + size], expect)
            if len(piece) != expect or d.unconsumed_tail:
                raise ResultError(f"{where}: DataArray {name}: a compressed block does not inflate to its declared "
                                  f"{expect} bytes")
            out.append(piece)
            pos += size
        data = b"".join(out)
    else:
        blob = _b64(text[:4 * math.ceil(hsize / 3)], where=where)[:hsize]
        if len(blob) < hsize:
            raise ResultError(f"{where}: DataArray {name}: a truncated binary header")
        n = int(np.frombuffer(blob, dtype=head_t)[0])
        if n != want:
            raise ResultError(f"{where}: DataArray {name} declares {n} bytes; allowed: {want} (the Piece's points "
                              "times the components)")
        blob = _b64(text, where=where)
        data = blob[hsize:hsize + n]
        if len(data) != n:
            raise ResultError(f"{where}: DataArray {name}: {len(data)} bytes of data; declared {n}")
    return np.frombuffer(data, dtype=dtype).astype(float)


def _parse(path: Path, *, where: str):
    """The XML root of a VTK file (checked: regular file, bounded size, no DTD)."""
    data = read_result_bytes(path, where=where)
    if b"<!DOCTYPE" in data or b"<!ENTITY" in data:
        raise ResultError(f"{where}: an XML document type definition (DOCTYPE/ENTITY); allowed: VTK XML without one")
    try:
        return ET.fromstring(data)
    except ET.ParseError as exc:
        raise ResultError(f"{where}: not a readable VTK XML file (ParseError: {exc})") from None


def _dataset_file(path: Path, *, where: str) -> Path:
    """A .pvd's last dataset (the last time step), else the file itself; inside the .pvd's folder."""
    if path.suffix != ".pvd":
        return path
    sets = _parse(path, where=where).findall(".//DataSet")
    if not sets:
        raise ResultError(f"{where}: a .pvd without DataSet entries")
    name = sets[-1].get("file")
    if not name or not name.strip():
        raise ResultError(f"{where}: the last DataSet has no file attribute; allowed: file=\"<dataset>.vtu\"")
    if Path(name).is_absolute():
        raise ResultError(f"{where}: the DataSet file {shown(name)} is an absolute path; allowed: a file inside the "
                          ".pvd's folder")
    inside_folder(path.absolute().parent, path.absolute().parent / name, where=where, what="DataSet file")
    return path.absolute().parent / name


def read_vtk_result(path: str | Path, *, field: str = "p_MPa", load: float | None = None,
                    h: float | None = None) -> ExternalResult:
    """One level's pressure from the point field ``field`` of a .vtu/.vtp/.pvd (see the module docstring)."""
    where = str(path)
    with parsing(where):
        f = _dataset_file(Path(path), where=where)
        if f != Path(path):
            open_result(f, where=f"{where}: DataSet {shown(f.name)}").close()  # regular, bounded, inside
        root = _parse(f, where=where)
        piece = root.find(".//Piece")
        pts_el = piece.find("./Points/DataArray") if piece is not None else None
        if pts_el is None:
            raise ResultError(f"{where}: no Piece/Points; allowed: a VTK XML UnstructuredGrid or PolyData")
        try:
            npts = int(piece.get("NumberOfPoints", ""))
            ncomp = int(pts_el.get("NumberOfComponents", "3"))
        except ValueError:
            raise ResultError(f"{where}: the Piece's NumberOfPoints or the Points' NumberOfComponents is not a whole "
                              "number") from None
        if not 0 < npts <= MAX_POINTS:
            raise ResultError(f"{where}: NumberOfPoints = {npts}; allowed: 1 to {MAX_POINTS}")
        if ncomp not in (2, 3):
            raise ResultError(f"{where}: the Points have {ncomp} component(s); allowed: 2 or 3 (x, y[, z])")
        pts = _array(pts_el, root=root, where=where, count=npts * ncomp).reshape(npts, ncomp)
        arrays = {el.get("Name"): el for el in piece.findall("./PointData/DataArray")}
        if field not in arrays:
            names = ", ".join(shown(str(n)) for n in list(arrays)[:8])
            raise ResultError(f"{where}: no point field {shown(field)!r} (fields: {names[:120]}); give --field")
        el = arrays[field]
        try:
            fcomp = int(el.get("NumberOfComponents", "1"))
        except ValueError:
            raise ResultError(f"{where}: field {shown(field)!r}: NumberOfComponents is not a whole number") from None
        if fcomp != 1:
            raise ResultError(f"{where}: field {shown(field)!r} has {fcomp} components (a vector field?); allowed: "
                              "a scalar point field")
        vals = _array(el, root=root, where=where, count=npts)
        if load is None:
            for fd in root.findall(".//FieldData/DataArray"):
                if fd.get("Name") == "P_N_per_mm":
                    tuples = int(fd.get("NumberOfTuples", "1"))
                    if tuples != 1:
                        raise ResultError(f"{where}: FieldData P_N_per_mm has {tuples} values; allowed: 1")
                    load = float(_array(fd, root=root, where=where, count=1)[0])
    if not (np.all(np.isfinite(vals)) and np.all(np.isfinite(pts))):
        raise ResultError(f"{where}: NaN or infinite values in the points or {shown(field)!r}")
    scale = float(np.max(np.abs(pts[:, :2]))) or 1.0
    top = np.abs(pts[:, 1]) <= 1e-9 * scale
    if top.sum() < 2:
        raise ResultError(f"{where}: {int(top.sum())} point(s) on the contact surface Y = 0; the surface does not "
                          "match the case (block top at y = 0)")
    x, p = pts[top, 0], vals[top]
    if p.min() < 0 or not np.any(p > 0):
        raise ResultError(f"{where}: field {shown(field)!r} on the surface is negative or nowhere positive; "
                          "allowed: a contact pressure >= 0, compression positive")
    if load is not None and not (math.isfinite(load) and load > 0):
        raise ResultError(f"{where}: load P_N_per_mm = {load:g}; allowed: finite and > 0")
    return make_result(where, x, p, load=load, h=h)
