"""An independent CalculiX model of the ``patch_test`` case (two elastic blocks), written without the exporter.

It shares nothing with :mod:`workbench.external.inp`, :mod:`workbench.external.benchmarks` or the case meshes (no
gmsh): the numbers are the case's (a lower block 1 x 1 mm, E = 200 GPa, nu = 0.3; an upper block 1 x 0.5 mm, E =
70 GPa, nu = 0.25; the upper block's top pressed down by 0.001 mm) typed in here, and the deck is built from scratch:

* each block a structured mesh of 8-node quadrilaterals (``CPE8``, plane strain, thickness 1 mm), the lower one
  ``n`` elements across, the upper one ``round(n / 1.4)`` (the interface nodes do not match);
* rollers: the lower block's bottom u_y = 0, the x = 0 edges of both blocks u_x = 0; the upper block's top u_y = -d
  (u_x free: it slides); the x = 1 mm sides free;
* frictionless surface-to-surface penalty contact (slope ``kappa E_upper / h``), slave the lower block's top,
  master the upper block's bottom; one increment (a flat interface: the contact area does not change);
* output: ``*NODE FILE U, RF`` (DISP, FORC) and ``*CONTACT FILE CSTR`` (CONTACT: CPRESS).

The exact solution is a uniform pressure ``p = d / (H_l (1 - nu_l^2) / E_l + H_u (1 - nu_u^2) / E_u)`` (each block in
uniaxial plane-strain compression, the interface slipping), ``P = p W``. Units: mm, N, MPa.
"""

from __future__ import annotations

from typing import NamedTuple

__all__ = ["WIDTH", "H_LOWER", "H_UPPER", "LOWER", "UPPER", "D", "p_exact", "Deck", "deck"]

WIDTH, H_LOWER, H_UPPER = 1.0, 1.0, 0.5
LOWER, UPPER = (200000.0, 0.3), (70000.0, 0.25)
D = 0.001


def p_exact(d: float = D) -> float:
    """The uniform pressure (MPa) at the top displacement d (mm)."""
    return d / (H_LOWER * (1 - LOWER[1] ** 2) / LOWER[0] + H_UPPER * (1 - UPPER[1] ** 2) / UPPER[0])


class Deck(NamedTuple):
    """The deck's text, the lower block's top nodes (left to right) and its bottom nodes."""

    text: str
    top: list[int]
    bottom: list[int]


def _block(x0: float, y0: float, width: float, height: float, nx: int, ny: int, first: int):
    """Nodes ``{(i, j): (number, x, y)}`` of a structured CPE8 grid (i, j on the half-step grid) and its elements
    (counter-clockwise corners, then the mid-edge nodes)."""
    nodes, k = {}, first
    for j in range(2 * ny + 1):
        for i in range(2 * nx + 1):
            if i % 2 and j % 2:
                continue
            nodes[(i, j)] = (k, x0 + width * i / (2 * nx), y0 + height * j / (2 * ny))
            k += 1
    elems = []
    for jj in range(ny):
        for ii in range(nx):
            i, j = 2 * ii, 2 * jj
            elems.append([nodes[c][0] for c in ((i, j), (i + 2, j), (i + 2, j + 2), (i, j + 2), (i + 1, j),
                                                (i + 2, j + 1), (i + 1, j + 2), (i, j + 1))])
    return nodes, elems


def deck(*, n: int = 7, d: float = D, kappa: float = 50.0) -> Deck:
    """The ``.inp`` of the independent patch test with ``n`` lower elements across (mm, MPa)."""
    nu_ = max(2, round(n / 1.4))
    lower, el_l = _block(0.0, -H_LOWER, WIDTH, H_LOWER, n, n, 1)
    upper, el_u = _block(0.0, 0.0, WIDTH, H_UPPER, nu_, max(2, round(nu_ * H_UPPER / WIDTH)), len(lower) + 1)
    ny_l = n
    ny_u = max(2, round(nu_ * H_UPPER / WIDTH))
    lines = ["*HEADING", "independent patch test (tests/ccx_independent_patch.py)", "*NODE, NSET=NALL"]
    lines += [f"{k}, {x:.13g}, {y:.13g}" for k, x, y in list(lower.values()) + list(upper.values())]
    lines.append("*ELEMENT, TYPE=CPE8, ELSET=ELOWER")
    lines += [f"{e + 1}, " + ", ".join(map(str, row)) for e, row in enumerate(el_l)]
    lines.append("*ELEMENT, TYPE=CPE8, ELSET=EUPPER")
    lines += [f"{len(el_l) + e + 1}, " + ", ".join(map(str, row)) for e, row in enumerate(el_u)]
    slave = [e + 1 for e in range(len(el_l)) if e // n == ny_l - 1]  # the top row: face S3 (nodes 3-4) on y = 0
    master = [len(el_l) + e + 1 for e in range(len(el_u)) if e // nu_ == 0]  # the bottom row: face S1 on y = 0
    top = [lower[(i, 2 * ny_l)][0] for i in range(2 * n + 1)]
    bottom = [lower[(i, 0)][0] for i in range(2 * n + 1)]
    symm = [v[0] for (i, _j), v in list(lower.items()) + list(upper.items()) if i == 0]
    driven = [upper[(i, 2 * ny_u)][0] for i in range(2 * nu_ + 1)]

    def nset(name, ids):
        return [f"*NSET, NSET={name}", *[", ".join(map(str, ids[k:k + 12])) for k in range(0, len(ids), 12)]]

    lines += nset("NBOTTOM", bottom) + nset("NSYMM", symm) + nset("NTOP", driven)
    h = WIDTH / n
    lines += ["*SURFACE, NAME=SSLAVE, TYPE=ELEMENT", *[f"{e}, S3" for e in slave],
              "*SURFACE, NAME=SMASTER, TYPE=ELEMENT", *[f"{e}, S1" for e in master],
              "*MATERIAL, NAME=MLOWER", "*ELASTIC", f"{LOWER[0]!r}, {LOWER[1]!r}",
              "*MATERIAL, NAME=MUPPER", "*ELASTIC", f"{UPPER[0]!r}, {UPPER[1]!r}",
              "*SOLID SECTION, ELSET=ELOWER, MATERIAL=MLOWER", "1.",
              "*SOLID SECTION, ELSET=EUPPER, MATERIAL=MUPPER", "1.",
              "*SURFACE INTERACTION, NAME=FRICTIONLESS", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
              f"{kappa * UPPER[0] / h:.13g}, 0.",
              "*CONTACT PAIR, INTERACTION=FRICTIONLESS, TYPE=SURFACE TO SURFACE", "SSLAVE, SMASTER",
              "*BOUNDARY", "NBOTTOM, 2, 2, 0.", "NSYMM, 1, 1, 0.",
              "*STEP, INC=100", "*STATIC", "1., 1., 1e-6, 1.", "*BOUNDARY", f"NTOP, 2, 2, {-d:.13g}",
              "*NODE FILE", "U, RF", "*CONTACT FILE", "CSTR", "*END STEP", ""]
    return Deck("\n".join(lines), top, bottom)

