"""The concave scenes as benchmarks: the concave body's mesh and the rigid B-spline particle meshed as a band.

* The body: the mesh ``workbench run`` solves at the level (:func:`workbench.scenes.concave.concave_mesh`: the
  design's clamped cubic B-spline top, refined where the LCP predicts contact over the whole path), groups ``body``,
  ``contact`` (the whole spline), ``clamped`` (the sides and the bottom).
* The particle (:mod:`analytic.designs`: a B-spline lower surface closed by a circular arc; only the B-spline can
  touch): a band (:mod:`meshes.rigid_band`) along the part of its lower surface that faces the body's refined zone
  at the largest displacement (both LCP pairs and the zone where their patches merge, :func:`meshes.concave.
  refine_intervals`), widened by ``MARGIN`` of its length at each end; nodes ``C(t)`` on the exact spline, spacing
  h_c / ``BAND_REFINE`` (:data:`workbench.external.benchmarks.block.BAND_REFINE`), thickness the spacing. Groups
  ``indenter`` (cells) and ``indenter_contact``. The particle starts where the design puts it (d = 0, apart from
  the body) and moves by d along the design's direction (0, -1).

Displacement control through the case's d (the paper's Table 1 steps), each a step to report. The theory is per
step and per patch: the LCP pairs (position, overlap delta, relative radius), Hertz's patch sizes eq. (4) and (5)
and the Hertz superposition at the patch loads the result carries.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from analytic import materials
from cases.schema import Case, Run
from meshes.rigid_band import curve_band
from workbench.external.benchmark import RESULT_COLUMNS, Benchmark, Body, ContactPair, Drive, Material, Support
from workbench.external.benchmarks import surfaces
from workbench.external.benchmarks.base import Exported, band_model, finish, mesh_stats, write_model
from workbench.external.benchmarks.block import BAND_REFINE
from workbench.external.benchmarks.runs import run_records
from workbench.external.mesh_model import read_msh

__all__ = ["part", "MARGIN", "particle_span"]

MARGIN = 0.1  # the band's parameter span is widened by this fraction of itself at each end


def particle_span(des, d_max: float) -> tuple[float, float]:
    """The parameter interval of the particle's B-spline lower surface that faces the body's refined zone at the
    displacement ``d_max`` (the closest points of 200 points per refined interval), widened by MARGIN per end."""
    from meshes.concave import refine_intervals

    piece = des.particle.pieces[0].translated(d_max * np.asarray(des.direction, dtype=float))
    t = np.concatenate([piece.project(des.concave.point(np.linspace(lo, hi, 200))).t
                        for lo, hi in refine_intervals(des, d=d_max)])
    lo, hi = float(t.min()), float(t.max())
    pad = MARGIN * (hi - lo)
    return max(0.0, lo - pad), min(1.0, hi + pad)


def _steps(run: Run, cm, E_star: float) -> list[dict]:
    """The LCP of every step: the plausible overlapping pairs (as the scene compares them)."""
    from workbench.scenes.concave import _plausible_overlap

    des, curve = cm.design, cm.design.concave
    table = dict(zip(des.table1_d, des.table1_delta, strict=True))
    out = []
    for d, lcp in zip(run.loading.d, cm.lcps, strict=True):
        pairs = [pr for pr in lcp.pairs if _plausible_overlap(pr)]
        out.append({"d": d, "paper_delta": table.get(d),
                    "delta": max((pr.delta for pr in pairs), default=0.0),
                    "pairs": [{"s": float(curve.arc_length(np.array([pr.t_a]))[0]),
                               "x": float(curve.point([pr.t_a])[0, 0]), "delta": pr.delta, "R": pr.relative_radius,
                               "radius_convex": pr.radius_b, "radius_concave": pr.radius_a} for pr in pairs]})
    return out


def part(case: Case, runs: tuple[Run, ...], *, level: float, mesh_cache: Path, folder: Path, stem: str) -> Exported:
    """The benchmark of a concave case (module docstring)."""
    from meshes.frozen import frozen_control_points
    from workbench.scenes.concave import concave_mesh

    run = runs[0]
    mat, ld = run.material, run.loading
    cm = concave_mesh(run, name=f"export_{case.name}", mesh_cache=mesh_cache, comm=None, write_xdmf=False)
    des = cm.design
    piece = des.particle.pieces[0]
    t_lo, t_hi = particle_span(des, max(ld.d))
    h = cm.h_contact / BAND_REFINE
    band = curve_band(piece, t_lo=t_lo, t_hi=t_hi, h=h, thickness=h)
    model = finish(read_msh(cm.files.msh).merge(band_model(band)))
    mesh = write_model(model, folder, stem)
    E_star = materials.plane_strain_modulus(mat.E, mat.nu)
    frozen = frozen_control_points(des.name, np.asarray(des.concave.control_points))
    top = surfaces.bspline(des.concave)
    if frozen is not None:  # the control points the mesh was built from (meshes/frozen.py; within 1e-9 mm)
        top["control_points"] = np.asarray(frozen).tolist()
    x_min, x_max, y_bottom = map(float, des.body_box)
    arc = des.particle.pieces[1]
    geometry = {
        "body": {"top": "the clamped cubic B-spline 'contact' (surfaces), left to right from x_min to x_max",
                 "x_min": x_min, "x_max": x_max, "y_bottom": y_bottom,
                 "sides": "vertical at x_min and x_max from the spline's ends down to y_bottom", "bottom": "y_bottom"},
        "particle": {"lower_surface": "the clamped cubic B-spline 'indenter_contact' (surfaces), clockwise",
                     "closing_arc": {"center": [float(c) for c in arc.center], "radius": float(arc.r),
                                     "note": "closes the particle above; never in contact"},
                     "band_parameters": [t_lo, t_hi], "direction": [float(v) for v in des.direction],
                     "initial": "d = 0: the particle as designed, above the body (first contact at the first LCP "
                                "overlap)"},
        "band": {"spacing": h, "thickness": h, "surface_nodes": int(len(band.params))},
        "surfaces": {"contact": top, "indenter_contact": surfaces.bspline(piece)},
    }
    steps = _steps(run, cm, E_star)
    top_nodes = model.nodes[model.group_nodes("contact")]
    top_nodes = top_nodes[np.argsort(top_nodes[:, 0])]
    s_nodes = des.concave.arc_length(des.concave.project(top_nodes).t)
    reference = {
        "primary": "hertz_superposition", "E_star": E_star,
        "note": "the close-to-conformal paper's per-step analysis: each plausible, overlapping LCP pair of the rigid "
                "particle at d (the rigid overlap delta, the pair's relative radius R) carries a Hertz patch",
        "predictions": {"steps": steps,
                        "patch_width_eq4": "2a = 4 P / (pi p0) from a patch's measured load P and peak p0",
                        "patch_width_eq5": "2a = 2 sqrt(4 P R / (pi E*)) from a patch's measured load and its pair's "
                                           "relative radius R",
                        "hertz_superposition": "the sum of the pairs' Hertz pressures, each at the load of the patch "
                                               "it lies in (shared equally by the pairs of one patch)",
                        "load_symmetry": ("1: the mirror-image pairs carry equal loads (patch P[1] / P[0])"
                                          if des.name == "symmetric" else None)},
        "how_scored": "per step (d) and per patch, at the patch loads the result carries: P, p0, the patch width "
                      "(edge and moments), eq. (4) and (5), the Hertz superposition's RMS/p0" +
                      ("; the load symmetry" if des.name == "symmetric" else ""),
        "idealisations": ["Hertz's patches assume half-planes and small patches against the radii; the "
                          "close-to-conformal pairs (R up to 234 mm) and the merging patches are where the paper "
                          "finds them wrong: the theory is what the steps test, not the exact answer."]}
    bench = Benchmark(
        case=case.name, scene="concave", description=case.description, level=level, h_contact=cm.h_contact,
        mesh=mesh,
        bodies=(Body(name="body", cells="body", material=Material(E=mat.E, nu=mat.nu)),
                Body(name="particle", cells="indenter", rigid=True)),
        pairs=(ContactPair(slave="contact", master="indenter_contact", slave_body="body", master_body="particle"),),
        supports=(Support(group="clamped", components=(0, 1), note="the sides and the bottom"),),
        drive=Drive(control="displacement", report=tuple(ld.d), direction=tuple(float(v) for v in des.direction),
                    body="particle"),
        runs=run_records(runs, slope=""),
        geometry=geometry, reference=reference,
        report={"position": "x_mm: the arc length s of the undeformed concave surface from its left end (x = "
                            f"{x_min:g} mm), reference configuration (the workbench's abscissa): arc_length gives s at "
                            "every node of 'contact' (the polyline through the nodes is shorter: by 0.017 mm at "
                            "concave_symmetric's CI level, from its coarse elements away from the contact)",
                "arc_length": {"X_mm": top_nodes[:, 0].tolist(), "s_mm": s_nodes.tolist()},
                "pressure": "p_MPa: the normal contact traction on the body, compression positive, per reference "
                            "length",
                "load": "P_N_per_mm: the particle's load along its direction at this step",
                "rows": "every contact node (or integration point) of the body's surface in the refined zone, at "
                        "every step",
                "steps": "one per d of the drive (step = its index)", "bodies": "the concave body (slave)",
                "measures": ["per step: P, p_max, the patches (centre, half-width, load, peak)",
                             "per patch: eq. (4) and eq. (5) widths, the moment width",
                             "Hertz superposition RMS/p0", "load symmetry (symmetric design)"],
                "columns": dict(RESULT_COLUMNS)},
        tolerances=dict(case.tolerances))
    return Exported(bench, model, folder, {**mesh_stats(model), "body_mesh": cm.files.msh.name,
                                           "band_surface_nodes": int(len(band.params))})
