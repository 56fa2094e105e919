"""A small reader of CalculiX ``.frd`` result files (ASCII): node coordinates and the last CONTACT block.

Why our own: the maintained PyPI readers the issue names (pyvista-frd-reader, ccx2paraview, frd2vtu, anyfileio)
are not installed in the project's environment, and the helper may not install packages; the part of the
format read here is small and fixed (CalculiX 2.20 writes it): a ``    2C`` node block of ``-1`` records
(node number I10, then the coordinates, E12.5 each in the short format, E25.15 in the long one), then result
blocks (``    1PSTEP``, ``  100CL`` header, ``-4 NAME ncomp``, ``-5`` component lines, ``-1`` node records, ``-3``
end), and `` 9999`` at the end of the file. Values are read by fixed width (adjacent numbers need not be
separated by blanks: ``-1.06194E-05-2.2E+03``).

The contact surface is the block's top, y = 0 in the reference configuration (the case's geometry): the nodes
with |Y| <= 1e-9 (body size); where two nodes coincide (the slave and the master surface touching at the
first contact point) the larger CPRESS is kept. CalculiX's CPRESS is a force per DEFORMED area (measured on
hertz_cylinder, h_c = a/40: its integral over the reference positions X is 1.1 % above the reaction force, over
the current positions X + u1 0.06 % off). The scorer's convention is the reference configuration (as the
csv's), so with a DISP block in the file the pressure is turned into force per reference length,
``p = CPRESS d(X + u1)/dX`` (the stretch of the surface from the nodal u1, ``np.gradient``: 0.988 at the
centre of hertz_cylinder; the integral then matches the reaction to 0.06 %); ``configuration =
"current"`` keeps CPRESS at the current positions instead. Units: mm, MPa.
"""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

import numpy as np

from workbench.external.results import ExternalResult, ResultError, make_result

__all__ = ["FrdData", "read_frd", "read_frd_result", "surface_pressure"]


class FrdData(NamedTuple):
    """Node numbers (n,), coordinates (n, 3) and the last block of each result name: name -> (components,
    node numbers (m,), values (m, k))."""

    nodes: np.ndarray
    coords: np.ndarray
    blocks: dict


def _values(line: str, start: int, width: int, count: int) -> list[float]:
    out = []
    for k in range(count):
        field = line[start + k * width:start + (k + 1) * width]
        if not field.strip():
            break
        out.append(float(field))
    return out


def read_frd(path: str | Path) -> FrdData:
    """Parse the node block and the LAST result block of every name (the last increment of the last step).

    Raises:
        ResultError: unreadable or truncated file (no `` 9999`` end, a block without ``-3``), no node block.
    """
    where = str(path)
    try:
        lines = Path(path).read_text(errors="replace").splitlines()
    except OSError as exc:
        raise ResultError(f"{where}: cannot be read ({exc.__class__.__name__}: {exc})") from None
    if not lines or lines[-1].strip() != "9999":
        raise ResultError(f"{where}: truncated .frd (the last line is not 9999); allowed: a complete CalculiX result")
    nodes, coords, blocks = None, None, {}
    i, n = 0, len(lines)
    try:
        while i < n:
            line = lines[i]
            key = line[:6].strip()
            if key == "2C":
                i += 1
                ids, xyz = [], []
                while i < n and not lines[i].startswith(" -3"):
                    rec = lines[i]
                    width = 25 if len(rec) >= 13 + 3 * 25 else 12
                    ids.append(int(rec[3:13]))
                    xyz.append(_values(rec, 13, width, 3))
                    i += 1
                if i >= n:
                    raise ResultError(f"{where}: truncated .frd (the node block has no -3 end)")
                nodes, coords = np.array(ids), np.array(xyz, dtype=float)
            elif line.startswith(" -4"):
                name = line[3:13].strip()
                ncomp = int(line[13:18])
                comps = []
                i += 1
                while i < n and lines[i].startswith(" -5"):
                    comps.append(lines[i][3:13].strip())
                    i += 1
                ids, vals = [], []
                while i < n and not lines[i].startswith(" -3"):
                    rec = lines[i]
                    if rec.startswith(" -1"):
                        width = 25 if len(rec) >= 13 + ncomp * 25 else 12
                        ids.append(int(rec[3:13]))
                        vals.append(_values(rec, 13, width, ncomp))
                    i += 1
                if i >= n:
                    raise ResultError(f"{where}: truncated .frd (the {name} block has no -3 end)")
                blocks[name] = (comps[:ncomp], np.array(ids), np.array(vals, dtype=float).reshape(len(ids), -1))
            i += 1
    except ValueError as exc:
        raise ResultError(f"{where}: line {i + 1} is not a CalculiX .frd record ({exc})") from None
    if nodes is None:
        raise ResultError(f"{where}: no node block (2C); allowed: a CalculiX .frd with node coordinates")
    return FrdData(nodes, coords, blocks)


def surface_pressure(data: FrdData, *, where: str, top_y: float = 0.0,
                     configuration: str = "reference") -> tuple[np.ndarray, np.ndarray]:
    """(x, p) of the nodes on the block top Y = ``top_y``, coincident nodes merged by their largest CPRESS:
    ``"reference"``: x = X, p = CPRESS d(X + u1)/dX; ``"current"``: x = X + u1, p = CPRESS."""
    if "CONTACT" not in data.blocks:
        raise ResultError(f"{where}: no CONTACT block; allowed: a .frd written with *CONTACT FILE CSTR")
    comps, ids, vals = data.blocks["CONTACT"]
    if "CPRESS" not in comps:
        raise ResultError(f"{where}: the CONTACT block has no CPRESS ({', '.join(comps)})")
    cp = dict(zip(ids.tolist(), vals[:, comps.index("CPRESS")].tolist(), strict=True))
    scale = float(np.max(np.abs(data.coords[:, :2]))) or 1.0
    on_top = np.abs(data.coords[:, 1] - top_y) <= 1e-9 * scale
    if not on_top.any():
        raise ResultError(f"{where}: no node on the contact surface y = {top_y:g} mm; the surface does not "
                          "match the case (block top at y = 0)")
    x = data.coords[on_top, 0].copy()
    u1 = np.zeros_like(x)
    if "DISP" in data.blocks:
        dcomps, dids, dvals = data.blocks["DISP"]
        u = dict(zip(dids.tolist(), dvals[:, 0].tolist(), strict=True))
        u1 = np.array([u.get(int(k), 0.0) for k in data.nodes[on_top]])
    p = np.array([cp.get(int(k), 0.0) for k in data.nodes[on_top]])
    order = np.lexsort((-p, x))
    x, p, u1 = x[order], p[order], u1[order]
    first = np.ones(x.size, dtype=bool)
    first[1:] = np.diff(x) > 1e-12 * scale
    x, p, u1 = x[first], p[first], u1[first]
    if configuration == "current":
        return x + u1, p
    if x.size >= 2 and np.any(u1):
        p = p * np.gradient(x + u1, x)  # force per reference length
    return x, p


def read_frd_result(path: str | Path, *, load: float | None = None, h: float | None = None,
                    configuration: str = "reference") -> ExternalResult:
    """One level's contact pressure from a CalculiX ``.frd`` (``load``: the full-body load if known)."""
    data = read_frd(path)
    x, p = surface_pressure(data, where=str(path), configuration=configuration)
    if not np.any(p > 0):
        raise ResultError(f"{path}: no positive CPRESS on the contact surface (no contact)")
    if x.size < 2:
        raise ResultError(f"{path}: {x.size} node(s) on the contact surface; allowed: at least 2")
    return make_result(str(path), x, np.clip(p, 0.0, None), load=load, h=h,
                       configuration=configuration)
