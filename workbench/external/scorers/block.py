"""Scoring the block scene: an elastic block under a rigid circle, parabola or wedge (``hertz_cylinder``,
``hertz_augmented_lagrangian``, ``wedge``, ``parabola_convective``, ``wedge_convective``).

Per level (one run, one body: the block's top; every measure from :mod:`measures.contact`, as the FEM pipeline):

* ``P``: the file's load column, else ``P_integral`` = the integral of the pressure (the file's ``weight_mm``, else
  the trapezoid rule), N/mm; ``load_balance`` = (P_integral - P) / P;
* ``p_max`` (MPa): the largest sample of the main patch (the one carrying the largest load); ``half_width`` (mm): the
  edge fit of that patch (square-root edge model, :func:`measures.contact.contact_edges`); ``half_width_moment``
  (mm): 2 sqrt(M2/M0) about x = 0 (= a for a Hertz pressure, 2 b / sqrt(6) for the wedge's);
* the theory at the level's load P (:func:`workbench.scenes.block_theory.block_theory`: Hertz for a circle or
  parabola, the classical wedge b = P / (E* m)); for a circle also the exact circle (:mod:`analytic.circle`, the
  case's own theory; Hertz is its parabolic approximation): relative errors and RMS(p - p_theory) / p_ref
  (:func:`measures.contact.rms_error`, as the FEM's rms);
* ``quantities``: ``p_max`` = p_max / p0 (Hertz), ``half_width`` = half-width / a, ``half_width_moment`` = the moment
  half-width / a (the wedge: half-widths over b only; its peak is log-singular).

Studies (three finest levels of a run): each quantity against the case's theory in the same ratio: the exact circle
(p0, b, 2 sqrt(M2/M0) of the circle's pressure over Hertz's at the finest level's load; alternative Hertz, 1), Hertz
(1) for a parabola, the classical wedge (1 and 2/sqrt(6)). Formal orders 2 (peak, moment) and 1.5 (edge).

Convective pairs (a ``small`` and a ``convective`` or ``finite`` run at one load; levels paired fine with fine):
``b_over_b0[convective]`` = (b_conv / b0(P_conv)) / (b_small / b0(P_small)) from the edges, as
:func:`workbench.scenes.convective.fem_b_over_b0`, and ``b_over_b0_moment[...]`` from the moment half-widths, against
Ciavarella-Hills converged at the block's beta and the finest convective level's load (first order the alternative:
its closed-form edge ratio, the moment ratio of its pressure; :func:`workbench.scenes.convective.convective_theory`
on the budget's 64001-point grid). A ``finite`` run's ratio is the same measure: finite strain holds the convective
effect (the surface moves before it meets the indenter) and more (the traction along the deformed normal, a
nonlinear bulk): the workbench's obstacle/finite model band says how far that is from the convective theory here.
Units: mm, N/mm, MPa.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from measures.contact import moment_half_width, rms_error
from workbench.external.results import ExternalResult, ResultError
from workbench.external.scorers.base import (
    ScoreError,
    by_group,
    level_record,
    main_patch,
    study,
    three_finest,
    weights_of,
)
from workbench.external.scorers.runs import ScoredBody, benchmark_runs

__all__ = ["BlockScorer", "theory_at", "FORMAL"]

FORMAL = {"p_max": 2.0, "half_width_moment": 2.0, "half_width": 1.5}
SHORT = {"p_max": "peak", "half_width": "edge half-width", "half_width_moment": "moment half-width",
         "b_over_b0": "ratio b/b0 (edges)", "b_over_b0_moment": "moment ratio b/b0"}


def theory_at(geometry, material, P: float, *, where: str):
    """The case's classical theory at the level's load ``P``; ResultError (one line) where it cannot be evaluated
    (a load of 0, or beyond what a half-plane under the indenter carries: a file in other units?)."""
    from workbench.scenes.block_theory import block_theory

    if not (math.isfinite(P) and P > 0):
        raise ResultError(f"{where}: its load P = {P:.6g} N/mm; allowed: a finite load > 0 (a pressure that "
                          "integrates to 0: all weights 0?)")
    try:
        th = block_theory(geometry, material, P=P)
        if geometry.indenter == "circle":
            from analytic.circle import circle_contact

            circle_contact(P, th.R, th.E_star)
    except (ValueError, ArithmeticError) as exc:
        raise ResultError(f"{where}: its load P = {P:.6g} N/mm is outside what the case's theory evaluates "
                          f"({' '.join(str(exc).split())[:160]}); positions in mm and pressures in MPa?") from None
    if not all(math.isfinite(v) and v > 0 for v in (th.half_width, th.p_ref)):
        raise ResultError(f"{where}: its load P = {P:.6g} N/mm gives a theory half-width {th.half_width:.3g} mm and "
                          f"peak {th.p_ref:.3g} MPa; allowed: a load whose theory is finite and > 0")
    return th


def _target(run):
    from workbench.scenes.block_theory import block_theory

    ld = run.loading
    return (block_theory(run.geometry, run.material, P=ld.P) if ld.P is not None
            else block_theory(run.geometry, run.material, half_width=ld.half_width))


class _Outcome(NamedTuple):
    """What :func:`workbench.scenes.convective.convective_theory` reads of an outcome."""

    theory: object
    run: object


class BlockScorer:
    """The block scene's scorer (module docstring)."""

    scene = "block"

    def check(self, case) -> None:
        finite = [r.label for r in case.runs() if r.solver.kinematics == "finite"]
        if finite:
            raise ScoreError(f"case {case.name}: run(s) {', '.join(finite)} have finite kinematics, which the case "
                             "compares in the current configuration; a result gives reference positions (allowed: a "
                             "case whose runs are small or convective; an external finite run is added to those)")

    def runs(self, case):
        return benchmark_runs(case, finite=True)

    def target_load(self, run) -> float:
        return _target(run).P

    def bodies(self, case):
        return (ScoredBody("body", "slave", ("block",)),)

    def symmetric(self, case) -> bool:
        return True

    def check_surface(self, case, run, res: ExternalResult) -> None:
        """ResultError when the positions leave the block top (|x| <= W/2)."""
        half_w = 0.5 * run.run.geometry.width_factor * _target(run.run).half_width
        far = float(np.max(np.abs(res.x)))
        if far > half_w * (1.0 + 1e-6):
            raise ResultError(f"{res.path}: positions reach |x| = {far:.6g} mm, beyond the case's block top "
                              f"(|x| <= W/2 = {half_w:.6g} mm): the surface does not match the case")

    def measure(self, case, group, *, h: float | None, samples_per_element: int) -> dict:
        res = group.result
        geometry, material = group.run.run.geometry, group.run.run.material
        x, p = res.x, res.p
        w = weights_of(res)
        pts = main_patch(res)
        main = pts.main
        with np.errstate(over="ignore", under="ignore"):
            P_int = float(np.sum(w * p))
        rec = level_record(res, P_integral=P_int, center=main.center, half_width=main.half_width, h=h,
                           samples_per_element=samples_per_element)
        P = rec["P"]
        th = theory_at(geometry, material, P, where=res.path)
        hw_m = 2.0 * moment_half_width(x, p, w, center=0.0)
        hertz = th.kind == "hertz"
        moment_th = th.half_width if hertz else 2.0 * th.half_width / math.sqrt(6.0)
        errors = {
            "p_max": (main.p_max - th.p_ref) / th.p_ref if hertz else math.nan,
            "half_width": (main.half_width - th.half_width) / th.half_width,
            "half_width_moment": (hw_m - moment_th) / moment_th,
            "rms": rms_error(x, p, th.pressure(x), center=0.0, half_width=max(main.half_width, th.half_width),
                             p_ref=th.p_ref),
            "load_balance": (P_int - P) / P,
        }
        exact = None
        if geometry.indenter == "circle":  # the case's own theory: the exact circle (Hertz is its parabolic form)
            from analytic.circle import circle_contact, circle_pressure

            ex = circle_contact(P, th.R, th.E_star)
            errors["p_max_vs_exact_circle"] = (main.p_max - ex.p0) / ex.p0
            errors["half_width_vs_exact_circle"] = (main.half_width - ex.half_width) / ex.half_width
            errors["rms_vs_exact_circle"] = rms_error(
                x, p, circle_pressure(x, b=ex.half_width, R=th.R, E_star=th.E_star), center=0.0,
                half_width=max(main.half_width, ex.half_width), p_ref=ex.p0)
            exact = {"p0": ex.p0, "half_width": ex.half_width}
        quantities = {"half_width": main.half_width / th.half_width, "half_width_moment": hw_m / th.half_width}
        if hertz:
            quantities = {"p_max": main.p_max / th.p_ref} | quantities
        return rec | {"_curve": (x, p), "p_max": main.p_max, "half_width": main.half_width, "half_width_moment": hw_m,
                      "center": main.center, "patches": len(pts.all),
                      "half_width_ratio": main.half_width / th.half_width,
                      "theory": {"kind": th.kind, "P": th.P, "p0": th.p_ref, "half_width": th.half_width,
                                 "E_star": th.E_star, "R": th.R, "m": th.m, "exact_circle": exact},
                      "quantities": quantities, "errors": errors}

    def _theory_of(self, run, fine: dict) -> tuple[dict, str, tuple | None]:
        """The case's theory of each quantity (ratios), its name, and the alternative, at the finest level's load."""
        t = fine["theory"]
        if t["kind"] == "wedge":
            return {"half_width": 1.0, "half_width_moment": 2.0 / math.sqrt(6.0)}, "the classical wedge", None
        if run.geometry.indenter == "circle":
            from workbench.scenes.budget_theory import circle_moment_half_width

            ex = t["exact_circle"]
            moment = 2.0 * circle_moment_half_width(b=ex["half_width"], R=t["R"], E_star=t["E_star"])
            return ({"p_max": ex["p0"] / t["p0"], "half_width": ex["half_width"] / t["half_width"],
                     "half_width_moment": moment / t["half_width"]}, "the exact circle", ("Hertz", 1.0))
        return {"p_max": 1.0, "half_width": 1.0, "half_width_moment": 1.0}, "Hertz", None

    def studies(self, case, records: list[dict]) -> dict:
        runs = {r.label: r for r in self.runs(case)}
        own = [r for r in runs.values() if not r.added]
        groups = by_group(records)
        out: dict = {}
        for (label, step, _body), levels in groups.items():
            if len(levels) < 3:
                continue
            fine = three_finest(levels)
            srun = runs[label]
            theory, name, alt = self._theory_of(srun.run, fine[0])
            sens = 0.5 if fine[0]["theory"]["kind"] == "hertz" else 1.0  # p0, a ~ sqrt(P); the wedge's b ~ P
            load_term = sens * abs(fine[0]["errors"]["load_balance"])
            pre = "" if len(own) == 1 and label == own[0].label else f"{label}/"
            for q, th in theory.items():
                if srun.kinematics != "small":  # the classical theory ignores what this run measures: no theory
                    th_q, name_q, alt_q = None, name, None
                else:
                    th_q, name_q, alt_q = th, name, (None if alt is None else (alt[0], alt[1]))
                out[pre + q] = study([lv["h"] for lv in fine], [lv["quantities"][q] for lv in fine],
                                     formal=FORMAL[q], theory=th_q, theory_name=name_q, alt=alt_q, load_term=load_term,
                                     label=f"{SHORT[q]} over the classical theory's at each level's load",
                                     group={"run": label, "step": step, "body": _body, "quantity": q})
        out |= self._convective(case, runs, groups)
        return out

    def _convective(self, case, runs: dict, groups: dict) -> dict:
        """b/b0 of a convective (or finite) run over the small one (:mod:`workbench.external.scorers.convective`)."""
        from workbench.external.scorers.convective import THEORY_N_PLOT, convective_studies
        from workbench.scenes.block_theory import BlockTheory
        from workbench.scenes.convective import convective_theory

        def solve(fine: dict, srun):
            t = fine["theory"]
            th = BlockTheory(t["kind"], t["P"], t["E_star"], t["half_width"], t["p0"], R=t["R"], m=t["m"])
            return convective_theory(_Outcome(th, srun.run), n_plot=THEORY_N_PLOT)

        kinds = {lv[0]["theory"]["kind"] for lv in groups.values() if lv}
        return convective_studies(runs, groups, solve=solve, sensitivity=0.5 if kinds == {"hertz"} else 1.0)

    def main_key(self, case, studies: dict) -> str | None:
        for key in ("b_over_b0_moment[convective]", "b_over_b0_moment[finite]", "p_max"):
            if key in studies:
                return key
        own = [r for r in self.runs(case) if not r.added]
        for r in own:
            for q in ("p_max", "half_width_moment"):
                for key in (q, f"{r.label}/{q}"):
                    if key in studies:
                        return key
        return next(iter(studies), None)
