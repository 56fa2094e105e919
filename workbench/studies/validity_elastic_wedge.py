"""The validity study's elastic-wedge part (issue 25): Ciavarella and Hills's theta < pi/5 claim, as the paper
states it.

The claim (their section 3): "providing theta < pi/5, the internal stress state for the elastically similar problem
does not differ by more than 0.5 % from the exact solution". The problem is an elastic wedge of external angle
theta (faces ``y = m |x|``, m = tan theta) pressed onto an elastic body of the same material; the exact solution
is the half-plane theory's (the classical wedge, :func:`analytic.wedge.wedge_pressure`, at E* of the pair and
the measured load, with the half-plane stresses of that pressure, :func:`analytic.halfplane_stress.
stress_under_pressure`). Beta = 0, so no convective effect enters: the only difference is the geometry, a wedge
that is not a half-plane.

Runs (through the registered ``halfplanes`` scene, small kinematics, mortar, P2, both bodies E and
``elastic_wedge_nu``): per theta, the **shaped** pair (the upper body is the wedge itself, its faces meshed:
``geometry.wedge_body = "shaped"``), and once for all angles the **flat** pair (the half-plane idealisation on the same
sizes: the upper block flat, the wedge an analytic gap; self-similar in theta, :func:`elastic_wedge_tasks`), each on
three levels b/h_c = ``elastic_wedge_h_ratios`` and once on the middle
level with the wider blocks ``elastic_wedge_width_far`` (the truncation). The load is the classical one of b = 1 mm.

At finite strain (issue 39, item 4; ``elastic_wedge_finite_laws``): per theta and law the shaped pair again, both
bodies that hyperelastic law, P1, the traction along the deformed interface (the wedge's current face normal:
``traction = "obstacle"``), kappa0 = :data:`workbench.studies.validity_halfplanes.FINITE_KAPPA0`, on the same levels
and meshes; measured: the moment half-width, over the small-strain shaped pair's (:func:`_finite_rows`). No probes:
its stresses are Cauchy's at the current positions, and the contact strain under a wedge is of the order of m.

Probes (both bodies, full model): x/b in +-:data:`PROBE_X`, z/b in :data:`PROBE_Z`, z the vertical depth below the
body's own surface: ``(x, -z)`` in the lower block, ``(x, m |x| + z)`` in the shaped wedge and ``(x, z)`` in the
flat upper block; b = P / (E* m) at each run's measured load. The half-plane stresses of the upper body are the
lower body's mirrored (``s_xz`` changes sign), as the two bodies of the same material carry the same pressure.

Quantities, each the largest ``max(|d s_xx|, |d s_yy|, |d s_xy|)`` over one body's probes, over the mean pressure
P/(2b) (the wedge's peak is log-singular); in the block (``geometry`` ...) and in the wedge (``geometry_wedge`` ...):

* ``geometry``: shaped FEM minus flat FEM, level by level (the claim's difference, with the discretisation
  errors of the two largely cancelling);
* ``shaped_vs_theory``: shaped FEM minus the half-plane solution (the paper's comparison, FEM error included);
* ``flat_vs_theory``: flat FEM minus the half-plane solution (the numerical floor: its exact answer is the theory).

The uncertainty of ``geometry`` on the finest level: the GCI of its three levels
(:func:`workbench.error_budget.grid_study`, absolute) plus the whole change from the middle level to the wide blocks
(no extrapolation in b/W: a maximum over probes need not follow one order). Verdict, on the block: "holds" when
geometry + U <= 0.5 % for every theta < pi/5, "does not hold" when geometry - U > 0.5 % for one, else
"undecided". Why the block: its surface is flat in both problems, so its Cartesian stresses compare point for
point, and the contact traction acts on it vertically as in the half-plane theory (the traction of the
``halfplane`` model), so its difference is the wedge's geometry alone. Inside the wedge the comparison depends on
choices the theory does not make: the face is inclined by theta, so near it the Cartesian components of the wedge
and of the mirrored half-plane differ by ~ theta |s| (measured: the largest wedge differences sit at z = b/4, at
and beyond the contact edge), and the vertical traction has a part p sin theta along the face (the frictionless
truth, along the deformed interface, lies between the two faces' normals; convective kinematics with the deformed
master's normal did not converge on the shaped wedge: DIVERGED_MAX_IT in the first step at pi/10). The wedge's
values are reported beside. Units: mm, N/mm, MPa.
"""

from __future__ import annotations

import functools
import math
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from analytic import materials
from vocabulary import FINITE, OBSTACLE
from workbench.error_budget import grid_study
from workbench.studies.scene_point import run_failure, run_point
from workbench.studies.validity_halfplanes import FINITE_KAPPA0

__all__ = ["EW_LABEL", "PROBE_X", "PROBE_Z", "ElasticWedgeTask", "build_mesh", "claim_elastic_wedge",
           "elastic_wedge_tasks", "solve_task"]

EW_LABEL = "ew"  # the runs' label (the scene names its mesh <name>_<label>)
EW_STEPS = 3  # load steps (force control), as the halfplanes cases
EW_METHOD = "augmented_lagrangian"  # as the halfplanes cases
PROBE_X = (0.0, 0.25, 0.5, 0.75, 1.0, 1.5)  # x / b, both signs (the rigid claim's probes)
PROBE_Z = (0.25, 0.5, 0.75, 1.0, 1.5, 2.0)  # depth / b below each body's own surface


@dataclass(frozen=True)
class ElasticWedgeTask:
    """One FEM run of the elastic-wedge part (b = 1 mm; units mm, N/mm, MPa).

    Attributes:
        param: theta (rad), face slope m = tan theta.  upper: ``shaped`` or ``flat`` (module docstring).
        level: ``h0``, ``h1``, ``h2`` or ``far``.  h_ratio, width_factor, growth: b/h_c, W/b (both bodies) and
            the grading.  E, nu: both bodies' material.  n_steps: load steps.
        scene, kinematics, traction: ``elastic_wedge``; ``small`` with the vertical traction ``halfplane``, or
            ``finite`` with ``obstacle`` (along the deformed interface: the wedge's current face normal).
        material, degree: both bodies' law (``linear``; a finite run's hyperelastic law) and the degree (2; 1).
    """

    param: float
    upper: str
    level: str
    h_ratio: float
    width_factor: float
    growth: float
    E: float
    nu: float
    n_steps: int = EW_STEPS
    scene: str = "elastic_wedge"
    kinematics: str = "small"
    traction: str = "halfplane"
    material: str = "linear"
    degree: int = 2

    @property
    def mesh_name(self) -> str:  # the shaped pair's mesh serves its finite runs too (the same blocks)
        return f"validity_ew_{self.upper}_t{self.param:.6f}_h{self.h_ratio:g}_W{self.width_factor:g}"

    @property
    def model(self) -> str:
        own = f"{self.upper}/{self.kinematics}"
        return f"{own}/{self.material}" if self.kinematics == FINITE else own


def elastic_wedge_tasks(cfg) -> list[ElasticWedgeTask]:
    """Every run of the part: per theta the shaped wedge's three levels and wide blocks, listed together, and the
    flat pair's once, at the first angle: the idealised problem is self-similar in theta (at fixed b its stresses
    over P/(2b) do not depend on m; measured: its moment ratios at pi/10 ... pi/4 agree to 1e-11), so one flat
    run per level serves every angle."""
    hs = cfg.elastic_wedge_h_ratios
    levels = [(f"h{i}", h, cfg.elastic_wedge_width) for i, h in enumerate(hs)]
    levels.append(("far", hs[1], cfg.elastic_wedge_width_far))
    pairs = [(theta, "shaped") for theta in cfg.elastic_wedge_theta]
    if cfg.elastic_wedge_theta:
        pairs.append((cfg.elastic_wedge_theta[0], "flat"))
    def grow(h):
        return 1.0 + (cfg.growth - 1.0) * hs[0] / h

    out = [ElasticWedgeTask(float(theta), upper, level, float(h), float(W), grow(h), float(cfg.E),
                            float(cfg.elastic_wedge_nu))
           for theta, upper in pairs for level, h, W in levels]
    out += [ElasticWedgeTask(float(theta), "shaped", level, float(h), float(W), grow(h), float(cfg.E),
                             float(cfg.elastic_wedge_nu), kinematics=FINITE, traction=OBSTACLE, material=law, degree=1)
            for theta in _finite_angles(cfg) for law in cfg.elastic_wedge_finite_laws for level, h, W in levels]
    return out


def _finite_angles(cfg) -> list[float]:
    """The angles of ``cfg.elastic_wedge_theta`` that have finite-strain runs (``elastic_wedge_finite_theta``)."""
    return [t for t in cfg.elastic_wedge_theta if any(abs(t - u) <= 1e-12 for u in cfg.elastic_wedge_finite_theta)]


def _run(task: ElasticWedgeTask):
    """The case-level run of ``task`` (as a case file would give it)."""
    from cases.schema import Body, Discretisation, Loading, Run, Solver
    from workbench.scenes.halfplanes_schema import HalfplanesGeometry

    bodies = (Body("block", task.E, task.nu, model=task.material), Body("wedge", task.E, task.nu, model=task.material))
    finite = task.kinematics == FINITE
    geo = HalfplanesGeometry(scene="halfplanes", indenter="wedge", wedge_angle=task.param, wedge_slope="exact",
                             apex="refined", wedge_body=task.upper, width_factor=task.width_factor,
                             height_factor=task.width_factor)
    return Run(label=EW_LABEL, material=bodies[0].material, geometry=geo,
               loading=Loading(control="force", half_width=1.0, steps=task.n_steps),
               discretisation=Discretisation(degree=task.degree, h_contact=1.0 / task.h_ratio, growth=task.growth),
               solver=Solver(method=EW_METHOD, kinematics=task.kinematics, traction=task.traction,
                             **({"kappa0": FINITE_KAPPA0} if finite else {})), bodies=bodies)


def build_mesh(task: ElasticWedgeTask, mesh_cache: str) -> dict:
    """Build (or reuse) the mesh of ``task`` through the scene; returns the mesh statistics."""
    import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

    from mpi4py import MPI

    from workbench.scenes import scene_for

    run = _run(task)
    mesh = scene_for(run).mesh(run, name=task.mesh_name, mesh_cache=Path(mesh_cache), comm=MPI.COMM_SELF)
    return {"mesh": task.mesh_name, "cells": mesh.files.stats.get("cells")}


def probe_points(*, b: float, m: float, shaped: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(lower points, upper points, (x/b, z/b) of each) of the probe grid (module docstring), mm."""
    xs = sorted({s * x for x in PROBE_X for s in (-1.0, 1.0)})
    xz = np.array([(x, z) for z in PROBE_Z for x in xs])
    lower = np.column_stack([xz[:, 0] * b, -xz[:, 1] * b])
    lift = m * np.abs(xz[:, 0]) * b if shaped else 0.0
    upper = np.column_stack([xz[:, 0] * b, lift + xz[:, 1] * b])
    return lower, upper, xz


def solve_task(task: ElasticWedgeTask, mesh_cache: str) -> dict:
    """Mesh (cached), solve and compare one run through the scene, then sample both bodies' stresses at the
    probes (module docstring). Never raises: a failure is the record's named ``error``."""
    rec = {"task": asdict(task), "model": task.model, "converged": False, "error": None}
    t0 = time.perf_counter()
    try:
        from fem.probe import stress_at_points

        o = run_point(_run(task), name=task.mesh_name, mesh_cache=mesh_cache)
        m = o.metrics
        b = m["analytic"]["half_width"]
        stresses = None  # a finite run: no probes (its stresses are Cauchy's at the current positions)
        if task.kinematics != FINITE:
            lower, upper, xz = probe_points(b=b, m=math.tan(task.param), shaped=task.upper == "shaped")
            st = {"lower": stress_at_points(o.result, lower), "upper": stress_at_points(o.result, upper)}
            stresses = {"x_over_b": xz[:, 0].tolist(), "z_over_b": xz[:, 1].tolist()}
            for body, s in st.items():
                stresses[body] = {"sxx": s.sxx.tolist(), "syy": s.syy.tolist(), "sxy": s.sxy.tolist()}
    except Exception as exc:  # noqa: BLE001  (named: diverged, refused or failed)
        return rec | {"error": run_failure(exc), "time_s": time.perf_counter() - t0}
    return rec | {"converged": True, "time_s": time.perf_counter() - t0, "cells": (m.get("mesh") or {}).get("cells"),
                  "ndofs": m["ndofs"], "P": m["P"], "b": b, "E_star": m["E_star"],
                  "iterations": int(sum(m["newton_iterations"])), "failed_iterations": int(m["failed_iterations"]),
                  "warnings": list(m["warnings"]),
                  "half_width": m["patch_half_width"] / b,
                  "moment": m["half_width_moment"] / (2.0 * b / math.sqrt(6.0)),
                  "load_balance": abs(m["P"] - m["P_pressure"]) / abs(m["P"]), "stresses": stresses}


@functools.lru_cache(maxsize=1)
def theory_unit() -> dict:
    """The half-plane solution at the probes (module docstring), over the mean pressure P/(2b) and at b = 1:
    ``{"lower"|"upper": {"sxx", "syy", "sxy"}}``. The classical wedge is self-similar (p / p_mean is a function of
    x/b alone, whatever E* and m), so one evaluation serves every angle and load; the upper body's stresses are
    the lower's mirrored (s_xy changes sign)."""
    from analytic.halfplane_stress import stress_under_pressure
    from analytic.wedge import wedge_pressure

    _, _, xz = probe_points(b=1.0, m=0.0, shaped=False)
    # E* m = 2 and b = 1: p_mean = E* m / 2 = 1
    ex = stress_under_pressure(xz[:, 0], xz[:, 1], b=1.0, nu=0.0,
                               pressure=lambda s: float(wedge_pressure(np.array([s]), b=1.0, m=1.0, E_star=2.0)[0]))
    return {"lower": {"sxx": ex.sxx, "syy": ex.szz, "sxy": ex.sxz},
            "upper": {"sxx": ex.sxx, "syy": ex.szz, "sxy": -ex.sxz}}


def _unit(rec: dict) -> dict:
    """``rec``'s probe stresses over its mean pressure P/(2b)."""
    p_mean = rec["P"] / (2.0 * rec["b"])
    return {body: {k: np.asarray(v) / p_mean for k, v in rec["stresses"][body].items()} for body in ("lower", "upper")}


def _max_diff(a: dict, b: dict) -> dict:
    """Largest component difference of two unit stress sets over the probes, per body and over both."""
    out = {body: max(float(np.nanmax(np.abs(np.asarray(a[body][k]) - np.asarray(b[body][k]))))
                     for k in ("sxx", "syy", "sxy"))
           for body in ("lower", "upper")}
    out["both"] = max(out["lower"], out["upper"])
    return out


def _band(cfg, lv: dict, body: str) -> dict:
    """``body``'s geometry difference on the finest level with its uncertainty (module docstring), and its
    shaped-against-theory value and floor there."""
    g = tuple(lv[k]["geometry"][body] for k in ("h0", "h1", "h2"))
    gs = grid_study(tuple(1.0 / h for h in cfg.elastic_wedge_h_ratios), g)
    width = abs(lv["far"]["geometry"][body] - lv["h1"]["geometry"][body])
    u_grid = gs.gci * abs(g[2])
    return {"geometry": g[2], "U_grid": u_grid, "status": gs.status,
            "order": gs.observed_order if math.isfinite(gs.observed_order) else None, "U_width": width,
            "U": u_grid + width, "shaped_vs_theory": lv["h2"]["shaped_vs_theory"][body],
            "floor": lv["h2"]["flat_vs_theory"][body]}


def _finite_rows(cfg, records: list[dict], theta: float) -> dict:
    """Per law at ``theta`` (issue 39, item 4): the finite-strain shaped pair's moment half-width over the
    classical wedge's (P1, extrapolated with its band over the three levels and the wide bodies, as the two
    half-planes' values) and its ratio F to the small-strain shaped pair's (P2, the same): F - 1 is what finite
    strain and the traction along the deformed interface change together, against the claim's bound."""
    from workbench.studies.validity_assemble import extrapolated_value

    def levels(model):
        return {r["task"]["level"]: {"moment": r.get("moment")} if r.get("converged") else {}
                for r in records if r["task"].get("scene") == "elastic_wedge" and r["task"]["param"] == theta
                and r["model"] == model}

    def warned(model):  # the levels whose run carries a solver warning (e.g. an oscillating pressure)
        return sorted(r["task"]["level"] for r in records if r["task"].get("scene") == "elastic_wedge"
                      and r["task"]["param"] == theta and r["model"] == model and r.get("warnings"))

    hs = cfg.elastic_wedge_h_ratios
    S = extrapolated_value(levels("shaped/small"), "moment", hs)
    out = {}
    for law in cfg.elastic_wedge_finite_laws:
        M = extrapolated_value(levels(f"shaped/{FINITE}/{law}"), "moment", hs)
        M["warned_levels"] = warned(f"shaped/{FINITE}/{law}")
        if M.get("value") is None or S.get("value") is None:
            why = M.get("reason") if M.get("value") is None else "the small-strain shaped pair has no value: " + \
                S["reason"]
            out[law] = {"moment": M, "small": S, "ratio": {"value": None, "reason": why}}
            continue
        F, u = M["value"] / S["value"], math.hypot(M["uncertainty"], S["uncertainty"])
        out[law] = {"moment": M, "small": S, "ratio": {"value": F, "uncertainty": u},
                    "beyond_bound": abs(F - 1.0) - u * F > cfg.claim_bound}
    return out


def claim_elastic_wedge(cfg, records: list[dict]) -> dict:
    """The paper's claim from the part's records: per theta the three quantities (module docstring) on every level,
    the grid uncertainty of ``geometry`` and the verdict over theta < ``cfg.claim_theta_max``."""
    runs = {(r["task"]["param"], r["task"]["upper"], r["task"]["level"]): r for r in records
            if r["task"].get("scene") == "elastic_wedge" and r.get("converged")
            and r["task"].get("kinematics", "small") == "small"}
    levels = ("h0", "h1", "h2", "far")
    rows, dropped = [], []
    for theta in cfg.elastic_wedge_theta:
        row = {"theta": theta, "theta_over_pi": theta / math.pi, "levels": {}}
        for level in levels:
            sh, fl = runs.get((theta, "shaped", level)), runs.get((cfg.elastic_wedge_theta[0], "flat", level))
            if sh is None or fl is None:
                row["levels"][level] = {"reason": "a run of the pair is missing or failed"}
                continue
            sh_u, fl_u, th_u = _unit(sh), _unit(fl), theory_unit()
            row["levels"][level] = {
                "geometry": _max_diff(sh_u, fl_u), "shaped_vs_theory": _max_diff(sh_u, th_u),
                "flat_vs_theory": _max_diff(fl_u, th_u),
                "moment_shaped": sh["moment"], "moment_flat": fl["moment"]}
        lv = row["levels"]
        if all("geometry" in lv[k] for k in levels):
            for body, suffix in (("lower", ""), ("upper", "_wedge")):
                row |= {f"{k}{suffix}": v for k, v in _band(cfg, lv, body).items()}
        else:
            dropped.append({"scene": "elastic_wedge", "param": theta, "what": "claim point unused",
                            "reason": "a run of the shaped/flat pair is missing or failed: "
                                      + "; ".join(f"{k}: {v['reason']}" for k, v in lv.items() if "reason" in v)})
        if cfg.elastic_wedge_finite_laws and theta in _finite_angles(cfg):
            row["finite"] = _finite_rows(cfg, records, theta)
            dropped += [{"scene": "elastic_wedge", "param": theta, "model": f"shaped/{FINITE}/{law}",
                         "what": "finite row unused", "reason": f["ratio"]["reason"]}
                        for law, f in row["finite"].items() if f["ratio"].get("value") is None]
        rows.append(row)
    tested = [r for r in rows if r["theta"] < cfg.claim_theta_max * (1.0 + 1e-9) and "geometry" in r]
    verdict = None
    if tested:
        worst = max(tested, key=lambda r: r["geometry"] + r["U"])
        bound = cfg.claim_bound
        if all(r["geometry"] + r["U"] <= bound for r in tested):
            state = "holds"
        elif any(r["geometry"] - r["U"] > bound for r in tested):
            state = "does not hold"
        else:
            state = "undecided"
        over = [r for r in tested if r["geometry"] - r["U"] > bound]
        at = over[0] if over else worst
        verdict = {"state": state, "bound": bound, "theta_max": cfg.claim_theta_max,
                   "angles_tested": [r["theta"] for r in tested], "worst_theta": at["theta"],
                   "geometry": at["geometry"], "U": at["U"], "shaped_vs_theory": at["shaped_vs_theory"],
                   "floor": at["floor"], "nu": cfg.elastic_wedge_nu,
                   "geometry_wedge": at["geometry_wedge"], "U_wedge": at["U_wedge"],
                   "text": (f"{state}: elastic wedge on a block of the same material (nu = {cfg.elastic_wedge_nu:g}, "
                            f"beta = 0), the stresses in the block under the contact, shaped minus "
                            f"half-plane-idealised FEM at theta = {at['theta'] / math.pi:.3g} pi: "
                            f"{100 * at['geometry']:.2f} % +- {100 * at['U']:.2f} % of P/(2b) (grid and block size) "
                            f"over |x| <= 1.5 b, b/4 <= z <= 2 b, even with the half-plane's own (vertical) traction; "
                            f"shaped FEM against the half-plane solution {100 * at['shaped_vs_theory']:.2f} %, "
                            f"numerical floor (idealised FEM against it) {100 * at['floor']:.2f} %; inside the wedge "
                            f"{100 * at['geometry_wedge']:.2f} % +- {100 * at['U_wedge']:.2f} %; the paper's bound "
                            f"{100 * bound:g} % for theta < {cfg.claim_theta_max / math.pi:.3g} pi")}
    return {"quantity": "max over the probes of max(|d s_xx|, |d s_yy|, |d s_xy|) / (P / 2b), in the block (the "
                        "verdict's) and in the wedge",
            "probes_x_over_b": PROBE_X, "probes_z_over_b": PROBE_Z, "nu": cfg.elastic_wedge_nu,
            "beta": materials.bimaterial(E1=cfg.E, nu1=cfg.elastic_wedge_nu, E2=cfg.E, nu2=cfg.elastic_wedge_nu).beta,
            "rows": rows, "verdict": verdict, "dropped": dropped}
