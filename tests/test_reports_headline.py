"""A case plot headlines the measure its verdict reads (issue 37): the convective panel of a halfplanes case
headlines the moment ratio b/b0 (checked at 0.2 %), not the edge ratio (5 %, unresolved at the CI grid), and its
residual panel is against the theory the case judges that run by. Tested on the text and the panel records,
not on pixels."""

from __future__ import annotations

import numpy as np

from workbench.reports.case_report import b_headline, judged_b_measure, judged_prediction, pressure_panels


def _halfplanes_metrics() -> dict:
    """The shape of ``halfplanes_beta_pos``'s metrics.json at CI level (values of issue 37)."""
    return {
        "case": "halfplanes_beta_pos",
        "analytic": {"runs": {"small": {"half_width": 1.0}, "convective": {"half_width": 1.0}},
                     "b_over_b0_fem": 0.9996, "b_over_b0_converged": 0.98099, "b_over_b0_first_order": 0.98176,
                     "b_over_b0_moment_fem": 0.97640, "b_over_b0_moment_converged": 0.97631,
                     "b_over_b0_moment_first_order": 0.97741},
        "tolerances": {"p_max": 0.005, "rms": 0.02, "b_over_b0": 0.05, "b_over_b0_moment": 0.002,
                       "rms_convective": 0.03},
        "errors": {"b_over_b0": 0.0190, "b_over_b0_moment": 9.2e-5, "rms_convective": 0.0099},
        "checks": {"b_over_b0": True, "b_over_b0_moment": True, "rms_convective": True},
        "checked_errors": {"rms": "rms"},
        "runs": [{"label": "small", "kinematics": "small"}, {"label": "convective", "kinematics": "convective"}],
    }


def _series(label: str, names: list[str]) -> dict:
    x = np.linspace(-1.5, 1.5, 7)
    return {"label": label, "x": x, "p": np.ones_like(x), "sigma_nn": None, "xlabel": "x", "xlim": (-1.5, 1.5),
            "predictions": {n: np.ones_like(x) for n in names}}


def test_the_halfplanes_headline_is_the_moment_ratio_it_is_judged_by():
    m = _halfplanes_metrics()
    assert judged_b_measure(m).check == "b_over_b0_moment"
    first, *rest = b_headline(m)
    assert first.startswith("judged by the moment ratio b/b0: FEM 0.97640 against converged theory 0.97631")
    assert "tolerance 2e-03 PASS" in first
    assert "edge" not in first and rest == [next(r for r in rest if r.startswith("also: edge ratio"))]


def test_the_convective_panel_marks_the_judged_measure_and_its_residual_is_against_the_converged_theory():
    m = _halfplanes_metrics()
    series = [_series("small", ["Hertz (at measured P, E*)"]),
              _series("convective", ["Hertz (at measured P, E*)", "Ciavarella-Hills (converged)"])]
    small, conv = pressure_panels(series, m)
    assert small["headline"] == [] and small["marks"] == [] and small["residual"] == "Hertz (at measured P, E*)"
    assert conv["headline"][0].startswith("judged by the moment ratio")
    assert conv["residual"] == "Ciavarella-Hills (converged)"
    labels = [label for label, _ in conv["marks"]]
    assert labels[0] == "moment ratio b/b0 FEM = 0.9764" and all(label.startswith("moment ratio") for label in labels)
    assert not any("0.9996" in label for label in labels)  # the unresolved edge ratio is no mark


def test_a_block_convective_case_with_edges_only_headlines_the_edges():
    m = {"analytic": {"runs": {"small": {"half_width": 2.5}}, "b_over_b0_fem": 1.0794,
                      "b_over_b0_converged": 1.0810, "b_over_b0_paper": 1.09},
         "tolerances": {"b_over_b0": 0.01}, "errors": {"b_over_b0": 1.5e-3}, "checks": {"b_over_b0": True},
         "runs": [{"label": "convective", "kinematics": "convective"}]}
    assert b_headline(m) == ["judged by the edge ratio b/b0: FEM 1.07940 against converged theory 1.08100 "
                             "(error 1.5e-03, tolerance 1e-02 PASS)"]
    assert b_headline({"analytic": {}}) == []


def test_the_residual_is_against_the_theory_the_checked_rms_names():
    m = {"checked_errors": {"rms": "rms_vs_exact_circle"}, "tolerances": {"rms": 0.01}, "runs": []}
    names = ["hertz (at measured P)", "exact circle (at measured P)"]
    assert judged_prediction("base", names, m) == "exact circle (at measured P)"
    assert judged_prediction("base", names, {"checked_errors": {"rms": "rms"}}) == "hertz (at measured P)"
    assert judged_prediction("base", [], m) is None


def test_each_convective_panel_heads_with_its_own_run():
    """Several convective runs (profile, pairing): each panel's headline and FEM edge mark give that run's own
    value (``b_over_b0_moment_fem_<convection>``); only the run whose value the check reads says "judged by" and
    carries the error and tolerance."""
    from workbench.reports.case_report import _b_marks

    an = {"b_over_b0_moment_fem": 0.97613, "b_over_b0_moment_fem_profile": 0.97613,
          "b_over_b0_moment_fem_pairing": 0.97409, "b_over_b0_moment_converged": 0.97631,
          "runs": {"small": {"half_width": 1.0}}}
    m = {"analytic": an, "tolerances": {"b_over_b0_moment": 2e-3}, "errors": {"b_over_b0_moment": 1.8e-4},
         "checks": {"b_over_b0_moment": True},
         "runs": [{"label": "small", "kinematics": "small"},
                  {"label": "profile", "kinematics": "convective", "convection": "profile"},
                  {"label": "pairing", "kinematics": "convective", "convection": "pairing"}]}
    assert b_headline(m, "profile") == ["judged by the moment ratio b/b0: FEM 0.97613 against converged theory "
                                        "0.97631 (error 1.8e-04, tolerance 2e-03 PASS)"]
    assert b_headline(m, "pairing") == ["moment ratio b/b0: FEM 0.97409 against converged theory 0.97631"]
    assert ("moment ratio b/b0 FEM = 0.97409", 0.97409) in _b_marks(m, "pairing")
