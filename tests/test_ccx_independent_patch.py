"""``workbench score patch_test`` on a CalculiX result the workbench did not write (issue 36, acceptance
"independent deck for a two-body case").

The model is ``tests/ccx_independent_patch.py``: the patch test's two blocks built from scratch (structured CPE8
quads, 7 and 5 elements across: non-matching, frictionless surface-to-surface penalty contact, the upper block's top
pressed down by 0.001 mm), sharing no code with ``workbench export``. ccx runs it here (about 1 s); the test skips,
naming the reason, where ccx is missing. The .frd is read by the small parser of ``tests/ccx_hand.py`` (no code of
:mod:`workbench.external.frd`) and written as a csv in the result schema: the deck's one increment starts from the
reference geometry, from which CalculiX builds its contact elements, so CPRESS is a force per reference length here
(checked: the step took one increment); the load is the lower block's bottom reaction.

Requirements: ``score``'s load is the file's (1e-12), its pressure integral the trapezoid rule computed here (1e-9),
its uniformity max |p / (P/W) - 1| the one computed here (1e-9); and the model passes the patch test (uniform to
1e-5; measured 5.6e-7 on the exported meshes in one increment), its load within 0.5 % of the exact P = p W (the
penalty's compliance: 0.36 % at h = W/7 with kappa = 50).
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from workbench.external.score import main as score_main

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ccx_hand as hand  # noqa: E402
import ccx_independent_patch as model  # noqa: E402

CCX = shutil.which("ccx")
pytestmark = pytest.mark.skipif(CCX is None, reason="ccx (CalculiX, Debian calculix-ccx) is not installed: "
                                                    "`make external` installs it")


@pytest.fixture(scope="module")
def done(tmp_path_factory) -> dict:
    work = tmp_path_factory.mktemp("independent_patch")
    dk = model.deck(n=7)
    (work / "patch.inp").write_text(dk.text)
    proc = subprocess.run([CCX, "-i", "patch"], cwd=work, capture_output=True, text=True, timeout=600,
                          env={"OMP_NUM_THREADS": "1", "PATH": "/usr/bin:/bin"})
    assert proc.returncode == 0 and "*ERROR" not in proc.stdout, proc.stdout[-2000:]
    increments = [ln for ln in (work / "patch.sta").read_text().splitlines()[2:] if ln.strip()]
    coords, blocks = hand.parse_frd(work / "patch.frd")
    X = np.array([coords[n][0] for n in dk.top])
    p = np.array([blocks["CONTACT"].get(n, [0.0] * 4)[3] for n in dk.top])  # CPRESS, per reference length here
    P = sum(blocks["FORC"][n][1] for n in dk.bottom)
    csv = hand.write_csv(work / "patch.csv", [{"x_mm": float(x), "p_MPa": float(v), "P_N_per_mm": P,
                                               "h_mm": model.WIDTH / 7, "run": "mortar", "step": 0,
                                               "body": "lower_block"} for x, v in zip(X, p, strict=True)])
    return {"csv": csv, "P": P, "increments": len(increments), "P_integral": hand.trapezoid(X, p),
            "uniformity": float(np.max(np.abs(p / (P / model.WIDTH) - 1.0)))}


def test_independent_patch_test_passes(done):
    assert done["increments"] == 1  # CPRESS per the reference geometry's area
    assert done["uniformity"] < 1e-5
    assert done["P"] == pytest.approx(model.p_exact() * model.WIDTH, rel=5e-3)


def test_score_equals_the_hand_computation(done, tmp_path):
    assert score_main(["patch_test", str(done["csv"]), "--out", str(tmp_path)]) == 0
    score = json.loads((tmp_path / "score_patch_test" / "score.json").read_text())
    (lv,) = score["levels"]
    assert lv["body"] == "lower_block" and not lv["half_model"]
    assert lv["P"] == pytest.approx(done["P"], rel=1e-12)
    assert lv["P_integral"] == pytest.approx(done["P_integral"], rel=1e-9)
    assert lv["quantities"]["uniformity"] == pytest.approx(done["uniformity"], rel=1e-9, abs=1e-15)
