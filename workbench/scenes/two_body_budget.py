"""Error budget of the elastic cylinder on an elastic block: three grids, three block sizes, the solver tolerance.

For every run of the case the scene is solved again:

* on the three ``[discretisation] budget_levels`` (h_c / a) with the largest block ``W_max = max(budget_widths)``
  (W/a, width = height), the grading refined with the levels (``growth - 1`` proportional to h_c, as the block
  budget); the values go through :func:`workbench.error_budget.grid_study` in h;
* on the finest level with the three block sizes: the same study in 1/W. The block is clamped at its bottom and
  free at its sides (the two-body scene has no half-plane far field), so the truncation is larger than the rigid
  block budget's. Where that study is asymptotic the value is corrected by ``f(inf) - f(W_max)`` and
  ``truncation`` is its GCI, otherwise no correction and ``truncation`` is the spread of the three values;
* the finest level on W_max again at the solver tolerances / 100 (``iterative``).

Rows (dimensionless, FEM over the exact circle's half-plane theory at the run's measured load and combined
modulus): ``p_max`` (largest nodal pressure), ``half_width`` (the contact edge b, square-root edge model between the
nodes) and ``half_width_moment`` (sqrt(M2/M0)). Theory 1; ``alt_theory`` is
Hertz's parabola at the same load (its p0 and a/2 over the exact circle's). The half disk's own size is not
varied: its departure from a half-plane (order (a/R)^2) stays in the extrapolated value, and the row's
``theory_in_band`` says whether the theory holds to within the band anyway.
"""

from __future__ import annotations

from analytic.hertz import hertz
from cases.schema import Case
from workbench.error_budget import tight_resolve
from workbench.scenes.base import SceneBudget
from workbench.scenes.budget_rows import budget_row, with_grid
from workbench.scenes.numbers import PEAK, WIDTH, declare

declare("budget", __name__, p_max=PEAK, half_width=WIDTH, half_width_moment=WIDTH)

__all__ = ["two_body_error_budget", "QUANTITIES"]

QUANTITIES = ("p_max", "half_width", "half_width_moment")
_TITLE = "Error budget (three grids, three block sizes; the half disk as it is)"


def _ratios(outcome) -> dict[str, float]:
    """FEM over the exact circle at the measured load, and Hertz over the exact circle (the alternative), from the
    run's typed comparison (:class:`workbench.scenes.two_body.CylinderComparison`)."""
    cmp = outcome.comparison
    th, signed = cmp.theory, cmp.signed
    hz = hertz(th.P, cmp.R, cmp.E_star)
    return {"p_max": 1.0 + signed["p_max"], "half_width": 1.0 + signed["half_width"],
            "half_width_moment": 1.0 + signed["half_width_moment"],
            "alt p_max": hz.p0 / th.p0, "alt half_width": hz.half_width / th.half_width,
            "alt half_width_moment": 0.5 * hz.half_width / cmp.moment_theory}


def two_body_error_budget(case: Case, *, solve, progress=print) -> SceneBudget:
    """The budget of a two-body cylinder case (empty without ``budget_levels``; module docstring)."""
    disc = case.discretisation
    levels, widths = sorted(disc.budget_levels), sorted(disc.budget_widths)
    if not levels or not widths:
        return SceneBudget({}, title=_TITLE)
    W_max, h_fine = widths[-1], levels[0]
    rows: dict[str, dict] = {}
    runs = case.runs()
    for run in runs:
        by_h, by_W = [], {}
        fine = None
        for h in levels:
            r = with_grid(run, h=h, W=W_max, h_coarse=levels[-1])
            o = solve(r)
            progress(f"[budget {run.label}] h_c = {h:g} a, W = {W_max:g} a: {o.result.ndofs} dofs")
            by_h.append(_ratios(o))
            fine = fine or (r, o)
        by_W[W_max] = by_h[0]
        for W in widths[:-1]:
            o = solve(with_grid(run, h=h_fine, W=W, h_coarse=levels[-1]))
            progress(f"[budget {run.label}] h_c = {h_fine:g} a, W = {W:g} a: {o.result.ndofs} dofs")
            by_W[W] = _ratios(o)
        o_t, how = tight_resolve(solve, fine[0], fine[1], progress=progress)
        tight = None if o_t is None else _ratios(o_t)
        suffix = "" if len(runs) == 1 else f"[{run.label}]"
        for q in QUANTITIES:
            rows[q + suffix] = budget_row(q, levels, widths, by_h, by_W, tight, tight_note="" if o_t else str(how),
                                          theory=1.0, theory_name="exact circle (half-plane theory, combined modulus)",
                                          alt_name="hertz")
    return SceneBudget(rows, title=_TITLE)
