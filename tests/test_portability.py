"""Another machine, emulated (issue 22): rerun a case under what a different machine changes; no verdict may
change and every number must stay within its class tolerance (``workbench.pipeline.portability``,
``make emulate`` runs every case under every perturbation)."""

from __future__ import annotations

import json
from pathlib import Path

from workbench.pipeline.portability import PERTURBATIONS, CaseRun, compare_runs, main, table


def test_hertz_cylinder_under_another_mumps_ordering(tmp_path, capsys):
    code = main(["--cases", "hertz_cylinder", "--perturb", "mumps_ordering", "--out", str(tmp_path)])
    out = capsys.readouterr().out
    assert code == 0, out
    # the ordering was really applied: MUMPS reports the ordering it used after analysis
    assert "MUMPS INFOG(7) = 0" in out and "NOT applied" not in out
    row = next(ln for ln in out.splitlines() if ln.startswith("| mumps_ordering | hertz_cylinder |"))
    cells = [c.strip() for c in row.strip("|").split("|")]
    assert cells[2] == "same dofs" and cells[3] == "same"
    ratios = [float(c) for c in cells[4:] if c != "-"]
    assert ratios and all(r <= 1 for r in ratios), row
    assert (tmp_path / "emulate.md").read_text().count("| mumps_ordering | hertz_cylinder |") == 1


def _case(root: Path, *, passed: bool, p_max: float) -> Path:
    (root / "c").mkdir(parents=True)
    m = {"case": "c", "P": 1.0, "pass": passed, "errors": {"load_balance": 1e-13, "p_max": 1e-4},  # a judged peak
         "runs": [{"label": "base", "p_max": p_max, "ndofs": 100}]}
    (root / "c" / "metrics.json").write_text(json.dumps(m))
    return root


def test_a_changed_verdict_or_a_number_beyond_its_class_fails(tmp_path):
    ref = _case(tmp_path / "ref", passed=True, p_max=100.0)
    flipped = _case(tmp_path / "flip", passed=False, p_max=100.0)
    oc = compare_runs("x", ref, [CaseRun("c", 0)], flipped, [CaseRun("c", 1)])
    assert not oc.ok and any("c/pass" in v for v in oc.verdict_changes) and any("exit 0 -> 1" in v
                                                                               for v in oc.verdict_changes)
    moved = _case(tmp_path / "moved", passed=True, p_max=101.0)  # 1 % on a peak: beyond the foreign 1.3e-3
    oc = compare_runs("y", ref, [CaseRun("c", 0)], moved, [CaseRun("c", 0)])
    assert not oc.ok and not oc.verdict_changes
    text = table([oc])
    assert "| y | c | same dofs | same |" in text and "✗" in text and "c/runs/base/p_max [physics]" in text
    assert set(PERTURBATIONS) >= {"mesh", "mumps_ordering", "numpy_baseline"}
    crashed = compare_runs("z", ref, [CaseRun("c", 2)], ref, [CaseRun("c", 2)])  # same exit, but no run at all
    assert not crashed.ok and "failed (exit 2" in crashed.verdict_changes[0]


def test_a_peak_no_theory_judges_holds_its_own_foreign_spread():
    """A case without ``errors/p_max`` (a wedge gap's log-singular apex, the node-to-segment patch test) does not
    judge its peak: another valid mesh moved halfplanes_wedge_rigid_limit's by 7.47e-3 (make emulate, issue 34)."""
    from workbench.pipeline.number_classes import FOREIGN, compare_portable

    old, new = {"w/runs/small/p_max": 370720.3}, {"w/runs/small/p_max": 367951.6}
    (mv,) = compare_portable(new, old)
    assert mv.ok and mv.tolerance == FOREIGN["unjudged_peak"] and mv.note == "mesh differs"
    (mv,) = compare_portable({**new, "w/errors/p_max": 1e-3}, {**old, "w/errors/p_max": 1e-3},
                             keys=["w/runs/small/p_max"])
    assert not mv.ok and mv.tolerance == FOREIGN["peak"]  # a judged peak keeps the tight kind
