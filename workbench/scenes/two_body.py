"""Two-body scene: two elastic bodies on non-matching meshes, each with its own material.

Reads top to bottom: estimate -> mesh (each body its own gmsh surface and sizes, :mod:`meshes.two_body`) -> the
meshed contact partner (:class:`fem.two_body.problem.MeshedPartner`) -> the solve -> comparison. Units mm, N, MPa.

* ``indenter = "cylinder"``: an elastic half disk of radius R (the upper body, the second ``[[body]]``; driven
  through its flat top, force control) on an elastic block (the first ``[[body]]``, bottom clamped). The block's top is
  the slave surface: the gap is vertical and the contact traction acts along the vertical on both bodies, the
  half-plane idealisation (``traction = "halfplane"`` in the metrics); the initial gap is measured to the exact
  circle. Theory: the exact circle's
  half-plane theory (:mod:`analytic.circle`) at the combined modulus ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2``
  and the measured load (frictionless, small strain: the normal problem does not depend on Dundurs' beta). The
  half disk is a finite body and the block is clamped at W x H: both are idealisations of the half-plane theory,
  of the order of (a/R)^2 (measured: docs/models.md) and a/W.
* ``indenter = "stacked"``: the contact patch test (Taylor and Papadopoulos 1991). Two blocks of width W on rollers
  (bottom ``roller_y``, the x = 0 edges ``roller_x``) pressed by a uniform displacement of the upper block's top
  (displacement control): the exact solution is a uniform stress, so the contact pressure is P / W at every
  contact node. Mortar carries it to round-off on non-matching meshes; node-to-segment does not.
"""

from __future__ import annotations

import functools
import math
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from analytic.circle import circle_contact, circle_pressure
from analytic.hertz import hertz_load_from_half_width
from analytic.materials import bimaterial, composite_modulus
from cases.schema import Case, Run
from measures.contact import moment_half_width, rms_error
from workbench.scenes.base import CaseComparison, LoadPath, Outcome, SceneMesh, Series, SolveMetrics, run_keys
from workbench.scenes.budget_theory import circle_moment_half_width
from workbench.scenes.numbers import ROUNDOFF, declare
from workbench.scenes.partners import meshed_partner
from workbench.scenes.two_body_budget import two_body_error_budget
from workbench.scenes.two_body_schema import TWO_BODY_SCHEMA

__all__ = ["CylinderComparison", "TwoBodyScene", "combined_modulus", "partner_for"]

# The load path of a two-body solve: no analytic predictor; the geometric active set of the driven body's rigid
# translation, then edge-fitted active-set updates (measured on the elastic cylinder at a/R = 0.05, h = a/40: 4 Newton
# iterations per step at most, against 7 with the plain semismooth Newton update). Force control takes no extra
# first step (first_step_fraction = 1: the first solve is at d = P / (0.3 E*), the stepper's stiffness guess, which
# lands within 8 % of the load here). Measured on the elastic cylinder at a/R = 0.0125 (W = 40 a, Newton
# iterations per solve): h = a/20 [4, 1, 2, 1] with 1, [4, 3, 1, 1, 1] with 0.5, [3, 5, 1, 1, 1] with the rigid
# cases' 0.1 (whose secant from a first step at 9 % of the load overshot it by 28 %); h = a/10 [2, 1, 1, 1],
# [2, 2, 1, 1, 1] and [2, 6, 1, 1, 1]. At h = a/40 the first solve takes 8 (1) or 9 (0.5) iterations: the
# prescribed set, too large, shrinks by one node per iteration.
SOLVER_DEFAULTS = {"predictor": "extrapolate", "active_set": "geometry", "active_set_update": "edge_fit",
                   "first_step_fraction": 1.0}


# mortar's contact patch test: the uniform pressure holds to round-off (measured 3e-12), a ceiling as the balance;
# node-to-segment's deviation (patch_uniformity_node_to_segment) is an error
declare("run_errors", __name__, patch_uniformity=ROUNDOFF)

# The patch test's contact covers the whole interface by construction: these resolution warnings do not apply.
_WHOLE_SURFACE = ("contact unresolved", "contact truncated")


def combined_modulus(run: Run) -> float:
    """E* (MPa) of the two bodies: ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2`` (:mod:`analytic.materials`)."""
    lower, upper = run.bodies
    return composite_modulus(lower.E, lower.nu, E1=upper.E, nu1=upper.nu)


def _dundurs(run: Run) -> dict:
    """Dundurs' alpha and beta of the run's bodies (body 1 the upper one: the indenter; :mod:`analytic.materials`)."""
    lower, upper = run.bodies
    bm = bimaterial(E1=upper.E, nu1=upper.nu, E2=lower.E, nu2=lower.nu)
    return {"alpha": bm.alpha, "beta": bm.beta}


def partner_for(run: Run):
    """The meshed contact partner of a two-body run (the upper body, driven through its top; the cylinder's initial
    gap measured to the exact circle)."""
    from fem.two_body.geometry import CircleSurface

    g = run.geometry
    cyl = g.indenter == "cylinder"
    return meshed_partner(run, master_surface=CircleSurface((0.0, g.radius), g.radius) if cyl else None,
                          driven_components=(0, 1) if cyl else (1,))


class CylinderComparison(NamedTuple):
    """A cylinder run against the exact circle at its measured load (the error budget reads this record).

    Attributes:
        theory: The exact circle's half-plane solution (:func:`analytic.circle.circle_contact`) at the measured
            load P (N/mm) and E* (MPa).
        R: The cylinder's radius (mm).
        E_star: The combined modulus (MPa).
        p_max: The FEM's largest pressure (MPa).  half_width: its contact edge b (mm).
        moment: its moment half-width sqrt(M2/M0) (mm).  moment_theory: the exact circle's (mm).
    """

    theory: Any
    R: float
    E_star: float
    p_max: float
    half_width: float
    moment: float
    moment_theory: float

    @property
    def signed(self) -> dict:
        """FEM over theory minus 1: ``p_max``, ``half_width``, ``half_width_moment``."""
        th = self.theory
        return {"p_max": self.p_max / th.p0 - 1.0, "half_width": self.half_width / th.half_width - 1.0,
                "half_width_moment": self.moment / self.moment_theory - 1.0}


@functools.lru_cache(maxsize=256)
def _estimate(run: Run) -> tuple[float, float]:
    """(P target in N/mm, Hertz half-width a0 in mm) of a cylinder run (computed once per run: the size model and
    the mesh both read it)."""
    g, ld = run.geometry, run.loading
    E_star = combined_modulus(run)
    if ld.half_width is not None:
        return hertz_load_from_half_width(ld.half_width, g.radius, E_star), ld.half_width
    return ld.P, math.sqrt(4.0 * ld.P * g.radius / (math.pi * E_star))


class TwoBodyScene:
    """Two elastic bodies on non-matching meshes (module docstring)."""

    name = "two_body"
    schema = TWO_BODY_SCHEMA

    def preflight(self, run: Run, *, where: str) -> None:
        """Nothing beyond the case schema's checks."""

    def estimate_cells(self, run: Run) -> float:
        """Model triangle count of both bodies before meshing (:func:`meshes.sizing.graded_triangles`)."""
        from meshes.sizing import TRI_PER_H2, graded_triangles

        g, disc = run.geometry, run.discretisation
        if g.indenter == "stacked":
            h = disc.h_contact * g.block_width
            areas = g.block_width * g.height_lower / h**2 + g.block_width * g.height_upper / (g.size_ratio * h) ** 2
            return areas * TRI_PER_H2
        _, a0 = _estimate(run)
        W, H, h0 = g.width_factor * a0, g.height_factor * a0, 0.9 * disc.h_contact * a0
        block = graded_triangles(L=3 * a0, h0=h0, h_far=W / 10, growth=disc.growth, area=W * H, c=math.pi)
        disk = graded_triangles(L=3 * a0, h0=g.size_ratio * h0, h_far=W / 10, growth=disc.growth,
                                area=0.5 * math.pi * g.radius**2, c=math.pi)
        return block + disk

    def mesh(self, run: Run, *, name: str, mesh_cache: Path, comm, stats_dir: Path | None = None) -> SceneMesh:
        from meshes.two_body import build_cylinder_on_block, build_stacked_blocks

        g, disc = run.geometry, run.discretisation
        stem = f"{name}_{run.label}".replace("/", "_").replace("=", "_")
        if g.indenter == "cylinder":
            P, a0 = _estimate(run)
            files = build_cylinder_on_block(radius=g.radius, width=g.width_factor * a0, height=g.height_factor * a0,
                                            contact_half_width=a0, h_contact=disc.h_contact * a0,
                                            disk_size_ratio=g.size_ratio, growth=disc.growth, out_dir=mesh_cache,
                                            name=stem, stats_dir=stats_dir, comm=comm)
            estimate = {"P": P, "half_width": a0}
            summary = f"a0 = {a0:.4g} mm, P target = {P:.6g} N/mm"
        else:
            h = disc.h_contact * g.block_width
            files = build_stacked_blocks(width=g.block_width, height_lower=g.height_lower, height_upper=g.height_upper,
                                         h_lower=h, h_upper=g.size_ratio * h, out_dir=mesh_cache, name=stem,
                                         stats_dir=stats_dir, comm=comm)
            estimate = {"P": math.nan, "half_width": g.block_width}
            summary = f"W = {g.block_width:.4g} mm, h_lower = {h:.4g} mm, h_upper = {g.size_ratio * h:.4g} mm"
        cells = files.stats.get("cells", "?")
        return SceneMesh(files, estimate, f"mesh {cells} cells ({'cached' if files.cached else 'built'}), {summary}")

    def obstacle(self, run: Run, mesh: SceneMesh):
        return partner_for(run)

    def load_path(self, run: Run, mesh: SceneMesh) -> LoadPath:
        if run.geometry.indenter == "cylinder":
            return LoadPath("force", mesh.estimate["P"], run.loading.steps, supports={"clamped": "clamped"},
                            solver=dict(SOLVER_DEFAULTS))
        d = tuple(run.loading.d)
        return LoadPath("displacement", d[-1], run.loading.steps, record_at=d,
                        supports={"clamped": "roller_y", "symmetry": "roller_x"},
                        solver={**SOLVER_DEFAULTS, "active_set_predictor": False})

    def compare(self, run: Run, result, mesh: SceneMesh, *, progress) -> Outcome:
        g = run.geometry
        smp = result.samples
        solved = SolveMetrics.of(result, warnings=[w for w in result.warnings
                                                   if g.indenter != "stacked" or not w.startswith(_WHOLE_SURFACE)])
        metrics = {  # run_keys' traction is the case's; the two-body partner's is the half-plane's, always
            **run_keys(run, "two_body"), "indenter": g.indenter, "pairing": g.pairing, "traction": "halfplane",
            "bodies": {b.name: {"role": role, "E": b.E, "nu": b.nu, "model": b.model}
                       for b, role in zip(run.bodies, ("lower", "upper"), strict=True)},
            "E_star": combined_modulus(run), **_dundurs(run), **solved.as_dict(), "mesh": mesh.files.stats,
        }
        errors = solved.solve_errors()
        comparison = None
        if g.indenter == "cylinder":
            E_star = metrics["E_star"]
            th = circle_contact(result.P, g.radius, E_star)
            main = max(result.patches, key=lambda pt: pt.P) if result.patches else None
            comparison = CylinderComparison(
                th, g.radius, E_star, p_max=main.p_max if main else math.nan,
                half_width=main.half_width if main else math.nan,
                moment=moment_half_width(smp.s, smp.p, smp.weight, center=0.0) if main else math.nan,
                moment_theory=circle_moment_half_width(b=th.half_width, R=g.radius, E_star=E_star))
            signed = comparison.signed
            p_th = circle_pressure(smp.s, b=th.half_width, R=g.radius, E_star=E_star)
            errors |= {"p_max": abs(signed["p_max"]), "half_width": abs(signed["half_width"]),
                       "half_width_moment": abs(signed["half_width_moment"]),
                       "rms": rms_error(smp.s, smp.p, p_th, center=0.0,
                                        half_width=max(th.half_width, comparison.half_width if main else 0.0),
                                        p_ref=th.p0)}
            metrics |= {"p_max": comparison.p_max, "patch_half_width": comparison.half_width,
                        "half_width_moment": comparison.moment,
                        "analytic": {"kind": "exact_circle", "P": result.P, "E_star": E_star,
                                     "half_width": th.half_width, "p0": th.p0, "R": g.radius,
                                     "half_width_moment": comparison.moment_theory, "signed": signed}}
            predictions = {"exact circle (at measured P)": p_th}
            lim = 1.6 * th.half_width
            theory = th
        else:
            p_exact = result.P / g.block_width
            dev = float(np.max(np.abs(smp.p / p_exact - 1.0))) if smp.p.size else math.nan
            errors[("patch_uniformity" if g.pairing == "mortar" else f"patch_uniformity_{g.pairing}")] = dev
            metrics |= {"p_max": float(np.max(smp.p)) if smp.p.size else math.nan, "p_uniform": p_exact,
                        "analytic": {"kind": "uniform", "P": result.P, "p": p_exact}}
            predictions = {"uniform P / W": np.full(smp.s.size, p_exact)}
            lim = 1.05 * g.block_width
            theory = None
        metrics["errors"] = errors
        series = Series(run.label, smp.s, smp.p, smp.sigma_nn, predictions, "x (mm, material)",
                        (-lim if g.indenter == "cylinder" else 0.0, lim), weight=smp.weight, q=smp.q)
        return Outcome(run.label, run, metrics, [series], theory, comparison, result)

    def judge(self, case: Case, outcomes: list[Outcome]) -> CaseComparison:
        """The patch test names mortar's uniformity and node-to-segment's error beside it; the cylinder names
        the idealisations."""
        by_pairing = {o.run.geometry.pairing: o for o in outcomes}
        bodies = " Bodies (lower, upper): " + "; ".join(  # the case's [[body]] names, of the first run
            f"{b.name} (E = {b.E:g} MPa, nu = {b.nu:g})" for b in outcomes[0].run.bodies) + "." if outcomes else ""
        if outcomes and outcomes[0].run.geometry.indenter == "stacked":
            mortar = by_pairing.get("mortar")
            nts = by_pairing.get("node_to_segment")
            parts = []
            if mortar is not None:
                parts.append(f"mortar: uniform pressure to {mortar.metrics['errors']['patch_uniformity']:.1e}")
            if nts is not None:
                parts.append("node-to-segment: off by up to "
                             f"{100 * nts.metrics['errors']['patch_uniformity_node_to_segment']:.2f} %")
            return CaseComparison({}, {}, "Contact patch test on non-matching meshes: " + "; ".join(parts) + "."
                                  + bodies, {})
        worst = max(outcomes, key=lambda o: o.metrics["errors"].get("half_width_moment", 0.0)) if outcomes else None
        if worst is None or "analytic" not in worst.metrics:
            return CaseComparison({}, {}, "", {})
        an = worst.metrics["analytic"]
        headline = (f"Theory: the exact circle's half-plane theory at E* = {an['E_star']:.6g} MPa and the measured "
                    f"load; FEM - theory: p_max {an['signed']['p_max']:+.2e}, moment half-width "
                    f"{an['signed']['half_width_moment']:+.2e} (a/R = {an['half_width'] / an['R']:.3g}). "
                    "The elastic half disk and the clamped W x H block are the idealisations the theory leaves out."
                    + bodies)
        return CaseComparison({}, {}, headline, {})

    def error_budget(self, case: Case, *, solve, progress):
        """Three grids, three block sizes and the solver tolerance (:mod:`workbench.scenes.two_body_budget`)."""
        return two_body_error_budget(case, solve=solve, progress=progress)
