"""Validity study: where the half-plane theories hold, model by model: ``workbench validity [--out DIR]``.

Writes ``<results>/validity/validity.json`` (the config, every run, every point with its theories and
uncertainties, the decomposition and the stress claim), then :mod:`workbench.studies.validity_report` writes
``report.md``/``report.html`` and :mod:`workbench.studies.validity_plot` the maps, both from the JSON alone.

Scenes (:class:`workbench.studies.config.ValidityConfig`): a rigid exact circle (a/R from 1e-3 to 0.4) and a
rigid wedge (face angle theta from pi/40 to pi/4, slope tan theta) on a clamped block, beta = -(1 - 2 nu)/(2 (1 - nu))
from -1/2 (nu = 0) to ~0 (nu = 0.499), each with every model (traction x kinematics). The target half-width is
a = 1 mm in every point, so one mesh serves a scene and a level; the load is the classical load of a.
Two ELASTIC half-planes with a parabolic gap (issue 25, :mod:`workbench.studies.validity_halfplanes`): Dundurs beta
of both signs (``halfplanes_beta``, through the E ratio at nu = 0) x b0/R, small and convective (Ciavarella-Hills's
model) through the ``halfplanes`` scene; their moment ratio convective over small against Ciavarella-Hills
converged and first order (:func:`assemble_halfplanes`). An ELASTIC wedge on a block of the same material
(:mod:`workbench.studies.validity_elastic_wedge`): the paper's theta < pi/5 internal-stress claim as it states it.

Measures (dimensionless, each over the classical value at the run's MEASURED load P): ``moment`` =
2 sqrt(M2/M0) of the contact pressure over the classical one (Hertz: a; wedge: 2 b / sqrt 6), ``p_max`` (circle)
over Hertz's p0, and ``half_width`` (the zero crossing) over the classical half-width. The theories give the
same ratios (:mod:`analytic.halfplane`): Hertz (1), the exact circle, Ciavarella-Hills converged on the circle and
on the parabola, the classical wedge (1), Ciavarella-Hills converged on the wedge, and the first-order closed
forms (half-width only: they give no pressure).

Uncertainty of a model's value (relative): three levels a/h_c give a GCI (:func:`workbench.error_budget.grid_study`)
and the Richardson value; one more run on the middle level with the block 4x wider
(``width_factor_far``) corrects the truncation (f_far - f_W on the middle level: the truncation error is a property
of the block, not of h_c), assumed of order 1 in a/W (the convective ratio's measured order, docs/error_budget.md;
contact quantities converge like (a/W)^2): correction (4/3) (f_far - f_W), its uncertainty |f_far - f_W| / 3
(covers any order between 1 and 2). U = GCI + truncation uncertainty.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from analytic import convective, halfplane, materials
from workbench.atomic import write_json
from workbench.error_budget import grid_study
from workbench.owned import ensure_dir
from workbench.studies.config import ValidityConfig, to_json
from workbench.studies.executor import (
    ExecutorChoice,
    add_executor_options,
    executor_from_args,
    run_points,
    worker_summary,
)
from workbench.studies.scene_point import TargetSized, run_failure, run_point
from workbench.studies.validity_elastic_wedge import ElasticWedgeTask, claim_elastic_wedge, elastic_wedge_tasks
from workbench.studies.validity_halfplanes import HalfplanesTask, halfplanes_tasks, halfplanes_theories

__all__ = ["Point", "Task", "assemble", "claim_points", "finite_settings", "main", "point_theories", "run_study",
           "run_validity_point", "solve_task", "tasks"]

# Finite-strain runs only (measured on the wedge, neo-Hookean, a/h = 4, 8, 16, W/a = 160 and 640, theta = pi/40 ..
# pi/4, nu = 0 and 0.3: 38 of 40 runs converge with these, none of the nu = 0.3 ones did before):
# * FINITE_STEPS load steps (3 steps: the first level follows the short first step with a 10-40 times larger
#   increment; fem.stepping also caps the finite increments' growth and uses a backtracking line search);
# * FINITE_THETA: the incomplete Nitsche variant (theta = 0). With the symmetric one (theta = 1) the semismooth
#   Newton iterates of the steep wedges cycle between two active sets (theta = pi/4, nu = 0.3, a/h = 8: the
#   residual stalls at 0.60 N/mm, det F alternating 0.8085 / 0.8188 at the apex, 30 iterations): 6 of 6 test points
#   failed with theta = 1, 0 of 6 with theta = 0. Both variants are consistent (the same limit as h -> 0; the
#   levels' extrapolation removes their O(h) difference);
# * FINITE_CUTBACKS step halvings per step and FINITE_MAX_IT Newton iterations per solve.
FINITE_STEPS = 24
FINITE_THETA = 0
FINITE_CUTBACKS = 4
FINITE_MAX_IT = 30
# St Venant-Kirchhoff loses ellipticity in compression: in plane-strain uniaxial compression (lateral stretch 1)
# its nominal stress lambda_1 (lambda + 2 mu) (lambda_1^2 - 1) / 2 peaks at the stretch 1/sqrt(3) = 0.577 and
# falls beyond it. Measured (a/h = 8, W/a = 160, the FINITE_* settings): SVK converges at theta = pi/40 and
# pi/20 (smallest principal stretch 0.84-0.89 and 0.77), and diverges from pi/10 on (nu = 0.3: at the load level
# 3/24, the last iterate's smallest stretch 0.38; nu = 0: 4/24, 0.39; pi/5, nu = 0: 1/24, 0.10 and inverted
# cells). The neo-Hookean solutions there reach 0.53-0.62 (pi/10), 0.21-0.24 (pi/5), 0.05-0.08 (pi/4). So SVK
# wedges above SVK_WEDGE_THETA_MAX are skipped with that reason.
SVK_WEDGE_THETA_MAX = math.pi / 20
SVK_WEDGE_SKIP = ("St Venant-Kirchhoff loses ellipticity below the stretch 1/sqrt(3) = 0.577 (plane-strain "
                  "uniaxial compression); wedges steeper than pi/20 reach smaller apex stretches (neo-Hookean, "
                  "a/h = 8: 0.53-0.62 at pi/10, 0.21-0.24 at pi/5, 0.05-0.08 at pi/4) and SVK diverged there "
                  "(pi/10, nu = 0.3: at the load level 3/24, smallest stretch 0.38)")
CLAIM_X = (0.0, 0.25, 0.5, 0.75, 1.0, 1.5)  # stress probes of the paper's claim, x / b (half model, x >= 0)
CLAIM_Z = (0.25, 0.5, 0.75, 1.0, 1.5, 2.0)  # and depths z / b


@dataclass(frozen=True)
class Task:
    """One FEM run of the study (a = 1 mm; units mm, N/mm, MPa).

    Attributes:
        scene: ``cylinder`` (exact circle, R = 1/param) or ``wedge`` (theta = param).
        param: a/R or theta (rad).  nu: Poisson ratio.  traction, kinematics: the model.
        level: ``h0``, ``h1``, ``h2`` (coarse to fine) or ``far`` (fine, wide block).
        h_ratio, width_factor, growth: a/h_c, W/a and the grading of the mesh.
        E, n_steps, mixed_from_nu, material_model: material and solver.
        stresses: also sample the stresses of the claim grid.
    """

    scene: str
    param: float
    nu: float
    traction: str
    kinematics: str
    level: str
    h_ratio: float
    width_factor: float
    growth: float
    E: float
    n_steps: int
    mixed_from_nu: float
    material_model: str = "linear"
    stresses: bool = False

    @property
    def mesh_name(self) -> str:
        return f"validity_{self.scene}_h{self.h_ratio:g}_W{self.width_factor:g}"

    @property
    def model(self) -> str:
        return f"{self.traction}/{self.kinematics}"


def beta_of(nu: float) -> float:
    """Dundurs beta of a rigid indenter on a body of Poisson ratio nu (plane strain)."""
    return materials.beta_rigid_indenter(nu)


def tasks(cfg: ValidityConfig) -> tuple[list[Task], list[dict]]:
    """Every run of the study, and every (point, model) skipped before running, with its reason."""
    out, skipped = [], []
    if not cfg.rigid:
        return out, skipped
    levels = [(f"h{i}", h, cfg.width_factor) for i, h in enumerate(cfg.h_ratios)]
    levels.append(("far", cfg.h_ratios[1], cfg.width_factor_far))
    scenes = [("cylinder", v) for v in cfg.cylinder_a_over_R] + [("wedge", v) for v in cfg.wedge_theta]
    for scene, param in scenes:
        for nu in cfg.nu:
            for traction, kin in cfg.models:
                if kin == "finite" and nu >= cfg.mixed_from_nu:
                    skipped.append({"scene": scene, "param": param, "nu": nu, "model": f"{traction}/{kin}",
                                    "reason": f"finite strain has no mixed formulation; nu = {nu:g} >= "
                                              f"{cfg.mixed_from_nu:g} locks the displacement formulation"})
                    continue
                if (kin == "finite" and scene == "wedge" and cfg.finite_material == "saint_venant_kirchhoff"
                        and param > SVK_WEDGE_THETA_MAX * (1.0 + 1e-9)):
                    skipped.append({"scene": scene, "param": param, "nu": nu, "model": f"{traction}/{kin}",
                                    "reason": SVK_WEDGE_SKIP})
                    continue
                for level, h, W in levels:
                    growth = 1.0 + (cfg.growth - 1.0) * cfg.h_ratios[0] / h
                    stresses = scene == "wedge" and nu == cfg.claim_nu and kin == "small" and level in ("h2", "far")
                    out.append(Task(scene, float(param), float(nu), traction, kin, level, float(h), float(W),
                                    growth, cfg.E, FINITE_STEPS if kin == "finite" else cfg.n_steps,
                                    cfg.mixed_from_nu,
                                    cfg.finite_material if kin == "finite" else "linear", stresses))
    return out, skipped


def _run(task: Task):
    from cases.schema import Discretisation, Loading, Material, Run, Solver
    from workbench.scenes.block_schema import BlockGeometry

    if task.scene == "cylinder":
        geo = BlockGeometry(scene="block", indenter="circle", radius=1.0 / task.param, width_factor=task.width_factor,
                            height_factor=task.width_factor, half_model=True)
    else:
        geo = BlockGeometry(scene="block", indenter="wedge", wedge_angle=task.param, wedge_slope="exact",
                            width_factor=task.width_factor, height_factor=task.width_factor, half_model=True)
    form = "mixed" if task.nu >= task.mixed_from_nu else "displacement"
    return Run(label=task.scene, material=Material(E=task.E, nu=task.nu, model=task.material_model), geometry=geo,
               loading=Loading(control="force", half_width=1.0, steps=task.n_steps),
               discretisation=Discretisation(degree=2, h_contact=1.0 / task.h_ratio, growth=task.growth),
               solver=Solver(method="nitsche", kinematics=task.kinematics, traction=task.traction,
                             formulation=form, theta=FINITE_THETA if task.kinematics == "finite" else 1))


def build_mesh(task: Task, mesh_cache: str) -> dict:
    """Build (or reuse) the mesh of ``task`` in the cache through its point's scene; returns its statistics."""
    run = _run(task)
    mesh = _scene(task).mesh(run, name=task.mesh_name, mesh_cache=Path(mesh_cache), comm=None)
    return {"mesh": task.mesh_name, "cells": mesh.files.stats.get("cells")}


def _scene(task: Task):
    """The point's scene: the block scene with the mesh sized from a = 1 mm itself (W = width_factor a, h_c = a /
    h_ratio: :class:`workbench.studies.scene_point.TargetSized`)."""
    return TargetSized(h_ratio=task.h_ratio)


_MESHES: dict = {}  # the meshes this worker has read, by cache key (run_one's ``meshes``)


def solve_task(task: Task, mesh_cache: str) -> dict:
    """Run one task in this process (MPI.COMM_SELF); returns its record. Never raises: any failure becomes the
    record's named ``error`` (an exception object holding PETSc state could not even be sent back)."""
    try:
        return _solve_task(task, mesh_cache)
    except Exception as exc:  # noqa: BLE001
        return {"task": asdict(task), "model": task.model, "converged": False,
                "error": f"failed: {type(exc).__name__}: {' '.join(str(exc).split())[:300]}"}


@dataclass(frozen=True)
class Point:
    """One point of the study for the shared runner (:func:`workbench.studies.executor.run_points`): build the
    mesh of ``task`` (``mesh``) or solve it (``solve``), with the mesh cache folder."""

    kind: str
    task: Task | HalfplanesTask
    mesh_cache: str


def run_validity_point(point: Point) -> dict:
    """The study's point function (module level: sent to the workers by name); a two-half-planes task goes to
    :mod:`workbench.studies.validity_halfplanes`."""
    if isinstance(point.task, HalfplanesTask):
        from workbench.studies import validity_halfplanes as hp

        return (hp.build_mesh if point.kind == "mesh" else hp.solve_task)(point.task, point.mesh_cache)
    if isinstance(point.task, ElasticWedgeTask):
        from workbench.studies import validity_elastic_wedge as ew

        return (ew.build_mesh if point.kind == "mesh" else ew.solve_task)(point.task, point.mesh_cache)
    if point.kind == "mesh":
        return build_mesh(point.task, point.mesh_cache)
    return solve_task(point.task, point.mesh_cache)


def _solve_task(task: Task, mesh_cache: str) -> dict:
    from workbench.scenes.budget_theory import moment_half_width

    rec = {"task": asdict(task), "model": task.model, "converged": False, "error": None}
    # finite strain: FINITE_* (above); a run that cannot converge fails in seconds, with its SNES reason
    extra = ({"max_cutbacks": FINITE_CUTBACKS, "max_it": FINITE_MAX_IT} if task.kinematics == "finite" else {})
    t0 = time.perf_counter()
    try:
        o = run_point(_run(task), name=task.mesh_name, mesh_cache=mesh_cache, scene=_scene(task), meshes=_MESHES,
                      case=f"validity {task.model}", **extra)
    except Exception as exc:  # noqa: BLE001  (named: diverged, refused or failed)
        return rec | {"error": run_failure(exc), "time_s": time.perf_counter() - t0}
    res, cmp = o.result, o.comparison
    cells = o.metrics["mesh"].get("cells")
    th = cmp.theory
    s = res.samples
    moment = 2.0 * moment_half_width(s.s, s.p, s.weight, center=0.0)
    classical_moment = th.half_width * (1.0 if task.scene == "cylinder" else 2.0 / math.sqrt(6.0))
    rec |= {"converged": True, "time_s": time.perf_counter() - t0, "cells": cells, "P": res.P,
            "iterations": int(sum(res.newton_iterations)), "warnings": list(res.warnings),
            "b_classical": th.half_width, "p0_classical": th.p_ref if task.scene == "cylinder" else None,
            "moment": moment / classical_moment, "half_width": cmp.half_width / th.half_width,
            "p_max": cmp.p_max / th.p_ref if task.scene == "cylinder" else None}
    if task.stresses:
        from fem.probe import stress_at_points

        b = th.half_width
        pts = np.array([(x * b, -z * b) for z in CLAIM_Z for x in CLAIM_X])
        st = stress_at_points(res, pts)
        rec["stresses"] = {"x": pts[:, 0].tolist(), "z": (-pts[:, 1]).tolist(), "sxx": st.sxx.tolist(),
                           "szz": st.syy.tolist(), "sxz": st.sxy.tolist()}  # FEM sxy = McEwen's s_xz (measured)
    return rec


def finite_settings() -> dict:
    """The solver settings of the finite-strain runs (the FINITE_* constants) and the SVK wedge limit, for the
    JSON and the report."""
    return {"load_steps": FINITE_STEPS, "nitsche_theta": FINITE_THETA, "max_cutbacks": FINITE_CUTBACKS,
            "max_it": FINITE_MAX_IT, "svk_wedge_theta_max": SVK_WEDGE_THETA_MAX}


def run_study(cfg: ValidityConfig, *, executor: ExecutorChoice | None = None,
              progress=print) -> tuple[list[dict], list[dict], dict]:
    """Run every task on ``executor`` (default: ``cfg.workers`` local processes): the meshes first, one point
    each, then the solves. Returns the records (each with its ``worker``), the skipped entries and the timing
    (with where the runs ran and the JIT compiles and retries: :func:`workbench.studies.executor.worker_summary`)."""
    executor = ExecutorChoice("local", cfg.workers) if executor is None else executor
    todo, skipped = tasks(cfg)
    # the two-half-planes part and the elastic wedge of the paper's claim (issue 25): after the rigid runs
    todo = [*todo, *halfplanes_tasks(cfg), *elastic_wedge_tasks(cfg)]
    cache = str(cfg.cache_dir)
    ensure_dir(cache, kind="mesh_cache", kinds=("mesh_cache",))  # the workbench's own, or refused
    meshes = {t.mesh_name: t for t in todo}
    timing = {}
    t0 = time.perf_counter()
    mesh_stats = run_points(run_validity_point, [Point("mesh", t, cache) for t in meshes.values()],
                            executor=executor)
    timing["meshes_s"] = time.perf_counter() - t0
    progress(f"validity: {len(meshes)} meshes in {timing['meshes_s']:.0f} s; {len(todo)} runs on "
             f"{executor.workers} {executor.kind} worker(s)")

    def said(i, n, _rec):
        if i % 50 == 0 or i == n:
            progress(f"validity: {i}/{n} runs, {time.perf_counter() - t0:.0f} s")

    # chunks of 4: the levels h0, h1, h2, far of one (point, model) share their forms (tasks() lists them together),
    # so one worker compiles them once. validity --tiny on 2 cold workers: 72 forms compiled (one process: 69);
    # with chunks of 2, 138
    records = run_points(run_validity_point, [Point("solve", t, cache) for t in todo], executor=executor,
                         chunksize=4, progress=said)
    timing["runs_s"] = time.perf_counter() - t0 - timing["meshes_s"]
    for m in mesh_stats:
        m.pop("worker", None)
    return records, skipped, {"meshes": mesh_stats, **timing, "where": worker_summary(records)}


# --- theories ---------------------------------------------------------------------------------------


def point_theories(scene: str, param: float, nu: float, *, E: float) -> dict:
    """The theories' ratios at a point (over the classical value at the same load; a = 1 mm, P its classical
    load): ``{name: {"moment": .., "p_max": .., "half_width": ..}}`` (a missing key: the theory does not give it)."""
    E_star = materials.plane_strain_modulus(E, nu)
    beta = beta_of(nu)
    out = {}
    if scene == "cylinder":
        R = 1.0 / param
        P = math.pi * E_star / (4.0 * R)  # Hertz load of a = 1
        p0 = 2.0 * P / math.pi
        out["hertz"] = {"moment": 1.0, "p_max": 1.0, "half_width": 1.0}
        for name, kind, bb in (("exact_circle", "circle", 0.0), ("ch_circle", "circle", beta),
                               ("ch_parabola", "parabola", beta)):
            s = halfplane.solve_halfplane(halfplane.profile(kind, R=R), P=P, E_star=E_star, beta=bb, n_nodes=4096)
            out[name] = {"moment": s.moment_half_width, "p_max": s.p_max / p0, "half_width": s.half_width}
        out["ch_first_order"] = {"half_width": convective.parabola_first_order_from_b0(param, beta)}
    else:
        m = math.tan(param)
        P = E_star * m  # classical load of b = 1
        out["wedge"] = {"moment": 1.0, "half_width": 1.0}
        s = halfplane.solve_halfplane(halfplane.profile("wedge", m=m), P=P, E_star=E_star, beta=beta, n_nodes=16384)
        out["ch_wedge"] = {"moment": s.moment_half_width / (2.0 / math.sqrt(6.0)), "half_width": s.half_width}
        out["ch_first_order"] = {"half_width": convective.wedge_first_order(m, beta)}
    return out


# --- assembling ---------------------------------------------------------------------------------------


def _value(levels: dict, quantity: str, h_ratios) -> dict:
    """Extrapolated value and relative uncertainty of ``quantity`` from the three levels and the far block."""
    f = [levels.get(f"h{i}", {}).get(quantity) for i in range(3)]
    far = levels.get("far", {}).get(quantity)
    if any(v is None or not math.isfinite(v) for v in f):
        missing = [f"h{i}" for i, v in enumerate(f) if v is None or not math.isfinite(v)]
        return {"value": None, "reason": f"no value on level(s) {', '.join(missing)} (see their runs)"}
    gs = grid_study(tuple(1.0 / h for h in h_ratios), tuple(f), expected_order=None)
    if far is None or not math.isfinite(far):
        return {"value": None, "reason": "the wide-block (truncation) run has no value (see its run)"}
    dW = far - f[1]
    value = gs.extrapolated + 4.0 / 3.0 * dW
    u_trunc = abs(dW) / 3.0 / abs(value)
    return {"value": value, "uncertainty": gs.gci + u_trunc, "gci": gs.gci, "truncation": u_trunc,
            "truncation_correction": 4.0 / 3.0 * dW / abs(value), "status": gs.status,
            "observed_order": gs.observed_order if math.isfinite(gs.observed_order) else None,
            "levels": f, "far": far}


def _complete(cfg: ValidityConfig, models: dict) -> str | None:
    """The most complete model with a moment value (the last of ``cfg.models`` that has one)."""
    for traction, kin in reversed(cfg.models):
        key = f"{traction}/{kin}"
        if models.get(key, {}).get("moment", {}).get("value") is not None:
            return key
    return None


def classify(d: float, u: float, thresholds, resolve_factor: float) -> tuple[str, str | None]:
    """The band of a theory's relative difference ``d`` from a model value of relative uncertainty ``u``.

    Returns ``(band, reason)``: band ``"<0.1%"``-style for the smallest threshold with d + u below it, ``">5%"``
    when d - u exceeds the largest, else ``"unresolved"``; a band is used only when u <= d / resolve_factor
    (the uncertainty well below the difference) or d + u is below the smallest threshold (the verdict holds
    whatever the difference); otherwise the reason says why it is dropped."""
    small = d + u <= thresholds[0]
    if not small and u * resolve_factor > d:
        return "unresolved", f"uncertainty {u:.2e} not well below the difference {d:.2e} (factor {resolve_factor:g})"
    for t in thresholds:
        if d + u <= t:
            return f"<{100 * t:g}%", None
    if d - u > thresholds[-1]:
        return f">{100 * thresholds[-1]:g}%", None
    for t in thresholds:
        if d - u <= t < d + u:
            return "unresolved", f"the band [{d - u:.2e}, {d + u:.2e}] straddles {100 * t:g}%"
    return "unresolved", "no band decided"


def _split(models: dict, complete: str | None, theories: dict, scene: str) -> dict | None:
    """Split the gap (most complete model - classical) of the moment ratio into its idealisations."""
    def val(key):
        m = models.get(key, {}).get("moment", {})
        return (m["value"], m["uncertainty"] * abs(m["value"])) if m.get("value") is not None else (None, None)

    hs, u_hs = val("halfplane/small")
    hc, u_hc = val("halfplane/convective")
    oc, u_oc = val("obstacle/convective")
    of, u_of = val("obstacle/finite")
    if complete is None or hs is None or hc is None or oc is None:
        return None
    tot, u_tot = val(complete)
    rows = {"total": (tot - 1.0, u_tot),
            "profile": (hs - 1.0, u_hs),
            "convective": (hc - hs, math.hypot(u_hc, u_hs)),
            "traction": (oc - hc, math.hypot(u_oc, u_hc)),
            "finite_strain": ((of - oc, math.hypot(u_of, u_oc)) if of is not None and complete == "obstacle/finite"
                              else (None, None))}
    out = {k: {"value": v, "uncertainty": u} for k, (v, u) in rows.items()}
    out["profile"]["theory"] = theories.get("exact_circle", {}).get("moment", 1.0) - 1.0 if scene == "cylinder" \
        else 0.0
    out["complete_model"] = complete
    return out


def assemble(cfg: ValidityConfig, records: list[dict], skipped: list[dict]) -> tuple[list[dict], list[dict]]:
    """Points (scene, param, nu): every model's values with uncertainty, the theories, their bands; and the
    list of dropped or failed entries with their reasons. The two-half-planes records go to
    :func:`assemble_halfplanes` (their points come after the rigid ones)."""
    hp_records = [r for r in records if r["task"]["scene"] == "halfplanes"]
    records = [r for r in records if r["task"]["scene"] not in ("halfplanes", "elastic_wedge")]
    by_point: dict = {}
    for r in records:
        t = r["task"]
        key = (t["scene"], t["param"], t["nu"])
        lev = by_point.setdefault(key, {}).setdefault(r["model"], {})
        lev[t["level"]] = ({q: r.get(q) for q in ("moment", "p_max", "half_width")} if r["converged"] else {})
    dropped = [dict(s, what="model skipped") for s in skipped]
    for r in records:
        if not r["converged"]:
            t = r["task"]
            dropped.append({"scene": t["scene"], "param": t["param"], "nu": t["nu"], "model": r["model"],
                            "level": t["level"], "what": "run failed", "reason": r["error"]})
    points = []
    for (scene, param, nu), models_levels in sorted(by_point.items()):
        theories = point_theories(scene, param, nu, E=cfg.E)
        models = {}
        for model, levels in models_levels.items():
            models[model] = {q: _value(levels, q, cfg.h_ratios) for q in ("moment", "p_max", "half_width")
                             if scene == "cylinder" or q != "p_max"}
            for q, v in models[model].items():
                if v.get("value") is None:
                    dropped.append({"scene": scene, "param": param, "nu": nu, "model": model, "quantity": q,
                                    "what": "value dropped", "reason": v["reason"]})
        complete = _complete(cfg, models)
        bands = {}
        if complete is not None:
            for name, th in theories.items():
                for q, tv in th.items():
                    mv = models[complete].get(q, {})
                    if mv.get("value") is None:
                        continue
                    d = abs(tv / mv["value"] - 1.0)
                    band, reason = classify(d, mv["uncertainty"], cfg.thresholds, cfg.resolve_factor)
                    bands.setdefault(name, {})[q] = {"difference": d, "uncertainty": mv["uncertainty"], "band": band,
                                                     "reason": reason}
                    if reason:
                        dropped.append({"scene": scene, "param": param, "nu": nu, "theory": name, "quantity": q,
                                        "what": "map point unresolved", "reason": reason})
        else:
            dropped.append({"scene": scene, "param": param, "nu": nu, "what": "point unused",
                            "reason": "no model has a moment value at this point"})
        points.append({"scene": scene, "param": param, "nu": nu, "beta": beta_of(nu), "models": models,
                       "theories": theories, "complete_model": complete, "bands": bands,
                       "split": _split(models, complete, theories, scene)})
    hp_points, hp_dropped = assemble_halfplanes(cfg, hp_records)
    return points + hp_points, dropped + hp_dropped


HP_COMPLETE = "halfplane/convective over halfplane/small"  # the two-half-planes part's measured model


def _hp_split(models: dict, theories: dict) -> dict | None:
    """Split the gap to Hertz of the moment half-width of two half-planes (relative, at the same load), exactly:
    total = S R - 1 = profile + convective, with S the small run over Hertz and R the ratio convective over small
    (each extrapolated, :func:`_value`): profile = S - 1 (the FEM's own distance from Hertz: theory 0 for a
    parabola), convective = S (R - 1). The convective part = its theory S (R_ch - 1) (converged Ciavarella-Hills;
    the first order beside it) + ``remainder`` S (R - R_ch): how much of the FEM-vs-classical gap the convective
    theory explains and how much remains. Uncertainties: S U_S; the convective part and the remainder S R U_R (the
    two runs' errors are correlated: the ratio's own GCI is used); the total their root sum of squares."""
    def val(key):
        m = models.get(key, {}).get("moment", {})
        return (m["value"], m["uncertainty"] * abs(m["value"])) if m.get("value") is not None else (None, None)

    S, u_S = val("halfplane/small")
    R, u_R = val(HP_COMPLETE)
    if S is None or R is None:
        return None
    r_ch, r_first = theories["ch_converged"]["moment"], theories["ch_first_order"]["moment"]
    u_conv = abs(S) * u_R
    return {"total": {"value": S * R - 1.0, "uncertainty": math.hypot(u_S, u_conv)},
            "profile": {"value": S - 1.0, "uncertainty": u_S, "theory": 0.0},
            "convective": {"value": S * (R - 1.0), "uncertainty": u_conv, "theory": S * (r_ch - 1.0),
                           "theory_first_order": S * (r_first - 1.0)},
            "remainder": {"value": S * (R - r_ch), "uncertainty": u_conv},
            "traction": {"value": None, "uncertainty": None}, "finite_strain": {"value": None, "uncertainty": None},
            "complete_model": HP_COMPLETE}


def assemble_halfplanes(cfg: ValidityConfig, records: list[dict]) -> tuple[list[dict], list[dict]]:
    """Points (b0/R, beta) of the two-half-planes part: each run's moment half-width over Hertz and their ratio
    convective over small per level, each extrapolated with its uncertainty (:func:`_value`: three levels and the
    far block); the theories' moment ratios (:func:`workbench.studies.validity_halfplanes.halfplanes_theories`)
    against the ratio, banded (:func:`classify`) and marked ``inside`` when |theory - FEM| <= U; the gap split
    (:func:`_hp_split`); and the dropped entries with their reasons."""
    by_point: dict = {}
    dropped = []
    for r in records:
        t = r["task"]
        lev = by_point.setdefault((t["param"], t["beta"]), {}).setdefault(r["model"], {})
        lev[t["level"]] = {"moment": r.get("moment")} if r["converged"] else {}
        if not r["converged"]:
            dropped.append({"scene": "halfplanes", "param": t["param"], "nu": t["nu"], "beta": t["beta"],
                            "model": r["model"], "level": t["level"], "what": "run failed", "reason": r["error"]})
    points = []
    for (param, beta), ml in sorted(by_point.items()):
        small, conv = ml.get("halfplane/small", {}), ml.get("halfplane/convective", {})
        ratio_levels = {}
        for level in ("h0", "h1", "h2", "far"):
            s_, c_ = small.get(level, {}).get("moment"), conv.get(level, {}).get("moment")
            ratio_levels[level] = {"moment": c_ / s_} if s_ and c_ is not None else {}
        models = {k: {"moment": _value(levels, "moment", cfg.halfplanes_h_ratios)}
                  for k, levels in (("halfplane/small", small), ("halfplane/convective", conv),
                                    (HP_COMPLETE, ratio_levels))}
        here = {"scene": "halfplanes", "param": param, "nu": 0.0, "beta": beta}
        for model, v in models.items():
            if v["moment"].get("value") is None:
                dropped.append(here | {"model": model, "quantity": "moment", "what": "value dropped",
                                       "reason": v["moment"]["reason"]})
        theories = halfplanes_theories(param, beta)
        mv = models[HP_COMPLETE]["moment"]
        bands = {}
        if mv.get("value") is not None:
            for name, th in theories.items():
                tv, value, u = th["moment"], mv["value"], mv["uncertainty"]
                d = abs(tv / value - 1.0)
                band, reason = classify(d, u, cfg.thresholds, cfg.resolve_factor)
                bands[name] = {"moment": {"difference": d, "uncertainty": u, "band": band, "reason": reason,
                                          "inside": abs(tv - value) <= u * abs(value)}}
                if reason:
                    dropped.append(here | {"theory": name, "quantity": "moment", "what": "map point unresolved",
                                           "reason": reason})
        else:
            dropped.append(here | {"what": "point unused", "reason": "no moment ratio (convective over small) at "
                                                                     "this point: " + mv["reason"]})
        points.append(here | {"models": models, "theories": theories,
                              "complete_model": HP_COMPLETE if mv.get("value") is not None else None,
                              "bands": bands, "split": _hp_split(models, theories)})
    return points, dropped


def claim_points(cfg: ValidityConfig, records: list[dict]) -> dict:
    """The paper's claim: FEM wedge stresses (obstacle traction, small strain, nu = claim_nu) against the
    half-plane wedge solution at the same load, over the probe grid |x| <= 1.5 b, b/4 <= z <= 2 b, relative to
    the mean pressure P/(2b) (the wedge's peak is log-singular). Also the halfplane-traction run against the
    same theory (the numerical floor) and the two FEM runs against each other (the traction effect alone)."""
    from analytic.halfplane_stress import stress_under_pressure
    from analytic.wedge import wedge_pressure

    runs = {}
    for r in records:
        t = r["task"]
        if r.get("stresses") is not None and t["scene"] == "wedge":  # the rigid wedge's (not the elastic wedge's)
            runs[(t["param"], t["traction"], t["level"])] = r
    rows = []
    for theta in cfg.wedge_theta:
        row = {"theta": theta, "theta_over_pi": theta / math.pi, "nu": cfg.claim_nu}
        for level in ("h2", "far"):
            hp, ob = runs.get((theta, "halfplane", level)), runs.get((theta, "obstacle", level))
            if hp is None or ob is None:
                row[level] = {"reason": "a run of the pair is missing or failed"}
                continue
            E_star = materials.plane_strain_modulus(cfg.E, cfg.claim_nu)
            m = math.tan(theta)
            res = {}
            for name, r in (("halfplane", hp), ("obstacle", ob)):
                b = r["P"] / (E_star * m)
                st = r["stresses"]
                ex = stress_under_pressure(np.array(st["x"]), np.array(st["z"]),
                                           pressure=lambda x, b=b, m=m, E_star=E_star: float(
                                               wedge_pressure(np.array([x]), b=b, m=m, E_star=E_star)[0]),
                                           b=b, nu=cfg.claim_nu)
                p_mean = r["P"] / (2.0 * b)
                dev = np.max([np.abs(np.array(st[k]) - getattr(ex, k)) for k in ("sxx", "szz", "sxz")], axis=0)
                deep = np.isclose(np.array(st["z"]) / b, max(CLAIM_Z), rtol=1e-6)
                res[name] = {"max_diff_over_p_mean": float(np.nanmax(dev)) / p_mean,
                             "deepest_row_max_diff_over_p_mean": float(np.nanmax(dev[deep])) / p_mean,
                             "p_mean": p_mean}
            p_mean = res["obstacle"]["p_mean"]
            direct = max(float(np.nanmax(np.abs(np.array(ob["stresses"][k]) - np.array(hp["stresses"][k]))))
                         for k in ("sxx", "szz", "sxz")) / p_mean
            row[level] = {"obstacle_vs_theory": res["obstacle"]["max_diff_over_p_mean"],
                          "obstacle_vs_theory_deepest_row": res["obstacle"]["deepest_row_max_diff_over_p_mean"],
                          "halfplane_vs_theory": res["halfplane"]["max_diff_over_p_mean"],
                          "obstacle_vs_halfplane_fem": direct}
        rows.append(row)
    verdict = None
    best = None
    for level in ("h2", "far"):  # the level whose numerical floor is the smaller
        tested = [r for r in rows if r["theta"] < cfg.claim_theta_max * (1.0 + 1e-9) and
                  "obstacle_vs_theory" in r.get(level, {})]
        if not tested:
            continue
        floor = max(r[level]["halfplane_vs_theory"] for r in tested)
        if best is None or floor < best[1]:
            best = (level, floor, tested)
    if best is not None:
        level, floor, tested = best
        worst = max(r[level]["obstacle_vs_theory"] for r in tested)
        direct = max(r[level]["obstacle_vs_halfplane_fem"] for r in tested)
        if direct + floor <= cfg.claim_bound:
            state = "holds"
        elif direct - floor > cfg.claim_bound:
            state = "does not hold"
        else:
            state = "undecided"
        verdict = {"level": level, "worst_obstacle_vs_theory": worst, "worst_floor": floor,
                   "worst_traction_effect": direct, "bound": cfg.claim_bound, "state": state,
                   "angles_tested": [r["theta"] for r in tested],
                   "text": (f"{state}: for theta <= pi/5 the FEM wedge with the traction along the face normal "
                            f"(nu = {cfg.claim_nu:g}, beta = {beta_of(cfg.claim_nu):.1e}) differs from the same FEM "
                            f"with the half-plane's vertical traction by up to {100 * direct:.2f} % of the mean "
                            f"pressure P/(2b) in |x| <= 1.5 b, b/4 <= z <= 2 b; numerical floor (vertical-traction "
                            f"FEM against the half-plane wedge stresses) {100 * floor:.2f} %; obstacle FEM against "
                            f"the half-plane stresses {100 * worst:.2f} %; the paper's bound "
                            f"{100 * cfg.claim_bound:g} %")}
    return {"quantity": "max over the probes of max(|d s_xx|, |d s_zz|, |d s_xz|) / (P / 2b)",
            "probes_x_over_b": CLAIM_X, "probes_z_over_b": CLAIM_Z, "rows": rows, "verdict": verdict}


class _Parser(argparse.ArgumentParser):
    """argparse whose errors are one stderr line and exit code 2."""

    def error(self, message: str):  # type: ignore[override]
        print(f"{self.prog}: error: {' '.join(message.split())}", file=sys.stderr)
        raise SystemExit(2)


def main(argv: list[str] | None = None) -> int:
    """CLI ``workbench validity [--out DIR] [--mesh-cache DIR] [--executor local|mpi] [--workers N] [--quick]
    [--tiny] [--halfplanes-only]``;
    bad options or config values: one line, exit 2, nothing run or written."""
    ap = _Parser(prog="workbench validity", description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=None, help="output folder (default: <results>/validity)")
    ap.add_argument("--mesh-cache", type=Path, default=None, help="mesh cache (default: <results>/mesh_cache)")
    add_executor_options(ap, workers=ValidityConfig.workers)
    ap.add_argument("--quick", action="store_true", help="two points per scene, nu = 0 and 0.499; two half-planes "
                    "at beta = -0.3 and +0.3, b0/R = 0.1; the elastic wedge at pi/10 and pi/5 (a smoke run)")
    ap.add_argument("--tiny", action="store_true", help="one point per scene, nu = 0, two half-planes at beta = "
                    "-0.3 and +0.3, the elastic wedge at pi/5, coarse levels on small blocks (the end-to-end test: "
                    "every layer in seconds, no meaningful numbers)")
    ap.add_argument("--halfplanes-only", action="store_true", help="the two-elastic-half-planes part alone (no rigid "
                    "circle or wedge, no elastic wedge)")
    args = ap.parse_args(argv)
    kw = {}
    if args.quick:
        kw = {"cylinder_a_over_R": (0.01, 0.2), "wedge_theta": (math.pi / 10, math.pi / 5), "nu": (0.0, 0.499),
              "halfplanes_beta": (-0.3, 0.3), "halfplanes_b0_over_R": (0.1,),
              "elastic_wedge_theta": (math.pi / 10, math.pi / 5)}
    if args.tiny:
        kw = {"cylinder_a_over_R": (0.1,), "wedge_theta": (math.pi / 10,), "nu": (0.0,), "h_ratios": (2.0, 3.0, 4.0),
              "width_factor": 20.0, "width_factor_far": 40.0, "halfplanes_beta": (-0.3, 0.3),
              "halfplanes_b0_over_R": (0.1,), "halfplanes_h_ratios": (2.0, 3.0, 4.0),
              "elastic_wedge_theta": (math.pi / 5,), "elastic_wedge_h_ratios": (2.0, 3.0, 4.5),
              "elastic_wedge_width": 12.0, "elastic_wedge_width_far": 24.0}
    if args.halfplanes_only:
        kw |= {"rigid": False, "elastic_wedge_theta": ()}
    try:
        executor = executor_from_args(args)
        cfg = ValidityConfig(out=args.out, mesh_cache=args.mesh_cache, workers=executor.workers, **kw)
    except ValueError as exc:
        print(f"workbench validity: error: {exc}", file=sys.stderr)
        return 2
    t0 = time.perf_counter()
    import resource

    records, skipped, timing = run_study(cfg, executor=executor)
    if executor.kind == "local":  # MPI workers are no children of this process: their time is in "where"
        timing["cpu_s_workers"] = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime + \
            resource.getrusage(resource.RUSAGE_CHILDREN).ru_stime
    points, dropped = assemble(cfg, records, skipped)
    claim = claim_points(cfg, records)
    claim_elastic = claim_elastic_wedge(cfg, records)
    dropped += [d | {"nu": cfg.elastic_wedge_nu} for d in claim_elastic.pop("dropped")]
    wall = time.perf_counter() - t0
    from workbench.studies.reference import measure_reference

    reference = measure_reference(executor=executor, mesh_cache=cfg.cache_dir)
    summary = {"runs": len(records), "converged": sum(r["converged"] for r in records),
               "failed": sum(not r["converged"] for r in records), "points": len(points), "dropped": len(dropped),
               "wall_time_s": wall, "executor": executor.kind, "workers": executor.workers,
               "cpu_count": os.cpu_count(), "jit_retries": timing["where"]["jit_retries"],
               "jit_compiles_on_workers": timing["where"]["jit_compiles"], "reference": reference, **timing}
    out = cfg.out_dir
    write_json(out / "validity.json", {"config": to_json(cfg), "summary": summary, "points": points,
                                       "dropped": dropped, "claim": claim, "claim_elastic_wedge": claim_elastic,
                                       "runs": records,
                                       "finite_settings": finite_settings()})
    from workbench.studies.validity_plot import main as plot_main
    from workbench.studies.validity_report import write_report

    write_report(out)
    plot_main(["--dir", str(out)])
    print(f"validity: {summary['runs']} runs ({summary['failed']} failed), {summary['points']} points, "
          f"{summary['dropped']} dropped entries, {wall:.0f} s on {executor.workers} {executor.kind} worker(s), "
          f"{summary['jit_retries']} JIT retries -> {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
