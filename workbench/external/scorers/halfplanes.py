"""Scoring two elastic half-planes with a parabolic or wedge gap (``halfplanes_beta_neg``, ``halfplanes_beta_pos``,
``halfplanes_wedge_beta_neg``, ``halfplanes_wedge_rigid_limit``): a ``small`` and a ``convective`` run (a finite-strain
code may add a ``finite`` one).

Bodies: the case's ``[[body]]`` names (the first, the lower flat block, is the slave surface in whose material
abscissa x the pressure is read; the second, the upper body carrying the profile, may be given for information);
``lower`` and ``upper`` are accepted for them.

Per level, with the scene's own theory (:mod:`workbench.scenes.halfplanes_theory`): the classical solution at the
level's load P and the bodies' combined modulus E* (Hertz for the parabola, the classical wedge b0 = P / (E* m));
``p_max`` (parabola only: the wedge's peak is log-singular), the edge-fit ``half_width`` and the moment half-width
``2 sqrt(M2/M0)`` about x = 0; quantities: p_max / p0, b / b0, 2 sqrt(M2/M0) / b0 (theory 1, 1, and 1 or 2/sqrt(6));
RMS(p - p_classical) / p_ref. The small run is studied against the classical solution (the normal problem of two
half-planes with small kinematics does not depend on Dundurs' beta); the convective and finite runs have no classical
theory (their ratios are information and the model bands' business).

The convective ratio: ``b_over_b0[convective]`` and ``b_over_b0_moment[convective]``
(:mod:`workbench.external.scorers.convective`) against Ciavarella-Hills at the bodies' beta
(:func:`workbench.scenes.halfplanes_theory.convective_theory`). Units: mm, N/mm, MPa.
"""

from __future__ import annotations

import math

import numpy as np

from measures.contact import moment_half_width, rms_error
from workbench.external.results import ExternalResult, ResultError
from workbench.external.scorers.base import by_group, level_record, main_patch, study, three_finest, weights_of
from workbench.external.scorers.runs import ScoredBody, benchmark_runs

__all__ = ["HalfplanesScorer"]

FORMAL = {"p_max": 2.0, "half_width": 1.5, "half_width_moment": 2.0}
SHORT = {"p_max": "peak", "half_width": "edge half-width", "half_width_moment": "moment half-width"}


class HalfplanesScorer:
    """The two-half-planes scene's scorer (module docstring)."""

    scene = "halfplanes"

    def check(self, case) -> None:
        """Every half-planes case can be judged (a small and a convective run: the scene's schema)."""

    def runs(self, case):
        return benchmark_runs(case, finite=True)

    def target_load(self, run) -> float:
        from workbench.scenes.halfplanes import _estimate

        return _estimate(run)[0]

    def bodies(self, case):
        lower, upper = case.runs()[0].bodies
        return (ScoredBody(lower.name, "slave", ("lower",)), ScoredBody(upper.name, "master", ("upper",)))

    def symmetric(self, case) -> bool:
        return True

    def check_surface(self, case, run, res: ExternalResult) -> None:
        from workbench.scenes.halfplanes import _estimate

        half_w = 0.5 * run.run.geometry.width_factor * _estimate(run.run)[1]
        far = float(np.max(np.abs(res.x)))
        if far > half_w * (1.0 + 1e-6):
            raise ResultError(f"{res.path}: positions reach |x| = {far:.6g} mm, beyond the case's blocks "
                              f"(|x| <= W/2 = {half_w:.6g} mm): the surface does not match the case")

    def measure(self, case, group, *, h: float | None, samples_per_element: int) -> dict:
        from workbench.scenes.halfplanes_theory import classical_theory

        res, run = group.result, group.run.run
        w = weights_of(res)
        pts = main_patch(res)
        main = pts.main
        with np.errstate(over="ignore", under="ignore"):
            P_int = float(np.sum(w * res.p))
        rec = level_record(res, P_integral=P_int, center=main.center, half_width=main.half_width, h=h,
                           samples_per_element=samples_per_element)
        P = rec["P"]
        try:
            th = classical_theory(run, P)
        except (ValueError, ArithmeticError) as exc:
            raise ResultError(f"{res.path}: its load P = {P:.6g} N/mm is outside what the classical theory evaluates "
                              f"({' '.join(str(exc).split())[:160]}); positions in mm and pressures in MPa?") from None
        if not all(math.isfinite(v) and v > 0 for v in (th.half_width, th.p_ref)):
            raise ResultError(f"{res.path}: its load P = {P:.6g} N/mm gives a theory half-width {th.half_width:.3g} "
                              "mm; allowed: a load whose theory is finite and > 0")
        moment = 2.0 * moment_half_width(res.x, res.p, w, center=0.0)
        quantities = {"half_width": main.half_width / th.half_width, "half_width_moment": moment / th.half_width}
        if th.kind == "parabola":
            quantities = {"p_max": main.p_max / th.p_ref} | quantities
        errors = {"half_width": main.half_width / th.half_width - 1.0, "half_width_moment": moment / th.moment - 1.0,
                  "rms": rms_error(res.x, res.p, th.pressure(res.x), center=0.0,
                                   half_width=max(th.half_width, main.half_width), p_ref=th.p_ref),
                  "load_balance": (P_int - P) / P}
        if th.kind == "parabola":
            errors["p_max"] = main.p_max / th.p_ref - 1.0
        return rec | {"_curve": (res.x, res.p), "p_max": main.p_max, "half_width": main.half_width,
                      "half_width_moment": moment,
                      "center": main.center, "patches": len(pts.all),
                      "half_width_ratio": main.half_width / th.half_width,
                      "theory": {"kind": "hertz" if th.kind == "parabola" else "wedge", "P": P, "E_star": th.E_star,
                                 "beta": th.beta, "half_width": th.half_width, "moment": th.moment, "p0": th.p_ref,
                                 "R": th.R, "m": th.m, "name": th.name},
                      "quantities": quantities, "errors": errors}

    def studies(self, case, records: list[dict]) -> dict:
        runs = {r.label: r for r in self.runs(case)}
        slave = self.bodies(case)[0].name
        groups = by_group(records)
        out: dict = {}
        for (label, step, body), levels in groups.items():
            if len(levels) < 3:
                continue
            fine = three_finest(levels)
            t = fine[0]["theory"]
            wedge = t["kind"] == "wedge"
            theory = {"half_width": 1.0, "half_width_moment": 2.0 / math.sqrt(6.0) if wedge else 1.0}
            if not wedge:
                theory = {"p_max": 1.0} | theory
            small = runs[label].kinematics == "small"
            load_term = (1.0 if wedge else 0.5) * abs(fine[0]["errors"]["load_balance"])
            pre = f"{label}/" + ("" if body == slave else f"{body}/")
            for q, th in theory.items():
                out[pre + q] = study([lv["h"] for lv in fine], [lv["quantities"][q] for lv in fine], formal=FORMAL[q],
                                     theory=th if small else None,
                                     theory_name=f"{t['name']} at E* (the level's load)", load_term=load_term,
                                     label=f"{SHORT[q]} over the classical theory's at each level's load",
                                     group={"run": label, "step": step, "body": body, "quantity": q})
        slave_groups = {k: v for k, v in groups.items() if k[2] == slave}
        from workbench.external.scorers.convective import THEORY_N_PLOT, convective_studies
        from workbench.scenes.halfplanes_theory import HalfplanesTheory, convective_theory

        def solve(fine: dict, srun):
            t = fine["theory"]
            th = HalfplanesTheory("wedge" if t["kind"] == "wedge" else "parabola", t["P"], t["R"], t["E_star"],
                                  t["half_width"], t["p0"], t["beta"], t["m"], t["moment"])
            return convective_theory(th, n_plot=THEORY_N_PLOT)

        kinds = {lv[0]["theory"]["kind"] for lv in slave_groups.values() if lv}
        return out | convective_studies(runs, slave_groups, solve=solve,
                                        sensitivity=0.5 if kinds == {"hertz"} else 1.0)

    def main_key(self, case, studies: dict) -> str | None:
        for key in ("b_over_b0_moment[convective]", "b_over_b0_moment[finite]", "small/half_width_moment"):
            if key in studies:
                return key
        return next(iter(studies), None)
