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

from workbench.cli import main

ROOT = Path(__file__).resolve().parents[1]


def wide_case_text() -> str:
    """hertz_cylinder.toml with the user's radius, modulus and load (P instead of the target half-width)."""
    text = (ROOT / "cases" / "hertz_cylinder.toml").read_text()
    edits = [(r'name = "hertz_cylinder"', 'name = "wide_contact"'), (r"\nradius = 10\.0", "\nradius = 4.0"),
             (r"\nE = 210000\.0", "\nE = 100.0"), (r"\nhalf_width = 0\.5", "\nP = 10.0")]
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
