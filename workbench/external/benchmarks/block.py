"""The block scenes as benchmarks: the case's block mesh and the rigid indenter meshed as a band.

* The block: the mesh ``workbench run`` solves at the level (:func:`workbench.scenes.block.block_mesh`; a half
  model stays half, with its ``symmetry`` edge), groups ``body`` (cells), ``contact`` (the whole top edge y = 0),
  ``clamped`` (bottom), ``sides``, ``symmetry`` (x = 0, half models).
* The indenter (:mod:`meshes.rigid_band`), groups ``indenter`` (cells) and ``indenter_contact`` (its surface):
  the exact circle, the parabola or the wedge with its apex a node, over |x| <= ``BAND_EXTENT`` a (a the target
  half-width; a circle at most 0.9 R), touching the block at the origin. Its spacing along the surface is h_c /
  ``BAND_REFINE`` on the curved surfaces (the chords of a linear master sag by h^2 / (8 R) and turn by h / R at every
  node: a quarter of the slave's spacing makes that 1/16 and 1/4 of the slave's own) and h_c on the wedge's
  straight faces (exact at any spacing); its thickness is its spacing.

Runs, drive and theory: force control to the case's target load P (full body), the indenter moving along -y; the
classical theory (Hertz; the exact circle for a circle indenter, the case's own; the classical wedge) and, with a
``convective`` prediction, Ciavarella and Hills's b/b0 at the block's beta (rigid indenter).
"""

from __future__ import annotations

from pathlib import Path

from analytic import materials
from cases.schema import Case, Run
from meshes.rigid_band import circle_band, parabola_band, wedge_band
from workbench.external.benchmark import RESULT_COLUMNS, Benchmark, Body, ContactPair, Drive, Material, Support
from workbench.external.benchmarks import surfaces
from workbench.external.benchmarks.base import Exported, band_model, finish, mesh_stats, write_model
from workbench.external.benchmarks.runs import run_records
from workbench.external.benchmarks.theory import (
    AT_MEASURED_LOAD,
    circle_values,
    convective_values,
    hertz_values,
    wedge_values,
)
from workbench.external.mesh_model import read_msh

__all__ = ["part", "BAND_EXTENT", "BAND_REFINE"]

BAND_EXTENT = 2.5  # the band covers |x| <= 2.5 a: the contact (a, or b up to 1.27 b0 convective) and a margin
BAND_REFINE = 4  # h_c / 4 along a curved rigid surface


def indenter_band(run: Run, *, a: float, h_c: float, m: float | None):
    """The rigid band of a block run (module docstring) and the exact description of its surface."""
    g = run.geometry
    curved = g.indenter != "wedge"
    h = h_c / BAND_REFINE if curved else h_c
    x_max = BAND_EXTENT * a if g.indenter != "circle" else min(BAND_EXTENT * a, 0.9 * g.radius)
    common = dict(x_max=x_max, h=h, thickness=h, half=g.half_model)
    if g.indenter == "circle":
        return circle_band(radius=g.radius, **common), surfaces.circle((0.0, g.radius), g.radius)
    if g.indenter == "parabola":
        return parabola_band(radius=g.radius, **common), surfaces.parabola(g.radius)
    return wedge_band(slope=m, **common), None


def _indenter_geometry(g, m: float | None) -> dict:
    if g.indenter == "circle":
        return {"shape": "circle", "radius": g.radius, "center": [0.0, g.radius],
                "surface": "the lower arc of x^2 + (y - R)^2 = R^2", "initial": "touches the block at the origin"}
    if g.indenter == "parabola":
        return {"shape": "parabola", "radius": g.radius, "surface": "y = x^2 / (2 R)",
                "initial": "touches the block at the origin"}
    return {"shape": "wedge", "theta": g.wedge_angle, "slope_convention": g.wedge_slope, "slope": m,
            "surface": "y = m |x|, m = tan(theta) ('exact') or m = theta ('paper', Ciavarella-Hills's profile)",
            "apex": [0.0, 0.0], "initial": "its apex touches the block at the origin"}


def _reference(case: Case, run: Run, th, h_band: float) -> dict:
    g = run.geometry
    beta = materials.beta_rigid_indenter(run.material.nu)
    preds: dict = {}
    if g.indenter == "circle":
        preds["exact_circle"] = circle_values(th.P, g.radius, th.E_star)
        preds["hertz"] = hertz_values(th.P, g.radius, th.E_star)
        primary, note = "exact_circle", ("the case's checks read the exact circle (the profile a circle really has); "
                                         "Hertz, its parabolic approximation, is the alternative its bands exclude")
    elif g.indenter == "parabola":
        preds["hertz"] = hertz_values(th.P, g.radius, th.E_star)
        primary, note = "hertz", "Hertz is exact for the parabolic profile (small strain, half-plane)"
    else:
        preds["wedge"] = wedge_values(th.P, th.m, th.E_star)
        primary, note = "wedge", "the classical wedge (Johnson); its peak is log-singular at the apex"
    if "convective" in case.analytic.predictions:
        preds["convective"] = convective_values(kind="wedge" if g.indenter == "wedge" else "parabola",
                                                size=th.m if g.indenter == "wedge" else g.radius, b0=th.half_width,
                                                beta=beta)
    return {"primary": primary, "note": note, "predictions": preds, "beta": beta,
            "how_scored": AT_MEASURED_LOAD + " A convective case's b/b0 compares the convective run with the small "
                          "run at one load." if "convective" in preds else AT_MEASURED_LOAD,
            "idealisations": [
                "The block is W x H with its bottom clamped, not a half-plane: its truncation is O(a/W) (the case's "
                "error budget extrapolates it away in 1/W; docs/error_budget.md).",
                "The rigid indenter is a meshed band whose every node moves with it; its surface nodes lie on the "
                "exact surface. " + (f"Its facets ({h_band:.4g} mm) are chords sagging by up to h^2 / (8 R) = "
                                     f"{h_band ** 2 / (8.0 * g.radius):.2g} mm with linear elements "
                                     "(surfaces.quadratic curves them)." if g.indenter != "wedge"
                                     else "The wedge's faces are straight: its facets are exact."),
            ]}


def part(case: Case, runs: tuple[Run, ...], *, level: float, mesh_cache: Path, folder: Path, stem: str) -> Exported:
    """The benchmark of a block case's runs of one geometry (module docstring)."""
    from workbench.scenes.block import block_mesh

    run = runs[0]
    g, mat = run.geometry, run.material
    if g.far_field != "clamped":
        raise ValueError(f"case {case.name}: geometry.far_field = {g.far_field!r} cannot be exported (its supports "
                         "are Flamant's displacement field at the measured load); allowed: 'clamped'")
    files, th = block_mesh(run, name=f"export_{case.name}", mesh_cache=mesh_cache, comm=None, write_xdmf=False)
    a, h_c = th.half_width, level * th.half_width
    band, surface = indenter_band(run, a=a, h_c=h_c, m=th.m)
    model = finish(read_msh(files.msh).merge(band_model(band)))
    mesh = write_model(model, folder, stem)
    W, H = g.width_factor * a, g.height_factor * a
    slope = f"m = {th.m:.4g}" if g.indenter == "wedge" else f"a/R = {a / g.radius:.3g} at the target"
    geometry = {
        "block": {"width": W, "height": H, "x": [0.0 if g.half_model else -W / 2, W / 2], "y": [-H, 0.0],
                  "top": "y = 0 (the contact surface)", "half_model": g.half_model,
                  "symmetry": "x = 0 (u_x = 0): the half x >= 0 is modelled" if g.half_model else None},
        "indenter": _indenter_geometry(g, th.m),
        "band": {"x_extent": float(band.nodes[:, 0].max()), "spacing": float(band.thickness),
                 "thickness": float(band.thickness), "surface_nodes": int(len(band.params))},
        "surfaces": {"indenter_contact": surface} if surface else {},
    }
    bench = Benchmark(
        case=case.name, scene="block", description=case.description, level=level, h_contact=h_c, mesh=mesh,
        bodies=(Body(name="block", cells="body", material=Material(E=mat.E, nu=mat.nu)),
                Body(name="indenter", cells="indenter", rigid=True)),
        pairs=(ContactPair(slave="contact", master="indenter_contact", slave_body="block", master_body="indenter"),),
        supports=(Support(group="clamped", components=(0, 1), note="the bottom y = -H"),
                  *((Support(group="symmetry", components=(0,), note="the symmetry edge x = 0 (half model)"),)
                    if g.half_model else ())),
        drive=Drive(control="force", report=(th.P,), body="indenter", half_model=g.half_model),
        runs=run_records(runs, slope=slope),
        geometry=geometry, reference=_reference(case, run, th, band.thickness),
        report={"position": "x_mm: the abscissa X of the block's top surface y = 0, reference configuration (a half "
                            "model may report x >= 0 only: the score mirrors it)",
                "pressure": "p_MPa: the normal contact traction on the block, compression positive, per reference "
                            "length",
                "load": "P_N_per_mm: the full-body load the indenter carries (twice a half model's reaction)",
                "rows": f"every contact node (or integration point) of the block's surface over at least |x| <= "
                        f"{1.5 * a:.6g} mm (1.5 a)",
                "steps": "one: the target load (step 0)", "bodies": "the block (slave)",
                "measures": ["p_max (Hertz and the exact circle; not the wedge's log-singular apex)",
                             "half_width (square-root edge fit)", "half_width_moment (2 sqrt(M2/M0))",
                             "rms (RMS(p - p_theory) / p_ref over the patch)", "load_balance (P against the pressure "
                             "integral)"] + (["b_over_b0 (convective run over small run, one load)"]
                                             if "convective" in case.analytic.predictions else []),
                "columns": dict(RESULT_COLUMNS)},
        tolerances=dict(case.tolerances))
    return Exported(bench, model, folder, {**mesh_stats(model), "block_mesh": files.msh.name,
                                           "band_surface_nodes": int(len(band.params))})

