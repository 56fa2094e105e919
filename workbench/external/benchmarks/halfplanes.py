"""The two-half-planes scenes as benchmarks: the upper body meshed with its real shape.

The workbench's own runs of these cases mesh two FLAT blocks and put the gap profile in analytically
(:class:`fem.two_body.geometry.ProfileSurface`): the half-plane theory's idealisation. Another code needs the
geometry the idealisation stands for, so the benchmark's upper body is shaped (:func:`meshes.two_body.
build_profile_blocks`): its lower face is the profile itself, ``y = x^2 / (2 R)`` (one quadratic Bezier curve per
segment: the parabola exactly) or the wedge ``y = m |x|`` with its apex a mesh corner, out to |x| = W/2 (a case with
finite-strain runs: the parabola over |x| <= 3 b0 and flat beyond, the body its finite runs mesh), vertical sides
up to ``f(W/2) + H``; its sizes are the scene's (h_c on the lower block's window, ``size_ratio`` h_c on the upper's,
the wedge's apex refined to a quarter). The lower block is the scene's W x H block. Groups as the flat pair's
(:mod:`meshes.two_body`): ``lower``, ``upper``, ``contact_lower``, ``contact_upper``, ``clamped``, ``driven``,
``sides``.

What the shape changes against the half-plane theory (said in the spec's ``idealisations``): the contact face is
inclined by the profile's slope (up to b0/R or m in the contact), so a traction along the face's normal is not the
theory's vertical one; and the body near the contact is a wedge or a parabolic body, not a half-plane (measured for
an elastic wedge of the same material, ``docs/models.md``: at theta = pi/5 the moment half-width is 4.4 % wider than
the flat idealisation's).
"""

from __future__ import annotations

from pathlib import Path

from cases.schema import Case, Run
from vocabulary import FINITE
from workbench.external.benchmark import RESULT_COLUMNS, Benchmark, Body, ContactPair, Drive, Material, Support
from workbench.external.benchmarks import surfaces
from workbench.external.benchmarks.base import Exported, finish, mesh_stats, scene_mesh, write_model
from workbench.external.benchmarks.runs import run_records
from workbench.external.benchmarks.theory import AT_MEASURED_LOAD, convective_values, hertz_values, wedge_values
from workbench.external.mesh_model import read_msh

__all__ = ["part", "SHAPE_EFFECT"]

SHAPE_EFFECT = (
    "The half-plane theory idealises both bodies as half-planes and the upper body's profile as a gap above a flat "
    "face (the workbench's own small-strain and convective runs of this case do the same: two flat blocks, the gap "
    "put in analytically; its finite-strain runs mesh this benchmark's body). This benchmark's upper body is the "
    "shaped body that idealisation stands for: its lower face is the profile, {face}, {extent} (y = {edge:.6g} mm at "
    "its ends |x| = W/2 = {half:.6g} mm), vertical sides up to y = {top:.6g} mm. What that changes: the contact "
    "face is inclined by the profile's slope ({slope} in the contact), so a traction along its "
    "normal is not the theory's vertical one; and the body near the contact is {body}, not a half-plane. Measured for "
    "an elastic wedge on a block of the same material (docs/models.md, 'An elastic wedge of the same material'): the "
    "moment half-width over the classical wedge's is 1.0046 (shaped) against 0.9990 (flat) at theta = pi/10, 1.0426 "
    "against 0.9990 at pi/5. Not measured for the parabola nor for dissimilar materials: a code's result on this "
    "benchmark differs from the flat idealisation's by this shape effect on top of its own error.")


def part(case: Case, runs: tuple[Run, ...], *, level: float, mesh_cache: Path, folder: Path, stem: str) -> Exported:
    """The benchmark of a two-half-planes case (module docstring)."""
    from meshes.two_body import build_profile_blocks
    from workbench.scenes.halfplanes import APEX_FACTOR, PARABOLA_CAP, _estimate
    from workbench.scenes.halfplanes_theory import bimaterial_of, profile_size

    run = runs[0]
    g, disc = run.geometry, run.discretisation
    P, b0 = _estimate(run)
    size = profile_size(run)  # R (parabola) or the face slope m (wedge)
    wedge = g.indenter == "wedge"
    W, H = g.width_factor * b0, g.height_factor * b0
    # a case with finite-strain runs: the upper body those runs mesh, the parabola capped (the whole parabola to W/2
    # is a nose W^2 / (8 R) tall, laterally soft: docs/models.md)
    cap = PARABOLA_CAP * b0 if not wedge and any(r.solver.kinematics == FINITE for r in runs) else None
    files = build_profile_blocks(width=W, height=H, contact_half_width=b0, h_contact=level * b0,
                                 size_ratio=g.size_ratio, growth=disc.growth,
                                 apex_factor=(APEX_FACTOR if g.apex == "refined" else 1.0) if wedge else None,
                                 wedge_slope=size if wedge else None, parabola_radius=None if wedge else size,
                                 parabola_cap=cap,
                                 out_dir=mesh_cache, name=f"export_{case.name}_shaped", write_xdmf=False)
    model = finish(read_msh(files.msh))
    mesh = write_model(model, folder, stem)
    lower, upper = run.bodies
    bm = bimaterial_of(run)
    edge = size * W / 2 if wedge else min(W / 2, cap or W / 2) ** 2 / (2.0 * size)
    face = f"y = m |x| with m = {size:.10g}" if wedge else f"y = x^2 / (2 R) with R = {size:g} mm"
    extent = "out to |x| = W/2" if cap is None else f"over |x| <= x_c = {cap:.6g} mm ({PARABOLA_CAP:g} b0), flat beyond"
    slope = f"m = {size:.4g}" if wedge else f"b0/R = {b0 / size:.3g}"
    preds = {"wedge": wedge_values(P, size, bm.E_star)} if wedge else {"hertz": hertz_values(P, size, bm.E_star)}
    if "convective" in case.analytic.predictions:
        preds["convective"] = convective_values(kind=g.indenter, size=size, b0=b0, beta=bm.beta)
    shape = SHAPE_EFFECT.format(face=face, extent=extent, half=W / 2, edge=edge, top=edge + H, slope=slope,
                                body="an elastic wedge" if wedge else "a parabolic body")
    geometry = {
        "lower": {"x": [-W / 2, W / 2], "y": [-H, 0.0], "top": "y = 0 (flat)"},
        "upper": {"shape": g.indenter, "face": face, "x": [-W / 2, W / 2], "face_end_height": edge,
                  "top": f"y = {edge + H:.10g} (driven)", "sides": "vertical from the face's ends to the top",
                  **({"slope": size, "theta": g.wedge_angle, "slope_convention": g.wedge_slope, "apex": [0.0, 0.0],
                      "apex_refinement": g.apex} if wedge else {"radius": size}),
                  **({} if cap is None else {"parabola_cap": cap})},
        "initial": "the upper body's face touches the lower block at the origin",
        "surfaces": {} if wedge else {"contact_upper": surfaces.parabola(size, cap=cap)},
    }
    bench = Benchmark(
        case=case.name, scene="halfplanes", description=case.description, level=level, h_contact=level * b0,
        mesh=mesh,
        bodies=(Body(name=lower.name, cells="lower", material=Material(E=lower.E, nu=lower.nu)),
                Body(name=upper.name, cells="upper", material=Material(E=upper.E, nu=upper.nu))),
        pairs=(ContactPair(slave="contact_lower", master="contact_upper", slave_body=lower.name,
                           master_body=upper.name),),
        supports=(Support(group="clamped", components=(0, 1), note="the lower block's bottom"),),
        drive=Drive(control="force", report=(P,), group="driven", body=upper.name, components=(0, 1)),
        runs=run_records(runs, slope=slope, two_bodies=True, beta=bm.beta),
        geometry=geometry,
        reference={"primary": g.indenter if wedge else "hertz", "E_star": bm.E_star, "alpha": bm.alpha,
                   "beta": bm.beta,
                   "note": "the classical solution at E* (small run; Dundurs' beta does not enter) and Ciavarella and "
                           "Hills's convective b/b0 at the bodies' beta (body 1 the upper one)",
                   "predictions": preds, "how_scored": AT_MEASURED_LOAD + " b/b0 compares the convective run with "
                   "the small run at one load.", "idealisations": [shape]},
        report={"position": "x_mm: the abscissa X of the lower block's top surface y = 0, reference configuration",
                "pressure": "p_MPa: the normal contact traction on the lower block (slave), compression positive",
                "load": "P_N_per_mm: the load the upper body carries", "rows": "every contact node of the lower "
                f"block's surface over at least |x| <= {2.0 * b0:.6g} mm (2 b0)",
                "steps": "one: the target load", "bodies": "the lower block (slave)",
                "measures": ["half_width", "half_width_moment", "rms", "load_balance"]
                + ([] if wedge else ["p_max"]) + ["b_over_b0 and b_over_b0_moment (convective over small)"],
                "columns": dict(RESULT_COLUMNS)},
        tolerances=dict(case.tolerances))
    what = ("the scene's sizes with the upper body shaped (the workbench's own run solves two flat blocks: "
            "another mesh)")
    return Exported(bench, model, folder, {**mesh_stats(model), "scene_mesh": scene_mesh(files, what=what)})
