"""Two elastic half-planes with a gap profile: the FE twin of the half-plane theory of dissimilar materials
(issue 25; Ciavarella and Hills's convective effect at any Dundurs beta).

Reads top to bottom: estimate -> mesh (two graded blocks, flat at y = 0, non-matching: :func:`meshes.two_body.
build_profile_blocks`) -> the meshed contact partner (the upper block, whose reference surface is the profile
above its flat face, ``y = X1^2 / (2 R)`` or the wedge ``y = m |X1|``: :class:`fem.two_body.geometry.ProfileSurface`)
-> the solve -> comparison. Units mm, N, MPa.

* The lower block (the first ``[[body]]``, Ciavarella-Hills's body 2) is clamped at its bottom; the upper block (the
  second, their body 1, which carries the profile) is driven through its top (force control). Both are W x H
  blocks with W = H = ``width_factor`` b0: half-planes up to the truncation a/W, which the error budget
  extrapolates in 1/W.
* ``wedge_body = "shaped"`` (wedge, small kinematics): the upper body is meshed as the wedge itself, its faces
  ``y = m |x|`` the contact facets and its apex a mesh corner (``build_profile_blocks(wedge_slope=m)``); the gap is
  measured along the same vertical rays to the same ``y = m |x|``, so only the body's shape differs from the flat
  idealisation (the validity study's elastic wedge: Ciavarella-Hills's theta < pi/5 claim).
* The contact traction acts along the slave normal (vertical) on both bodies (``traction = "halfplane"``): the
  half-plane theory's frictionless surfaces. With ``small`` kinematics the pairing is fixed in the reference
  configuration: the normal problem is Hertz's at ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2`` whatever beta. With
  ``convective`` kinematics a lower-surface point meets the upper body's material point at the same current
  abscissa, and the profile travels with that point: the relative tangential displacement of dissimilar
  materials enters the gap, which is Ciavarella and Hills's model (:mod:`fem.two_body.convective`).
* ``finite`` kinematics (issue 39; :mod:`fem.two_body.finite_problem`): both bodies hyperelastic, P1 mortar in the
  current configuration, the traction along the deformed master normal (the case's ``traction = "obstacle"``).
  The upper body is meshed: a block whose lower face is the parabola ``y = X1^2 / (2 R)`` over
  ``|X1| <= PARABOLA_CAP b0`` and flat beyond (``build_profile_blocks(parabola_radius=R, parabola_cap=...)``; the
  whole parabola up to W/2, which ``workbench export`` still gives the external codes, is a nose W^2 / (8 R) tall
  whose laterally soft tip kept Newton from converging on the budget's grids: docs/models.md), and the gap is the
  distance to its deformed facets. Why not the flat block with the profile as a gap function: at
  finite strain that is no body at all. The profile's material (a layer up to ``b0^2 / (2 R)`` thick under the
  contact) would be missing from the bulk, and carrying ``h`` in the current-configuration gap needs a rule for
  where on the deformed flat face to read it (the material point of Ciavarella-Hills's eq. (8), the current abscissa
  of the pairing model, ...). That rule is exactly the modelling choice between ``profile`` and ``pairing`` that the
  finite-strain runs are meant to decide, so it cannot be an input. The meshed parabola has no such rule: every
  term of the same order as the convective effect (the geometry, the tangential displacements, the traction
  direction, the material law) comes from the one body. b/b0 is measured as for the other runs, in the lower
  body's material abscissa, with the pressure per deformed length weighted by the current slave length
  (``p weight``: the normal force per reference length of the lower body).
* The wedge's apex: the profile's slope jumps at X1 = 0. With ``apex = "refined"`` (the default) both contact lines
  have a node at x = 0, refined there as the block scene's apex, and the mortar segments are cut at the apex's
  projection (:func:`fem.two_body.geometry.mortar_points`), so no Gauss segment straddles the kink. That is exact for
  small kinematics; with the profile model the kink sits at X_m1 + delta = 0, and delta(0) = 0 by symmetry (the
  relative tangential displacement is odd in x), up to the meshes' asymmetry.
* Theory at the measured load: the classical solution at E* (small run): Hertz (parabola) or the wedge
  (:mod:`analytic.wedge`: b = P / (E* m), the peak log-singular: half-widths and RMS only); the converged
  Ciavarella-Hills solution at the bodies' beta (:func:`analytic.materials.bimaterial`, body 1 the upper one) and
  b0/R (parabola) or m (wedge), b0 the classical half-width at that load (:func:`analytic.convective.solve`); its
  first-order closed form is the alternative the bands must exclude.
  b/b0 is measured as the block scene's (:func:`workbench.scenes.convective.fem_b_over_b0`): each run's half-width
  over Hertz's at its own measured load, convective over small; both in the lower body's material abscissa.
"""

from __future__ import annotations

import functools
import math
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from analytic import wedge
from analytic.hertz import hertz_load_from_half_width
from cases.schema import Case, Run
from measures.contact import moment_half_width, rms_error
from vocabulary import FINITE, MASTER_NORMAL
from workbench.scenes.base import CaseComparison, LoadPath, Outcome, SceneMesh, Series, SolveMetrics, run_keys
from workbench.scenes.budget_theory import curve_moment_half_width
from workbench.scenes.halfplanes_budget import halfplanes_error_budget
from workbench.scenes.halfplanes_schema import HALFPLANES_SCHEMA
from workbench.scenes.halfplanes_theory import (
    HalfplanesComparison,
    HalfplanesTheory,
    bimaterial_of,
    classical_theory,
    convective_theory,
    profile_size,
)
from workbench.scenes.numbers import FRACTION_THEORY, MESH_SENSITIVE, WIDTH, declare
from workbench.scenes.partners import meshed_partner
from workbench.scenes.two_body import SOLVER_DEFAULTS

# the judge's Dundurs parameters (0 for equal materials) are fractions; the FEM's b/b0 is a measured width ratio;
# rms_convective moves by percents with the mesh
declare("analytic", __name__, alpha=FRACTION_THEORY, beta=FRACTION_THEORY, b_over_b0_fem=WIDTH,
        b_over_b0_moment_fem=WIDTH)
declare("case_errors", __name__, rms_convective=MESH_SENSITIVE)
# a case with several convective or finite runs: each one's ratios, by its tag (run_tag)
declare("analytic", __name__, **{f"b_over_b0{m}_fem_{tag}": WIDTH for m in ("", "_moment")
                                 for tag in ("profile", "pairing", "neo_hookean", "saint_venant_kirchhoff")})

APEX_FACTOR = 0.25  # a wedge's apex: element size over the contact size (as the block scene's apex_factor)
# finite strain: the meshed parabola over |X1| <= PARABOLA_CAP b0, flat beyond (a half-plane with a parabolic bump;
# module docstring)
PARABOLA_CAP = 3.0

__all__ = ["HalfplanesRun", "HalfplanesScene", "HalfplanesTheory", "bimaterial_of", "classical_theory",
           "convective_theory", "derived", "profile_size", "run_tag"]


class HalfplanesRun(NamedTuple):
    """What a run of the scene derives from its case inputs, computed once per run (:func:`derived`) and read by
    every hook (the size model, the mesh, the partner, the comparison).

    Attributes:
        bimaterial: Dundurs' alpha, beta and E* (MPa) of the bodies (body 1 the upper one).
        profile_size: The profile's R (mm) or the wedge's slope m.
        P: The target load (N/mm).
        half_width: The classical half-width b0 at the target load (mm).
    """

    bimaterial: Any
    profile_size: float
    P: float
    half_width: float


@functools.lru_cache(maxsize=256)
def derived(run: Run) -> HalfplanesRun:
    """The run's derived quantities (:class:`HalfplanesRun`; a run is a frozen record, so this is computed once)."""
    g, ld = run.geometry, run.loading
    bm, size = bimaterial_of(run), profile_size(run)
    if ld.half_width is not None:
        if g.indenter == "wedge":
            return HalfplanesRun(bm, size, wedge.wedge_load_from_half_width(ld.half_width, size, bm.E_star),
                                 ld.half_width)
        return HalfplanesRun(bm, size, hertz_load_from_half_width(ld.half_width, size, bm.E_star), ld.half_width)
    return HalfplanesRun(bm, size, ld.P, classical_theory(run, ld.P).half_width)


def run_tag(run: Run) -> str:
    """What a convective or finite run of the scene moves, as a name: its convection (``profile``, ``pairing``) or
    its bodies' law at finite strain (``neo_hookean``; ``<lower>_<upper>`` when the two differ)."""
    if run.solver.kinematics == "convective":
        return run.geometry.convection
    models = [b.model for b in run.bodies]
    return models[0] if len(set(models)) == 1 else "_".join(models)


def _estimate(run: Run) -> tuple[float, float]:
    """(P target in N/mm, classical half-width b0 in mm) of :func:`derived` (the external benchmarks and scorers
    size their meshes from it)."""
    dr = derived(run)
    return dr.P, dr.half_width


class HalfplanesScene:
    """Two elastic half-planes with a parabolic or wedge gap profile (module docstring)."""

    name = "halfplanes"
    schema = HALFPLANES_SCHEMA

    def preflight(self, run: Run, *, where: str) -> None:
        """Nothing beyond the case schema's checks."""

    def estimate_cells(self, run: Run) -> float:
        """Model triangle count of both blocks before meshing (:func:`meshes.sizing.graded_triangles`)."""
        from meshes.sizing import graded_triangles

        g, disc = run.geometry, run.discretisation
        a0 = derived(run).half_width
        W, H, h0 = g.width_factor * a0, g.height_factor * a0, 0.9 * disc.h_contact * a0
        return sum(graded_triangles(L=3 * a0, h0=r * h0, h_far=W / 10, growth=disc.growth, area=W * H, c=math.pi)
                   for r in (1.0, g.size_ratio))

    def mesh(self, run: Run, *, name: str, mesh_cache: Path, comm, stats_dir: Path | None = None) -> SceneMesh:
        from meshes.two_body import build_profile_blocks

        g, disc = run.geometry, run.discretisation
        stem = f"{name}_{run.label}".replace("/", "_").replace("=", "_")
        dr = derived(run)
        P, a0 = dr.P, dr.half_width
        apex = APEX_FACTOR if g.indenter == "wedge" and g.apex == "refined" else None
        shaped = g.indenter == "wedge" and g.wedge_body == "shaped"
        if shaped and apex is None:  # the shaped wedge's apex is a corner: a node of both contact lines
            apex = 1.0
        finite = run.solver.kinematics == FINITE  # the real parabola, meshed (module docstring)
        files = build_profile_blocks(width=g.width_factor * a0, height=g.height_factor * a0, contact_half_width=a0,
                                     h_contact=disc.h_contact * a0, size_ratio=g.size_ratio, growth=disc.growth,
                                     apex_factor=apex, wedge_slope=dr.profile_size if shaped else None,
                                     parabola_radius=dr.profile_size if finite and not shaped else None,
                                     parabola_cap=PARABOLA_CAP * a0 if finite and not shaped else None,
                                     out_dir=mesh_cache, name=stem, stats_dir=stats_dir, comm=comm)
        cells = files.stats.get("cells", "?")
        return SceneMesh(files, {"P": P, "half_width": a0},
                         f"mesh {cells} cells ({'cached' if files.cached else 'built'}), b0 = {a0:.4g} mm, "
                         f"P target = {P:.6g} N/mm")

    def obstacle(self, run: Run, mesh: SceneMesh):
        """The upper block as the meshed partner, carrying the profile (module docstring)."""
        from fem.two_body.geometry import ProfileSurface

        g = run.geometry
        if run.solver.kinematics == FINITE:  # the meshed parabola's facets, in the current configuration
            return meshed_partner(run, master_surface=None, traction=MASTER_NORMAL)
        return meshed_partner(run, master_surface=ProfileSurface(g.indenter, derived(run).profile_size),
                              traction="halfplane", convection=g.convection,
                              cut_kinks=g.indenter != "wedge" or g.apex != "none")

    def load_path(self, run: Run, mesh: SceneMesh) -> LoadPath:
        return LoadPath("force", mesh.estimate["P"], run.loading.steps, supports={"clamped": "clamped"},
                        solver=dict(SOLVER_DEFAULTS))

    def compare(self, run: Run, result, mesh: SceneMesh, *, progress) -> Outcome:
        g, smp = run.geometry, result.samples
        bm = derived(run).bimaterial
        th = classical_theory(run, result.P)
        main = max(result.patches, key=lambda pt: pt.P) if result.patches else None
        cmp = HalfplanesComparison(main.half_width if main else math.nan,
                                   moment_half_width(smp.s, smp.p, smp.weight, center=0.0) if main else math.nan,
                                   main.p_max if main else math.nan)
        p_th = th.pressure(smp.s)
        signed = cmp.signed(th)
        vs_classical = {k: abs(v) for k, v in signed.items()} | {
            "rms": rms_error(smp.s, smp.p, p_th, center=0.0,
                             half_width=max(th.half_width, cmp.half_width if main else 0.0), p_ref=th.p_ref)}
        if run.solver.kinematics != "small":  # the classical solution ignores what this run measures: info only
            vs_classical = {f"{k}_vs_classical": v for k, v in vs_classical.items()}
        solved = SolveMetrics.of(result)
        errors = solved.solve_errors() | vs_classical
        profile = {"b0_over_R": th.half_width / th.R} if th.kind == "parabola" else {"m": th.m}
        metrics = {
            **run_keys(run, "halfplanes"), "indenter": g.indenter, "pairing": g.pairing,
            "traction": MASTER_NORMAL if run.solver.kinematics == FINITE else "halfplane",
            "convection": g.convection if run.solver.kinematics == "convective" else None,
            "bodies": {b.name: {"role": role, "E": b.E, "nu": b.nu, "model": b.model}
                       for b, role in zip(run.bodies, ("lower", "upper"), strict=True)},
            "alpha": bm.alpha, "beta": bm.beta, **profile, "E_star": bm.E_star, **solved.as_dict(),
            "p_max": cmp.p_max, "patch_half_width": cmp.half_width, "half_width_moment": 2.0 * cmp.moment,
            "analytic": {"kind": "hertz" if th.kind == "parabola" else "wedge", "P": result.P, "E_star": bm.E_star,
                         "beta": bm.beta, "half_width": th.half_width, "half_width_moment": th.moment,
                         **({"R": th.R, "p0": th.p_ref} if th.kind == "parabola" else {"m": th.m, "p_mean": th.p_ref}),
                         "signed": signed},
            "errors": errors, "mesh": mesh.files.stats,
        }
        lim = 1.6 * th.half_width
        series = Series(run.label, smp.s, smp.p, smp.sigma_nn, {f"{th.name} (at measured P, E*)": p_th},
                        "x (mm, lower body's material)", (-lim, lim), weight=smp.weight, q=smp.q)
        return Outcome(run.label, run, metrics, [series], th, cmp, result)

    def judge(self, case: Case, outcomes: list[Outcome]) -> CaseComparison:
        """b/b0 of each convective or finite run over the small one against Ciavarella-Hills at the bodies' beta.

        The first convective run (else the first finite one) is the case's main comparison (``b_over_b0_fem``,
        ``b_over_b0_moment_fem``, the errors, the plot's converged pressure); with several such runs each also
        gets ``b_over_b0_fem_<tag>`` and ``b_over_b0_moment_fem_<tag>`` (:func:`run_tag`: its convection or its
        bodies' law)."""
        bodies = (" Bodies (lower, upper): " + "; ".join(f"{b.name} (E = {b.E:g} MPa, nu = {b.nu:g})"
                                                       for b in outcomes[0].run.bodies) + ".") if outcomes else ""
        small = next((o for o in outcomes if o.run.solver.kinematics == "small"), None)
        moved = [o for o in outcomes if o.run.solver.kinematics != "small"]
        if small is None or not moved:
            return CaseComparison({}, {}, bodies.strip(), {})
        moved.sort(key=lambda o: o.run.solver.kinematics != "convective")  # stable: the first convective first
        conv = moved[0]
        th = conv.theory
        sol = convective_theory(th)

        def ratios(o: Outcome) -> tuple[float, float]:
            return ((o.comparison.half_width / o.theory.half_width)
                    / (small.comparison.half_width / small.theory.half_width),
                    (o.comparison.moment / o.theory.half_width) / (small.comparison.moment / small.theory.half_width))

        ratio, ratio_m = ratios(conv)
        several = len(moved) > 1
        fem_rows = ([(f"FEM {o.run.label} ({run_tag(o.run)}) / small, {what}", r) for o in moved
                     for what, r in zip(("edge", "moment half-widths"), ratios(o), strict=True)] if several else
                    [("FEM (convective / small, same load), edge", ratio), ("FEM, moment half-widths", ratio_m)])
        rows = [*fem_rows,
                ("first order (closed form)", sol.b_over_b0_first_order),
                ("first iterate", sol.b_over_b0_first_iterate),
                ("converged (full nonlinear)", sol.b_over_b0_converged)]
        table = ["| source | b/b0 |", "|---|---|"] + [f"| {k} | {v:.5f} |" for k, v in rows]
        w_class = curve_moment_half_width(sol.x, sol.p_classical)
        moment_theory = curve_moment_half_width(sol.x, sol.p_converged) / w_class
        moment_first = curve_moment_half_width(sol.x, sol.p_first_order) / w_class
        fem_moment = ([(f"FEM {o.run.label} ({run_tag(o.run)})", ratios(o)[1]) for o in moved] if several
                      else [("FEM", ratio_m)])
        table += ["", "| moment ratio (2 sqrt(M2/M0), convective over classical) | value |", "|---|---|",
                  *(f"| {k} | {v:.5f} |" for k, v in fem_moment), f"| first order | {moment_first:.5f} |",
                  f"| converged | {moment_theory:.5f} |"]
        for o in moved:
            sr = o.series[0]
            sr.predictions["Ciavarella-Hills (converged)"] = np.interp(sr.x, sol.x * o.theory.half_width,
                                                                      sol.p_converged * o.theory.P
                                                                      / o.theory.half_width)
        sr = conv.series[0]
        rms_conv = rms_error(sr.x, sr.p, sr.predictions["Ciavarella-Hills (converged)"], center=0.0,
                             half_width=conv.comparison.half_width, p_ref=th.p_ref)
        profile = ({"b0_over_R": th.half_width / th.R} if th.kind == "parabola" else {"m": th.m})
        moduli = [b.E for b in conv.run.bodies]
        analytic = {"beta": sol.beta, "alpha": conv.metrics["alpha"], **profile,
                    "stiffness_ratio": max(moduli) / min(moduli),
                    "b_over_b0_first_order": sol.b_over_b0_first_order,
                    "b_over_b0_first_iterate": sol.b_over_b0_first_iterate,
                    "b_over_b0_converged": sol.b_over_b0_converged, "b_over_b0_fem": ratio,
                    "b_over_b0_moment_fem": ratio_m, "b_over_b0_moment_converged": moment_theory,
                    "b_over_b0_moment_first_order": moment_first, "convection": conv.metrics["convection"]}
        if several:
            for o in moved:
                r, rm = ratios(o)
                analytic |= {f"b_over_b0_fem_{run_tag(o.run)}": r, f"b_over_b0_moment_fem_{run_tag(o.run)}": rm}
        shape = f"b0/R = {th.half_width / th.R:.4g}" if th.kind == "parabola" else f"wedge m = {th.m:.6g}"
        if several:
            fems = ", ".join(f"{run_tag(o.run)} {ratios(o)[1]:.5f}" for o in moved)
            headline = (f"Two half-planes, beta = {sol.beta:+.4f}, {shape}: moment ratio b/b0 FEM {fems}; converged "
                        f"Ciavarella-Hills {moment_theory:.5f}, first order {moment_first:.5f}." + bodies)
        else:
            headline = (f"Two half-planes, beta = {sol.beta:+.4f}, {shape}, convection "
                        f"{conv.metrics['convection']!r}: moment ratio b/b0 FEM {ratio_m:.5f}, converged "
                        f"Ciavarella-Hills {moment_theory:.5f}, first order {moment_first:.5f} (edges: FEM "
                        f"{ratio:.5f}, theory {sol.b_over_b0_converged:.5f})." + bodies)
        errors = {"b_over_b0": abs(ratio / sol.b_over_b0_converged - 1.0),
                  "b_over_b0_moment": abs(ratio_m / moment_theory - 1.0), "rms_convective": rms_conv}
        return CaseComparison(analytic, errors, headline, {"Convective ratio b/b0": table})

    def error_budget(self, case: Case, *, solve, progress):
        """Three grids, three block sizes and the solver tolerance (:mod:`workbench.scenes.halfplanes_budget`)."""
        return halfplanes_error_budget(case, solve=solve, progress=progress)
