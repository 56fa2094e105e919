"""The validity study's two-elastic-half-planes part (issue 25): Ciavarella-Hills over beta of both signs.

Each point is a Dundurs beta and a parabolic gap b0/R (:class:`workbench.studies.validity_config.ValidityConfig`
``halfplanes_beta`` x ``halfplanes_b0_over_R``), solved through the registered ``halfplanes`` scene
(:mod:`workbench.scenes.halfplanes`: two graded blocks, non-matching meshes, the upper one carrying the profile)
with ``small`` and ``convective`` kinematics (``convection = "profile"``: Ciavarella and Hills's eq. (8); with
``cfg.halfplanes_pairing`` also ``"pairing"``, issue 39), on three levels b0/h_c and once on the middle level with the
wider block, as the rigid scenes of the study.

Materials: both bodies nu = 0 (plane strain), so beta = (mu_1 - mu_2) sign-corrected by
:func:`analytic.materials.bimaterial` (body 1 = the upper body) is (r - 1) / (2 (r + 1)) with r = E_lower / E_upper:
r = (1 + 2 beta) / (1 - 2 beta) spans beta in (-1/2, 1/2) with one pair of Poisson ratios, and E* = ``cfg.E``
(1/E* = 1/E_upper + 1/E_lower) is the same at every point, so one mesh serves every point of a level. Beta > 0: the
upper (profile) body is the softer one; beta < 0: the stiffer one (beta -> -1/2: the rigid indenter on nu = 0).

Measure (dimensionless): the moment half-width 2 sqrt(M2/M0) of each run over Hertz's half-width at its own
measured load, and their ratio convective over small on the same mesh (``ratio``), which the theories give as the
moment ratio of the converged Ciavarella-Hills pressure over the classical one (and of the first-order pressure),
at the point's beta and b0/R (:func:`analytic.convective.solve`). Units: mm, N/mm, MPa.

Finite strain (issue 39; ``cfg.halfplanes_finite_laws``): per point and law, both bodies that hyperelastic law, P1
on the levels ``cfg.halfplanes_finite_h_ratios``, the upper body meshed as the parabola capped at 3 b0 (the scene's
``finite`` geometry, so each b0/R has meshes of its own), the traction along the deformed master normal, the
augmented Lagrangian at kappa0 = :data:`FINITE_KAPPA0` (as ``cases/halfplanes_finite_parabola.toml``). Their moment
half-width over Hertz's is divided by the small run's (P2, extrapolated) in the assembly.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass
from pathlib import Path

from analytic import convective, materials
from vocabulary import FINITE, OBSTACLE
from workbench.studies.scene_point import run_failure, run_point

__all__ = ["FINITE_KAPPA0", "HP_LABEL", "HalfplanesTask", "bodies_for", "build_mesh", "halfplanes_tasks",
           "halfplanes_theories", "solve_task"]

HP_LABEL = "hp"  # the runs' label: the scene names its mesh <name>_<label>, shared by both kinematics
HP_STEPS = 3  # load steps (force control), as the halfplanes cases
HP_METHOD = "augmented_lagrangian"  # as the halfplanes cases (nitsche needs one slave traction; penalty leaves 1.8e-4)
THEORY_N_PLOT = 64001  # the theory's plot grid for its moments (the halfplanes budget's: ~1e-7 on the moments)
FINITE_KAPPA0 = 100.0  # the finite runs' augmentation factor (cases/halfplanes_finite_parabola.toml: same answer)


@dataclass(frozen=True)
class HalfplanesTask:
    """One FEM run of the two-half-planes part (b0 = 1 mm; units mm, N/mm, MPa).

    Attributes:
        param: b0/R of the parabolic gap.  beta: Dundurs beta of the pair (nominal; the record holds the bodies').
        kinematics: ``small`` or ``convective``.  level: ``h0``, ``h1``, ``h2`` or ``far``.
        h_ratio, width_factor, growth: b0/h_c, W/b0 (both blocks, W = H) and the grading.
        E_star: the pair's plane-strain modulus E* (MPa).  n_steps: load steps.
        scene, nu, traction: constants (``halfplanes``, 0; ``halfplane``, ``obstacle`` for finite runs) that keep
            the records' shape of the rigid scenes' (:class:`workbench.studies.validity.Task`).
        material: both bodies' law (``linear``; a finite run's hyperelastic law).  degree: 2 (finite runs: 1).
        convection: a convective run's model (``profile``, or ``pairing``: the particles that touch carry the
            displacements and forces, docs/models.md); the others keep ``profile`` (unused).
    """

    param: float
    beta: float
    kinematics: str
    level: str
    h_ratio: float
    width_factor: float
    growth: float
    E_star: float
    n_steps: int = HP_STEPS
    scene: str = "halfplanes"
    nu: float = 0.0
    traction: str = "halfplane"
    material: str = "linear"
    degree: int = 2
    convection: str = "profile"

    @property
    def mesh_name(self) -> str:
        if self.kinematics == FINITE:  # the meshed parabola: its own mesh per b0/R
            return f"validity_halfplanes_finite_R{1.0 / self.param:g}_h{self.h_ratio:g}_W{self.width_factor:g}"
        return f"validity_halfplanes_h{self.h_ratio:g}_W{self.width_factor:g}"

    @property
    def model(self) -> str:
        own = f"{self.traction}/{self.kinematics}"
        if self.kinematics == FINITE:
            return f"{own}/{self.material}"
        return f"{own}/{self.convection}" if self.kinematics == "convective" and self.convection != "profile" else own


def bodies_for(beta: float, *, E_star: float) -> tuple[tuple[float, float], tuple[float, float]]:
    """((E_lower, nu_lower), (E_upper, nu_upper)) of the pair with Dundurs ``beta`` (body 1 the upper) and ``E_star``:
    nu = 0 on both, E_lower / E_upper = (1 + 2 beta) / (1 - 2 beta) (module docstring)."""
    r = (1.0 + 2.0 * beta) / (1.0 - 2.0 * beta)
    E_up = E_star * (1.0 + 1.0 / r)
    return (r * E_up, 0.0), (E_up, 0.0)


def halfplanes_tasks(cfg) -> list[HalfplanesTask]:
    """Every run of the part: per (b0/R, beta, kinematics) the three levels and the far block, listed together
    (the executor sends them in chunks of 4, which share their forms)."""
    def levels(ratios):
        out = [(f"h{i}", h, cfg.width_factor) for i, h in enumerate(ratios)]
        return out + [("far", ratios[1], cfg.width_factor_far)]

    def growth(ratios, h):
        return 1.0 + (cfg.growth - 1.0) * ratios[0] / h

    hp, fin = cfg.halfplanes_h_ratios, cfg.halfplanes_finite_h_ratios
    runs = [("small", "profile"), ("convective", "profile")] + ([("convective", "pairing")]
                                                                 if cfg.halfplanes_pairing else [])
    out = []
    for b0R in cfg.halfplanes_b0_over_R:
        for beta in cfg.halfplanes_beta:
            out += [HalfplanesTask(float(b0R), float(beta), kin, level, float(h), float(W), growth(hp, h), float(cfg.E),
                                   convection=conv)
                    for kin, conv in runs for level, h, W in levels(hp)]
            out += [HalfplanesTask(float(b0R), float(beta), FINITE, level, float(h), float(W), growth(fin, h),
                                   float(cfg.E), traction=OBSTACLE, material=law, degree=1)
                    for law in cfg.halfplanes_finite_laws for level, h, W in levels(fin)]
    return out


def _run(task: HalfplanesTask):
    """The case-level run of ``task`` (the scene's records, as a case file would give them)."""
    from cases.schema import Body, Discretisation, Loading, Run, Solver
    from workbench.scenes.halfplanes_schema import HalfplanesGeometry

    (E_lo, nu_lo), (E_up, nu_up) = bodies_for(task.beta, E_star=task.E_star)
    bodies = (Body("lower", E_lo, nu_lo, model=task.material), Body("upper", E_up, nu_up, model=task.material))
    finite = task.kinematics == FINITE
    geo = HalfplanesGeometry(scene="halfplanes", indenter="parabola", radius=1.0 / task.param,
                             width_factor=task.width_factor, height_factor=task.width_factor,
                             convection=task.convection)
    solver = Solver(method=HP_METHOD, kinematics=task.kinematics, traction=task.traction,
                    **({"kappa0": FINITE_KAPPA0} if finite else {}))
    return Run(label=HP_LABEL, material=bodies[0].material, geometry=geo,
               loading=Loading(control="force", half_width=1.0, steps=task.n_steps),
               discretisation=Discretisation(degree=task.degree, h_contact=1.0 / task.h_ratio, growth=task.growth),
               solver=solver, bodies=bodies)


def build_mesh(task: HalfplanesTask, mesh_cache: str) -> dict:
    """Build (or reuse) the two blocks of ``task``'s level through the scene; returns the mesh statistics."""
    import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

    from mpi4py import MPI

    from workbench.scenes import scene_for

    run = _run(task)
    mesh = scene_for(run).mesh(run, name=task.mesh_name, mesh_cache=Path(mesh_cache), comm=MPI.COMM_SELF)
    return {"mesh": task.mesh_name, "cells": mesh.files.stats.get("cells")}


def solve_task(task: HalfplanesTask, mesh_cache: str) -> dict:
    """Mesh (cached), solve and compare one run through the scene (:func:`workbench.pipeline.run_case.run_one`).
    Never raises: a failure is the record's named ``error`` (diverged, refused, failed)."""
    rec = {"task": asdict(task), "model": task.model, "converged": False, "error": None}
    t0 = time.perf_counter()
    try:
        o = run_point(_run(task), name=task.mesh_name, mesh_cache=mesh_cache)
    except Exception as exc:  # noqa: BLE001  (named: diverged, refused or failed)
        return rec | {"error": run_failure(exc), "time_s": time.perf_counter() - t0}
    m = o.metrics
    b0 = m["analytic"]["half_width"]
    moment = m["half_width_moment"] / b0
    if not math.isfinite(moment):
        return rec | {"error": "failed: no contact patch measured", "time_s": time.perf_counter() - t0}
    return rec | {"converged": True, "time_s": time.perf_counter() - t0, "cells": (m.get("mesh") or {}).get("cells"),
                  "ndofs": m["ndofs"], "P": m["P"], "beta_bodies": m["beta"], "b0_over_R": m["b0_over_R"],
                  "iterations": int(sum(m["newton_iterations"])), "failed_iterations": int(m["failed_iterations"]),
                  "warnings": list(m["warnings"]),
                  "moment": moment, "half_width": m["patch_half_width"] / b0, "load_balance":
                  abs(m["P"] - m["P_pressure"]) / abs(m["P"])}


def halfplanes_theories(b0_over_R: float, beta: float) -> dict:
    """The theories' moment ratios at a point (convective over classical at the same load; Hertz: 1):
    ``{"hertz": {"moment": 1}, "ch_converged": {"moment", "half_width"}, "ch_first_order": {...}}``."""
    from workbench.scenes.budget_theory import curve_moment_half_width

    sol = convective.solve(convective.parabola_profile(b0_over_R), beta=beta, n_plot=THEORY_N_PLOT)
    w = curve_moment_half_width(sol.x, sol.p_classical)
    return {"hertz": {"moment": 1.0, "half_width": 1.0},
            "ch_converged": {"moment": curve_moment_half_width(sol.x, sol.p_converged) / w,
                             "half_width": float(sol.b_over_b0_converged)},
            "ch_first_order": {"moment": curve_moment_half_width(sol.x, sol.p_first_order) / w,
                               "half_width": float(sol.b_over_b0_first_order)}}


def check_bodies(beta: float, *, E_star: float) -> float:
    """Dundurs beta of :func:`bodies_for`'s pair from :func:`analytic.materials.bimaterial` (body 1 the upper)."""
    (E_lo, nu_lo), (E_up, nu_up) = bodies_for(beta, E_star=E_star)
    return materials.bimaterial(E1=E_up, nu1=nu_up, E2=E_lo, nu2=nu_lo).beta
