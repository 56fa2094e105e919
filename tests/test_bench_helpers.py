"""Fast checks of the benchmark helpers (workbench/studies/rates.py, bench.py, bench_report.py, config.py):
exponent fit, ladder selection, report text, the typed config.

No timing is asserted: the benchmark reports times, it does not test them.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from workbench.studies.bench_config import BenchConfig
from workbench.studies.bench_measure import LOG_EVENTS, first_reaching, rel_diff
from workbench.studies.bench_report import to_markdown
from workbench.studies.config import from_json, to_json
from workbench.studies.rates import ExponentFit, fit_exponent

RMS_TARGET = BenchConfig().rms_target

# An exact power law is fitted to round-off: the only error is floating point in polyfit on ~5 points,
# so 1e-10 on the exponent is ~1e5 eps of headroom.
EXACT = 1e-10


@pytest.mark.parametrize("k", [1.0, 1.3, 1.5])
def test_fit_exponent_recovers_exact_power_law(k):
    n = np.array([2.5e3, 1e4, 4e4, 1.6e5, 1e6])
    t = 3e-6 * n**k
    fit = fit_exponent(n, t)
    assert isinstance(fit, ExponentFit)
    assert abs(fit.exponent - k) < EXACT
    assert abs(fit.prefactor / 3e-6 - 1.0) < 1e-8  # exp of the intercept: a few ulps amplified by log(1e6)
    assert fit.n_points == 5 and fit.max_residual < EXACT


def test_fit_exponent_largest_sizes_only():
    # overhead-dominated small sizes (constant 1 s) then t ~ n: the last three give exponent ~1 exactly
    # only if the fit really ignores the first two points.
    n = np.array([1e2, 1e3, 1e4, 1e5, 1e6])
    t = np.array([1.0, 1.0, 1e-3 * 1e4, 1e-3 * 1e5, 1e-3 * 1e6])
    assert abs(fit_exponent(n, t, n_last=3).exponent - 1.0) < EXACT
    assert fit_exponent(n, t).exponent < 0.9  # all points: pulled down by the flat start


@pytest.mark.parametrize(
    ("n", "t", "msg"),
    [
        ([1e3], [1.0], "ndofs must hold"),
        ([1e4, 1e3], [1.0, 2.0], "strictly increasing"),
        ([1e3, 1e4], [1.0, 0.0], "err must be"),
    ],
)
def test_fit_exponent_rejects_bad_input(n, t, msg):
    with pytest.raises(ValueError, match=msg):
        fit_exponent(n, t)


def test_first_reaching_takes_the_first_row_in_ladder_order():
    rows = [{"rms": 0.02}, {"rms": math.nan}, {"rms": 0.004, "id": 2}, {"rms": 0.001, "id": 3}]
    assert first_reaching(rows)["id"] == 2  # not the most accurate one: the first (cheapest) that reaches
    assert first_reaching(rows, target=0.002)["id"] == 3
    assert first_reaching(rows[:2]) is None
    assert RMS_TARGET == 0.005  # the 0.5 %


def test_rel_diff():
    assert rel_diff(0.0, 0.0) == 0.0
    assert rel_diff(1.0, 1.0 + 1e-9) == pytest.approx(1e-9, rel=1e-6)
    assert rel_diff(-2.0, 2.0) == 2.0


def test_report_states_unmet_targets():
    lin = {
        "ndofs": 2568,
        "solve_s": 0.07,
        "linear_s": 0.01,
        "linear_resolve_s": 0.004,
        "linear_solves_equivalent": 7.0,
        "newton_iterations": [1, 1],
        "newton_per_step": 1.0,
        "events": {n: {"count": 1, "time_s": 0.0} for n in LOG_EVENTS},
    }
    text = to_markdown({"load_avg_start": (1.0, 1.0, 1.0), "cpu_count": 2, "linear": lin})
    assert "| contact solve <= 1.5 linear solves (default case) | 7 | NOT met |" in text


def test_quick_config_and_json_round_trip():
    """--quick keeps the published settings except the sizes; the config survives its JSON (the report reads
    it), and a bad section or scale family is refused."""
    import json

    full, quick = BenchConfig(), BenchConfig().quick()
    assert quick.baseline_ladder == full.baseline_ladder[:1] and quick.mpi_levels == (None,)
    assert quick.scale["graded"] == full.scale["graded"][:3] and quick.targets == full.targets
    assert from_json(BenchConfig, json.loads(json.dumps(to_json(quick)))) == quick
    with pytest.raises(ValueError, match="sections"):
        BenchConfig(sections=("nope",))
    with pytest.raises(ValueError, match="scale family"):
        BenchConfig(scale={"coarse": (0.5,)})


def test_report_reads_its_settings_from_the_json():
    """The targets come from the JSON's config: a looser linear-solve target turns the same row into 'met'."""
    lin = {"ndofs": 2568, "solve_s": 0.07, "linear_s": 0.01, "linear_resolve_s": 0.004,
           "linear_solves_equivalent": 7.0, "newton_iterations": [1, 1], "newton_per_step": 1.0,
           "events": {n: {"count": 1, "time_s": 0.0} for n in LOG_EVENTS}}
    cfg = to_json(BenchConfig(targets={**BenchConfig().targets, "linear_solves": 8.0}))
    text = to_markdown({"load_avg_start": (1.0, 1.0, 1.0), "cpu_count": 2, "linear": lin, "config": cfg})
    assert "| contact solve <= 8 linear solves (default case) | 7 | met |" in text


def test_the_report_does_not_import_the_study():
    """Reports read JSON only: bench_report and bench_plot import neither bench.py nor dolfinx."""
    import subprocess
    import sys

    code = ("import sys, workbench.studies.bench_report, workbench.studies.bench_plot; "
            "bad = [m for m in ('workbench.studies.bench', 'dolfinx') if m in sys.modules]; "
            "sys.exit(1 if bad else 0)")
    assert subprocess.run([sys.executable, "-c", code], timeout=120).returncode == 0


def _scale_row(ndofs, kind, lu, gamg, its, tri):
    return {"family": "graded", "h_over_a": 0.1, "ndofs": ndofs, "overrides": {"linear_solver": "auto"},
            "linear_kind": kind, "newton_iterations": its, "solve_s": 1.0, "linear_s": 0.5,
            "linear_resolve_s": 0.3, "linear_solves_equivalent": 2.0, "rms": 0.001, "peak_rss_mb": 100.0,
            "events": {"MatLUFactorSym": {"count": 1}, "MatLUFactorNum": {"count": 1}, "MatSolve": {"count": tri}},
            "linear_by_kind_s": {} if lu is None else {"lu": lu, "gamg": gamg}}


def test_report_names_the_crossover_and_where_the_cost_goes():
    """Section 3 states the measured LU/GAMG crossover, the Newton and triangular solves per row, and warns
    when the largest three rows mix LU and GAMG."""
    from workbench.studies.bench_report import _crossover, _why

    rows = [_scale_row(1000, "lu", 0.1, 0.3, [2], 6), _scale_row(4000, "lu", 0.5, 0.4, [5, 1, 1], 42),
            _scale_row(9000, "gamg", None, None, [2], 0)]
    sc = {"graded": {"rows": rows, "fits": {}}}
    cross = "\n".join(_crossover(sc))
    assert "GAMG faster from 4000 dofs" in cross and "1000: 3" in cross
    why = "\n".join(_why(sc))
    assert "4000: 7 Newton its, 42 triangular solves" in why and "mix LU and GAMG" in why
    assert "mix LU and GAMG" not in "\n".join(_why({"graded": {"rows": rows[:2], "fits": {}}}))
