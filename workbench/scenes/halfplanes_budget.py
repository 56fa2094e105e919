"""Error budget of two half-planes with a profile: three grids, three block sizes, the solver tolerance (issue 25).

Every run of the case (a ``small`` one and one or more ``convective`` or ``finite`` ones) is solved again on the
three ``[discretisation] budget_levels`` (h_c / b0) at the largest block ``W_max = max(budget_widths)``, on the finest
level at the three block sizes, and at the finest level with the solver tolerances / 100; each row goes through
:func:`workbench.scenes.budget_rows.budget_row` (Richardson in h, the 1/W correction, the iterative error,
round-off). Both blocks are clamped/driven W x H blocks (no half-plane far field for two bodies), so the truncation
is O(b0/W), extrapolated in 1/W where that study is asymptotic.

Rows (dimensionless):

* ``b_over_b0`` and ``b_over_b0_moment``: the convective run over the small run at the same load (edges; moment
  half-widths; with several convective or finite runs one row per run, ``b_over_b0_moment[<label>]``), each
  half-width over the classical one at its own measured load. Theory: converged Ciavarella-Hills
  at the bodies' beta and the fine run's b0/R (parabola) or m (wedge); alternative: the first-order theory (its
  closed form for the edge, the moment ratio of its pressure for the moments). The theory's moments are taken on
  its fine plot grid: ``theory_uncertainty`` is that grid's error on the classical moment (closed forms b0/2,
  b0/sqrt(6): :func:`analytic.wedge.wedge_moment_half_width`).
* ``half_width``, ``half_width_moment`` (and, parabola only, ``p_max``: the wedge's peak is log-singular) of the
  small run over the classical solution (Hertz or the wedge at E*; theory 1: the normal problem of two
  half-planes with small kinematics does not depend on beta).
"""

from __future__ import annotations

from analytic import wedge
from cases.schema import Case
from workbench.error_budget import FORMAL_ORDER, FORMAL_ORDER_EDGE, tight_resolve
from workbench.scenes.base import SceneBudget
from workbench.scenes.budget_rows import budget_row, with_grid
from workbench.scenes.budget_theory import curve_moment_half_width
from workbench.scenes.halfplanes_theory import convective_theory
from workbench.scenes.numbers import PEAK, WIDTH, declare

declare("budget", __name__, p_max=PEAK, half_width=WIDTH, half_width_moment=WIDTH, b_over_b0=WIDTH,
        b_over_b0_moment=WIDTH)

__all__ = ["halfplanes_error_budget"]

_TITLE = "Error budget (three grids, three block sizes of both half-planes)"
_THEORY_N_PLOT = 64001


def _classical_ratios(o) -> dict[str, float]:
    """The small run over the classical solution: half_width, half_width_moment (and p_max: parabola only), from
    its typed comparison and theory (:class:`workbench.scenes.halfplanes_theory.HalfplanesComparison`)."""
    return {k: 1.0 + v for k, v in o.comparison.signed(o.theory).items()}


def _solve_grid(run, levels, widths, *, solve, progress) -> dict:
    """One run on the budget's grids, ``{(h, W): outcome}``, by nested iteration (issue 38,
    :mod:`fem.nested_start`): the levels at the largest block from the coarsest up, each started from the last
    one's solution; each smaller block's finest level from that block's coarsest level (solved for it, not a row).
    Each level converges to its own tolerances; only the iterations differ from a cold solve.

    Finite-strain runs too: measured (neo-Hookean, W = 20 b0, b0/5 -> b0/10) the nested level converged in 219
    Newton iterations (13 solves, with cut-backs), where the cold solve of that level diverged in its first load
    step (docs/error_budget.md)."""
    W_max, h_fine, h_coarse = widths[-1], levels[0], levels[-1]
    grid: dict = {}

    def one(h, W, start, row=True):
        extra = {} if start is None else {"nested_start": start}
        o = solve(with_grid(run, h=h, W=W, h_coarse=h_coarse), **extra)
        r = o.result
        progress(f"[budget {run.label}] h_c = {h:g} b0, W = {W:g} b0: {r.ndofs} dofs, "
                 f"{sum(r.newton_iterations)} Newton its{' (nested)' if start is not None else ''}, "
                 f"{r.wall_time_s:.1f} s{'' if row else ' (start of the finest level)'}")
        if row:
            grid[(h, W)] = o
        return r.nested_start

    start = None
    for h in reversed(levels):
        start = one(h, W_max, start)
    for W in widths[:-1]:
        one(h_fine, W, one(h_coarse, W, None, row=False))
    return grid


def halfplanes_error_budget(case: Case, *, solve, progress=print) -> SceneBudget:
    """The budget (module docstring); empty without ``budget_levels``."""
    disc = case.discretisation
    levels, widths = sorted(disc.budget_levels), sorted(disc.budget_widths)
    if not levels or not widths:
        return SceneBudget({}, title=_TITLE)
    W_max, h_fine = widths[-1], levels[0]
    out: dict[str, dict] = {}
    runs = case.runs()
    for run in runs:
        k = run.label
        out[k] = _solve_grid(run, levels, widths, solve=solve, progress=progress)
        o_t, how = tight_resolve(solve, with_grid(run, h=h_fine, W=W_max, h_coarse=levels[-1]),
                                 out[k][(h_fine, W_max)], progress=progress)
        out[k]["tight"] = o_t
        out[k]["tight_note"] = "" if o_t is not None else str(how)
    rows: dict[str, dict] = {}
    small_run = next((r for r in runs if r.solver.kinematics == "small"), None)
    small = None if small_run is None else out[small_run.label]
    moved = [r.label for r in runs if r.solver.kinematics != "small"]  # convective and finite runs, each a row
    if small is not None:
        def hz(key):
            o = small[key]
            return None if o is None else _classical_ratios(o) | {f"alt {q}": 1.0 for q in _classical_ratios(o)}

        by_h = [hz((h, W_max)) for h in levels]
        by_W = {W: hz((h_fine, W)) for W in widths}
        classical = small[(h_fine, W_max)].theory
        for q in _classical_ratios(small[(h_fine, W_max)]):
            rows[q] = budget_row(q, levels, widths, by_h, by_W, hz("tight"), tight_note=small["tight_note"],
                                 theory=1.0, theory_name=f"{classical.name} (E*, measured load)",
                                 alt_name=classical.name,
                                 formal_order=FORMAL_ORDER_EDGE if q == "half_width" else FORMAL_ORDER)
            for key in ("alt_theory", "alt_value", "alt_in_band"):
                rows[q].pop(key)
    for label in moved if small is not None else ():
        conv = out[label]
        fine = conv[(h_fine, W_max)]
        th = fine.theory
        sol = convective_theory(th, n_plot=_THEORY_N_PLOT)
        w_conv = curve_moment_half_width(sol.x, sol.p_converged)
        w_class = curve_moment_half_width(sol.x, sol.p_classical)
        exact_class = wedge.wedge_moment_half_width(1.0) if th.kind == "wedge" else 0.5  # Hertz: a/2
        theory_err = abs(w_class - exact_class) / exact_class
        theory = {"half_width": sol.b_over_b0_converged, "moment": w_conv / w_class}
        alt = {"half_width": sol.b_over_b0_first_order,
               "moment": curve_moment_half_width(sol.x, sol.p_first_order) / w_class}

        def ratio(key, conv=conv, alt=alt):
            oc, os_ = conv[key], small[key]
            if oc is None or os_ is None:
                return None
            vc, vs = oc.comparison, os_.comparison
            r = {"half_width": (vc.half_width / oc.theory.half_width) / (vs.half_width / os_.theory.half_width),
                 "moment": (vc.moment / oc.theory.half_width) / (vs.moment / os_.theory.half_width)}
            return r | {f"alt {q}": alt[q] for q in r}

        by_h = [ratio((h, W_max)) for h in levels]
        by_W = {W: ratio((h_fine, W)) for W in widths}
        note = "; ".join(n for n in (small["tight_note"], conv["tight_note"]) if n)
        for name, q in (("b_over_b0", "half_width"), ("b_over_b0_moment", "moment")):
            key = name if len(moved) == 1 else f"{name}[{label}]"
            rows[key] = budget_row(q, levels, widths, by_h, by_W, ratio("tight"), tight_note=note,
                                   theory=theory[q], theory_name="Ciavarella-Hills, converged",
                                   alt_name="first order", theory_uncertainty=theory_err if q == "moment" else None,
                                   formal_order=FORMAL_ORDER_EDGE if q == "half_width" else FORMAL_ORDER)
            rows[key]["beta"] = th.beta
            rows[key] |= {"b0_over_R": th.half_width / th.R} if th.kind == "parabola" else {"m": th.m}
    _models_in_finite_bands(rows, runs)
    return SceneBudget(rows, title=_TITLE)


def _models_in_finite_bands(rows: dict, runs) -> None:
    """Each finite run's moment row gains ``models`` (each small-strain convective run's extrapolated moment ratio,
    by label) and ``models_in_band`` (whether it lies in the finite row's band): which small-strain convective model,
    if any, the finite-strain answer follows (issue 39)."""
    conv = [r.label for r in runs if r.solver.kinematics == "convective"]
    for r in runs:
        key = f"b_over_b0_moment[{r.label}]"
        if r.solver.kinematics != "finite" or key not in rows:
            continue
        row = rows[key]
        band = row["uncertainty"] * abs(row["fine"])
        models = {c: rows[f"b_over_b0_moment[{c}]"]["extrapolated"] for c in conv
                  if f"b_over_b0_moment[{c}]" in rows}
        row["models"] = models
        row["models_in_band"] = {c: bool(abs(v - row["extrapolated"]) <= band) for c, v in models.items()}

