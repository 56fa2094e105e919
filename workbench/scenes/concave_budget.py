"""Error budget of a concave case: every step's P, peak pressure, patch loads and widths over three grids.

The scene is solved again on the three ``[discretisation] budget_levels`` (h_c as a fraction of the smallest
predicted patch half-width), the grading refined with them (``growth - 1`` proportional to h_c, the case's
growth on the coarsest level: every element shrinks by the same factor). Each quantity goes through
:func:`workbench.error_budget.grid_study` in h (fine value, Richardson value, observed order, GCI, named status).

The concave body is the real geometry, not a truncated half-plane: ``truncation`` is 0. The finest level is
solved once more with every solver tolerance divided by ``TIGHTENING`` (:func:`workbench.error_budget.
tight_resolve`): ``iterative`` = |f_tight - f| / |f| (floored at ``ITERATIVE_FLOOR``, the tight solve's own
tolerance), ``roundoff`` = ``ROUNDOFF_FLOOR`` (1e-9 relative), and the band is ``uncertainty |fine|`` with
``uncertainty = gci + iterative + roundoff``. The grid study is told the row's theory: a sequence that crosses
it is "crossing" (no extrapolation; the band is the spread). Rows, per step ``stepN (d = ... mm)`` (and per
patch k where the patch count is the same on all three grids; otherwise one ``patches`` row names the counts,
nothing is studied):

* ``P`` (the load, with ``load_balance_by_h`` = |P - P_pressure| / P on every grid) and ``p_max``: no theory;
* ``patch_P[k]``: the patch's load (int p ds over the patch): no theory;
* ``width_fem[k]``: zero-crossing width; theory eq. (4) ``4 P / (pi p0)`` of the fine grid (the Hertz width of
  the patch's own load and peak);
* ``width_moment[k]``: ``4 sqrt(M2/M0)`` of the patch pressure (smooth; = 2a for a Hertz patch); theory eq. (5)
  ``2 sqrt(4 P R / (pi E*))``, Hertz with the relative radius R of the one LCP pair in the patch at the
  patch's extrapolated load (null when the patch holds no pair or several);
* ``load_symmetry``: ``patch_P[1] / patch_P[0]`` where the step has two patches, each holding one LCP pair,
  and the two pairs are mirror images (equal indentation and relative radius to ``SYMMETRY_RTOL``): theory 1
  (the mirror-symmetric geometry loads both pairs equally; a solver whose contact search or projection is
  biased breaks it). The mesh is not mirror-symmetric, so the ratio reaches 1 only to the discretisation error
  of the two loads, and its three values are that error's noise (issue 22: 0.9999954, 0.99999921, 1.00000006
  on one machine, 0.9999954, 1.0000010, 0.99999976 on another). The check is therefore on the fine ratio, not
  on an extrapolation: ``extrapolated`` = the fine value (the Richardson value is kept as ``richardson``), and
  the band is the larger of the ratio's own study band and the two patch loads' uncertainties summed
  (``symmetry_band``: a ratio of two values each uncertain by u0, u1 is uncertain by u0 + u1), plus the
  iterative and round-off terms. A solution whose loads differ by more than their own discretisation error fails;
* ``first_contact_width[k]``: ``width_moment[k]`` at the first step where the patch of an LCP pair appears
  (its activation, the smallest load it carries): theory eq. (5) of that pair (Hertz's own limit), and the
  alternative eq. (4) of the same patch.
"""

from __future__ import annotations

import dataclasses
import math

from analytic import hertz, materials
from cases.schema import Case, Run
from workbench.error_budget import ROUNDOFF_FLOOR, grid_study, iterative_error, tight_resolve, uncertainty
from workbench.scenes.base import SceneBudget
from workbench.scenes.numbers import ESTIMATE, LOAD, PEAK, VERDICT, WIDTH, declare

# A row's values (fine, extrapolated, theory, alt_value) by its quantity; a row's theory is evaluated at the load the
# FEM carries (the superposition of the FEM's patch loads), so it moves with the run: physics, not theory
declare("budget", __name__, P=LOAD, patch_P=LOAD, load_symmetry=LOAD, p_max=PEAK, width_fem=WIDTH,
        width_moment=WIDTH, first_contact_width=WIDTH)
declare("budget_fields", __name__, observed_order=ESTIMATE, gci=ESTIMATE, truncation=ESTIMATE,
        theory_in_band=VERDICT, alt_in_band=VERDICT)

__all__ = ["ROUNDOFF_BAND", "SYMMETRY_RTOL", "concave_error_budget", "json_number",
           "refined_run", "step_rows", "symmetry_row"]

ROUNDOFF_BAND = ROUNDOFF_FLOOR   # relative floor of a band (issue 22: 1e-9, was 1e-12)
SYMMETRY_RTOL = 1e-9    # two LCP pairs are mirror images when delta and R agree to this (relative)
PAIR_TRACK_S = 1.0      # mm: an LCP pair is followed from step to step within this arc length
_TITLE = "Error budget (three grids; finite body, no truncation)"


def refined_run(run: Run, *, h: float, h_coarse: float) -> Run:
    """The run on level h with the grading ``1 + (growth - 1) h / h_coarse`` (every element shrinks by the
    same factor, the far field too)."""
    growth = 1.0 + (run.discretisation.growth - 1.0) * h / h_coarse
    d = dataclasses.replace(run.discretisation, h_contact=h, growth=growth)
    return dataclasses.replace(run, discretisation=d)


def json_number(v):
    """A finite float, or None (JSON null) for None/NaN/inf."""
    return None if v is None or (isinstance(v, float) and not math.isfinite(v)) else float(v)


def concave_error_budget(case: Case, *, solve, progress=print) -> SceneBudget:
    """The budget of a concave case (empty without ``budget_levels``; rows in the module docstring).

    Args:
        case: The case (its ``[discretisation] budget_levels``).
        solve: ``solve(run) -> Outcome`` (the pipeline's run, bound to the mesh cache and communicator).
        progress: One-line progress printer.
    """
    levels = sorted(case.discretisation.budget_levels)
    if not levels:
        return SceneBudget({}, title=_TITLE)
    budget: dict[str, dict] = {}
    runs: dict[str, list] = {}
    for run in case.runs():
        steps = []
        fine = None
        for h in levels:
            r_h = refined_run(run, h=h, h_coarse=levels[-1])
            o = solve(r_h)
            progress(f"[budget {run.label}] h_c = {h:g} a: {o.result.ndofs} dofs")
            steps.append(o.comparison)  # the scene's per-step measures (concave.step_measures)
            fine = fine or (r_h, o)
        o_t, how = tight_resolve(solve, fine[0], fine[1], progress=progress)
        if o_t is not None:
            progress(f"[budget {run.label}] h_c = {levels[0]:g} a at tolerances / {how:g}")
        runs[run.label] = steps
        E_star = materials.plane_strain_modulus(run.material.E, run.material.nu)
        pre = "" if len(case.runs()) == 1 else f"{run.label}/"
        budget |= _run_rows(levels, steps, E_star=E_star, pre=pre,
                            tight=None if o_t is None else o_t.comparison,
                            tight_note="" if o_t is not None else how)
    return SceneBudget(budget, title=_TITLE, runs=runs)


def step_rows(levels, steps, *, E_star: float, pre: str = "") -> dict:
    """The rows of one run from its step measures on three levels (``levels``: h fine first; ``steps[level][step]``:
    the ``steps`` entries of :func:`workbench.scenes.concave.step_measures`), without a tight re-solve: the same rows
    for the workbench's budget and for an external code's results (:mod:`workbench.external.scorers.concave`)."""
    return _run_rows(levels, steps, E_star=E_star, pre=pre)


def _run_rows(levels, steps, *, E_star: float, pre: str, tight: list | None = None, tight_note: str = "") -> dict:
    """The rows of one run from its step metrics on every level (``steps[level][step]``, fine level first);
    ``tight``: the finest level's steps solved again at the tight tolerances (None: not measured)."""
    rows: dict[str, dict] = {}
    activated: list[tuple[float, float]] = []  # LCP pairs (s, R) whose patch has appeared
    for i, fine in enumerate(steps[0]):
        per = [st[i] if i < len(st) else None for st in steps]
        if any(p is None for p in per):
            continue
        t_step = tight[i] if tight is not None and i < len(tight) else None

        def tv(fn, t_step=t_step):
            """``fn`` of the tight step (None where it is missing or its patches differ)."""
            try:
                return None if t_step is None else float(fn(t_step))
            except (KeyError, IndexError, TypeError, ZeroDivisionError):
                return None

        def row(values, theory, fn=None, **kw):
            return _row(levels, values, theory, tight=None if fn is None else tv(fn), tight_note=tight_note, **kw)

        tag = f"{pre}step{i + 1} (d = {fine['d']:g} mm)"
        for q in ("P", "p_max"):
            rows[f"{tag} {q}"] = row([p[q] for p in per], None, lambda t, q=q: t[q])
        rows[f"{tag} P"]["load_balance_by_h"] = {
            str(h): abs(p["P"] - p["P_pressure"]) / abs(p["P"]) if p["P"] else None
            for h, p in zip(levels, per, strict=True)}
        counts = {len(p["patches"]) for p in per}
        if len(counts) != 1:
            rows[f"{tag} patches"] = {"fine": float(len(fine["patches"])), "extrapolated": None,
                                      "observed_order": None, "gci": None, "truncation": 0.0, "theory": None,
                                      "theory_in_band": None,
                                      "status": f"patch count differs between levels: {sorted(counts)}"}
            continue
        pairs = fine["lcp_pairs"]
        for k, pt in enumerate(fine["patches"]):
            loads = [p["patches"][k]["P"] for p in per]
            load_row = rows[f"{tag} patch_P[{k}]"] = row(loads, None, lambda t, k=k: t["patches"][k]["P"])
            rows[f"{tag} width_fem[{k}]"] = row([p["patches"][k]["width_fem"] for p in per], pt.get("width_eq4"),
                                                lambda t, k=k: t["patches"][k]["width_fem"],
                                                theory_name="eq. (4) Hertz width")
            widths = [p["patches"][k].get("width_moment", math.nan) for p in per]
            width_t = tv(lambda t, k=k: t["patches"][k]["width_moment"])
            eq5 = None
            if len(pt["pairs"]) == 1 and load_row["extrapolated"] is not None:
                eq5 = hertz.patch_width_eq5(load_row["extrapolated"], pairs[pt["pairs"][0]]["R"], E_star)
            rows[f"{tag} width_moment[{k}]"] = _row(levels, widths, eq5, tight=width_t, tight_note=tight_note,
                                                    theory_name="eq. (5) Hertz, LCP pair R")
            for j in pt["pairs"]:
                key = (pairs[j]["s"], pairs[j]["R"])
                if any(_same_pair(key, a) for a in activated):
                    continue
                activated.append(key)
                if len(pt["pairs"]) == 1:
                    rows[f"{tag} first_contact_width[{k}]"] = _row(
                        levels, widths, eq5, tight=width_t, tight_note=tight_note,
                        theory_name="eq. (5) Hertz, LCP pair R", alt=("eq. (4)", pt.get("width_eq4")))
        sym = _mirror_pairs(fine, pairs)
        if sym:
            rows[f"{tag} load_symmetry"] = symmetry_row(
                levels, [p["patches"][1]["P"] / p["patches"][0]["P"] for p in per],
                [rows[f"{tag} patch_P[0]"], rows[f"{tag} patch_P[1]"]],
                tight=tv(lambda t: t["patches"][1]["P"] / t["patches"][0]["P"]), tight_note=tight_note)
    return rows


def symmetry_row(levels, ratios, load_rows: list[dict], *, tight: float | None = None,
                 tight_note: str = "") -> dict:
    """The ``load_symmetry`` row (module docstring): the fine ratio against 1 within the larger of its own band
    and the two patch loads' uncertainties summed (+ iterative + round-off)."""
    r = _row(levels, ratios, 1.0, tight=tight, tight_note=tight_note, theory_name="1 (mirror-symmetric LCP pairs)")
    if r["gci"] is None:
        return r
    loads = [lr.get("uncertainty") for lr in load_rows]
    sym = None if any(u is None for u in loads) else float(sum(loads))
    disc = max(r["gci"], sym or 0.0)
    total = uncertainty(disc, r["iterative"], r["roundoff"])
    r |= {"richardson": r["extrapolated"], "extrapolated": r["fine"], "symmetry_band": sym, "uncertainty": total,
          "theory_in_band": bool(abs(1.0 - r["fine"]) <= total * abs(r["fine"])),
          "error_vs_theory": abs(r["fine"] - 1.0)}
    return r


def _same_pair(a: tuple[float, float], b: tuple[float, float]) -> bool:
    """The same LCP pair at two displacements: (s, R) within PAIR_TRACK_S mm and 5 % (measured along the
    Table 1 paths: a pair moves < 0.25 mm and its R by < 0.5 %; distinct pairs are >= 2.4 mm apart)."""
    return abs(a[0] - b[0]) <= PAIR_TRACK_S and abs(a[1] - b[1]) <= 0.05 * max(abs(a[1]), abs(b[1]))


def _mirror_pairs(step: dict, pairs: list) -> bool:
    """Two patches, one LCP pair each, the two pairs with equal indentation and relative radius."""
    pts = step["patches"]
    if len(pts) != 2 or any(len(p["pairs"]) != 1 for p in pts):
        return False
    a, b = (pairs[p["pairs"][0]] for p in pts)
    return all(abs(a[k] - b[k]) <= SYMMETRY_RTOL * max(abs(a[k]), abs(b[k])) for k in ("delta", "R"))


def _row(levels, values, theory, *, tight: float | None = None, tight_note: str = "", theory_name: str | None = None,
         alt: tuple | None = None) -> dict:
    """One budget row (keys of the results contract, plus status, by_h, error_vs_theory, theory_name, alt, and
    the uncertainty terms; ``tight``: the fine value at the tight tolerances)."""
    theory = json_number(theory)
    if not all(v is not None and math.isfinite(v) for v in values):
        row = {"fine": json_number(values[0]), "extrapolated": None, "observed_order": None, "gci": None,
               "truncation": 0.0, "theory": theory, "theory_in_band": None,
               "status": "undefined (a non-finite value on a level)",
               "by_h": {str(h): json_number(v) for h, v in zip(levels, values, strict=True)}}
    else:
        iterative = iterative_error(values[0], tight)
        floor = ((iterative or 0.0) + ROUNDOFF_FLOOR) * abs(values[0])
        g = grid_study(tuple(levels), tuple(values), reference=theory, floor=floor)
        total = uncertainty(g.gci, iterative, ROUNDOFF_FLOOR)
        band = total * abs(g.fine)
        row = {"fine": g.fine, "extrapolated": g.extrapolated, "observed_order": json_number(g.observed_order),
               "gci": g.gci, "truncation": 0.0, "iterative": iterative, "roundoff": ROUNDOFF_FLOOR,
               "uncertainty": total, "theory": theory,
               "theory_in_band": None if theory is None else bool(abs(theory - g.extrapolated) <= band),
               "status": g.status, "truncation_status": "n/a (finite body)",
               "by_h": dict(zip([str(v) for v in levels], values, strict=True)),
               "error_vs_theory": None if theory is None else abs(g.extrapolated - theory) / abs(theory)}
        if alt is not None and json_number(alt[1]) is not None:
            row |= {"alt_theory": alt[0], "alt_value": float(alt[1]),
                    "alt_in_band": bool(abs(alt[1] - g.extrapolated) <= band)}
    if row.get("gci") is not None and row.get("iterative") is None:
        row["iterative_status"] = tight_note or "not measured"
    if theory is not None and theory_name:
        row["theory_name"] = theory_name
    return row
