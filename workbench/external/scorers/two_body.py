"""Scoring two elastic bodies: an elastic cylinder on an elastic block (``elastic_cylinder``,
``elastic_cylinder_dissimilar``) and the contact patch test (``patch_test``).

Bodies: the case's ``[[body]]`` names (the first, the lower block, is the slave surface the verdict reads; the second,
the upper body, may be given too and is measured the same way for information); ``lower`` and ``upper`` (the mesh's
cell groups) are accepted for them.

**Cylinder** (the scene's own measures, :class:`workbench.scenes.two_body.TwoBodyScene`): the theory is the exact
circle's half-plane theory (:mod:`analytic.circle`) at the combined modulus ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2``
(:func:`workbench.scenes.two_body.combined_modulus`) and the level's load P (the file's column, else the pressure's
integral); per level ``p_max`` (MPa) and the edge-fit ``half_width`` (mm) of the main patch, the moment half-width
sqrt(M2/M0) about x = 0 (mm) and RMS(p - p_circle) / p0. Quantities (studied over the three finest levels, theory 1,
alternative Hertz's parabola at the same load): p_max / p0, b / b_circle, sqrt(M2/M0) over the circle's
(:func:`workbench.scenes.budget_theory.circle_moment_half_width`). Formal orders 2, 1.5, 2.

**Patch test** (stacked blocks): the exact pressure is uniform, P / W at every point of the interface
(W = ``block_width``, P the level's load). ``uniformity`` = max |p / (P/W) - 1| over the samples of the level, as the
case's own ``patch_uniformity``. It is not extrapolated (mortar carries it to round-off on every mesh); the verdict
compares the largest value over the levels with the case's tolerance (1e-8) and with the workbench's two pairings
(mortar uniform to round-off, node-to-segment not). Units: mm, N/mm, MPa.
"""

from __future__ import annotations

import numpy as np

from measures.contact import moment_half_width, rms_error
from workbench.external.results import ExternalResult, ResultError
from workbench.external.scorers.base import by_group, level_record, main_patch, study, three_finest, weights_of
from workbench.external.scorers.runs import ScoredBody, benchmark_runs

__all__ = ["TwoBodyScorer"]

FORMAL = {"p_max": 2.0, "half_width": 1.5, "half_width_moment": 2.0}
SHORT = {"p_max": "peak", "half_width": "edge half-width", "half_width_moment": "moment half-width"}


def _cylinder(case) -> bool:
    return case.runs()[0].geometry.indenter == "cylinder"


class TwoBodyScorer:
    """The two-body scene's scorer (module docstring)."""

    scene = "two_body"

    def check(self, case) -> None:
        """Every two-body case can be judged (small kinematics only: the scene's schema)."""

    def runs(self, case):
        return benchmark_runs(case, finite=False)

    def target_load(self, run) -> float | None:
        from workbench.scenes.two_body import _estimate

        return _estimate(run)[0] if run.geometry.indenter == "cylinder" else None

    def bodies(self, case):
        lower, upper = case.runs()[0].bodies
        return (ScoredBody(lower.name, "slave", ("lower",)), ScoredBody(upper.name, "master", ("upper",)))

    def symmetric(self, case) -> bool:
        return _cylinder(case)

    def check_surface(self, case, run, res: ExternalResult) -> None:
        g = run.run.geometry
        if g.indenter == "cylinder":
            from workbench.scenes.two_body import _estimate

            half_w = 0.5 * g.width_factor * _estimate(run.run)[1]
            lo, hi = -half_w, half_w
        else:
            lo, hi = 0.0, g.block_width
        tol = 1e-6 * (hi - lo)
        if float(res.x.min()) < lo - tol or float(res.x.max()) > hi + tol:
            raise ResultError(f"{res.path}: positions reach x = {float(res.x.min()):.6g} .. {float(res.x.max()):.6g} "
                              f"mm, beyond the case's contact surface ({lo:.6g} .. {hi:.6g} mm): the surface does not "
                              "match the case")

    def measure(self, case, group, *, h: float | None, samples_per_element: int) -> dict:
        res = group.result
        run = group.run.run
        w = weights_of(res)
        with np.errstate(over="ignore", under="ignore"):
            P_int = float(np.sum(w * res.p))
        if run.geometry.indenter == "stacked":
            return self._stacked(res, run, P_int, h=h, samples_per_element=samples_per_element)
        from analytic.circle import circle_contact, circle_pressure
        from analytic.hertz import hertz
        from workbench.scenes.budget_theory import circle_moment_half_width
        from workbench.scenes.two_body import combined_modulus

        pts = main_patch(res)
        main = pts.main
        rec = level_record(res, P_integral=P_int, center=main.center, half_width=main.half_width, h=h,
                           samples_per_element=samples_per_element)
        P, R, E_star = rec["P"], run.geometry.radius, combined_modulus(run)
        try:
            th = circle_contact(P, R, E_star)
        except (ValueError, ArithmeticError) as exc:
            raise ResultError(f"{res.path}: its load P = {P:.6g} N/mm is outside what the exact circle evaluates "
                              f"({' '.join(str(exc).split())[:160]}); positions in mm and pressures in MPa?") from None
        m_th = circle_moment_half_width(b=th.half_width, R=R, E_star=E_star)
        m_fe = moment_half_width(res.x, res.p, w, center=0.0)
        p_th = circle_pressure(res.x, b=th.half_width, R=R, E_star=E_star)
        hz = hertz(P, R, E_star)
        quantities = {"p_max": main.p_max / th.p0, "half_width": main.half_width / th.half_width,
                      "half_width_moment": m_fe / m_th}
        return rec | {"_curve": (res.x, res.p), "p_max": main.p_max, "half_width": main.half_width,
                      "half_width_moment": m_fe,
                      "center": main.center, "patches": len(pts.all),
                      "half_width_ratio": main.half_width / th.half_width,
                      "theory": {"kind": "exact_circle", "P": P, "E_star": E_star, "R": R, "p0": th.p0,
                                 "half_width": th.half_width, "half_width_moment": m_th,
                                 "hertz": {"p0": hz.p0, "half_width": hz.half_width}},
                      "quantities": quantities,
                      "errors": {"p_max": quantities["p_max"] - 1.0, "half_width": quantities["half_width"] - 1.0,
                                 "half_width_moment": quantities["half_width_moment"] - 1.0,
                                 "rms": rms_error(res.x, res.p, p_th, center=0.0,
                                                  half_width=max(th.half_width, main.half_width), p_ref=th.p0),
                                 "load_balance": (P_int - P) / P}}

    def _stacked(self, res: ExternalResult, run, P_int: float, *, h, samples_per_element) -> dict:
        W = run.geometry.block_width
        rec = level_record(res, P_integral=P_int, center=0.5 * W, half_width=0.5 * W, h=h,
                           samples_per_element=samples_per_element)
        p_exact = rec["P"] / W
        dev = float(np.max(np.abs(res.p / p_exact - 1.0)))
        return rec | {"_curve": (res.x, res.p), "p_max": float(np.max(res.p)), "p_uniform": p_exact,
                      "quantities": {"uniformity": dev},
                      "theory": {"kind": "uniform", "P": rec["P"], "p": p_exact},
                      "errors": {"patch_uniformity": dev, "load_balance": (P_int - rec["P"]) / rec["P"]}}

    def studies(self, case, records: list[dict]) -> dict:
        runs = {r.label: r for r in self.runs(case)}
        slave = self.bodies(case)[0].name
        out: dict = {}
        for (label, step, body), levels in by_group(records).items():
            pre = "" if len(runs) == 1 else f"{label}/"
            pre += "" if body == slave else f"{body}/"
            if not _cylinder(case):
                values = [lv["quantities"]["uniformity"] for lv in levels]
                tol = case.tolerances.get("patch_uniformity")
                out[pre + "uniformity"] = {
                    "kind": "bound", "label": "max |p / (P/W) - 1| over the interface (uniform pressure)",
                    "fine": values[0], "max": max(values), "h": [lv["h"] for lv in levels], "ratios": values,
                    "theory": 0.0, "theory_name": "the uniform pressure P / W", "tolerance": tol,
                    "within_tolerance": None if tol is None else bool(max(values) <= tol),
                    "status": "not extrapolated: the largest over the levels (round-off for a consistent method)",
                    "extrapolated": max(values),
                    "band": 0.0, "uncertainty": 0.0, "group": {"run": label, "step": step, "body": body,
                                                                 "quantity": "uniformity"}}
                continue
            if len(levels) < 3:
                continue
            fine = three_finest(levels)
            t = fine[0]["theory"]
            alt = {"p_max": t["hertz"]["p0"] / t["p0"], "half_width": t["hertz"]["half_width"] / t["half_width"],
                   "half_width_moment": 0.5 * t["hertz"]["half_width"] / t["half_width_moment"]}
            load_term = 0.5 * abs(fine[0]["errors"]["load_balance"])
            for q in FORMAL:
                out[pre + q] = study([lv["h"] for lv in fine], [lv["quantities"][q] for lv in fine], formal=FORMAL[q],
                                     theory=1.0, theory_name="the exact circle (combined modulus)",
                                     alt=("Hertz", alt[q]), load_term=load_term,
                                     label=f"{SHORT[q]} over the exact circle's at each level's load",
                                     group={"run": label, "step": step, "body": body, "quantity": q})
        return out

    def main_key(self, case, studies: dict) -> str | None:
        key = "p_max" if _cylinder(case) else "uniformity"
        return key if key in studies else next((k for k in studies if k.endswith(key)), None)
