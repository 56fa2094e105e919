"""The two-body scenes as benchmarks: both elastic bodies as the workbench meshes them, each with its case material.

Groups (:mod:`meshes.two_body`): cells ``lower`` (the first ``[[body]]``, slave side) and ``upper`` (the second,
driven); facets ``contact_lower``, ``contact_upper``, ``clamped`` (bottom of the lower body), ``driven`` (top of the
upper body), ``sides``, ``symmetry`` (x = 0 edges, stacked blocks).

* ``cylinder`` (elastic_cylinder, elastic_cylinder_dissimilar): an elastic half disk of radius R on a W x H block,
  the block's bottom clamped, the disk's flat top moved rigidly (u_x = 0, u_y = -d) to the case's target load:
  the exact circle's half-plane theory at the combined modulus ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2``.
* ``stacked`` (patch_test): two blocks on rollers (the lower block's bottom u_y = 0, the x = 0 edges u_x = 0), the
  upper block's top moved down by d (u_y only): the exact pressure is uniform, ``p = d / sum(H_i (1 - nu_i^2) /
  E_i)`` (each block in uniaxial plane-strain compression, the frictionless interface free to slip), P = p W.
"""

from __future__ import annotations

from pathlib import Path

from analytic.materials import composite_modulus
from cases.schema import Case, Run
from workbench.external.benchmark import RESULT_COLUMNS, Benchmark, Body, ContactPair, Drive, Material, Support
from workbench.external.benchmarks import surfaces
from workbench.external.benchmarks.base import Exported, finish, mesh_stats, write_model
from workbench.external.benchmarks.runs import run_records
from workbench.external.benchmarks.theory import AT_MEASURED_LOAD, circle_values, hertz_values
from workbench.external.mesh_model import read_msh

__all__ = ["part", "uniform_pressure"]


def uniform_pressure(run: Run, d: float) -> float:
    """The patch test's exact pressure (MPa) at the top displacement d (mm): the two blocks in series, each in
    uniaxial plane-strain compression (lateral stress 0, the interface slipping): ``d = p sum(H_i (1 - nu_i^2) /
    E_i)``."""
    g, (lower, upper) = run.geometry, run.bodies
    return d / (g.height_lower / composite_modulus(lower.E, lower.nu) + g.height_upper / composite_modulus(
        upper.E, upper.nu))


def _bodies(run: Run) -> tuple[Body, Body]:
    lower, upper = run.bodies
    return (Body(name=lower.name, cells="lower", material=Material(E=lower.E, nu=lower.nu)),
            Body(name=upper.name, cells="upper", material=Material(E=upper.E, nu=upper.nu)))


def part(case: Case, runs: tuple[Run, ...], *, level: float, mesh_cache: Path, folder: Path, stem: str) -> Exported:
    """The benchmark of a two-body case's runs (module docstring)."""
    from workbench.scenes import scene_for

    run = runs[0]
    g, ld = run.geometry, run.loading
    sm = scene_for(run).mesh(run, name=f"export_{case.name}", mesh_cache=mesh_cache, comm=None)
    model = finish(read_msh(sm.files.msh))
    mesh = write_model(model, folder, stem)
    bodies = _bodies(run)
    lower, upper = bodies
    pair = ContactPair(slave="contact_lower", master="contact_upper", slave_body=lower.name, master_body=upper.name)
    cols = {"columns": dict(RESULT_COLUMNS)}
    E_star = composite_modulus(run.bodies[0].E, run.bodies[0].nu, E1=run.bodies[1].E, nu1=run.bodies[1].nu)
    if g.indenter == "cylinder":
        P, a = sm.estimate["P"], sm.estimate["half_width"]
        W, H = g.width_factor * a, g.height_factor * a
        geometry = {"block": {"width": W, "height": H, "x": [-W / 2, W / 2], "y": [-H, 0.0], "top": "y = 0"},
                    "cylinder": {"shape": "half disk", "radius": g.radius, "center": [0.0, g.radius],
                                 "surface": "the lower half of x^2 + (y - R)^2 = R^2; flat top y = R (driven)",
                                 "initial": "touches the block at the origin"},
                    "surfaces": {"contact_upper": surfaces.circle((0.0, g.radius), g.radius)}}
        supports = (Support(group="clamped", components=(0, 1), note="the block's bottom"),)
        drive = Drive(control="force", report=(P,), group="driven", body=upper.name, components=(0, 1))
        reference = {"primary": "exact_circle", "E_star": E_star,
                     "note": "the exact circle's half-plane theory at the combined modulus E* (frictionless, small "
                             "strain: the normal problem does not depend on Dundurs' beta)",
                     "predictions": {"exact_circle": circle_values(P, g.radius, E_star),
                                     "hertz": hertz_values(P, g.radius, E_star)},
                     "how_scored": AT_MEASURED_LOAD,
                     "idealisations": ["The half disk is a finite body, not a half-plane: its own compliance moves "
                                       "p_max and the moment half-width by O((a/R)^2) (docs/models.md: below 3e-5 at "
                                       "a/R = 0.0125).",
                                       "The block is W x H, clamped: O(a/W) (the case's budget extrapolates it).",
                                       "Curved surface 'contact_upper': a linear mesh meshes it as chords (the "
                                       "workbench measures the gap to the exact circle; surfaces.quadratic puts a "
                                       "quadratic code's mid-edge nodes on it)."]}
        report = {"position": "x_mm: the abscissa X of the block's top surface y = 0, reference configuration",
                  "pressure": "p_MPa: the normal contact traction on the block (slave), compression positive",
                  "load": "P_N_per_mm: the load the cylinder carries", "rows": "every contact node of the block's "
                  "surface over at least |x| <= 1.5 a", "steps": "one: the target load", "bodies": "the block (slave)",
                  "measures": ["p_max", "half_width", "half_width_moment", "rms", "load_balance"], **cols}
        slope = f"a/R = {a / g.radius:.3g}"
    else:
        W = g.block_width
        geometry = {"lower_block": {"x": [0.0, W], "y": [-g.height_lower, 0.0]},
                    "upper_block": {"x": [0.0, W], "y": [0.0, g.height_upper]},
                    "interface": "y = 0, non-matching meshes", "surfaces": {}}
        supports = (Support(group="clamped", components=(1,), note="the lower block's bottom (a roller)"),
                    Support(group="symmetry", components=(0,), note="the x = 0 edges of both blocks (rollers)"))
        drive = Drive(control="displacement", report=tuple(ld.d), group="driven", body=upper.name, components=(1,))
        p = [uniform_pressure(run, d) for d in ld.d]
        reference = {"primary": "uniform", "E_star": None,
                     "note": "the contact patch test (Taylor and Papadopoulos 1991): the exact stress is uniform",
                     "predictions": {"uniform": {"formula": "p = d / (H_lower (1 - nu_l^2) / E_l + H_upper "
                                                            "(1 - nu_u^2) / E_u), P = p W",
                                                 "d": list(ld.d), "p": p, "P": [v * W for v in p]}},
                     "how_scored": "uniformity: max |p / (P/W) - 1| over the contact nodes, P the result's load",
                     "idealisations": []}
        report = {"position": "x_mm: the abscissa X of the interface y = 0 (0 <= x <= W), reference configuration",
                  "pressure": "p_MPa: the normal contact traction on the lower block (slave)",
                  "load": "P_N_per_mm: the interface load", "rows": "every contact node of the lower block's top",
                  "steps": "one per d of the drive", "bodies": "the lower block (slave)",
                  "measures": ["patch_uniformity", "load_balance"], **cols}
        slope = "0 (flat)"
    bench = Benchmark(
        case=case.name, scene="two_body", description=case.description, level=level,
        h_contact=level * (g.block_width if g.indenter == "stacked" else sm.estimate["half_width"]), mesh=mesh,
        bodies=bodies, pairs=(pair,), supports=supports, drive=drive,
        runs=run_records(runs, slope=slope, two_bodies=True, patch_test=g.indenter == "stacked"),
        geometry=geometry, reference=reference, report=report, tolerances=dict(case.tolerances))
    return Exported(bench, model, folder, {**mesh_stats(model), "scene_mesh": sm.files.msh.name})
