"""Error budget of a block case: discretisation (three grids), domain truncation (three block sizes), theory
(the block scene's, :meth:`workbench.scenes.block.BlockScene.error_budget`).

For every run of the case the scene is solved again on a grid of runs:

* the three ``[discretisation] budget_levels`` (h_c / a) on the largest block ``W_max = max(budget_widths)``,
  the grading refined with them (``growth - 1`` proportional to h_c, the case's growth on the coarsest level):
  refining h_c alone leaves the graded far field as it is, and its error (measured 1.1e-4 on the Hertz peak
  and moment half-width at growth 1.3) then stalls the sequence on a wrong limit. The values go through
  :func:`workbench.error_budget.grid_study` in h: the fine value, the Richardson value, the observed order,
  the GCI and a named status;
* every budget block has the ``halfplane`` far field (:mod:`fem.far_field`: bottom and sides move as the
  half-plane under the line load P; measured truncation ~(a/W)^4 for the Hertz quantities, ~(a/W)^3 for the
  convective ratio, instead of (a/W)^2 and a/W with the clamped block; ``far_field`` in each row);
* the finest level on the three ``budget_widths`` (W / a, block width = height) -> the same study in 1/W (the
  half-plane is W -> infinity). Where it is asymptotic the value is corrected by ``f(inf) - f(W_max)``
  (``truncation_correction``, relative) and ``truncation`` is the W study's GCI (what is left after the
  correction); otherwise no correction and ``truncation`` is the spread band of the three values (the
  meshes of different blocks differ slightly, so the W sequence carries a mesh noise of ~1e-6 to 1e-5).

Each headline quantity is dimensionless (divided by the classical value at the run's measured load):

* Classical wedge (small kinematics): ``half_width`` and ``half_width_moment`` against the classical wedge
  (closed form: 2 sqrt(M2/M0) = 2 b / sqrt(6)).
* Hertz scenes (circle or parabola, small kinematics): ``p_max`` (largest sample, contact law),
  ``half_width`` (zero crossing), ``half_width_moment`` (2 sqrt(M2/M0), smooth: see
  :mod:`workbench.scenes.budget_theory`). Theory: the profile's own half-plane theory (exact circle for a
  circle, Hertz for a parabola); ``alt_theory`` names the other one (Hertz for a circle).
* Convective scenes: ``b_over_b0`` (zero crossings) and ``b_over_b0_moment`` (moment half-widths) of the
  convective run over the small run at the same load. Theory: converged Ciavarella-Hills; alternative: the
  first-order theory (its closed-form b/b0, and the moment ratio of its pressure). The theory's moments are
  taken on its 64001-point grid: ``theory_uncertainty`` is that grid's error on the classical moment (closed
  form known), 5.3e-6 for the wedge (log apex).

``extrapolated`` = Richardson value in h (at W_max; the fine value where no order is claimed) + the W
correction. The numerical uncertainty (issue 22), every term relative and recorded in the row:

* ``gci``: the h study (:func:`workbench.error_budget.grid_study`, told the row's theory, so a sequence that
  crosses it is ``"crossing"`` with the spread band; an observed order above 1.1 x the formal order q keeps
  its Richardson value, but the GCI is at least Roy's Fs = 3 at order q, ``band_order`` says which; q =
  ``FORMAL_ORDER`` = 2 for the moments and the peak, ``FORMAL_ORDER_EDGE`` = 1.5 for the zero crossings);
* ``truncation``: the W study (above);
* ``iterative``: the finest level (h_fine, W_max) solved again with every solver tolerance / 100
  (:func:`workbench.error_budget.tight_resolve`): ``|f_tight - f| / |f|``, floored at 1e-12 (the tight
  tolerance); null with ``iterative_status`` when the tight solve failed;
* ``roundoff``: ``ROUNDOFF_FLOOR`` = 1e-9;
* ``theory_uncertainty`` where the theory has one (the convective moments' grid).

``uncertainty`` is their sum; ``theory_in_band``: ``|theory - extrapolated| <= uncertainty |fine|`` (and
``alt_in_band`` likewise).

For a Hertz scene the finest-level, largest-block run is also probed on the symmetry axis
(``subsurface.csv``), and every run's interior stress is compared with McEwen's field over |x|, z <= 4 a
(:mod:`fem.interior`): rows ``interior_stress_l2`` (RMS error / p0 on the three grids and its rate; an error
norm, not extrapolated) and ``vm_max`` (largest von Mises stress / p0 over the box's Gauss points, the full
study, theory McEwen's maximum 0.5575 p0 at 0.704 a for nu = 0.3), and ``subsurface["interior"]``.
"""

from __future__ import annotations

import dataclasses
import math
from typing import NamedTuple

import numpy as np

from analytic.subsurface import hertz_subsurface_stress, von_mises_plane_strain
from analytic.wedge import wedge_moment_half_width
from cases.schema import Case, Run
from workbench.error_budget import (
    FORMAL_ORDER,
    FORMAL_ORDER_EDGE,
    ROUNDOFF_FLOOR,
    grid_study,
    iterative_error,
    tight_resolve,
    uncertainty,
)
from workbench.scenes.base import SceneBudget
from workbench.scenes.block_theory import exact_circle
from workbench.scenes.budget_theory import circle_moment_half_width, curve_moment_half_width, moment_half_width
from workbench.scenes.numbers import ERROR, ESTIMATE, PEAK, VERDICT, WIDTH, declare

# A row's values (fine, extrapolated, theory, alt_value) by its quantity: the interior stress error is a fraction
# (RMS / p0, theory 0); the others relative to themselves. Its estimates and band verdicts as every row's.
declare("budget", __name__, p_max=PEAK, half_width=WIDTH, half_width_moment=WIDTH, b_over_b0=WIDTH,
        b_over_b0_moment=WIDTH, interior_stress_l2=ERROR, vm_max=PEAK)
declare("budget_fields", __name__, observed_order=ESTIMATE, gci=ESTIMATE, truncation=ESTIMATE,
        theory_in_band=VERDICT, alt_in_band=VERDICT)

__all__ = ["BUDGET_FAR_FIELD", "SUBSURFACE_DEPTH", "SUBSURFACE_POINTS", "block_error_budget"]

SUBSURFACE_POINTS = 81    # probe points on the axis (issue 12: >= 50)
SUBSURFACE_DEPTH = 4.0    # down to 4 a (issue 12: >= 3 a)
_THEORY_N_PLOT = 64001    # Ciavarella-Hills grid for the moments (converged to ~1e-7 relative)
# The budget's blocks move on their outer boundary as the half-plane under the line load (fem/far_field.py):
# measured (h_c = a/80), the truncation left at W = 40 a is 1.6e-6 (Hertz moment half-width) and 2.7e-6 (wedge
# convective moment ratio), against 3.9e-4 and ~1e-2 with the clamped block of the case runs.
BUDGET_FAR_FIELD = "halfplane"
_TITLE = "Error budget (three grids, three block sizes)"
INTERIOR_BOX = 4.0        # interior stress error over |x| <= 4 a, 0 <= z <= 4 a (Hertz scenes)


def _with(run: Run, *, h: float, W: float | None, h_coarse: float) -> Run:
    """The run on level h (grading ``1 + (growth - 1) h / h_coarse``: every element shrinks by the same
    factor, the far field too) and on a block of W/a with the ``halfplane`` far field (None: the geometry as it
    is)."""
    g = run.geometry if W is None else dataclasses.replace(run.geometry, width_factor=W, height_factor=W,
                                                             far_field=BUDGET_FAR_FIELD)
    growth = 1.0 + (run.discretisation.growth - 1.0) * h / h_coarse
    d = dataclasses.replace(run.discretisation, h_contact=h, growth=growth)
    return dataclasses.replace(run, geometry=g, discretisation=d)


def _measures(outcome) -> dict[str, float]:
    """Dimensionless headline measures of one block outcome (classical values at its measured load)."""
    th, cmp, res = outcome.theory, outcome.comparison, outcome.result
    s = res.samples
    w = moment_half_width(s.s, s.p, s.weight, center=0.0 if res.half else None)
    out = {"half_width": cmp.half_width / th.half_width, "moment": w / th.half_width}
    if th.kind == "hertz":
        out["p_max"] = cmp.p_max / th.p_ref
    return out


def _study(levels, widths, fine_by_h: list[float], fine_by_W: list[float], theory, alt, *,
           tight: float | None = None, theory_uncertainty: float | None = None, tight_note: str = "",
           formal_order: float = FORMAL_ORDER) -> dict:
    """One budget row: the h study (tested against ``theory``), the W study, and the uncertainty terms
    (module docstring); ``tight``: the finest value solved again at the tight tolerances (None: not measured)."""
    f_fine = fine_by_h[0]
    iterative = iterative_error(f_fine, tight)
    floor = ((iterative or 0.0) + ROUNDOFF_FLOOR) * abs(f_fine)
    hs = grid_study(tuple(levels), tuple(fine_by_h), expected_order=None, reference=theory, floor=floor,
                    formal_order=formal_order)
    ws = grid_study(tuple(1.0 / np.asarray(widths)), tuple(fine_by_W), expected_order=None)
    f_wmax = fine_by_W[int(np.argmax(widths))]
    scale = abs(hs.fine)
    # asymptotic in 1/W: the fine value is corrected by f(inf) - f(W_max), and the W study's GCI is what is left;
    # otherwise no correction, and the band of the three block sizes
    correction = ws.extrapolated - f_wmax if ws.status in ("asymptotic", "converged") else 0.0
    truncation = ws.gci * abs(ws.fine) / scale
    extrapolated = hs.extrapolated + correction
    total = uncertainty(hs.gci, truncation, iterative, ROUNDOFF_FLOOR, theory_uncertainty)
    band = total * scale
    row = {
        "fine": hs.fine, "extrapolated": extrapolated, "observed_order": _num(hs.observed_order),
        "gci": hs.gci, "truncation": truncation, "iterative": iterative, "roundoff": ROUNDOFF_FLOOR,
        "uncertainty": total, "band_order": _num(hs.band_order), "theory": _num(theory),
        "theory_in_band": None if theory is None else bool(abs(theory - extrapolated) <= band),
        "status": hs.status, "truncation_status": ws.status, "truncation_correction": correction / scale,
        "truncation_order": _num(ws.observed_order), "far_field": BUDGET_FAR_FIELD,
        "by_h": dict(zip([str(v) for v in levels], fine_by_h, strict=True)),
        "by_W": dict(zip([str(v) for v in widths], fine_by_W, strict=True)),
        "error_vs_theory": None if theory is None else abs(extrapolated - theory) / abs(theory),
    }
    if theory_uncertainty is not None:
        row["theory_uncertainty"] = theory_uncertainty
    if iterative is None:
        row["iterative_status"] = tight_note or "not measured"
    if alt is not None:
        name, value = alt
        row["alt_theory"] = name
        row["alt_value"] = value
        row["alt_in_band"] = bool(abs(value - extrapolated) <= band)
    return row


def _formal(q: str) -> float:
    """The formal order a measure's band may rely on: a zero crossing (``half_width``) FORMAL_ORDER_EDGE, the
    smooth measures (moments, the peak) FORMAL_ORDER."""
    return FORMAL_ORDER_EDGE if q == "half_width" else FORMAL_ORDER


def _num(v):
    return None if v is None or (isinstance(v, float) and not math.isfinite(v)) else float(v)


def block_error_budget(case: Case, *, solve, progress=print) -> SceneBudget:
    """The error budget of a block case (empty without ``budget_levels``) with the Hertz axis samples.

    Args:
        case: The case (its ``[discretisation] budget_levels`` and ``budget_widths``).
        solve: ``solve(run) -> Outcome`` (:func:`workbench.pipeline.run_case.run_one` bound to the mesh
            cache and communicator).

    Returns:
        :class:`workbench.scenes.base.SceneBudget`: ``rows`` the JSON dict ``{quantity: row}``, ``subsurface``
        the axis samples of the Hertz run (or None).
    """
    disc = case.discretisation
    if not disc.budget_levels:
        return SceneBudget({}, title=_TITLE)
    levels = sorted(disc.budget_levels)
    widths = sorted(disc.budget_widths)
    W_max, h_fine = widths[-1], levels[0]
    grid = [(h, W_max) for h in levels] + [(h_fine, W) for W in widths[:-1]]
    meas: dict[str, dict] = {}
    outcomes: dict[str, dict] = {}
    tight_notes: dict[str, str] = {}
    for run in case.runs():
        for h, W in grid:
            o = solve(_with(run, h=h, W=W, h_coarse=levels[-1]))
            progress(f"[budget {run.label}] h_c = {h:g} a, W = {W:g} a: {o.result.ndofs} dofs")
            meas.setdefault(run.label, {})[(h, W)] = _measures(o)
            outcomes.setdefault(run.label, {})[(h, W)] = o
        # the iterative error: the finest level once more at tolerances / TIGHTENING
        fine_run = _with(run, h=h_fine, W=W_max, h_coarse=levels[-1])
        o_t, how = tight_resolve(solve, fine_run, outcomes[run.label][(h_fine, W_max)], progress=progress)
        if o_t is not None:
            progress(f"[budget {run.label}] h_c = {h_fine:g} a, W = {W_max:g} a at tolerances / {how:g}")
            meas[run.label]["tight"] = _measures(o_t)
            outcomes[run.label]["tight"] = o_t
        else:
            tight_notes[run.label] = how
    budget: dict[str, dict] = {}
    by_kin = {r.solver.kinematics: r.label for r in case.runs()}

    def series(fn):
        return [fn((h, W_max)) for h in levels], [fn((h_fine, W)) for W in widths]

    def tight(fn):
        """``fn`` at the tight re-solve of the finest level (None where a run's tight solve failed)."""
        try:
            return fn("tight")
        except KeyError:
            return None

    note = "; ".join(f"{k}: {v}" for k, v in tight_notes.items())

    subsurface = None
    if {"small", "convective"} <= set(by_kin):
        from workbench.scenes.convective import convective_theory

        ls, lc = by_kin["small"], by_kin["convective"]
        conv_fine = outcomes[lc][(h_fine, W_max)]
        sol = convective_theory(conv_fine, n_plot=_THEORY_N_PLOT)
        w_conv = curve_moment_half_width(sol.x, sol.p_converged)
        w_class = curve_moment_half_width(sol.x, sol.p_classical)
        # the theory's own error: its classical moment on the same grid against the closed form (wedge
        # b0/sqrt(6), parabola b0/2); measured 5.3e-6 (wedge, log apex) and 1.4e-9 (parabola)
        exact_class = wedge_moment_half_width(1.0) if conv_fine.theory.kind == "wedge" else 0.5
        theory_err = abs(w_class - exact_class) / exact_class
        for key, q in (("b_over_b0", "half_width"), ("b_over_b0_moment", "moment")):
            fh, fw = series(lambda k, q=q: meas[lc][k][q] / meas[ls][k][q])
            theory = sol.b_over_b0_converged if q == "half_width" else w_conv / w_class
            alt = ("first order", sol.b_over_b0_first_order if q == "half_width"
                   else curve_moment_half_width(sol.x, sol.p_first_order) / w_class)
            ft = tight(lambda k, q=q: meas[lc][k][q] / meas[ls][k][q])
            budget[key] = _study(levels, widths, fh, fw, theory, alt, tight=ft, tight_note=note,
                                 theory_uncertainty=theory_err if q == "moment" else None,
                                 formal_order=_formal(q))
    else:
        for run in case.runs():
            if run.solver.kinematics != "small":
                continue
            fine = outcomes[run.label][(h_fine, W_max)]
            th = fine.theory
            a_h = th.half_width
            suffix = "" if len(case.runs()) == 1 else f"[{run.label}]"
            if th.kind == "wedge":  # classical wedge: half-widths only (the peak is log-singular)
                # p = (E* m / pi) arccosh(b/|x|): 2 sqrt(M2/M0) = 2 b / sqrt(6) (analytic.wedge)
                theory = {"half_width": 1.0, "moment": 2.0 * wedge_moment_half_width(1.0)}
                for q, name in (("half_width", "half_width"), ("moment", "half_width_moment")):
                    scale = 2.0 if q == "moment" else 1.0
                    fh, fw = series(lambda k, q=q, s=scale, m=meas[run.label]: s * m[k][q])
                    ft = tight(lambda k, q=q, s=scale, m=meas[run.label]: s * m[k][q])
                    budget[name + suffix] = _study(levels, widths, fh, fw, theory[q], None, tight=ft, tight_note=note,
                                                   formal_order=_formal(q))
                continue
            if run.geometry.indenter == "circle":
                ex = exact_circle(th)
                theory = {"p_max": ex.p0 / th.p_ref, "half_width": ex.half_width / a_h,
                          "moment": 2.0 * circle_moment_half_width(b=ex.half_width, R=th.R, E_star=th.E_star) / a_h}
                alt = {"p_max": ("hertz", 1.0), "half_width": ("hertz", 1.0), "moment": ("hertz", 1.0)}
            else:
                theory = {"p_max": 1.0, "half_width": 1.0, "moment": 1.0}
                alt = {}
            for q, name in (("p_max", "p_max"), ("half_width", "half_width"), ("moment", "half_width_moment")):
                scale = 2.0 if q == "moment" else 1.0  # Hertz: sqrt(M2/M0) = a/2
                fh, fw = series(lambda k, q=q, s=scale, m=meas[run.label]: s * m[k][q])
                ft = tight(lambda k, q=q, s=scale, m=meas[run.label]: s * m[k][q])
                budget[name + suffix] = _study(levels, widths, fh, fw, theory[q], alt.get(q), tight=ft,
                                               tight_note=note, formal_order=_formal(q))
            interior = {k: _interior(outcomes[run.label][k]) for k in (*grid, "tight") if k in outcomes[run.label]}
            budget.update(_interior_rows(levels, widths, interior, suffix=suffix))
            if subsurface is None:
                subsurface = _subsurface(fine)
                subsurface["summary"]["interior"] = _interior_summary(levels, W_max, interior, fine)
                by = {f"W={W:g},h={h:g}": _subsurface(outcomes[run.label][(h, W)])["summary"]["max_abs_error_over_p0"]
                      for h, W in grid if (h, W) != (h_fine, W_max)}
                subsurface["summary"]["max_abs_error_over_p0_other_runs"] = by
    return SceneBudget(budget, subsurface, title=_TITLE)


def _exact_hertz_field(th, nu: float):
    """McEwen's field (Hertz a, p0 at the measured load) in the mesh frame: ``(x, y) -> (sxx, syy, sxy, szz)``.

    FEM y (up) = -z; the half-plane's s_zz is the FEM s_yy, its out-of-plane s_yy the FEM s_zz; its s_xz (Johnson's
    sign) equals the FEM s_xy (checked against Flamant's field far from the contact)."""

    def exact(x, y):
        ex = hertz_subsurface_stress(x, -np.asarray(y), a=th.half_width, p0=th.p_ref, nu=nu)
        return ex.sxx, ex.szz, ex.sxz, ex.syy

    return exact


def _vm_max_exact(nu: float) -> tuple[float, float]:
    """Largest von Mises stress of McEwen's field (over p0) and its depth (over a): on the axis (checked on an
    801 x 801 grid of |x|, z <= 4 a: the maximum is on the axis), sampled every 1e-5 a."""
    z = np.linspace(0.0, SUBSURFACE_DEPTH, 400001)
    vm = von_mises_plane_strain(hertz_subsurface_stress(np.zeros_like(z), z, a=1.0, p0=1.0, nu=nu))
    i = int(np.argmax(vm))
    return float(vm[i]), float(z[i])


class _Interior(NamedTuple):
    """One run's interior error (MPa, mm) with its Hertz scales a (mm), p0 (MPa) and nu."""

    l2: float
    vm_max_fem: float
    at_fem: tuple[float, float]
    a: float
    p0: float
    nu: float


def _interior(outcome) -> _Interior:
    """Interior stress error of a Hertz run over |x|, z <= INTERIOR_BOX a (fem.interior)."""
    from fem.interior import interior_stress_error

    th, nu = outcome.theory, outcome.run.material.nu
    a = th.half_width
    e = interior_stress_error(outcome.result, _exact_hertz_field(th, nu), x_max=INTERIOR_BOX * a,
                              z_max=INTERIOR_BOX * a)
    return _Interior(e.l2, e.vm_max_fem, e.at_fem, a, th.p_ref, nu)


def _rate(levels, errors) -> float | None:
    """Least-squares slope of log(error) against log(h) over the levels (None when an error is not > 0)."""
    e = np.asarray(errors, dtype=float)
    if not np.all(e > 0):
        return None
    return float(np.polyfit(np.log(np.asarray(levels, dtype=float)), np.log(e), 1)[0])


def _interior_rows(levels, widths, interior: dict, *, suffix: str) -> dict:
    """Budget rows of the interior field: the L2 (RMS) stress error over p0 on the three grids (a norm of an
    error: its observed rate, no extrapolation) and the largest von Mises stress over p0 (a value: the full study,
    theory McEwen's maximum)."""
    W_max, h_fine = max(widths), min(levels)
    l2 = [interior[(h, W_max)].l2 / _p0(interior, h, W_max) for h in levels]
    rate = _rate(levels, l2)
    rows = {f"interior_stress_l2{suffix}": {
        "fine": l2[0], "extrapolated": None, "observed_order": rate, "gci": None, "truncation": None,
        "theory": 0.0, "theory_in_band": None,
        "status": (f"error norm over abs(x), z <= {INTERIOR_BOX:g} a: RMS(sigma_h - sigma_McEwen) / p0 = "
                   + ", ".join(f"{v:.2e}" for v in l2) + f" at h_c/a = {', '.join(f'{h:g}' for h in levels)}; "
                   + ("rate n/a" if rate is None else f"rate {rate:.2f}")),
        "by_h": dict(zip([str(v) for v in levels], l2, strict=True)),
    }}
    vm_exact, _ = _vm_max_exact(interior[(h_fine, W_max)].nu)
    fh = [interior[(h, W_max)].vm_max_fem / _p0(interior, h, W_max) for h in levels]
    fw = [interior[(h_fine, W)].vm_max_fem / _p0(interior, h_fine, W) for W in widths]
    t = interior.get("tight")
    rows[f"vm_max{suffix}"] = _study(levels, widths, fh, fw, vm_exact, None,
                                     tight=None if t is None else t.vm_max_fem / t.p0)
    return rows


def _p0(interior, h, W):
    return interior[(h, W)].p0


def _interior_summary(levels, W_max, interior: dict, fine) -> dict:
    th = fine.theory
    a, p0 = th.half_width, th.p_ref
    vm_exact, z_exact = _vm_max_exact(fine.run.material.nu)
    f = interior[(min(levels), W_max)]
    return {"box_over_a": INTERIOR_BOX, "far_field": BUDGET_FAR_FIELD, "width_factor": W_max,
            "l2_over_p0_by_h": {str(h): interior[(h, W_max)].l2 / interior[(h, W_max)].p0 for h in levels},
            "l2_rate": _rate(levels, [interior[(h, W_max)].l2 for h in levels]),
            "vm_max_fem_over_p0": f.vm_max_fem / p0, "vm_max_fem_at_over_a": [f.at_fem[0] / a, -f.at_fem[1] / a],
            "vm_max_exact_over_p0": vm_exact, "vm_max_exact_depth_over_a": z_exact}


def _subsurface(outcome) -> dict:
    """Stresses on the symmetry axis of a Hertz run against McEwen's closed form (Hertz a, p0 at the
    measured load); FEM y = -z."""
    from fem.probe import stress_at_points

    th = outcome.theory
    a, p0, nu = th.half_width, th.p_ref, outcome.run.material.nu
    z = np.linspace(0.0, SUBSURFACE_DEPTH * a, SUBSURFACE_POINTS)
    fem = stress_at_points(outcome.result, np.column_stack([np.zeros_like(z), -z]))
    ex = hertz_subsurface_stress(np.zeros_like(z), z, a=a, p0=p0, nu=nu)
    vm_ex = von_mises_plane_strain(ex)
    cols = {"z_mm": z, "sxx_fem": fem.sxx, "syy_fem": fem.syy, "szz_fem": fem.szz, "vm_fem": fem.vm,
            # FEM y (vertical) is the half-plane's z; FEM zz (out of plane) is the half-plane's yy
            "sxx_exact": ex.sxx, "syy_exact": ex.szz, "szz_exact": ex.syy, "vm_exact": vm_ex}
    err = {k: float(np.nanmax(np.abs(cols[f"{k}_fem"] - cols[f"{k}_exact"]))) / p0
           for k in ("sxx", "syy", "szz", "vm")}
    i_f, i_e = int(np.nanargmax(fem.vm)), int(np.argmax(vm_ex))
    summary = {
        "a_mm": a, "p0_MPa": p0, "points": SUBSURFACE_POINTS, "depth_over_a": SUBSURFACE_DEPTH,
        "h_contact": outcome.run.discretisation.h_contact, "width_factor": outcome.run.geometry.width_factor,
        "max_abs_error_over_p0": err,
        "vm_max_fem_over_p0": float(fem.vm[i_f]) / p0, "z_vm_max_fem_over_a": float(z[i_f]) / a,
        "vm_max_exact_over_p0": float(vm_ex[i_e]) / p0, "z_vm_max_exact_over_a": float(z[i_e]) / a,
        "nan_points": int(np.count_nonzero(~np.isfinite(fem.vm))),
    }
    return {"columns": cols, "summary": summary}
