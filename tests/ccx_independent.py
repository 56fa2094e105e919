"""An independent CalculiX model of the ``hertz_cylinder`` scene, written without the workbench's exporter.

It shares nothing with :mod:`workbench.external.inp` / :mod:`workbench.external.export` (no gmsh, no case
mesh, no deck writer): the numbers are the case's (R = 10 mm, E = 210 GPa, nu = 0.3, a = 0.5 mm, block
W = H = 40 a, half model) typed in here, and the deck is built from scratch:

* the half block [0, W/2] x [-H, 0] as a structured tensor-product mesh of 8-node quadrilaterals (``CPE8``,
  plane strain, thickness 1 mm): spacing ``h`` up to ``1.5 a`` from the symmetry plane and from the top, then
  growing geometrically (factor ``growth``) to the block's side and bottom;
* a rigid cylinder: one ring of ``CPE8`` elements between R and R - t whose nodes form a ``*RIGID BODY``
  driven through its reference node by a prescribed approach ``d`` (u_x = 0; its rotation node fixed); its outer face
  is the master surface; its nodes are at half-steps in angle, so none sits on the block's top (y = 0);
* frictionless surface-to-surface penalty contact (``*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR``,
  slope ``kappa E / h``); bottom clamped, symmetry edge u_x = 0;
* output: ``*NODE FILE U, RF`` (the .frd's DISP and FORC blocks) and ``*CONTACT FILE CSTR`` (CONTACT: CPRESS).

Units: mm, N, MPa; forces are N per mm of thickness. Numbers are written with 13 significant digits: CalculiX
reads at most 20 characters per field (a longer one is cut, silently for coordinates: 7.812498983739147e-06
was read as 7.8 and gave non-positive Jacobians).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["R", "E", "NU", "A", "WIDTH", "HEIGHT", "graded", "deck"]

R, E, NU, A = 10.0, 210000.0, 0.3, 0.5
WIDTH = HEIGHT = 40.0 * A


def graded(length: float, *, h: float, fine: float, growth: float) -> np.ndarray:
    """Corner coordinates 0 .. length: spacing h up to ``fine``, then growing by ``growth`` per element (the
    last element takes what is left if it is longer than half the previous one, else it is merged)."""
    xs = [0.0]
    while xs[-1] < fine - 1e-12:
        xs.append(min(xs[-1] + h, fine))
    step = xs[-1] - xs[-2]
    while xs[-1] < length - 1e-12:
        step *= growth
        xs.append(min(xs[-1] + step, length))
    if len(xs) > 2 and xs[-1] - xs[-2] < 0.5 * (xs[-2] - xs[-3]):
        xs.pop(-2)
    return np.array(xs)


def deck(*, h: float, d: float, element: str = "CPE8", growth: float = 1.25, kappa: float = 50.0,
         band: float = 2.5) -> str:
    """The ``.inp`` text of the independent model at contact spacing ``h`` (mm) and approach ``d`` (mm); the
    block's ``element`` is ``CPE8`` or ``CPE4`` (the rigid ring is CPE8 either way: a curved master surface)."""
    if element not in ("CPE8", "CPE4"):
        raise ValueError(f"element = {element!r}; allowed: CPE8, CPE4")
    quad = element == "CPE8"
    xs = graded(0.5 * WIDTH, h=h, fine=1.5 * A, growth=growth)
    ys = -graded(HEIGHT, h=h, fine=1.5 * A, growth=growth)[::-1]  # -H .. 0
    # quadratic grid: index (2i, 2j) corners, odd indices midsides; the element centres are not nodes
    gx = np.concatenate([np.column_stack([xs[:-1], 0.5 * (xs[:-1] + xs[1:])]).ravel(), xs[-1:]])
    gy = np.concatenate([np.column_stack([ys[:-1], 0.5 * (ys[:-1] + ys[1:])]).ravel(), ys[-1:]])
    num = {}
    lines = ["*HEADING", "independent hertz_cylinder model (tests/ccx_independent.py)", "*NODE, NSET=NALL"]
    for j, y in enumerate(gy):
        for i, x in enumerate(gx):
            if (i % 2 and j % 2) or (not quad and (i % 2 or j % 2)):
                continue
            num[(i, j)] = len(num) + 1
            lines.append(f"{num[(i, j)]}, {x:.13g}, {y:.13g}")
    nxe, nye = len(xs) - 1, len(ys) - 1
    top_elems = []
    lines.append(f"*ELEMENT, TYPE={element}, ELSET=EBLOCK")
    e = 0
    for jj in range(nye):
        for ii in range(nxe):
            i, j = 2 * ii, 2 * jj
            n = [num[(i, j)], num[(i + 2, j)], num[(i + 2, j + 2)], num[(i, j + 2)]]
            if quad:
                n += [num[(i + 1, j)], num[(i + 2, j + 1)], num[(i + 1, j + 2)], num[(i, j + 1)]]
            e += 1
            lines.append(f"{e}, " + ", ".join(map(str, n)))
            if jj == nye - 1 and xs[ii] < band * A:
                top_elems.append(e)  # face 3 (nodes 3-4) is on y = 0
    # rigid ring: angles at half steps, from just left of x = 0 to x = band a
    dth = h / R
    th_max = math.asin(band * A / R)
    n_el = int(math.ceil(th_max / dth))
    th = -0.25 * dth + 0.5 * dth * np.arange(2 * (n_el + 1) + 1)  # corners at even, midsides at odd indices
    t = 0.2 * R
    ring = {}
    node = len(num)
    ring_lines = []
    for r_i, r in enumerate((R, R - 0.5 * t, R - t)):
        for k, s in enumerate(th):
            if r_i == 1 and k % 2:
                continue
            node += 1
            ring[(r_i, k)] = node
            ring_lines.append(f"{node}, {r * math.sin(s):.13g}, {R - r * math.cos(s):.13g}")
    ref, rot = node + 1, node + 2
    lines += ["*NODE, NSET=NCYL", *ring_lines, "*NODE, NSET=NREF", f"{ref}, 0.0, {R!r}", f"{rot}, 0.0, {R!r}"]
    lines.append("*ELEMENT, TYPE=CPE8, ELSET=ECYL")
    cyl = []
    for k in range(0, len(th) - 1, 2):
        # corners counter-clockwise: on R left to right (angle grows to the right below the centre), then R - t
        n = [ring[(0, k)], ring[(0, k + 2)], ring[(2, k + 2)], ring[(2, k)],
             ring[(0, k + 1)], ring[(1, k + 2)], ring[(2, k + 1)], ring[(1, k)]]
        e += 1
        cyl.append(e)
        lines.append(f"{e}, " + ", ".join(map(str, n)))
    bottom = [num[(i, 0)] for i in range(len(gx)) if (i, 0) in num]
    symm = [num[(0, j)] for j in range(len(gy)) if (0, j) in num]

    def nset(name, ids):
        return [f"*NSET, NSET={name}", *[", ".join(map(str, ids[k:k + 12])) for k in range(0, len(ids), 12)]]

    lines += nset("NBOTTOM", bottom) + nset("NSYMM", symm)
    lines += ["*SURFACE, NAME=SSLAVE, TYPE=ELEMENT", *[f"{el}, S3" for el in top_elems],
              "*SURFACE, NAME=SMASTER, TYPE=ELEMENT", *[f"{el}, S1" for el in cyl],
              "*MATERIAL, NAME=STEEL", "*ELASTIC", f"{E!r}, {NU!r}",
              "*SOLID SECTION, ELSET=EBLOCK, MATERIAL=STEEL", "1.",
              "*SOLID SECTION, ELSET=ECYL, MATERIAL=STEEL", "1.",
              f"*RIGID BODY, NSET=NCYL, REF NODE={ref}, ROT NODE={rot}",
              "*SURFACE INTERACTION, NAME=FRICTIONLESS", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
              f"{kappa * E / h:.13g}, 0.",
              "*CONTACT PAIR, INTERACTION=FRICTIONLESS, TYPE=SURFACE TO SURFACE", "SSLAVE, SMASTER",
              "*BOUNDARY", "NBOTTOM, 1, 2, 0.", "NSYMM, 1, 1, 0.", f"{rot}, 1, 3, 0.",
              "*STEP, INC=100", "*STATIC", "0.2, 1., 1e-5, 0.25",
              "*BOUNDARY", f"{ref}, 1, 1, 0.", f"{ref}, 2, 2, {-d:.13g}",
              "*NODE FILE", "U, RF", "*CONTACT FILE", "CSTR",
              "*NODE PRINT, NSET=NBOTTOM, TOTALS=ONLY", "RF", "*END STEP", ""]
    return "\n".join(lines)
