"""Concave scenes of the close-to-conformal paper: a rigid convex particle pressed into a concave body.

Reads top to bottom: design curves -> LCP contact pairs at every displacement step (pure geometry) -> mesh
refined at the predicted pairs -> displacement-controlled FEM through the Table 1 steps -> per step: load,
peak, patches, elliptical fits, eq. (4)/(5) patch sizes and Hertz superposition against the FEM.

Pressures are plotted against the arc length s of the UNDEFORMED concave surface (mm), as in the paper.
In 2D there is no universal load-indentation law, so every Hertz prediction is evaluated at the load the
FEM patch actually carries. Units: mm, N, MPa.

Hertz superposition is evaluated two ways:
    "independent": each plausible LCP pair with an overlap gets a Hertz patch carrying the FEM load of the
        patch it lies in (split equally when one FEM patch holds several pairs) -- the paper's use of Hertz.
    "best fit": the loads of the pairs' Hertz patches are fitted by least squares to the FEM pressure: the
        best any superposition of those Hertz patches can do. If even that misses, superposition fails.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
from scipy import optimize

from analytic import hertz, materials
from analytic.fit import fit_elliptical
from analytic.superposition import ContactPair as HertzPair
from analytic.superposition import superpose
from cases.schema import Case, Run
from measures.contact import find_patches
from workbench.scenes.base import (
    CaseComparison,
    LoadPath,
    Outcome,
    SceneBudget,
    SceneMesh,
    Series,
    SolveMetrics,
    run_keys,
)
from workbench.scenes.budget_theory import moment_half_width
from workbench.scenes.concave_budget import concave_error_budget
from workbench.scenes.concave_schema import CONCAVE_SCHEMA
from workbench.scenes.numbers import DISPLACEMENT, MESH_SENSITIVE, VERDICT, Number, declare

# What step_measures writes per step (the intermediate steps' first touches span ~5 facets: their own foreign-mesh
# kinds), and the case-level Hertz checks concave_case_comparison writes (the elliptical fit's RMS and eq. (4)
# against eq. (5) move by percents with the mesh; the best superposition is an optimiser's result).
declare("step", __name__, d=DISPLACEMENT, P=Number("physics", "step_load"), P_pressure=Number("physics", "step_load"),
        p_max=Number("physics", "step_peak"), n_patches=VERDICT,
        superposition_independent_rms_over_p0=Number("error", "step_error", "unit"),
        superposition_best_rms_over_p0=MESH_SENSITIVE)
declare("case_errors", __name__, fit_rms=MESH_SENSITIVE, patch_size=MESH_SENSITIVE)

__all__ = ["ConcaveMesh", "ConcaveScene", "concave_mesh", "concave_case_comparison", "step_measures", "lcp_at",
           "scene_design"]
_SAMPLES_LCP = 300


_FAMILY: dict = {}  # (design, family) -> the member's ConcaveDesign (built and LCP-checked once per process)


def scene_design(geometry):
    """The :class:`analytic.designs.ConcaveDesign` of a run's geometry: the paper's design ``geometry.design``
    (the cached one, float for float), or the family member ``geometry.family`` of that kind
    (:func:`analytic.design_family.build`, LCP-checked; ValueError, one line, if the check fails)."""
    from analytic.designs import design

    if geometry.family is None:
        return design(geometry.design)
    key = (geometry.design, geometry.family)
    if key not in _FAMILY:
        from analytic.design_family import build
        from workbench.scenes.concave_schema import family_member

        _FAMILY[key] = build(family_member(geometry.design, geometry.family))[0]
    return _FAMILY[key]


def lcp_at(des, d: float):
    """The LCP contact pairs of a design's particle at displacement d (mm) (pure geometry)."""
    from analytic.designs import particle_at
    from analytic.lcp import find_contact_pairs

    return find_contact_pairs(des.concave, particle_at(des, d), n_samples=_SAMPLES_LCP)


def _plausible_overlap(pr) -> bool:
    """An LCP pair that is plausible, overlapping and of finite positive relative radius."""
    return pr.plausible and pr.gap < 0 and 0 < pr.relative_radius < math.inf


def _arc_length_of(curve, X: np.ndarray) -> np.ndarray:
    """Arc length (mm) along the undeformed concave curve of the material surface points X (n, 2)."""
    t = curve.project(X).t
    return curve.arc_length(t)


def _best_superposition(s, p, pairs, *, E_star, p_ref):
    """Least-squares loads (>= 0) of Hertz patches at the given pairs; returns (loads, p_fit, rms/p_ref)."""
    if not pairs:
        return [], np.zeros_like(p), math.nan
    def resid(logP):
        hp = [HertzPair(s=pr.s, R=pr.R, P=float(np.exp(lp))) for pr, lp in zip(pairs, logP, strict=True)]
        return superpose(hp, E_star=E_star, s=s).p - p

    x0 = np.log([max(pr.P, 1e-6 * p_ref) for pr in pairs])
    sol = optimize.least_squares(resid, x0, method="lm" if len(s) > len(pairs) else "trf")
    loads = np.exp(sol.x)
    fit = resid(sol.x) + p
    rms = float(np.sqrt(np.mean((fit - p) ** 2)) / p_ref)
    return loads.tolist(), fit, rms


def _step_metrics(snap, *, curve, lcp, E_star, label):
    """Per-step comparison of one FEM snapshot with Hertz theory (all at the measured patch loads)."""
    return step_measures(snap.samples, d=snap.d, P=snap.P, P_pressure=snap.P_pressure, iterations=snap.iterations,
                         curve=curve, lcp=lcp, E_star=E_star, label=label)


def step_measures(smp, *, d: float, P: float, P_pressure: float, iterations, curve, lcp, E_star: float, label: str):
    """One step's measures (the ``steps`` entry of ``metrics.json``) and its pressure :class:`Series`, from surface
    samples at the material positions ``smp.X`` (any order; the arc length is measured along the undeformed concave
    curve): patches, elliptical fits, eq. (4)/(5) widths, the Hertz superposition at the measured patch loads. Pure
    numpy (the FEM's snapshots and an external code's samples alike: :mod:`workbench.external.scorers.concave`).
    ``d`` (mm), ``P`` and ``P_pressure`` (N/mm): the step's displacement, load and pressure resultant."""
    s = _arc_length_of(curve, smp.X)
    order = np.argsort(s, kind="stable")
    smp = smp._replace(**{f: getattr(smp, f)[order] for f in smp._fields if getattr(smp, f) is not None})
    s = s[order]
    smp = smp._replace(s=s)
    patches = find_patches(smp)
    p = smp.p
    p_max = float(p.max()) if p.size else 0.0
    pairs = [pr for pr in lcp.pairs if _plausible_overlap(pr)]
    pair_s = [float(curve.arc_length(np.array([pr.t_a]))[0]) for pr in pairs]
    out_patches = []
    edges = [(pt.center - pt.half_width, pt.center + pt.half_width) for pt in patches]
    for k, pt in enumerate(patches):
        lo, hi = edges[k]
        # this patch's share of the surface: up to half-way to the neighbouring patches (p = 0 between them)
        left = -math.inf if k == 0 else 0.5 * (edges[k - 1][1] + lo)
        right = math.inf if k == len(patches) - 1 else 0.5 * (hi + edges[k + 1][0])
        own = (s >= left) & (s <= right)
        inside = (s >= lo - 0.05 * pt.half_width) & (s <= hi + 0.05 * pt.half_width)
        fit = fit_elliptical(s[inside], p[inside]) if inside.sum() >= 5 else None
        in_pairs = [k for k, sp in enumerate(pair_s) if lo <= sp <= hi]
        entry = {
            "center": pt.center, "half_width": pt.half_width, "p_max": pt.p_max, "P": pt.P,
            "width_eq4": hertz.patch_width_eq4(pt.P, pt.p_max) if pt.p_max > 0 else math.nan,
            "width_fem": 2.0 * pt.half_width,
            # smooth width from the pressure's moments, 4 sqrt(M2/M0) (= 2a for a Hertz patch): an integral of p,
            # it converges smoothly where the zero crossing (width_fem) jumps between quadrature points
            "width_moment": 4.0 * moment_half_width(s[own], p[own], smp.weight[own]),
            "fit": fit._asdict() if fit else None,
            "pairs": in_pairs,
            "width_eq5": [hertz.patch_width_eq5(pt.P, pairs[k].relative_radius, E_star) for k in in_pairs],
            "R_pairs": [pairs[k].relative_radius for k in in_pairs],
        }
        out_patches.append(entry)
    # independent superposition: each pair carries the load of its FEM patch (shared equally)
    indep = []
    for entry in out_patches:
        for k in entry["pairs"]:
            indep.append(HertzPair(s=pair_s[k], R=pairs[k].relative_radius, P=entry["P"] / len(entry["pairs"])))
    p_ref = max(p_max, 1e-300)
    if indep:
        p_indep = superpose(indep, E_star=E_star, s=s).p
        rms_indep = float(np.sqrt(np.mean((p_indep - p) ** 2)) / p_ref)
    else:
        p_indep, rms_indep = np.zeros_like(p), math.nan
    loads, p_best, rms_best = _best_superposition(s, p, indep, E_star=E_star, p_ref=p_ref)
    fit_main = max((e for e in out_patches if e["fit"]), key=lambda e: e["P"], default=None)
    metrics = {
        "label": label,
        "d": d,
        "delta_lcp": max((pr.delta for pr in pairs), default=0.0),
        "P": P,
        "P_pressure": P_pressure,
        "p_max": p_max,
        "iterations": iterations,
        "patches": out_patches,
        "n_patches": len(out_patches),
        "fit": fit_main["fit"] if fit_main else None,
        "lcp_pairs": [{"s": pair_s[k], "delta": pr.delta, "radius_convex": pr.radius_b,
                       "radius_concave": pr.radius_a, "R": pr.relative_radius} for k, pr in enumerate(pairs)],
        "lcp_intersections": len(lcp.intersections),
        "superposition_independent_rms_over_p0": rms_indep,
        "superposition_best_rms_over_p0": rms_best,
        "superposition_best_loads": loads,
    }
    predictions = {"Hertz superposition (patch loads)": p_indep, "best-fit Hertz superposition": p_best}
    if fit_main:
        f = fit_main["fit"]
        predictions["elliptical fit (main patch)"] = hertz.hertz_pressure(s, a=f["half_width"], p0=f["p_max"],
                                                                          center=f["center"])
    span = [e["center"] - e["half_width"] for e in out_patches] + [e["center"] + e["half_width"] for e in out_patches]
    if span:
        lo, hi = min(span), max(span)
        pad = max(0.3 * (hi - lo), 0.2)
        xlim = (lo - pad, hi + pad)
    else:
        xlim = (float(s.min()), float(s.max()))
    series = Series(f"{label}: d = {d:.3g} mm, P = {P:.4g} N/mm", s, p, smp.sigma_nn, predictions,
                    "s (mm, arc length of the undeformed concave surface)", xlim)
    return metrics, series


class ConcaveMesh(NamedTuple):
    """Mesh of a concave run and the geometry it was sized from.

    Attributes:
        files: The (cached) mesh files.
        design: The :class:`analytic.designs.ConcaveDesign`.
        lcps: LCP result at every displacement of the run.
        a_est: Estimated smallest patch half-width sqrt(R delta) (mm) at the first step with an overlap.
        h_contact: Element size on the refined contact zone (mm).
    """

    files: Any
    design: Any
    lcps: list
    a_est: float
    h_contact: float


def _short(values: list) -> str:
    text = repr(values)
    return text if len(text) <= 60 else text[:57] + "..."


def concave_a_est(run: Run, *, lcps=None) -> float:
    """The smallest expected patch half-width (mm), a ~ sqrt(R delta) at the first step with an overlap (the mesh
    is sized from it); ValueError if no step brings the particle into contact."""
    ld = run.loading
    des = scene_design(run.geometry)
    a_est = math.inf
    for i, d in enumerate(ld.d):
        lcp = lcps[i] if lcps is not None else lcp_at(des, d)
        for pr in lcp.pairs:
            if _plausible_overlap(pr):
                a_est = min(a_est, math.sqrt(pr.relative_radius * pr.delta))
        if math.isfinite(a_est):
            break
    if not math.isfinite(a_est):
        raise ValueError(f"{run.label}: loading.d = {list(ld.d)} never brings the particle into contact "
                         "(no overlapping plausible LCP pair); allowed: displacements that reach the body")
    return a_est


def concave_mesh(run: Run, *, name: str, mesh_cache: Path, comm, stats_dir: Path | None = None,
                 write_xdmf: bool = True) -> ConcaveMesh:
    """The (cached) mesh of a concave run, refined where the LCP predicts contact over the whole path.
    ``write_xdmf=False`` writes the gmsh ``.msh`` only (no dolfinx: ``workbench export``)."""
    from meshes.concave import build_concave_mesh

    ld, disc = run.loading, run.discretisation
    des = scene_design(run.geometry)
    lcps = [lcp_at(des, d) for d in ld.d]
    a_est = concave_a_est(run, lcps=lcps)
    h_c = disc.h_contact * a_est
    files = build_concave_mesh(design=des, h_contact=h_c, growth=disc.growth, out_dir=mesh_cache, name=name,
                               comm=comm, stats_dir=stats_dir, write_xdmf=write_xdmf)
    return ConcaveMesh(files, des, lcps, a_est, h_c)


def _run_metrics(run: Run, result, mesh: ConcaveMesh, steps: list[dict]) -> dict:
    """The run's JSON entry of ``metrics.json["runs"]``."""
    last = steps[-1]
    E_star = materials.plane_strain_modulus(run.material.E, run.material.nu)
    solved = SolveMetrics.of(result, patches=[{k: e[k] for k in ("center", "half_width", "p_max", "P")}
                                              for e in last["patches"]],
                             warnings=[w for s in steps for w in s["warnings"]])
    return run_keys(run, "concave") | {
        "design": mesh.design.name, "material_model": run.material.model,
        "h_contact_mm": mesh.h_contact, **solved.as_dict(), "mesh": mesh.files.stats, "steps": steps,
        "analytic": {"E_star": E_star, "lcp": [s["lcp_pairs"] for s in steps]},
        "errors": {"load_balance": max(abs(s["P"] - s["P_pressure"]) / abs(s["P"]) for s in steps if s["P"] > 0)},
    }


_INTERVALS: dict = {}  # design name -> refine_intervals (the preflight asks for every level)


class ConcaveScene:
    """A concave elastic body under the rigid convex particle, displacement-controlled through ``loading.d``."""

    name = "concave"
    schema = CONCAVE_SCHEMA

    def preflight(self, run: Run, *, where: str) -> None:
        """Reject a displacement path that never brings the particle into contact (pure geometry, LCP)."""
        from cases import CaseError

        try:
            des = scene_design(run.geometry)
        except ValueError as exc:
            raise CaseError(f"{where}: variant {run.label!r}: {' '.join(str(exc).split())}") from None
        # The body is |y_bottom| deep (20 mm): a particle pushed through half of it is no contact problem, and
        # the LCP of d = 1e300 overflowed and ran for more than a minute.
        d_max = 0.5 * abs(float(des.body_box[2]))
        if max(run.loading.d) > d_max:
            raise CaseError(f"{where}: variant {run.label!r}: loading.d = {_short(list(run.loading.d))} goes beyond "
                            f"half the body's depth; allowed: 0 < d <= {d_max:g} mm (Table 1 of the paper: "
                            f"{min(des.table1_d)} ... {max(des.table1_d)} mm)")
        if not any(_plausible_overlap(pr) for pr in lcp_at(des, run.loading.d[-1]).pairs):
            raise CaseError(
                f"{where}: variant {run.label!r}: loading.d = {list(run.loading.d)!r} never brings the "
                "particle into contact with the concave body; allowed: a largest displacement beyond first contact "
                f"(Table 1 of the paper starts at d = {min(des.table1_d)} mm)")


    def estimate_cells(self, run: Run) -> float:
        """Model triangle count of the run's mesh before meshing (:func:`meshes.sizing.graded_triangles`): the
        refined arcs of the concave curve (:func:`meshes.concave.refine_intervals`), graded to a tenth of the
        body's width."""
        from meshes.concave import SIZE_SAFETY, refine_intervals
        from meshes.sizing import graded_triangles

        des = scene_design(run.geometry)
        if des.name not in _INTERVALS:
            _INTERVALS[des.name] = refine_intervals(des)
        ivals = _INTERVALS[des.name]
        x_min, x_max, y_bottom = map(float, des.body_box)
        curve = des.concave
        L = sum(float(curve.arc_length([b])[0] - curve.arc_length([a])[0]) for a, b in ivals)
        area = (x_max - x_min) * (float(curve.sample(201)[:, 1].mean()) - y_bottom)
        h_c = run.discretisation.h_contact * concave_a_est(run)
        return graded_triangles(L=L, h0=SIZE_SAFETY * h_c, h_far=(x_max - x_min) / 10.0,
                                growth=run.discretisation.growth, area=area, c=len(ivals) * math.pi)
    def mesh(self, run: Run, *, name: str, mesh_cache: Path, comm, stats_dir: Path | None = None) -> SceneMesh:
        cm = concave_mesh(run, name=name, mesh_cache=mesh_cache, comm=comm, stats_dir=stats_dir)
        summary = (f"mesh {cm.files.stats.get('cells', '?')} cells ({'cached' if cm.files.cached else 'built'}), "
                   f"h_c = {cm.h_contact:.4g} mm (a_est = {cm.a_est:.4g} mm)")
        return SceneMesh(cm.files, cm, summary)

    def obstacle(self, run: Run, mesh: SceneMesh):
        from fem.obstacles import CurveObstacle

        des = mesh.estimate.design
        return CurveObstacle(des.particle, direction=tuple(des.direction))

    def load_path(self, run: Run, mesh: SceneMesh) -> LoadPath:
        ld = run.loading
        return LoadPath("displacement", ld.d[-1], ld.steps, record_at=ld.d)

    def compare(self, run: Run, result, mesh: SceneMesh, *, progress) -> Outcome:
        cm = mesh.estimate
        E_star = materials.plane_strain_modulus(run.material.E, run.material.nu)
        steps, series = [], []
        for snap, lcp in zip(result.snapshots, cm.lcps, strict=True):
            m, sr = _step_metrics(snap, curve=cm.design.concave, lcp=lcp, E_star=E_star, label=run.label)
            m["warnings"] = list(snap.warnings)
            for w in snap.warnings:
                progress(f"[{run.label}] d = {snap.d:.3g} mm: WARNING: {w}")
            steps.append(m)
            series.append(sr)
        return Outcome(run.label, run, _run_metrics(run, result, cm, steps), series, None, steps, result)

    def judge(self, case: Case, outcomes: list[Outcome]) -> CaseComparison:
        return concave_case_comparison(case, outcomes)

    def error_budget(self, case: Case, *, solve, progress) -> SceneBudget:
        """Every step's P, peak and patch widths over the three budget levels
        (:func:`workbench.scenes.concave_budget.concave_error_budget`)."""
        return concave_error_budget(case, solve=solve, progress=progress)


def concave_case_comparison(case, outcomes) -> CaseComparison:
    """Per-step table, P-delta stiffness and the superposition verdict of a concave case."""
    steps = [s for o in outcomes for s in o.comparison]
    rows = ["| d (mm) | delta LCP (mm) | P (N/mm) | p0 (MPa) | patches | 2a FEM (mm) | eq. (4) 2a (mm) | "
            "eq. (5) 2a (mm) | R (mm) | fit RMS/p0 | superposition RMS/p0 (patch loads) | best superposition RMS/p0 |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for s in steps:
        for k, e in enumerate(s["patches"] or [None]):
            if e is None:
                rows.append(f"| {s['d']:.3f} | {s['delta_lcp']:.4g} | {s['P']:.4g} | - | 0 |" + " - |" * 7)
                continue
            eq5 = ", ".join(f"{w:.3f}" for w in e["width_eq5"]) or "-"
            R = ", ".join(f"{r:.3g}" for r in e["R_pairs"]) or "-"
            fit = f"{e['fit']['rms_over_p0']:.3g}" if e["fit"] else "-"
            first = k == 0
            rows.append(
                f"| {s['d']:.3f} | {s['delta_lcp']:.4g} | {s['P']:.4g} | {e['p_max']:.4g} | {k + 1}/{s['n_patches']} | "
                f"{e['width_fem']:.3f} | {e['width_eq4']:.3f} | {eq5} | {R} | {fit} | "
                + (f"{s['superposition_independent_rms_over_p0']:.3g} | {s['superposition_best_rms_over_p0']:.3g} |"
                   if first else "| |"))
    loaded = [s for s in steps if s["P"] > 0]
    stiffness = None
    if len(loaded) >= 2:
        a, b = loaded[-2], loaded[-1]
        if b["delta_lcp"] > a["delta_lcp"]:
            stiffness = (b["P"] - a["P"]) / (b["delta_lcp"] - a["delta_lcp"])
    last = steps[-1]
    headline = (f"{len(steps)} steps; at d = {last['d']:.2f} mm: P = {last['P']:.4g} N/mm, p0 = {last['p_max']:.4g} "
                f"MPa, {last['n_patches']} patch(es); best Hertz superposition RMS/p0 = "
                f"{last['superposition_best_rms_over_p0']:.3g}")
    pd = ["| d (mm) | delta (mm) | P (N/mm) |", "|---|---|---|"] + [
        f"| {s['d']:.3f} | {s['delta_lcp']:.4g} | {s['P']:.5g} |" for s in steps]
    # Hertz checks at the first loaded step (where the paper finds the symmetric patches Hertzian):
    # eq. (4) against eq. (5) patch size, and the elliptical-fit RMS/p0 of the largest patch.
    errors = {}
    first = next((s for s in steps if s["P"] > 0 and s["patches"]), None)
    if first is not None:
        main = max(first["patches"], key=lambda e: e["P"])
        if main["width_eq5"]:
            errors["patch_size"] = abs(main["width_eq4"] - main["width_eq5"][0]) / main["width_eq5"][0]
        if main["fit"]:
            errors["fit_rms"] = main["fit"]["rms_over_p0"]
    top = {"steps": steps, "stiffness": stiffness,
           "superposition_rms_over_p0": last["superposition_best_rms_over_p0"]}
    return CaseComparison({}, errors, headline, {"Steps": rows, "Load against indentation": pd}, top)
