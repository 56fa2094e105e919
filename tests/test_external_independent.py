"""``workbench score`` on a CalculiX result the workbench did not write (issue 26, acceptance "independent .frd").

The model is ``tests/ccx_independent.py``: the hertz_cylinder scene built from scratch (structured CPE8 quads,
a ``*RIGID BODY`` cylinder, frictionless surface-to-surface penalty contact, displacement control), sharing no
code with ``workbench export``. ccx runs it here (about 20 s); the test skips, naming the reason, where ccx is
missing. The .frd is then read twice: by ``workbench score --format frd`` and by the small parser below, which
shares no code with ``workbench.external.frd``.

Requirements:
* ``score``'s p_max is the largest nodal CPRESS of the file to 1e-9 (``--configuration current``: CPRESS as
  written), and the largest CPRESS times the surface stretch d(X + u1)/dX of its node, by central differences
  here, in the default reference configuration;
* its load (the pressure integral) is the trapezoid integral of CPRESS over X + u1 done here (1e-9), agrees to
  1e-3 with Simpson's rule on the quadratic faces, and to 5e-3 with twice the vertical reaction of the clamped
  bottom (the .frd's FORC block, a half model; measured +0.22 %: CalculiX's nodal CPRESS has a tail past the
  contact edge on quadratic faces, so its integral is not the contact force to better than that);
* its half-width agrees to 1e-3 with the edge computed here from the nodal CPRESS (the square-root edge model:
  CPRESS^2 linear through the two outermost loaded nodes, extrapolated to zero) and its moment half-width with
  2 sqrt(M2/M0) integrated here.
"""

from __future__ import annotations

import json
import math
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from workbench.external.score import main as score_main

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ccx_independent as model  # noqa: E402

CCX = shutil.which("ccx")
pytestmark = pytest.mark.skipif(CCX is None, reason="ccx (CalculiX, Debian calculix-ccx) is not installed: "
                                                    "`make external` installs it")
H_CONTACT = 0.05  # mm = a/10, the case's CI level
APPROACH = 0.058  # mm: about the workbench FEM's approach at the case's target load (d = 0.05798 mm)


def _parse(path: Path) -> tuple[dict, dict]:
    """Node coordinates {id: (x, y)} and the LAST block of every result name {name: {id: [values]}} of an
    ASCII .frd (short format: I10 node number after `` -1``, then 12-character fields)."""
    coords, blocks = {}, {}
    name, cur = None, None
    in_nodes = False
    for line in path.read_text().splitlines():
        if line.startswith("    2C"):
            in_nodes = True
        elif line.startswith(" -4"):
            name, cur = line.split()[1], {}
        elif line.startswith(" -1") and (in_nodes or cur is not None):  # not the element block (3C)
            node = int(line[3:13])
            vals = [float(line[13 + 12 * k:25 + 12 * k]) for k in range((len(line) - 13) // 12)]
            if in_nodes:
                coords[node] = (vals[0], vals[1])
            elif cur is not None:
                cur[node] = vals
        elif line.startswith(" -3"):
            if cur is not None:
                blocks[name] = cur
            in_nodes, name, cur = False, None, None
    return coords, blocks


@pytest.fixture(scope="module")
def frd(tmp_path_factory) -> Path:
    work = tmp_path_factory.mktemp("independent")
    (work / "independent.inp").write_text(model.deck(h=H_CONTACT, d=APPROACH))
    proc = subprocess.run([CCX, "-i", "independent"], cwd=work, capture_output=True, text=True, timeout=900,
                          env={"OMP_NUM_THREADS": "1", "PATH": "/usr/bin:/bin"})
    assert proc.returncode == 0 and "*ERROR" not in proc.stdout, proc.stdout[-2000:]
    return work / "independent.frd"


@pytest.fixture(scope="module")
def hand(frd) -> dict:
    """Everything computed here from the file alone (mm, N/mm, MPa; full-body values of the half model)."""
    coords, blocks = _parse(frd)
    cpress = {n: v[3] for n, v in blocks["CONTACT"].items()}  # COPEN, CSLIP1, CSLIP2, CPRESS, ...
    top = sorted((n for n, (_x, y) in coords.items() if y == 0.0 and n in blocks["DISP"]),
                 key=lambda n: coords[n][0])
    X = np.array([coords[n][0] for n in top])
    u1 = np.array([blocks["DISP"][n][0] for n in top])
    p = np.array([cpress.get(n, 0.0) for n in top])
    x = X + u1
    # stretch d(X + u1)/dX by central differences (one-sided at the ends)
    stretch = np.empty_like(X)
    stretch[1:-1] = (x[2:] - x[:-2]) / (X[2:] - X[:-2])
    stretch[0] = (x[1] - x[0]) / (X[1] - X[0])
    stretch[-1] = (x[-1] - x[-2]) / (X[-1] - X[-2])
    bottom = [n for n, (_x, y) in coords.items() if abs(y + model.HEIGHT) < 1e-9]
    reaction = 2.0 * sum(blocks["FORC"][n][1] for n in bottom)

    def edge(pos, pres):
        k = int(np.flatnonzero(pres > 0)[-1])  # outermost loaded node
        q1, q2 = pres[k], pres[k - 1]
        return pos[k] + (pos[k] - pos[k - 1]) * q1**2 / (q2**2 - q1**2)

    def moment(pos, pres):  # full body: mirror the half about x = 0 (node at 0 once)
        xs = np.concatenate([-pos[:0:-1], pos])
        ps = np.concatenate([pres[:0:-1], pres])
        m0 = sum(0.5 * (ps[i] + ps[i + 1]) * (xs[i + 1] - xs[i]) for i in range(len(xs) - 1))
        f2 = ps * xs**2
        m2 = sum(0.5 * (f2[i] + f2[i + 1]) * (xs[i + 1] - xs[i]) for i in range(len(xs) - 1))
        return m0, 2.0 * math.sqrt(m2 / m0)

    pref = p * stretch
    # Simpson's rule on each quadratic face (corner, midside, corner) over X + u1, mirrored: 2 x the half
    simpson = 2.0 * sum((x[i + 2] - x[i]) / 6.0 * (p[i] + 4.0 * p[i + 1] + p[i + 2]) for i in range(0, len(x) - 2, 2))
    return {"cpress_max": max(cpress.values()), "pref_max": float(pref.max()), "reaction": reaction,
            "P_simpson": simpson,
            "P_current": moment(x, p)[0], "P_reference": moment(X, pref)[0],
            "edge_current": edge(x, p), "edge_reference": edge(X, pref),
            "moment_current": moment(x, p)[1], "moment_reference": moment(X, pref)[1], "nodes": len(top)}


def _score(frd: Path, out: Path, *extra: str) -> dict:
    assert score_main(["hertz_cylinder", str(frd), "--format", "frd", "--out", str(out), *extra]) == 0
    return json.loads((out / "score_hertz_cylinder" / "score.json").read_text())["levels"][0]


def test_independent_model_is_a_sensible_hertz_contact(hand):
    assert hand["nodes"] > 50
    assert 4000 < hand["reaction"] < 5100  # near the case's target load 4531 N/mm
    assert 0.48 < hand["moment_current"] < 0.53 and 5000 < hand["cpress_max"] < 6500
    # CalculiX's nodal CPRESS on quadratic faces has a tail past the edge (measured at h = a/10: 690, 288, 195 MPa
    # at x = 0.50, 0.525, 0.55 mm, 0 from 0.575): the edge fit lands beyond a (0.566 mm)
    assert 0.5 < hand["edge_current"] < 0.6


def test_score_current_p_max_is_the_largest_cpress(frd, hand, tmp_path):
    lv = _score(frd, tmp_path, "--configuration", "current")
    assert lv["half_model"] and lv["configuration"] == "current"
    assert lv["p_max"] == pytest.approx(hand["cpress_max"], rel=1e-9)
    assert lv["P"] == pytest.approx(hand["P_current"], rel=1e-9)  # the same trapezoid over X + u1
    assert lv["P"] == pytest.approx(hand["P_simpson"], rel=1e-3)  # another quadrature of the quadratic faces
    # the nodal CPRESS integral against the load the clamped bottom carries: measured +0.22 % (the CPRESS tail
    # past the edge, above); external ccx takes the load from the reaction for that reason
    assert lv["P"] == pytest.approx(hand["reaction"], rel=5e-3)
    assert lv["half_width"] == pytest.approx(hand["edge_current"], rel=1e-3)
    assert lv["half_width_moment"] == pytest.approx(hand["moment_current"], rel=1e-3)


def test_score_reference_p_max_is_cpress_times_stretch(frd, hand, tmp_path):
    lv = _score(frd, tmp_path)
    assert lv["configuration"] == "reference"
    assert lv["p_max"] == pytest.approx(hand["pref_max"], rel=1e-9)
    assert 0.98 < hand["pref_max"] / hand["cpress_max"] < 0.995  # the surface is compressed by ~1.2 %
    assert lv["P"] == pytest.approx(hand["P_reference"], rel=1e-9)
    assert lv["P"] == pytest.approx(hand["P_simpson"], rel=1e-3)
    assert lv["P"] == pytest.approx(hand["reaction"], rel=5e-3)
    assert lv["half_width"] == pytest.approx(hand["edge_reference"], rel=1e-3)
    assert lv["half_width_moment"] == pytest.approx(hand["moment_reference"], rel=1e-3)
