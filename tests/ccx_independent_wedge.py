"""An independent CalculiX model of the ``wedge`` case's theta = pi/20 run, written without the workbench's exporter.

It shares nothing with :mod:`workbench.external.inp`, :mod:`workbench.external.benchmarks` or the case meshes (no
gmsh): the numbers are the case's (E = 210 GPa, nu = 0.3, theta = pi/20 with face slope m = tan theta, b = 0.5 mm at
the target load, block W = H = 40 b, half model) typed in here, and the deck is built from scratch:

* the half block [0, W/2] x [-H, 0] as a structured tensor-product mesh of 8-node quadrilaterals (``CPE8``, plane
  strain, thickness 1 mm): spacing ``h`` up to ``1.5 b`` from the symmetry plane and from the top, then growing
  geometrically to the block's side and bottom (:func:`ccx_independent.graded`, the Hertz model's grading);
* a rigid wedge: one row of ``CPE8`` elements along its face y = m x from the apex (0, 0) to x = 2.5 b, ``t`` thick
  (straight elements: the face is straight), its nodes a ``*RIGID BODY`` driven through a reference node at the apex
  by a prescribed approach ``d`` (u_x = 0: the symmetry plane; its rotation node fixed); its lower faces are the
  master surface; the apex is a node, coincident with the block's corner node at the origin;
* frictionless surface-to-surface penalty contact (slope ``kappa E / h``); bottom clamped, symmetry edge u_x = 0;
* twenty equal increments (CalculiX builds its contact elements from the geometry at the start of an increment:
  its CPRESS is per area of that geometry, which twenty increments bring to within 1e-4 of the current one);
* output: ``*NODE FILE U, RF`` (the .frd's DISP and FORC blocks) and ``*CONTACT FILE CSTR`` (CONTACT: CPRESS).

Units: mm, N, MPa; forces per mm of thickness. Numbers are written with 13 significant digits (CalculiX reads 20
characters per field).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import NamedTuple

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ccx_independent import graded  # noqa: E402  (the Hertz model's grading, a test helper)

__all__ = ["E", "NU", "THETA", "M", "B", "WIDTH", "HEIGHT", "E_STAR", "P_TARGET", "Deck", "deck"]

E, NU = 210000.0, 0.3
THETA = math.pi / 20.0
M = math.tan(THETA)
B = 0.5
WIDTH = HEIGHT = 40.0 * B
E_STAR = E / (1.0 - NU * NU)
P_TARGET = E_STAR * M * B  # the classical wedge: b = P / (E* m)


class Deck(NamedTuple):
    """The deck's text, the block's top nodes (numbers, left to right) and the wedge's reference node."""

    text: str
    top: list[int]
    ref: int


def deck(*, h: float, d: float, growth: float = 1.25, kappa: float = 50.0, band: float = 2.5,
         increments: int = 20) -> Deck:
    """The ``.inp`` of the independent wedge model at contact spacing ``h`` (mm) and approach ``d`` (mm)."""
    xs = graded(0.5 * WIDTH, h=h, fine=1.5 * B, growth=growth)
    ys = -graded(HEIGHT, h=h, fine=1.5 * B, growth=growth)[::-1]  # -H .. 0
    gx = np.concatenate([np.column_stack([xs[:-1], 0.5 * (xs[:-1] + xs[1:])]).ravel(), xs[-1:]])
    gy = np.concatenate([np.column_stack([ys[:-1], 0.5 * (ys[:-1] + ys[1:])]).ravel(), ys[-1:]])
    num: dict[tuple[int, int], int] = {}
    lines = ["*HEADING", "independent wedge model theta = pi/20 (tests/ccx_independent_wedge.py)", "*NODE, NSET=NALL"]
    for j, y in enumerate(gy):
        for i, x in enumerate(gx):
            if i % 2 and j % 2:
                continue
            num[(i, j)] = len(num) + 1
            lines.append(f"{num[(i, j)]}, {x:.13g}, {y:.13g}")
    nxe, nye = len(xs) - 1, len(ys) - 1
    top_elems, elements = [], ["*ELEMENT, TYPE=CPE8, ELSET=EBLOCK"]
    e = 0
    for jj in range(nye):
        for ii in range(nxe):
            i, j = 2 * ii, 2 * jj
            n = [num[(i, j)], num[(i + 2, j)], num[(i + 2, j + 2)], num[(i, j + 2)],
                 num[(i + 1, j)], num[(i + 2, j + 1)], num[(i + 1, j + 2)], num[(i, j + 1)]]
            e += 1
            elements.append(f"{e}, " + ", ".join(map(str, n)))
            if jj == nye - 1 and xs[ii] < band * B:
                top_elems.append(e)  # face 3 (nodes 3-4) is on y = 0
    top = [num[(i, 2 * nye)] for i in range(len(gx))]
    # the rigid wedge: face nodes at x = k dx / 2 (corners at even k), the apex k = 0; a copy t above
    n_el = int(math.ceil(band * B / h))
    dx = band * B / n_el
    t = 2.0 * h
    node = len(num)
    wedge, wedge_lines = {}, []
    for row, lift in enumerate((0.0, 0.5 * t, t)):
        for k in range(2 * n_el + 1):
            if row == 1 and k % 2:
                continue
            x = 0.5 * k * dx
            node += 1
            wedge[(row, k)] = node
            wedge_lines.append(f"{node}, {x:.13g}, {M * x + lift:.13g}")
    ref, rot = node + 1, node + 2
    lines += ["*NODE, NSET=NWEDGE", *wedge_lines, "*NODE, NSET=NREF", f"{ref}, 0.0, 0.0", f"{rot}, 0.0, 0.0"]
    lines += elements
    lines.append("*ELEMENT, TYPE=CPE8, ELSET=EWEDGE")
    faces = []
    for k in range(0, 2 * n_el, 2):
        n = [wedge[(0, k)], wedge[(0, k + 2)], wedge[(2, k + 2)], wedge[(2, k)],
             wedge[(0, k + 1)], wedge[(1, k + 2)], wedge[(2, k + 1)], wedge[(1, k)]]
        e += 1
        faces.append(e)
        lines.append(f"{e}, " + ", ".join(map(str, n)))
    bottom = [num[(i, 0)] for i in range(len(gx))]
    symm = [num[(0, j)] for j in range(len(gy))]

    def nset(name, ids):
        return [f"*NSET, NSET={name}", *[", ".join(map(str, ids[k:k + 12])) for k in range(0, len(ids), 12)]]

    lines += nset("NBOTTOM", bottom) + nset("NSYMM", symm)
    lines += ["*SURFACE, NAME=SSLAVE, TYPE=ELEMENT", *[f"{el}, S3" for el in top_elems],
              "*SURFACE, NAME=SMASTER, TYPE=ELEMENT", *[f"{el}, S1" for el in faces],
              "*MATERIAL, NAME=STEEL", "*ELASTIC", f"{E!r}, {NU!r}",
              "*SOLID SECTION, ELSET=EBLOCK, MATERIAL=STEEL", "1.",
              "*SOLID SECTION, ELSET=EWEDGE, MATERIAL=STEEL", "1.",
              f"*RIGID BODY, NSET=NWEDGE, REF NODE={ref}, ROT NODE={rot}",
              "*SURFACE INTERACTION, NAME=FRICTIONLESS", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
              f"{kappa * E / h:.13g}, 0.",
              "*CONTACT PAIR, INTERACTION=FRICTIONLESS, TYPE=SURFACE TO SURFACE", "SSLAVE, SMASTER",
              "*BOUNDARY", "NBOTTOM, 1, 2, 0.", "NSYMM, 1, 1, 0.", f"{rot}, 1, 3, 0.",
              f"*STEP, INC={10 * increments}", "*STATIC", f"{1.0 / increments!r}, 1., 1e-6, {1.0 / increments!r}",
              "*BOUNDARY", f"{ref}, 1, 1, 0.", f"{ref}, 2, 2, {-d:.13g}",
              "*NODE FILE", "U, RF", "*CONTACT FILE", "CSTR", "*END STEP", ""]
    return Deck("\n".join(lines), top, ref)
