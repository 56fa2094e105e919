"""The convective ratio b/b0 of an external code: a ``convective`` (or ``finite``) run over the ``small`` run of the
same scene at one load, level by level, against Ciavarella-Hills (block scenes under a rigid profile, and two elastic
half-planes).

Each run's half-width is first divided by the classical one at its own measured load (the quantities
``half_width`` and ``half_width_moment`` of its level record), which removes the small load mismatch of two runs, as
:func:`workbench.scenes.convective.fem_b_over_b0` and the half-planes' judge do; then

    b/b0 (edges)  = (b_conv / b0(P_conv)) / (b_small / b0(P_small)),
    b/b0 (moment) = (w_conv / b0(P_conv)) / (w_small / b0(P_small)),   w = 2 sqrt(M2/M0) about x = 0.

The two runs' levels are paired fine with fine (the i-th finest of each). Theory: the converged Ciavarella-Hills
solution at the scene's beta and profile at the finest convective level's load (its closed-form first order the
alternative the verdict must tell it from); the moment ratios of the theory are taken on a 64001-point grid
(:func:`workbench.scenes.budget_theory.curve_moment_half_width`, as the budgets). Formal orders: 1.5 (edges),
2 (moments). The uncertainty adds both runs' load terms (their relative load balances times the half-width's
sensitivity to P: 1/2 for Hertz, 1 for the wedge).
"""

from __future__ import annotations

from workbench.external.scorers.base import study

__all__ = ["THEORY_N_PLOT", "convective_studies"]

THEORY_N_PLOT = 64001  # the budgets' Ciavarella-Hills grid for the moments (converged to ~1e-7)
_FORMAL = {"half_width": 1.5, "half_width_moment": 2.0}
_LABEL = {"b_over_b0": "ratio b/b0 (edges)", "b_over_b0_moment": "moment ratio b/b0"}


def convective_studies(runs: dict, groups: dict, *, solve, sensitivity: float) -> dict:
    """``b_over_b0[run]`` and ``b_over_b0_moment[run]`` of every convective or finite run with three levels paired
    with the small run's (module docstring).

    Args:
        runs: label -> :class:`workbench.external.scorers.runs.ScoredRun`.
        groups: (run, step, body) -> level records fine first (the slave body's are used).
        solve: ``solve(fine_record, scored_run) -> analytic.convective.ConvectiveSolution`` at the record's load.
        sensitivity: d ln(half-width) / d ln(P) of the classical solution (1/2 Hertz, 1 the wedge).
    """
    from workbench.scenes.budget_theory import curve_moment_half_width

    slave = {lab: lv for (lab, _s, body), lv in groups.items() if lv and lv[0].get("role", "slave") == "slave"}
    small = next((lv for lab, lv in slave.items() if runs[lab].kinematics == "small"), None)
    out: dict = {}
    if small is None:
        return out
    for label, levels in slave.items():
        if runs[label].kinematics not in ("convective", "finite") or min(len(levels), len(small)) < 3:
            continue
        pairs = list(zip(levels[:3], small[:3], strict=True))
        sol = solve(pairs[0][0], runs[label])
        w_class = curve_moment_half_width(sol.x, sol.p_classical)
        theory = {"b_over_b0": (sol.b_over_b0_converged, sol.b_over_b0_first_order),
                  "b_over_b0_moment": (curve_moment_half_width(sol.x, sol.p_converged) / w_class,
                                       curve_moment_half_width(sol.x, sol.p_first_order) / w_class)}
        load_term = sensitivity * (abs(pairs[0][0]["errors"]["load_balance"])
                                   + abs(pairs[0][1]["errors"]["load_balance"]))
        for key, q in (("b_over_b0", "half_width"), ("b_over_b0_moment", "half_width_moment")):
            ratios = [c["quantities"][q] / s["quantities"][q] for c, s in pairs]
            row = study([c["h"] for c, _s in pairs], ratios, formal=_FORMAL[q], theory=theory[key][0],
                        theory_name="Ciavarella-Hills (converged)", alt=("first order", theory[key][1]),
                        load_term=load_term, label=f"{_LABEL[key]}: the {label} run over the small run",
                        group={"run": label, "over": "small", "quantity": key})
            out[f"{key}[{label}]"] = row | {"beta": sol.beta, "files": [[c["file"], s["file"]] for c, s in pairs]}
    return out
