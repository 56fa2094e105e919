"""Scoring the concave scenes: a rigid convex particle pressed into a concave body through the Table 1
displacements (``concave_symmetric``, ``close_to_conformal``).

A result gives, per step (the index of the displacement d in ``[loading] d``), the pressure at reference points
(x, y) of the concave surface (columns ``x_mm`` and ``y_mm``, both needed). Per level and step, with the scene's own
code (:func:`workbench.scenes.concave.step_measures`: the one definition the workbench's runs use):

* the points are projected onto the design's concave curve (its B-spline, :mod:`analytic.designs`) and measured
  along its undeformed arc length s (mm); weights: the file's ``weight_mm``, else the trapezoid rule in s;
* ``P``: the file's load column (the particle's reaction, N/mm), else ``P_integral``: the resultant of the pressure
  along the particle's direction, sum(w p |n_o . e_d|) with n_o the particle's normal at the point closest to each
  sample (the FEM's ``P_pressure``, :mod:`fem.problem`);
* ``p_max`` (MPa), the patches (:func:`measures.contact.find_patches` in s): each patch's load ``patch_P[k]`` (N/mm),
  zero-crossing width ``width_fem[k]`` = 2 b (mm) against eq. (4) 4 P / (pi p0) of its own load and peak, and
  moment width ``width_moment[k]`` = 4 sqrt(M2/M0) (mm) against eq. (5), Hertz with the relative radius of the LCP
  pair it holds (:func:`analytic.lcp.find_contact_pairs` at the step's d) at its load; the elliptical fit; the Hertz
  superposition at the measured patch loads (independent and least-squares best, RMS / p0).

Studies (three finest levels holding every step): the concave budget's rows
(:func:`workbench.scenes.concave_budget.step_rows`): per step ``P`` and ``p_max``, per patch ``patch_P[k]``,
``width_fem[k]`` (theory eq. (4)), ``width_moment[k]`` (theory eq. (5) at the extrapolated load), at a pair's first
step ``first_contact_width[k]``, and ``load_symmetry`` (patch_P[1] / patch_P[0], theory 1) where the step's two patches
hold mirror-image LCP pairs. The verdict reads first the row the case's own ``[bands]`` judge (close_to_conformal:
the secondary pair's first-contact width against eq. (5); concave_symmetric: the last step's load symmetry), and names
every other theory row in or outside its band; the workbench's model bands say which model holds each.
Units: mm, N/mm, MPa.
"""

from __future__ import annotations

import math

import numpy as np

from measures.contact import SurfaceSamples, trapezoid_weights
from workbench.external.results import ExternalResult, ResultError
from workbench.external.scorers.base import level_record
from workbench.external.scorers.runs import ScoredBody, benchmark_runs

__all__ = ["ConcaveScorer", "SURFACE_TOLERANCE"]

SURFACE_TOLERANCE = 1e-3  # a sample's distance from the concave curve, over the body's width (a file in m: 1e-3 off)


def _design(run):
    from workbench.scenes.concave import scene_design

    return scene_design(run.geometry)


class ConcaveScorer:
    """The concave scene's scorer (module docstring)."""

    scene = "concave"

    def check(self, case) -> None:
        """Every concave case can be judged (its schedule and design come from the case)."""

    def runs(self, case):
        return benchmark_runs(case, finite=False)

    def target_load(self, run) -> None:
        return None

    def bodies(self, case):
        return (ScoredBody("body", "slave", ("concave",)),)

    def symmetric(self, case) -> bool:
        return False

    def check_surface(self, case, run, res: ExternalResult) -> None:
        """ResultError without y, or for points off the concave curve (the surface does not match the case)."""
        if res.y is None:
            raise ResultError(f"{res.path}: no y column; allowed: x_mm and y_mm, the reference position of each sample "
                              "on the concave surface (the score measures along its arc length)")
        des = _design(run.run)
        x_min, x_max, _ = map(float, des.body_box)
        proj = des.concave.project(np.column_stack([res.x, res.y]))
        far = float(np.max(np.abs(proj.distance)))
        if far > SURFACE_TOLERANCE * (x_max - x_min):
            i = int(np.argmax(np.abs(proj.distance)))
            raise ResultError(f"{res.path}: the point ({res.x[i]:.6g}, {res.y[i]:.6g}) mm is {far:.3g} mm off the "
                              f"case's concave surface (allowed: within {SURFACE_TOLERANCE * (x_max - x_min):.3g} "
                              "mm): the surface does not match the case (positions in mm?)")

    def measure(self, case, group, *, h: float | None, samples_per_element: int) -> dict:
        from analytic import materials
        from workbench.scenes.concave import lcp_at, step_measures

        res, srun = group.result, group.run
        run = srun.run
        des = _design(run)
        curve = des.concave
        X = np.column_stack([res.x, res.y])
        proj = curve.project(X)
        s = curve.arc_length(proj.t)
        order = np.argsort(s, kind="stable")
        s, X, p = s[order], X[order], res.p[order]
        w = trapezoid_weights(s) if res.weight is None else res.weight[order]
        q = p if res.q is None else res.q[order]
        d = float(run.loading.d[group.step])
        from analytic.designs import particle_at

        direction = np.asarray(des.direction, dtype=float)
        cosine = np.abs(particle_at(des, d).project(X).normal @ direction)  # the FEM's n_o: the particle's normal
        with np.errstate(over="ignore", under="ignore"):
            P_int = float(np.sum(w * p * cosine))
        smp = SurfaceSamples(s=s, X=X, x=X, p=p, q=q, sigma_nn=p, gap=np.zeros_like(s), weight=w)
        E_star = materials.plane_strain_modulus(run.material.E, run.material.nu)
        P_file = res.load if res.load is not None else P_int
        metrics, _series = step_measures(smp, d=d, P=P_file, P_pressure=P_int, iterations=None, curve=curve,
                                         lcp=lcp_at(des, d), E_star=E_star, label=srun.label)
        if not metrics["patches"]:
            raise ResultError(f"{res.path}: step {group.step} (d = {d:g} mm): no contact patch (no positive pressure "
                              "between two samples)")
        main = max(metrics["patches"], key=lambda e: e["P"])
        rec = level_record(res, P_integral=P_int, center=main["center"], half_width=main["half_width"], s=s, h=h,
                           samples_per_element=samples_per_element)
        quantities = {"P": rec["P"], "p_max": metrics["p_max"]}
        for k, e in enumerate(metrics["patches"]):
            quantities |= {f"patch_P[{k}]": e["P"], f"width_fem[{k}]": e["width_fem"],
                           f"width_moment[{k}]": e["width_moment"]}
        metrics = {k: v for k, v in metrics.items() if k not in ("iterations", "label")}
        return rec | {"_curve": (s, p), "d": d, "p_max": metrics["p_max"], "half_width": main["half_width"],
                      "patches": len(metrics["patches"]), "quantities": quantities, "step_measures": metrics,
                      "errors": {"load_balance": (P_int - rec["P"]) / rec["P"]}}

    def studies(self, case, records: list[dict]) -> dict:
        from analytic import materials
        from workbench.scenes.concave_budget import step_rows

        out: dict = {}
        runs = {r.label: r for r in self.runs(case)}
        for label, srun in runs.items():
            n_steps = len(srun.run.loading.d)
            files: dict[str, dict[int, dict]] = {}
            for rec in records:
                if rec["run"] == label and rec["body"] == "body":
                    files.setdefault(rec["file"], {})[rec["step"]] = rec
            complete = [(float(np.median([r["h"] for r in steps.values()])), steps) for steps in files.values()
                        if len(steps) == n_steps]
            complete.sort(key=lambda t: t[0])
            if len(complete) < 3 or len({h for h, _ in complete[:3]}) < 3:
                continue
            fine = complete[:3]
            levels = [h for h, _ in fine]
            steps = [[{**st[i]["step_measures"], "label": label} for i in range(n_steps)] for _h, st in fine]
            E_star = materials.plane_strain_modulus(srun.run.material.E, srun.run.material.nu)
            pre = "" if len(runs) == 1 else f"{label}/"
            for key, row in step_rows(levels, steps, E_star=E_star, pre=pre).items():
                out[key] = _as_study(row, key, label=label, h=levels)
        return out

    def main_key(self, case, studies: dict) -> str | None:
        """The row the case's own ``[bands]`` judge first (close_to_conformal: the secondary pair's first-contact
        width against eq. (5); concave_symmetric: the last step's load symmetry), else the last step's moment width of
        its first patch, else its load."""
        named = [*case.bands.get("contain_theory", ()), *case.bands.get("exclude_theory", ())]
        for name in named:
            keys = [k for k in studies if k.endswith(f" {name}") and studies[k].get("extrapolated") is not None]
            if keys:
                return keys[-1]
        for suffix in (" width_moment[0]", " P"):
            keys = [k for k in studies if k.endswith(suffix) and studies[k].get("extrapolated") is not None]
            if keys:
                return keys[-1]
        return None


def _as_study(row: dict, key: str, *, label: str, h: list[float]) -> dict:
    """A concave budget row in the scorer's study form: ``band`` = GCI |fine| and ``uncertainty`` absolute (the row's
    relative uncertainty, GCI + round-off, kept as ``uncertainty_relative``)."""
    fine = row.get("fine")
    out = dict(row) | {"label": key.split(") ", 1)[-1], "h": h, "group": {"run": label, "quantity": key},
                       "load_term": 0.0}
    if row.get("gci") is None or fine is None:
        return out | {"band": math.nan, "uncertainty": math.nan, "extrapolated": row.get("extrapolated"),
                      "status": row.get("status", "undefined")}
    out |= {"band": row["gci"] * abs(fine), "uncertainty_relative": row["uncertainty"],
            "uncertainty": row["uncertainty"] * abs(fine), "ratios": list(row["by_h"].values())}
    if row.get("theory") is not None:
        dev = row["extrapolated"] - row["theory"]
        band = out["uncertainty"]
        out |= {"deviation": dev, "outside_band": bool(abs(dev) > band),
                "remainder": math.copysign(abs(dev) - band, dev) if abs(dev) > band else 0.0}
    return out
