"""Band checks (issue 12, point 3): a tolerance that is the error budget's own band.

Requirement: ``[bands]`` of a case lists budget quantities whose band must contain their theory
(``contain_theory``) or exclude the alternative theory (``exclude_alt``); a row without a theory or a band, or
no row at all, fails the check and says why (nothing is dropped silently). A bad ``[bands]`` entry is rejected
with one line naming the field and the allowed values, exit code 2, nothing written.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from test_cases_validation import GOOD

from workbench.cli import main
from workbench.pipeline.bands import band_checks, band_rows

ROOT = Path(__file__).resolve().parents[1]


def _row(x, gci, theory, alt=None):
    r = {"fine": x, "extrapolated": x, "observed_order": 2.0, "gci": gci, "truncation": 0.0, "theory": theory,
         "theory_in_band": None if theory is None else abs(theory - x) <= gci * abs(x)}
    if alt is not None:
        r |= {"alt_theory": "first order", "alt_value": alt, "alt_in_band": abs(alt - x) <= gci * abs(x)}
    return r


BUDGET = {
    "b_over_b0_moment": _row(1.27240, 1e-4, 1.272402, alt=1.28868),   # converged in, first order out
    "b_over_b0": _row(1.16512, 5e-3, 1.164566, alt=1.16094),          # band too wide: first order in
    "p_max[coarse]": _row(1.0, 1e-6, 1.00001),                         # theory outside a tight band
    "step1 (d = 0.6 mm) load_symmetry": _row(1.0, 0.0, 1.0),
    "step1 (d = 0.6 mm) width_moment[0]": _row(0.9, 1e-3, None),
}


def test_rows_are_selected_by_quantity_variant_and_step():
    assert band_rows(BUDGET, "b_over_b0") == ["b_over_b0"]
    assert band_rows(BUDGET, "p_max") == ["p_max[coarse]"]
    assert band_rows(BUDGET, "load_symmetry") == ["step1 (d = 0.6 mm) load_symmetry"]
    assert band_rows(BUDGET, "width_moment") == ["step1 (d = 0.6 mm) width_moment[0]"]
    assert band_rows(BUDGET, "half_width") == []


def test_band_checks_pass_and_fail_on_the_band():
    c = band_checks({"contain_theory": ("b_over_b0_moment", "b_over_b0", "p_max", "load_symmetry"),
                     "exclude_alt": ("b_over_b0_moment", "b_over_b0")}, BUDGET)
    assert c["contain_theory:b_over_b0_moment"].passed
    assert c["exclude_alt:b_over_b0_moment"].passed            # the moment ratio tells first order apart
    assert c["contain_theory:b_over_b0"].passed
    # the zero-crossing ratio cannot tell them apart, and the theory is inside too: unresolved, not a failure
    # (issue 22), with the band it would need: |1.164566 - 1.16094| / 2 = 1.81e-3 against +-5.8e-3
    assert c["exclude_alt:b_over_b0"].passed and c["exclude_alt:b_over_b0"].reason == ""
    note = c["exclude_alt:b_over_b0"].unresolved["b_over_b0"]
    assert "unresolved" in note and "1.81e-03" in note and "5.83e-03" in note
    assert c["exclude_alt:b_over_b0_moment"].unresolved == {}
    assert not c["contain_theory:p_max"].passed
    assert "theory outside the band" in c["contain_theory:p_max"].reason
    assert c["contain_theory:load_symmetry"].passed


def test_missing_rows_theories_and_bands_fail_with_a_reason():
    undefined = dict(BUDGET, **{"half_width": _row(1.0, 1e-3, 1.0) | {"gci": None, "theory_in_band": None}})
    c = band_checks({"contain_theory": ("width_moment", "half_width_moment", "half_width"),
                     "exclude_alt": ("p_max",)}, undefined)
    assert not c["contain_theory:width_moment"].passed and "no theory" in c["contain_theory:width_moment"].reason
    assert not c["contain_theory:half_width_moment"].passed
    assert c["contain_theory:half_width_moment"].reason == "no budget row"
    assert not c["contain_theory:half_width"].passed and "band undefined" in c["contain_theory:half_width"].reason
    assert not c["exclude_alt:p_max"].passed and "no alternative" in c["exclude_alt:p_max"].reason


BUDGET_BLOCK = "[discretisation]\nbudget_levels = [0.2, 0.1, 0.05]\nbudget_widths = [640.0, 2560.0, 10000.0]\n"
BAD = {
    "unknown_kind": BUDGET_BLOCK + '[bands]\ncontains = ["p_max"]\n',
    "not_a_list": BUDGET_BLOCK + '[bands]\ncontain_theory = "p_max"\n',
    "empty_list": BUDGET_BLOCK + "[bands]\ncontain_theory = []\n",
    "not_strings": BUDGET_BLOCK + "[bands]\ncontain_theory = [1.0]\n",
    "repeated": BUDGET_BLOCK + '[bands]\ncontain_theory = ["p_max", "p_max"]\n',
    "unknown_quantity": BUDGET_BLOCK + '[bands]\ncontain_theory = ["load_symmetry"]\n',
    "without_budget": '[bands]\ncontain_theory = ["p_max"]\n',
    "not_a_table": 'bands = 1.0\n',
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_bands_exit_2_one_line(name, tmp_path, capsys):
    p = tmp_path / f"{name}.toml"
    text = GOOD + BAD[name] if name != "not_a_table" else BAD[name] + GOOD
    p.write_text(text)
    out = tmp_path / "results"
    code = main(["run", str(p), "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2, (name, err)
    assert len(err.splitlines()) == 1 and "bands" in err, err
    assert not out.exists() or not any(out.iterdir())


def test_concave_quantities_are_refused_in_a_block_scene_and_accepted_in_a_concave_one(tmp_path):
    from cases import load_case

    text = (ROOT / "cases" / "concave_symmetric.toml").read_text()
    p = tmp_path / "c.toml"
    p.write_text(text.split("[bands]")[0] + '[bands]\ncontain_theory = ["load_symmetry", "first_contact_width"]\n')
    assert load_case(p).bands == {"contain_theory": ("load_symmetry", "first_contact_width")}


def test_exclude_theory_and_patch_index_selection():
    budget = {"step1 (d = 0.46 mm) first_contact_width[0]": _row(0.344, 1e-3, 0.391),
              "step2 (d = 0.47 mm) first_contact_width[1]": _row(0.14370, 1e-3, 0.14374)}
    assert band_rows(budget, "first_contact_width[1]") == ["step2 (d = 0.47 mm) first_contact_width[1]"]
    c = band_checks({"exclude_theory": ("first_contact_width[0]",), "contain_theory": ("first_contact_width[1]",)},
                    budget)
    assert c["exclude_theory:first_contact_width[0]"].passed
    assert c["contain_theory:first_contact_width[1]"].passed
    c = band_checks({"exclude_theory": ("first_contact_width",)}, budget)
    assert not c["exclude_theory:first_contact_width"].passed
    assert "theory inside the band" in c["exclude_theory:first_contact_width"].reason


def test_exclusion_fails_only_when_the_alternative_is_inside_and_the_theory_is_not():
    """Issue 22: alternative inside and theory outside the band is the one failing exclusion."""
    budget = {"p_max": _row(1.0001544, 2.4e-6, 1.0001563, alt=1.0001560)}  # alt 1.6e-6 off, theory 1.9e-6
    budget["p_max"]["theory_in_band"] = False   # as if the theory were outside
    c = band_checks({"exclude_alt": ("p_max",)}, budget)["exclude_alt:p_max"]
    assert not c.passed and "alternative theory inside the band" in c.reason and c.unresolved == {}
    budget["p_max"]["theory_in_band"] = True
    c = band_checks({"exclude_alt": ("p_max",)}, budget)["exclude_alt:p_max"]
    assert c.passed and "unresolved" in c.unresolved["p_max"]


def test_unresolved_names_the_grid_that_would_resolve_it():
    """With an order the note predicts h_c: band 4e-4 at h_c = 0.0125, order 2, needed 1e-4 -> h_c = 0.00625."""
    r = _row(1.0, 4e-4, 1.0001, alt=0.9999) | {"uncertainty": 4e-4, "band_order": 2.0,
                                               "by_h": {"0.0125": 1.0, "0.025": 1.0, "0.05": 1.0}}
    r["theory_in_band"] = r["alt_in_band"] = True
    c = band_checks({"exclude_alt": ("q",)}, {"q": r})["exclude_alt:q"]
    assert c.passed and "h_c ~ 0.00625 at order 2.00" in c.unresolved["q"], c.unresolved
