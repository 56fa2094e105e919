"""Rate fitting and reporting of the convergence study (workbench.studies.rates, workbench.studies.convergence,
workbench.studies.convergence_report) on synthetic data; no dolfinx, < 1 s.

The fit is a least-squares line in log-log over the finest three levels, so an exact power law must come out
to round-off (tolerance 1e-10: a few ulps of log amplified by the 3-point fit), and pre-asymptotic coarse
levels must not change it.
"""

import math

import numpy as np
import pytest

from workbench.studies.config import to_json
from workbench.studies.convergence import (
    cheapest,
    ideal_growth,
    judge_rates,
    l2_pressure_error,
    observed_rates,
)
from workbench.studies.convergence_config import ConvergenceConfig
from workbench.studies.convergence_report import to_markdown
from workbench.studies.rates import RateFit, fit_rate

CONFIG = ConvergenceConfig()
EXPECTED_RATES, GROWTH_RANGE, RATE_BAND = CONFIG.expected_rates, CONFIG.growth_range, CONFIG.rate_band

H = np.array([0.2, 0.1, 0.05, 0.025, 0.0125])


def test_exact_power_law_in_h_and_ndofs():
    """err = 3 h^1.5 and ndofs = 40 h^-2 (uniform 2D refinement): slopes 1.5 and -0.75 exactly."""
    err = 3.0 * H**1.5
    fit = fit_rate(H, err)
    assert isinstance(fit, RateFit)
    assert abs(fit.slope - 1.5) < 1e-10, fit
    assert abs(fit.intercept - math.log(3.0)) < 1e-10, fit
    assert fit.n_points == 3 and fit.max_residual < 1e-10
    assert abs(fit_rate(40.0 * H**-2, err).slope + 0.75) < 1e-10


def test_only_the_finest_three_levels_count():
    """Coarse levels on another rate (pre-asymptotic) are ignored: still slope 2 to round-off."""
    err = 0.5 * H**2
    err[:2] = [0.9, 0.7]  # far off the asymptote
    assert abs(fit_rate(H, err).slope - 2.0) < 1e-10
    # all five levels would see the coarse ones: the slope moves far away from 2
    assert abs(fit_rate(H, err, n_finest=5).slope - 2.0) > 0.3


def test_noisy_data_within_band():
    """Multiplicative noise of +-2 % on err = h: |slope - 1| <= log(1.02/0.98)/log(2) ~ 0.058 (worst case of
    a 3-point fit over a factor 4 in h); seeded, so the test is deterministic."""
    rng = np.random.default_rng(0)
    err = H * (1.0 + 0.02 * rng.uniform(-1.0, 1.0, H.size))
    assert abs(fit_rate(H, err).slope - 1.0) <= math.log(1.02 / 0.98) / math.log(2.0)


@pytest.mark.parametrize(
    ("x", "err", "kw", "match"),
    [
        (H, H[:-1], {}, "equal length"),
        (H[:2], H[:2], {}, "need at least"),
        (H, H, {"n_finest": 1}, "n_finest"),
        (H, np.r_[H[:-1], 0.0], {}, "err must be finite and > 0"),
        (H, np.r_[H[:-1], np.nan], {}, "err must be finite and > 0"),
        (np.r_[H[:-2], H[-3], H[-1]], H, {}, "strictly monotone"),
        (np.r_[H[:-1], -1.0], H, {}, "x must be finite and > 0"),
    ],
)
def test_bad_input_raises_value_error(x, err, kw, match):
    with pytest.raises(ValueError, match=match):
        fit_rate(x, err, **kw)


def _rows(case, method, degree, rate, nan_last=False):
    rows = []
    for h in H:
        e = 0.1 * h**rate
        rows.append({"case": case, "series": "case", "method": method, "degree": degree,
                     "h_contact": float(h), "ndofs": 100.0 / h**2, "rms": e, "time_s": 1.0 / h,
                     "p_max": math.nan if nan_last and h == H[-1] else e})
    return rows


def test_observed_rates_groups_and_orders_rows():
    """Rows in any order; per configuration the slopes are the power-law exponents (h) and -rate/2 (ndofs)."""
    rows = _rows("c", "nitsche", 2, 2.0) + _rows("c", "penalty", 1, 1.0, nan_last=True)
    rows = rows[::-1]
    rates = observed_rates(rows, metrics={"c": ("rms", "p_max")})
    got = {(r["method"], r["metric"]): r for r in rates}
    assert abs(got["nitsche", "rms"]["slope_h"] - 2.0) < 1e-10
    assert abs(got["nitsche", "rms"]["slope_ndofs"] + 1.0) < 1e-10
    assert abs(got["penalty", "rms"]["slope_h"] - 1.0) < 1e-10
    assert got["penalty", "p_max"]["slope_h"] is None and "finite" in got["penalty", "p_max"]["note"]


def test_cheapest_picks_fastest_row_below_target():
    rows = _rows("c", "nitsche", 2, 2.0) + _rows("c", "penalty", 1, 1.0)
    best = cheapest(rows, metric="rms", target=5e-4)
    # nitsche P2: 0.1 h^2 <= 5e-4 from h = 0.05 (2.5e-4); penalty P1 never (0.1 h >= 1.25e-3)
    assert best["c/case"]["method"] == "nitsche" and best["c/case"]["h_contact"] == 0.05
    assert cheapest(rows, metric="rms", target=1e-9)["c/case"] is None


class _Theory:
    """Hertz-like theory stub: p = p0 sqrt(1 - (x/a)^2)."""

    half_width, p_ref = 1.0, 2.0

    def pressure(self, x):
        return self.p_ref * np.sqrt(np.clip(1.0 - (x / self.half_width) ** 2, 0.0, None))


class _Samples:
    def __init__(self, s, p, w):
        self.s, self.p, self.weight = s, p, w


def test_l2_pressure_error_of_a_constant_offset():
    """p = p_th + 0.1 p_ref on the band: the weighted mean error is exactly 0.1 (round-off tolerance)."""
    pts, wts = np.polynomial.legendre.leggauss(2)
    edges = np.linspace(0.0, 1.2, 25)
    s = (0.5 * (edges[:-1] + edges[1:])[:, None] + 0.5 * np.diff(edges)[:, None] * pts).ravel()
    w = (0.5 * np.diff(edges)[:, None] * wts).ravel()
    th = _Theory()
    assert abs(l2_pressure_error(_Samples(s, th.pressure(s) + 0.2, w), th, half_width_fem=1.0) - 0.1) < 1e-12
    assert l2_pressure_error(_Samples(s, th.pressure(s), w), th, half_width_fem=1.0) == 0.0


def test_l2_pressure_error_inner_band():
    """x_max restricts the band: an offset of 0.2 p_ref on |x| <= 0.5 only, zero elsewhere, gives exactly 0.1
    on |x| <= 0.5 (round-off) and less on the default band; a non-positive x_max is a ValueError."""
    pts, wts = np.polynomial.legendre.leggauss(2)
    edges = np.linspace(0.0, 1.2, 25)
    s = (0.5 * (edges[:-1] + edges[1:])[:, None] + 0.5 * np.diff(edges)[:, None] * pts).ravel()
    w = (0.5 * np.diff(edges)[:, None] * wts).ravel()
    th = _Theory()
    p = th.pressure(s) + np.where(s <= 0.5, 0.2, 0.0)
    assert abs(l2_pressure_error(_Samples(s, p, w), th, half_width_fem=1.0, x_max=0.5) - 0.1) < 1e-12
    assert l2_pressure_error(_Samples(s, p, w), th, half_width_fem=1.0) < 0.1
    with pytest.raises(ValueError, match="x_max"):
        l2_pressure_error(_Samples(s, p, w), th, half_width_fem=1.0, x_max=0.0)


def test_ideal_growth_scales_with_h_and_stays_in_the_schema_range():
    """growth - 1 proportional to h_c (the whole size field scales with h_c), inside [1.05, 2]."""
    levels = [0.4, 0.2, 0.1, 0.05, 0.025]
    g = [ideal_growth(h) for h in levels]
    ratios = [(gi - 1.0) / h for gi, h in zip(g, levels, strict=True)]
    assert max(ratios) - min(ratios) < 1e-12
    assert g[0] <= GROWTH_RANGE[1] and abs(g[-1] - GROWTH_RANGE[0]) < 1e-12
    for bad in (0.0125, 0.6):
        with pytest.raises(ValueError, match="h_contact"):
            ideal_growth(bad)


def test_judge_rates_band():
    """|slope - expected| <= 0.15 is 'within'; Hertz ideal expects 1.0, wedge 0.5; no expectation: ''."""
    assert EXPECTED_RATES["hertz_cylinder/ideal"]["rms"] == 1.0 and RATE_BAND == 0.15
    base = {"series": "ideal", "method": "nitsche", "degree": 2}
    rates = [{**base, "case": "hertz_cylinder", "metric": "rms", "slope_h": 1.14},
             {**base, "case": "hertz_cylinder", "metric": "l2", "slope_h": 0.84},
             {**base, "case": "wedge_convective", "metric": "rms", "slope_h": None},
             {**base, "case": "hertz_cylinder", "metric": "p_max", "slope_h": 3.0}]
    got = [r["verdict"] for r in judge_rates(rates)]
    assert got == ["within", "outside", "no fit", ""]
    with pytest.raises(ValueError, match="band"):
        judge_rates(rates, band=0.0)


def _study(rate: float) -> dict:
    """A minimal study JSON (Hertz ideal series only): every error = 0.1 h^rate, rms target never met."""
    levels = [0.2, 0.1, 0.05]
    rows = []
    for method in ("penalty", "nitsche"):
        for degree in (1, 2):
            for h in levels:
                e = 0.1 * h**rate
                rows.append({"case": "hertz_cylinder", "series": "ideal", "method": method, "degree": degree,
                             "h_contact": h, "growth": 1.0 + 2.0 * h, "ndofs": int(100 / h**2),
                             "time_s": 1.0 / h, "cold_s": 1.0 / h, "newton_iterations": 5, "warnings": "",
                             "failed": "", "repeat_spread": 0.0,
                             **{m: e for m in ("p_max", "half_width", "rms", "l2", "l2_inner")}})
    rates = judge_rates(observed_rates(rows))
    return {"levels": {"case": [], "ideal": levels}, "repeats": 3, "n_finest": 3, "growth_per_h": 2.0,
            "metrics": {"hertz_cylinder": ("p_max", "half_width", "rms", "l2", "l2_inner")},
            "series": {"hertz_cylinder": {"ideal": {"width_factor": 640.0}}}, "rms_target": 1e-9,
            "rate_band": RATE_BAND, "rows": rows, "rates": rates, "cheapest_rms": cheapest(rows, target=1e-9),
            "study_wall_time_s": 1.0, "kappa0_level": 0.0125}


def test_report_states_observed_against_expected():
    """An exact h^1 law is reported as +1.00 'within' for rms and l2 (1.0 expected); h^2 as 'outside'."""
    md = to_markdown(_study(1.0))
    assert "| hertz_cylinder | ideal | nitsche | 2 | rms | 1.00 | +1.00 | within |" in md
    assert "| hertz_cylinder | ideal | penalty | 1 | l2 | 1.00 | +1.00 | within |" in md
    md2 = to_markdown(_study(2.0))
    assert "| hertz_cylinder | ideal | nitsche | 2 | rms | 1.00 | +2.00 | outside |" in md2
    assert "hertz_cylinder/ideal: none within the levels; Nitsche P2 reaches rms" in md2


def test_config_defaults_are_the_published_study():
    """The typed config holds what were module constants: levels, bands, targets; bad levels are refused."""
    assert CONFIG.levels == (0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625, 0.003125)
    assert CONFIG.ideal_levels == (0.4, 0.2, 0.1, 0.05, 0.025) and CONFIG.n_finest == 3
    assert CONFIG.rms_target == 0.005 and CONFIG.kappa0_sweep == (1e2, 1e3, 1e4, 1e5)
    # The expected rates are derived here, not read back from the config: the Hertz pressure has a square-root
    # edge, p ~ sqrt(2 (a - x)/a), so the element holding the edge carries an error ~ sqrt(h) over a length h:
    # ||e||^2 ~ h * h, ||e|| ~ h^1 for any degree (the smooth interior adds only h^2). The wedge pressure has a log
    # singularity at the apex, error ~ |log h| over a length h: ||e|| ~ h^(1/2) (up to the log). The sqrt-edge rate
    # is checked numerically below (P1 interpolation of the Hertz profile, edge off the nodes: slope 0.999).
    derived = {"hertz_cylinder/ideal": {"rms": 1.0, "l2": 1.0},
               "wedge_convective/ideal": {"rms": 0.5, "l2": 0.5},
               "wedge_convective/case": {"rms": 0.5, "l2": 0.5}}
    assert to_json(CONFIG)["expected_rates"] == derived

    def l2_interpolation_error(h):
        x = np.arange(-2 - 0.37 * h, 2 + h, h)
        xf = np.linspace(-2, 2, 200001)
        pf = np.sqrt(np.clip(1 - xf**2, 0, None))
        return math.sqrt(np.trapezoid((pf - np.interp(xf, x, np.sqrt(np.clip(1 - x**2, 0, None)))) ** 2, xf))

    hs = [0.04, 0.02, 0.01, 0.005]
    slope = np.polyfit(np.log(hs), np.log([l2_interpolation_error(h) for h in hs]), 1)[0]
    assert abs(slope - derived["hertz_cylinder/ideal"]["l2"]) < 0.05, slope
    with pytest.raises(ValueError, match="levels"):
        ConvergenceConfig(levels=(0.1, 0.2, 0.05))
    with pytest.raises(ValueError, match="h_contact"):
        ConvergenceConfig(ideal_levels=(0.4, 0.2, 0.0125))
    with pytest.raises(ValueError, match="repeats"):
        ConvergenceConfig(repeats=0)


def test_the_report_does_not_import_the_study():
    """Reports read JSON only: convergence_report and convergence_plot import neither convergence.py nor dolfinx."""
    import subprocess
    import sys

    code = ("import sys, workbench.studies.convergence_report, workbench.studies.convergence_plot; "
            "bad = [m for m in ('workbench.studies.convergence', 'dolfinx') if m in sys.modules]; "
            "sys.exit(1 if bad else 0)")
    assert subprocess.run([sys.executable, "-c", code], timeout=120).returncode == 0
