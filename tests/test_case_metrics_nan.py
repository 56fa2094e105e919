"""case_metrics never drops a run's NaN error silently (issue 12): the case-level error is NaN, its check
fails, and errors_undefined names the run."""

from __future__ import annotations

import math

from cases import load_case
from workbench.pipeline.run_case import case_metrics
from workbench.scenes import Outcome


def _outcome(run, label, errors):
    metrics = {"label": label, "method": "nitsche", "kinematics": "small", "ndofs": 10, "newton_iterations": [1],
               "load_steps": [{}], "P": 1.0, "P_pressure": 1.0, "patches": [], "analytic": {}, "errors": errors}
    return Outcome(label, run, metrics, [], None, None, None)


def test_nan_in_one_run_is_nan_for_the_case():
    case = load_case("hertz_cylinder")
    run = case.runs()[0]
    good = {"p_max": 1e-4, "half_width": 1e-3, "rms": 1e-3, "load_balance": 1e-12}
    bad = dict(good, half_width=math.nan)
    m = case_metrics(case, [_outcome(run, "a", good), _outcome(run, "b", bad)], h_contact=None, wall_time_s=0.0)
    assert math.isnan(m["errors"]["half_width"])
    assert m["checks"]["half_width"] is False and m["pass"] is False
    assert m["errors_undefined"] == {"half_width": ["b"]}
    assert m["errors"]["p_max"] == 1e-4 and m["checks"]["p_max"] is True
    ok = case_metrics(case, [_outcome(run, "a", good)], h_contact=None, wall_time_s=0.0)
    assert ok["pass"] is True and ok["errors_undefined"] == {}
