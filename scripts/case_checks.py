"""Case-level comparisons that need more than one run (pure numpy).

* Convective cases (a ``small`` and a ``convective`` run of the same block scene): the FEM ratio b/b0 at
  the same load against the Ciavarella-Hills theory (first order, first iterate, converged).
* Concave cases: per displacement step, elliptical fits, eq. (4)/(5) patch sizes and Hertz
  superposition against the FEM (computed by :mod:`scripts.scene_concave`, summarised here).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from analytic import convective, materials
from scripts.compare import rms_error

__all__ = ["CaseComparison", "case_level_comparisons", "convective_theory", "fem_b_over_b0"]

# Figures printed by Ciavarella & Hills for the two convective scenes (their section 3 and 4).
PAPER_B_OVER_B0 = {"wedge": 1.097, "parabola": 1.09}


class CaseComparison(NamedTuple):
    """Case-level analytic values, errors, a one-line headline, extra Markdown tables, and extra top-level
    fields of ``metrics.json`` (e.g. the per-step table of a concave case)."""

    analytic: dict
    errors: dict
    headline: str
    tables: dict
    top: dict = {}


def convective_theory(outcome) -> convective.ConvectiveSolution:
    """Ciavarella-Hills prediction for a block run's profile at its measured load.

    The wedge depends on (m beta) only; the parabola on (b0/R, beta), with b0 the classical half-width at
    the measured load. beta is that of a rigid indenter on the block material.
    """
    th = outcome.theory
    nu = outcome.metrics["nu"]
    beta = materials.beta_rigid_indenter(nu)
    if th.kind == "wedge":
        profile = convective.wedge_profile(th.m)
    else:
        profile = convective.parabola_profile(th.half_width / th.R)
    # a fine plot grid: the FEM samples are interpolated on it for rms_convective (801 points cost ~1 %)
    return convective.solve(profile, beta=beta, n_plot=8001)


def fem_b_over_b0(small, conv) -> float:
    """FEM b/b0 at the same load: each half-width is first normalised by its classical value at its own
    measured load, which removes the (tiny) load mismatch of the two force-controlled runs."""
    r_small = small.metrics["patch_half_width"] / small.theory.half_width
    r_conv = conv.metrics["patch_half_width"] / conv.theory.half_width
    return r_conv / r_small


def case_level_comparisons(case, outcomes) -> CaseComparison:
    """Comparisons of a case that involve several runs or whole-case theory."""
    by_kin = {o.metrics["kinematics"]: o for o in outcomes if o.metrics.get("scene") == "block"}
    if "convective" in case.analytic.predictions and {"small", "convective"} <= set(by_kin):
        small, conv = by_kin["small"], by_kin["convective"]
        sol = convective_theory(conv)
        ratio = fem_b_over_b0(small, conv)
        kind = small.theory.kind
        paper = PAPER_B_OVER_B0.get("wedge" if kind == "wedge" else "parabola")
        rows = [
            ("FEM (convective / small, same load)", ratio),
            ("first order (closed form)", sol.b_over_b0_first_order),
            ("first iterate", sol.b_over_b0_first_iterate),
            ("converged (full nonlinear)", sol.b_over_b0_converged),
            ("paper's printed figure", paper),
        ]
        table = ["| source | b/b0 |", "|---|---|"] + [f"| {k} | {v:.5f} |" for k, v in rows]
        err = abs(ratio - sol.b_over_b0_converged) / sol.b_over_b0_converged
        # pressure of the convective run against the converged convective theory (x in b0, p in P/b0)
        th = conv.theory
        sr = conv.series[0]
        p_conv = np.interp(sr.x, sol.x * th.half_width, sol.p_converged * th.P / th.half_width)
        sr.predictions["convective theory (converged)"] = p_conv
        rms_conv = rms_error(sr.x, sr.p, p_conv, center=0.0, half_width=conv.metrics["patch_half_width"],
                             p_ref=th.p_ref)
        analytic = {
            "beta": sol.beta,
            "b_over_b0_first_order": sol.b_over_b0_first_order,
            "b_over_b0_first_iterate": sol.b_over_b0_first_iterate,
            "b_over_b0_converged": sol.b_over_b0_converged,
            "b_over_b0_paper": paper,
            "b_over_b0_fem": ratio,
        }
        headline = (f"b/b0: FEM {ratio:.4f}, converged theory {sol.b_over_b0_converged:.4f}, first order "
                    f"{sol.b_over_b0_first_order:.4f}, paper prints {paper}")
        errors = {"b_over_b0": err, "rms_convective": rms_conv}
        return CaseComparison(analytic, errors, headline, {"Convective ratio b/b0": table})
    concave = [o for o in outcomes if o.metrics.get("scene") == "concave"]
    if concave:
        from scripts.scene_concave import concave_case_comparison

        return concave_case_comparison(case, concave)
    return CaseComparison({}, {}, "", {})
