"""A user's wide contact (issue 13, acceptance): a copy of ``cases/hertz_cylinder.toml`` with R = 4 mm,
E = 100 MPa, nu = 0.3 and P = 10 N/mm (a/R = 0.17; two identical cylinders R = 8 mm, E = 200 MPa run as the rigid
equivalent) passes against the theory that applies, the exact circle, and its report says how far Hertz is off.

Measured (h_c = a/20, the case's own block): FEM half-width 0.676836 mm, peak 9.37286 MPa; exact circle
0.677084 mm and 9.36833 MPa (errors 0.037 % and 0.048 %); Hertz 0.680778 mm and 9.35135 MPa (the FEM is 0.58 % off
Hertz in the half-width: the parabola idealisation, not the solver).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from workbench.cli import main

ROOT = Path(__file__).resolve().parents[1]


def wide_case_text(*, P: float = 10.0, name: str = "wide_contact") -> str:
    """hertz_cylinder.toml with the user's radius, modulus and load (P instead of the target half-width)."""
    text = (ROOT / "cases" / "hertz_cylinder.toml").read_text()
    edits = [(r'name = "hertz_cylinder"', f'name = "{name}"'), (r"\nradius = 10\.0", "\nradius = 4.0"),
             (r"\nE = 210000\.0", "\nE = 100.0"), (r"\nhalf_width = 0\.5", f"\nP = {P!r}")]
    for old, new in edits:
        text, n = re.subn(old, new, text, count=1)
        assert n == 1, old
    return text


def test_wide_contact_passes_against_the_exact_circle(tmp_path):
    case = tmp_path / "wide_contact.toml"
    case.write_text(wide_case_text())
    out = tmp_path / "results"
    assert main(["run", str(case), "--h-contact", "0.05", "--out", str(out)]) == 0
    folder = out / "wide_contact"
    m = json.loads((folder / "metrics.json").read_text())
    (run,) = m["runs"]
    exact = run["analytic"]["exact_circle"]
    assert 0.1 <= exact["half_width"] / exact["R"] <= 0.25
    assert abs(run["patch_half_width"] / exact["half_width"] - 1) <= 1e-3   # acceptance: 0.1 %
    assert abs(run["p_max"] / exact["p0"] - 1) <= 2e-3                      # acceptance: 0.2 %
    assert m["pass"], m["checks"]
    assert m["checked_errors"]["half_width"] == "half_width_vs_exact_circle"
    assert m["checked_errors"]["p_max"] == "p_max_vs_exact_circle"
    # against Hertz the same FEM is more than 0.5 % off in the half-width: it would have failed without a reason
    assert m["errors"]["half_width"] > 5e-3
    assert abs(m["analytic"]["hertz_vs_exact_circle_half_width"] - 0.005456) <= 1e-5
    report = (folder / "report.md").read_text()
    assert "Hertz is 0.55 % off in the half-width" in report and "the parabola idealisation" in report
    assert "| half_width | half_width_vs_exact_circle |" in report
    assert "docs/models.md" in report and "traction = halfplane" in report and "material model = linear" in report


# Issue 22: the copy passes with its bands (the make-run budget: three grids, three blocks, the tight re-solve).
# P (N/mm) of the exact circle's a/R with R = 4 mm, E = 100 MPa, nu = 0.3: E* R [K(k) - E(k)].
WIDE = {0.17: 10.0, 0.25: 22.103282, 0.01: 0.034524}


@pytest.mark.parametrize("a_over_R", [0.17, 0.25])
def test_wide_contact_passes_its_bands(tmp_path, a_over_R):
    """Measured (a/R = 0.17): p_max crosses the exact circle between h_c = a/40 and a/80 (1.0018154, 1.0018139
    around 1.0018153: "crossing", band from the spread 2.2e-5, Hertz 1.8e-3 away); the moment half-width has
    order 5.0 on the three grids and 1.1 from a/80 to a/160 (measured once), so its band is at order 2 (Fs 3):
    5.1e-6 around 0.9963807, the exact circle 1.8e-6 away; the tight re-solve moves nothing (iterative 1e-12)."""
    case = tmp_path / "wide.toml"
    case.write_text(wide_case_text(P=WIDE[a_over_R], name="wide"))
    out = tmp_path / "results"
    assert main(["run", str(case), "--out", str(out)]) == 0
    m = json.loads((out / "wide" / "metrics.json").read_text())
    exact = m["runs"][0]["analytic"]["exact_circle"]
    assert abs(exact["half_width"] / exact["R"] - a_over_R) < 1e-3
    assert m["pass"], {k: c["reason"] for k, c in m["band_checks"].items() if not c["passed"]}
    assert len(m["band_checks"]) == 6 and all(c["passed"] for c in m["band_checks"].values())
    for q in ("p_max", "half_width", "half_width_moment"):
        r = m["error_budget"][q]
        assert r["theory_in_band"] and not r["alt_in_band"], (q, r)   # Hertz is told apart at these a/R
        assert r["iterative"] is not None and r["iterative"] < 1e-8, (q, r)
        assert r["uncertainty"] == pytest.approx(r["gci"] + r["truncation"] + r["iterative"] + r["roundoff"])
    mom = m["error_budget"]["half_width_moment"]
    assert mom["uncertainty"] < 2e-5 and mom["error_vs_theory"] < 5e-6, mom   # still a tight band
