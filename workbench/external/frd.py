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

Malformed input is refused in one line naming the file and line (the command exits 2): a record with fewer or
more values than its block declares (a ``-5`` component line with IEXIST = 1, such as DISP's ``ALL``, is computed
by cgx and has no value in the records), a node with other than 3 coordinates, a non-finite coordinate or value,
a node given twice, a block without records, more than 4e6 nodes. The file is opened as
:func:`workbench.external.result_files.open_result` says and read line by line (only the node block and the last
CONTACT, DISP and FORC blocks of each step are kept).

Steps: CalculiX heads every result block with a ``    1PSTEP`` line whose last integer is the step number
(``*STEP`` of the deck, from 1). :attr:`FrdData.steps` holds, per step in the order of the file, the last block of
each kept name (the step's last written increment: the decks of :mod:`workbench.external.inp` write the end of
every step only); :attr:`FrdData.blocks` is the last step's (the last CONTACT and DISP of the file, as before).
:func:`chain_pressure` reads the contact pressure of one step at the nodes of a surface given in order along
it, any shape: CPRESS times the stretch ``ds/dS`` of the surface (current over reference length, both along the
chain of nodes). CalculiX expands a plane model into one layer of 3D elements whose nodes it numbers after the
model's largest node ``nk``, three per node (z = -t/2, 0, t/2): node n's are ``nk + 3 (n - 1) + 1 .. 3``
(CalculiX 2.20; a mid-edge node of a 6-node triangle has two of them). Segment-to-segment contact reports CPRESS
on the model's own nodes; node-to-surface contact on the expanded ones: a node without its own CPRESS takes the
largest of its expanded nodes' (they carry one value: measured on the patch test).
"""

from __future__ import annotations

import io
from pathlib import Path
from typing import NamedTuple

import numpy as np

from workbench.external.result_files import MAX_POINTS, merge_coincident, open_result, parsing
from workbench.external.results import ExternalResult, ResultError, make_result

__all__ = ["FrdData", "read_frd", "read_frd_result", "surface_pressure", "chain_pressure", "step_block"]

KEPT = ("CONTACT", "DISP", "FORC")  # the result blocks read (the last of each per step); the others are skipped


class FrdData(NamedTuple):
    """Node numbers (n,), coordinates (n, 3) and the last block of each kept result name: name -> (components,
    node numbers (m,), values (m, k)); ``steps``: step number -> such a dict, per step (module docstring)."""

    nodes: np.ndarray
    coords: np.ndarray
    blocks: dict
    steps: dict


def _values(line: str, start: int, width: int, count: int, *, where: str) -> list[float]:
    """``count`` fixed-width numbers from column ``start``; ResultError unless exactly ``count`` are there."""
    out = []
    for k in range(count):
        field = line[start + k * width:start + (k + 1) * width]
        if not field.strip():
            break
        out.append(float(field))
    rest = line[start + count * width:].strip()
    if len(out) != count or rest:
        raise ResultError(f"{where}: a record with {len(out) + (1 if rest else 0)}{'+' if rest else ''} values; "
                          f"allowed: {count}")
    return out


def _width(rec: str, count: int) -> int:
    """The field width of a ``-1`` record: 25 (long format) or 12 (short)."""
    return 25 if len(rec.rstrip()) >= 13 + count * 25 else 12


def _values_expected(comp_line: str) -> tuple[str, bool]:
    """A ``-5`` line: the component's name and whether the records hold a value for it (IEXIST != 1)."""
    name = comp_line[3:13].strip()
    ints = comp_line[13:38]
    iexist = ints[20:25].strip()
    return name, iexist != "1"


def read_frd(path: str | Path) -> FrdData:
    """Parse the node block and the LAST CONTACT and DISP blocks (the last increment of the last step).

    Raises:
        ResultError: unreadable or truncated file (no `` 9999`` end, a block without ``-3``), no node block, a
            malformed record (see the module docstring).
    """
    where = str(path)
    nodes, coords, steps = None, None, {}
    step = 1
    last = ""
    lineno = 0
    with open_result(path, where=where) as fh, parsing(where):
        lines = io.TextIOWrapper(fh, encoding="ascii", errors="replace", newline=None)

        def nxt() -> str | None:
            nonlocal lineno, last
            line = lines.readline()
            if not line:
                return None
            lineno += 1
            line = line.rstrip("\n")
            if line.strip():
                last = line
            return line

        def at() -> str:
            return f"{where}: line {lineno}"

        line = nxt()
        while line is not None:
            key = line[:6].strip()
            if line[:10].strip() == "1PSTEP":
                fields = line[10:].split()
                if fields:
                    step = int(fields[-1])
            elif key == "2C":
                ids, xyz = [], []
                line = nxt()
                while line is not None and not line.startswith(" -3"):
                    if line.startswith(" -1"):
                        if len(ids) >= MAX_POINTS:
                            raise ResultError(f"{where}: more than {MAX_POINTS} nodes; allowed: at most {MAX_POINTS}")
                        ids.append(int(line[3:13]))
                        xyz.append(_values(line, 13, _width(line, 3), 3, where=f"{at()}: node {ids[-1]}"))
                    line = nxt()
                if line is None:
                    raise ResultError(f"{where}: truncated .frd (the node block has no -3 end)")
                nodes, coords = np.array(ids, dtype=np.int64), np.array(xyz, dtype=float).reshape(-1, 3)
                if nodes.size == 0:
                    raise ResultError(f"{where}: the node block (2C) has no nodes")
                if np.unique(nodes).size != nodes.size:
                    raise ResultError(f"{where}: a node number appears twice in the node block; allowed: each once")
                bad = ~np.all(np.isfinite(coords), axis=1)
                if bad.any():
                    raise ResultError(f"{where}: node {int(nodes[bad][0])} has a non-finite coordinate; allowed: "
                                      "finite coordinates (mm)")
            elif line.startswith(" -4"):
                name = line[3:13].strip()
                ncomp = int(line[13:18])
                if not 1 <= ncomp <= 100:
                    raise ResultError(f"{at()}: block {name[:12]} declares {ncomp} components; allowed: 1 to 100")
                comps = []
                line = nxt()
                while line is not None and line.startswith(" -5"):
                    comps.append(_values_expected(line))
                    line = nxt()
                names = [c for c, has in comps[:ncomp] if has]
                count = len(names)
                if count == 0:
                    raise ResultError(f"{at()}: block {name[:12]} has no component with values")
                ids, vals = [], []
                while line is not None and not line.startswith(" -3"):
                    if line.startswith(" -1") and name in KEPT:
                        if len(ids) >= MAX_POINTS:
                            raise ResultError(f"{where}: more than {MAX_POINTS} records in block {name}")
                        ids.append(int(line[3:13]))
                        vals.append(_values(line, 13, _width(line, count), count, where=f"{at()}: {name}"))
                    line = nxt()
                if line is None:
                    raise ResultError(f"{where}: truncated .frd (the {name[:12]} block has no -3 end)")
                if name in KEPT:
                    if not ids:
                        raise ResultError(f"{where}: the {name} block has no node records")
                    arr = np.array(vals, dtype=float).reshape(len(ids), count)
                    if not np.all(np.isfinite(arr)):
                        row = int(np.flatnonzero(~np.all(np.isfinite(arr), axis=1))[0])
                        raise ResultError(f"{where}: the {name} block has a NaN or infinite value at node {ids[row]}; "
                                          "allowed: finite values")
                    steps.setdefault(step, {})[name] = (names, np.array(ids, dtype=np.int64), arr)
            line = nxt()
    if last.strip() != "9999":
        raise ResultError(f"{where}: truncated .frd (the last line is not 9999); allowed: a complete CalculiX result")
    if nodes is None:
        raise ResultError(f"{where}: no node block (2C); allowed: a CalculiX .frd with node coordinates")
    return FrdData(nodes, coords, steps[list(steps)[-1]] if steps else {}, steps)


def step_block(data: FrdData, step: int, name: str, *, where: str) -> tuple[list, np.ndarray, np.ndarray]:
    """The (components, node numbers, values) of result ``name`` at the end of ``step``; ResultError if absent."""
    if step not in data.steps or name not in data.steps[step]:
        raise ResultError(f"{where}: no {name} block in step {step}; the file has steps {sorted(data.steps)}")
    return data.steps[step][name]


def surface_pressure(data: FrdData, *, where: str, top_y: float = 0.0,
                     configuration: str = "reference") -> tuple[np.ndarray, np.ndarray, int]:
    """(x, p, merged) of the nodes on the block top Y = ``top_y``, coincident nodes merged by their largest CPRESS
    (:func:`workbench.external.result_files.merge_coincident`; ``merged`` of them dropped): ``"reference"``:
    x = X, p = CPRESS d(X + u1)/dX; ``"current"``: x = X + u1, p = CPRESS."""
    if "CONTACT" not in data.blocks:
        raise ResultError(f"{where}: no CONTACT block; allowed: a .frd written with *CONTACT FILE CSTR")
    comps, ids, vals = data.blocks["CONTACT"]
    if "CPRESS" not in comps:
        raise ResultError(f"{where}: the CONTACT block has no CPRESS component")
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
    x, p, u1, merged = merge_coincident(x, p, u1, scale=scale)
    if configuration == "current":
        return x + u1, p, merged
    if x.size >= 2 and np.any(u1):
        p = p * np.gradient(x + u1, x)  # force per reference length
    return x, p, merged


def read_frd_result(path: str | Path, *, load: float | None = None, h: float | None = None,
                    configuration: str = "reference") -> ExternalResult:
    """One level's contact pressure from a CalculiX ``.frd`` (``load``: the full-body load if known)."""
    data = read_frd(path)
    x, p, merged = surface_pressure(data, where=str(path), configuration=configuration)
    if not np.all(np.isfinite(x)) or not np.all(np.isfinite(p)):
        raise ResultError(f"{path}: the surface positions or pressures are not finite (the displacements?)")
    if not np.any(p > 0):
        raise ResultError(f"{path}: no positive CPRESS on the contact surface (no contact)")
    if x.size < 2:
        raise ResultError(f"{path}: {x.size} node(s) on the contact surface; allowed: at least 2")
    return make_result(str(path), x, np.clip(p, 0.0, None), load=load, h=h,
                       configuration=configuration, merged=merged)


def chain_pressure(data: FrdData, *, step: int, chain: np.ndarray, where: str,
                   per: str = "current") -> tuple[np.ndarray, np.ndarray]:
    """The contact pressure per reference length at the nodes ``chain`` (frd node numbers in order along a
    surface) at the end of ``step``: ``(p, stretch)``, ``ds/dS`` the stretch of the surface at each node: the
    current over the reference length along the chain, by central differences of the cumulative lengths (one-sided
    at the ends; :func:`numpy.gradient`). ``per``: what CPRESS is a force per (CalculiX: per area of the geometry
    its contact elements were built from, the start of the last increment): ``"current"`` length, then
    ``p = CPRESS ds/dS`` (which integrates over the reference arc length to the same force), or ``"reference"``
    length, then ``p = CPRESS``. 0 where a node has no CPRESS."""
    comps, ids, vals = step_block(data, step, "CONTACT", where=where)
    if "CPRESS" not in comps:
        raise ResultError(f"{where}: the CONTACT block of step {step} has no CPRESS component")
    cp = dict(zip(ids.tolist(), vals[:, comps.index("CPRESS")].tolist(), strict=True))
    nk = int(data.nodes.max())
    expanded: dict[int, float] = {}
    for n, v in cp.items():  # node-to-surface contact reports CPRESS on the expanded 3D nodes (module docstring)
        if n > nk:
            m = (n - nk - 1) // 3 + 1
            expanded[m] = max(expanded.get(m, 0.0), v)
    for m, v in expanded.items():
        cp.setdefault(m, v)
    index = {int(n): i for i, n in enumerate(data.nodes.tolist())}
    missing = [int(n) for n in chain if int(n) not in index]
    if missing:
        raise ResultError(f"{where}: node {missing[0]} of the contact surface is not in the node block")
    rows = np.array([index[int(n)] for n in chain])
    X = data.coords[rows, :2]
    dcomps, dids, dvals = step_block(data, step, "DISP", where=where)
    u = dict(zip(dids.tolist(), dvals[:, :2].tolist(), strict=True))
    x = X + np.array([u.get(int(n), (0.0, 0.0)) for n in chain])
    S = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(X, axis=0).T))])
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(x, axis=0).T))])
    if S.size < 2 or not np.all(np.diff(S) > 0):
        raise ResultError(f"{where}: the contact surface's nodes repeat a position; allowed: a chain of distinct nodes")
    stretch = np.gradient(s, S)
    if per not in ("current", "reference"):
        raise ValueError(f"per = {per!r}; allowed: current, reference")
    p = np.array([cp.get(int(n), 0.0) for n in chain]) * (stretch if per == "current" else 1.0)
    if not np.all(np.isfinite(p)):
        raise ResultError(f"{where}: the contact pressure of step {step} is not finite")
    return p, stretch
