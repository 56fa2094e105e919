"""Numerical-stability sweep on stiff and extreme cases: ``workbench stability [--study NAME ...] [--out DIR]``.

Writes ``<results>/stability/stability.json`` (the config and one record per run) and ``report.md``, then
:mod:`workbench.studies.stability_plot` draws ``method.png`` and ``incompressible.png`` from the JSON.
Every run either converges within its accuracy band or carries a NAMED reason: a solver failure
(``diverged: ... SNES reason -5 (DIVERGED_MAX_IT)``), a warning of the solver's own checks
(``contact unresolved``, ``penetration``, ``no contact``, ``contact truncated``; :mod:`fem.postprocess`), or a
model limit stated with the run (e.g. the exact circle is not Hertz's parabola at a/R = 0.4). A converged run
outside its band with none of these is counted ``SILENT`` -- the sweep's failure mode; the report lists them.

Scene (unless a study says otherwise): rigid exact circle R = 10 mm on a block (half model, W = H = 40 a,
clamped bottom), plane strain, E = 200 GPa, nu = 0.3, a/R = 0.05, force control to the Hertz load of a, P2,
h_contact = a/10, Nitsche gamma0 = 10, theta = 1, ``small`` kinematics, ``halfplane`` traction. Each run is a
:class:`Spec`, which becomes a case run (:meth:`Spec.run`, a :class:`cases.schema.Run`): its solve is
:func:`workbench.scenes.wiring.solve_run` (with the study's overrides: formulation, iterations, cut-backs,
predictor), its errors the block scene's comparison (through the scene registry,
:mod:`workbench.studies.scene_point`) against Hertz (or the wedge) at the MEASURED load; its mesh is
:mod:`meshes.block` sized from the target half-width (:func:`_mesh`).

Every spec (and the ``conformal`` design) is one point of :func:`workbench.studies.executor.run_points`, run on
``MPI.COMM_SELF`` in this process (``--workers 1``, the default: the published times), in local processes
(``--workers N``) or on MPI ranks (``mpiexec -n N python -m mpi4py.futures -m workbench stability``).

What is swept, and the accuracy bands, are :class:`StabilityConfig` (band 2 %: see there).

Studies: ``method`` (penalty kappa0, Nitsche gamma0 x theta, with a 1-norm condition estimate of the
Jacobian, :mod:`fem.conditioning`), ``augmented_lagrangian`` (kappa0 over five decades: every run must
converge, :func:`classify_augmented_lagrangian`), ``incompressible`` (nu -> 1/2, P1/P2 displacement vs
Taylor-Hood mixed), ``convective`` (wedge b/b0, small vs convective kinematics, as beta -> 0), ``loads`` (a/R
over 2.6 decades, mesh scaled with a), ``resolution`` (h_c from 2a to a/8: the "contact unresolved" warning),
``scale`` (E over nine decades: non-dimensional results), ``conformal`` (close-to-conformal design, first
Table 1 steps: the 0.00043 mm indentation and relative radius ~228 mm), ``faults`` (Newton cut-back, an
unrecoverable step), ``two_body`` (two elastic bodies, E ratios 1e-3 ... 1e3 and nu = 0.499 on either side:
:class:`TwoBodySpec`, the elastic cylinder case through the scene registry and the case pipeline,
:func:`classify_two_body`). Select studies with ``--study NAME`` (repeatable), e.g. ``--study two_body``.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

import argparse
import dataclasses
import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from analytic import convective, materials, wedge
from cases.schema import Discretisation, Loading, Material, Run, Solver
from workbench.atomic import write_json, write_text
from workbench.owned import ensure_dir
from workbench.paths import default_paths
from workbench.scenes.block_schema import BlockGeometry
from workbench.studies.config import STABILITY_STUDIES, StabilityConfig, to_json
from workbench.studies.executor import (
    ExecutorChoice,
    add_executor_options,
    executor_from_args,
    run_points,
    worker_summary,
)
from workbench.studies.scene_point import TargetSized, run_failure
from workbench.studies.where_report import where_section

__all__ = ["STUDIES", "Spec", "StabilityConfig", "TwoBodySpec", "classify", "classify_augmented_lagrangian",
           "classify_two_body", "convective_ratios", "main", "penalty_sweep", "report_markdown", "run_block_spec",
           "run_conformal", "run_sweep", "run_two_body_spec", "scale_invariance", "specs", "two_body_specs"]

STUDIES = STABILITY_STUDIES
AL = "augmented_lagrangian"  # the method and the study of its stiffness sweep


# The sweep's solver options beyond the record's defaults (:class:`fem.options.ContactOptions`): the case files'
# traction (vertical gap and traction, as the half-plane theory the runs are compared with assumes).
SWEEP_OPTIONS = {"traction": "halfplane"}
# The options a run's record names in ``stability.json["runs"][i]["params"]`` (read by the report and the plots).
PARAM_OPTIONS = ("method", "kappa0", "gamma0", "theta", "formulation", "kinematics", "max_it", "max_cutbacks",
                 "active_set_predictor")


@dataclass(frozen=True)
class Spec:
    """One block run of the sweep (units mm, N, MPa).

    Attributes:
        study, label: study name and run label.
        indenter: ``circle``, ``parabola`` or ``wedge`` (face slope = wedge_angle, the paper's profile).
        R: indenter radius (mm).  a_over_R: target Hertz half-width over R (circle, parabola).
        half_width: target classical half-width (mm) for the wedge.  wedge_angle: rad.
        E, nu: block material.  size_factor: block width and height over a.
        degree, h_ratio: element degree and a / h_contact.
        n_steps: load steps.
        control: ``force`` (target the Hertz load) or ``displacement`` (target ``d`` mm, faults study).
        d: displacement target (mm) for displacement control.
        options: solver options of this run: :class:`fem.options.ContactOptions` fields by name (e.g.
            ``{"method": "penalty", "kappa0": 1e2, "max_it": 4}``), over :data:`SWEEP_OPTIONS` over the record's
            defaults (:meth:`option`); a name that is not a field is a TypeError.
        condition: estimate the Jacobian's condition number.
        band: accuracy band of the errors (None: not compared, e.g. the convective run's classical errors).
        model_limit: named reason why the theory itself departs from the scene (used only if out of band).
        expect_failure: the run is meant to fail (faults study).
    """

    study: str
    label: str
    indenter: str = "circle"
    R: float = 10.0
    a_over_R: float = 0.05
    half_width: float = 0.5
    wedge_angle: float | None = None
    E: float = 2.0e5
    nu: float = 0.3
    size_factor: float = 40.0
    degree: int = 2
    h_ratio: float = 10.0
    n_steps: int = 3
    control: str = "force"
    d: float = 0.0
    options: dict = dataclasses.field(default_factory=dict, hash=False)
    condition: bool = False
    band: float | None = StabilityConfig.band
    model_limit: str | None = None
    expect_failure: bool = False

    def __post_init__(self):
        from fem.options import ContactOptions

        names = ContactOptions.field_names()
        for key in self.options:
            if key not in names:
                raise TypeError(f"Spec options: {key!r} is not a ContactOptions field")

    def option(self, name: str):
        """The value of the ContactOptions field ``name`` for this run (this spec's, the sweep's, the record's)."""
        from fem.options import ContactOptions

        return (ContactOptions.defaults() | SWEEP_OPTIONS | self.options)[name]

    def params(self) -> dict:
        """The run's parameters for its JSON record: the spec's fields and the options :data:`PARAM_OPTIONS`."""
        out = {f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.name != "options"}
        return out | {name: self.option(name) for name in PARAM_OPTIONS}

    @property
    def target_half_width(self) -> float:
        """The classical half-width the mesh is sized from (mm): a = a_over_R R, or the wedge's b."""
        return self.half_width if self.indenter == "wedge" else self.a_over_R * self.R

    def run(self) -> Run:
        """This spec as a case run (half model, labelled by its indenter): what the wiring reads; its
        ``[solver]`` fields are the spec's options of the same names. Built directly, not loaded, so a study may
        go beyond a case file's ranges (h_c = 2 a)."""
        size = self.size_factor
        if self.indenter == "wedge":
            geo = BlockGeometry(scene="block", indenter="wedge", wedge_angle=self.wedge_angle, wedge_slope="paper",
                                width_factor=size, height_factor=size, half_model=True)
        else:
            geo = BlockGeometry(scene="block", indenter=self.indenter, radius=self.R, width_factor=size,
                                height_factor=size, half_model=True)
        if self.control == "force":
            loading = Loading(control="force", half_width=self.target_half_width, steps=self.n_steps)
        else:  # the target half-width sizes the mesh (TargetSized) and nothing else
            loading = Loading(control="displacement", half_width=self.target_half_width, d=(self.d,),
                              steps=self.n_steps)
        solver = Solver(**{f.name: self.option(f.name) for f in dataclasses.fields(Solver)})
        return Run(label=self.indenter, material=Material(E=self.E, nu=self.nu), geometry=geo, loading=loading,
                   discretisation=Discretisation(degree=self.degree, h_contact=1.0 / self.h_ratio), solver=solver)

    def solver_overrides(self) -> dict:
        """The study's options beyond the case run (:func:`workbench.scenes.wiring.solve_run` overrides): the
        spec's options, and no extra first step without the active-set predictor."""
        first = 1.0 if not self.option("active_set_predictor") else self.option("first_step_fraction")
        return dict(self.options) | {"first_step_fraction": first}


def _messages(recs: list[dict]) -> list[str]:
    """The report's "Messages" block: every point's error and warnings, one line each (none: no block)."""
    warned = [r for r in recs if r.get("warnings") or r.get("error")]
    if not warned:
        return []
    lines = ["Messages:", ""]
    for r in warned:
        msgs = ([r["error"]] if r.get("error") else []) + list(r.get("warnings", []))
        lines += [f"- {r['label']}: {msg}" for msg in msgs]
    return lines + [""]


def _decade(v: float) -> str:
    """``1e3`` for a power of ten, else ``%g``."""
    k = round(math.log10(v))
    return f"1e{k}" if v == 10.0**k else f"{v:g}"


def specs(cfg: StabilityConfig | None = None) -> list[Spec]:
    """Every block run of the sweep, study by study (``cfg``: :class:`StabilityConfig`, default values)."""
    cfg = StabilityConfig() if cfg is None else cfg
    out = []
    for k in cfg.penalty_kappa0:  # 1. method parameters
        out.append(Spec("method", f"penalty kappa0={_decade(k)}", options=dict(method="penalty", kappa0=k),
                        condition=True, band=cfg.band))
    for theta in cfg.nitsche_theta:
        for g in cfg.nitsche_gamma0:
            out.append(Spec("method", f"nitsche gamma0={g:g} theta={theta}", options=dict(gamma0=g, theta=theta),
                            condition=True, band=cfg.band))
    for k in cfg.al_kappa0:  # 1b. augmented Lagrangian: every stiffness must converge
        out.append(Spec(AL, f"{AL} kappa0={_decade(k)}", options=dict(method=AL, kappa0=k), band=cfg.band))
    for nu in cfg.incompressible_nu:  # 2. near-incompressibility
        for deg, form, h in cfg.incompressible_elements:
            out.append(Spec("incompressible", f"nu={nu:g} P{deg} {form}", nu=nu, degree=deg,
                            options=dict(formulation=form), h_ratio=h, band=cfg.band_p1 if deg == 1 else cfg.band))
    for nu, size in cfg.convective_runs:
        for kin in ("small", "convective"):
            form = "mixed" if nu >= cfg.convective_mixed_from_nu else "displacement"
            out.append(Spec("convective", f"wedge nu={nu:g} block {size:g}b {kin}", indenter="wedge",
                            wedge_angle=cfg.convective_wedge_angle, nu=nu, h_ratio=cfg.convective_h_ratio,
                            size_factor=size, options=dict(formulation=form, kinematics=kin),
                            band=cfg.band_wedge if kin == "small" else None))
    for aR in cfg.loads_a_over_R:  # 3. loads
        limit = (f"model limit: a/R = {aR:g} > {cfg.model_limit_a_over_R:g}, the exact circle departs from "
                 "Hertz's parabola (see the parabola run at the same a/R)") if aR > cfg.model_limit_a_over_R else None
        out.append(Spec("loads", f"circle a/R={aR:g}", a_over_R=aR, model_limit=limit, band=cfg.band))
    for aR in cfg.parabola_a_over_R:
        out.append(Spec("loads", f"parabola a/R={aR:g}", indenter="parabola", a_over_R=aR, band=cfg.band))
    for hr in cfg.resolution_h_ratio:  # 3b. resolution warning
        out.append(Spec("resolution", f"h_c = a/{hr:g}", h_ratio=hr, band=cfg.band))
    for E in cfg.scale_E:  # 4. scale invariance
        out.append(Spec("scale", f"E={_decade(E)}", E=E, band=cfg.band))
    out.append(Spec("faults", "cut-back: single step, max_it=4", control="displacement", d=cfg.fault_d, n_steps=1,
                    options=dict(max_it=4, active_set_predictor=False), band=cfg.band))
    out.append(Spec("faults", "unrecoverable: max_it=1, 1 cut-back", control="displacement", d=cfg.fault_d,
                    n_steps=1, options=dict(max_it=1, max_cutbacks=1, active_set_predictor=False),
                    expect_failure=True, band=cfg.band))
    return out


def run_block_spec(spec: Spec, *, comm, mesh_cache: Path | None = None) -> dict:
    """Run one block spec through the case pipeline (:func:`workbench.pipeline.run_case.run_one`: the block scene
    with the mesh sized from the target, :class:`workbench.studies.scene_point.TargetSized`); returns its record
    (parameters, converged, iterations, time, errors, warnings).

    Args:
        spec: The run.
        comm: MPI communicator.
        mesh_cache: Mesh cache folder (default ``<results>/mesh_cache``).
    """
    from fem.solver import ContactSolveError
    from workbench.pipeline.run_case import run_one

    run = spec.run()
    a = spec.target_half_width
    scene = TargetSized(h_ratio=spec.h_ratio)
    meshes: dict = {}
    rec = {"study": spec.study, "label": spec.label, "params": spec.params()}
    t0 = time.perf_counter()
    try:
        o = run_one(run, name=f"stability_{spec.indenter}",
                    mesh_cache=mesh_cache if mesh_cache is not None else default_paths().mesh_cache, comm=comm,
                    progress=lambda _msg: None, scene=scene, meshes=meshes, case=spec.label,
                    **spec.solver_overrides())
    except (ContactSolveError, ValueError) as exc:  # named: diverged, or refused (e.g. displacement at nu = 0.4999)
        return _head(rec, scene, a) | {"converged": False, "error": run_failure(exc),
                                       "time_s": time.perf_counter() - t0, "warnings": [], "errors": {},
                                       "iterations": None}
    res, cmp = o.result, o.comparison
    rec = _head(rec, scene, a) | {
        "converged": True, "error": None, "time_s": time.perf_counter() - t0, "ndofs": res.ndofs,
        "iterations": int(sum(res.newton_iterations)), "max_iterations": int(max(res.newton_iterations)),
        "solves": len(res.newton_iterations), "cutbacks": sum(1 for r in res.load_steps if r["kind"] == "cutback"),
        "warnings": list(res.warnings), "P": res.P, "d": res.d}
    if spec.option("method") == AL or any("uzawa" in r for r in res.load_steps):
        rec["uzawa"] = _uzawa(res)
    hw, pmax, th = cmp.half_width, cmp.p_max, cmp.theory
    rec |= {"errors": cmp.errors, "half_width": hw, "p_max": pmax, "n_patches": len(res.patches),
            "half_width_theory": th.half_width, "p_ref_theory": th.p_ref,
            "nondim": {"p_max/E*": pmax / th.E_star, "a/R": hw / spec.R, "P/(E* R)": res.P / (th.E_star * spec.R)}}
    if spec.condition:
        from fem.conditioning import jacobian_condition

        c = jacobian_condition(res, meshes[scene.built.files.key])  # the mesh the result was solved on
        rec["condition"] = c._asdict()
    return rec


def _head(rec: dict, scene: TargetSized, a: float) -> dict:
    """The record's mesh and target (known once the point's scene has meshed it): cells, a and its load."""
    mesh = scene.built
    return rec | {"cells": mesh.files.stats.get("cells") if mesh else None, "target_half_width": a,
                  "P_target": mesh.estimate.P if mesh else None}


def _uzawa(res) -> dict:
    """The augmented Lagrangian's own loop from its load-step records: Newton solves per load level (``uzawa``),
    their total, and the largest final gap violation over max|u| (``uzawa_gap``); empty if not recorded."""
    steps = [r for r in res.load_steps if "uzawa" in r]
    if not steps:
        return {}
    gaps = [r["uzawa_gap"] for r in steps if r.get("uzawa_gap") is not None]
    return {"solves": [int(r["uzawa"]) for r in steps], "total": int(sum(r["uzawa"] for r in steps)),
            "gap_max": max(gaps) if gaps else None}


def classify(rec: dict) -> str:
    """``ok`` | ``named: <reason>`` | ``SILENT`` (converged, out of band, nothing named) for one record."""
    spec = rec["params"]
    if not rec["converged"]:
        tag = "expected failure" if spec.get("expect_failure") else "failure"
        return f"named ({tag}): {rec['error'].splitlines()[0]}"
    if spec.get("expect_failure"):
        return "SILENT"  # meant to fail but converged: nothing told the user it was not the run asked for
    worst = max((v for k, v in rec["errors"].items() if k in ("p_max", "half_width", "rms") and v == v),
                default=math.nan)
    rec["worst_error"] = worst
    within = spec.get("band") is None or (worst == worst and worst <= spec["band"])
    if rec["warnings"]:
        names = list(dict.fromkeys(w.split(":")[0] for w in rec["warnings"]))
        return "named (warning): " + "; ".join(names) + ("" if within else " [out of band]")
    if within:
        return "ok"
    if spec.get("model_limit"):
        return f"named ({spec['model_limit'].split(':')[0]}): {spec['model_limit']}"
    return "SILENT"


def classify_augmented_lagrangian(rec: dict) -> str:
    """The augmented-Lagrangian sweep's own classification: every stiffness must converge.

    A run that does not converge is ``FAILED (must converge): <reason>``, an expectation violated (counted
    with the SILENT runs: the sweep exits 1), not a named pass as a diverged penalty run is. A converged run
    is classified as any other (:func:`classify`: ``ok``, ``named (warning)`` or ``SILENT``).
    """
    if not rec["converged"]:
        return f"FAILED (must converge): {rec['error'].splitlines()[0]}"
    return classify(rec)


def augmented_lagrangian_summary(records: list[dict]) -> dict:
    """The AL sweep in one record: per kappa0 its Newton and Uzawa iterations and its errors; how far the
    errors move over the converged runs; and the largest relative deviation of d, p_max and the half-width
    from the middle kappa0's run (an augmented Lagrangian enforces the constraint at convergence whatever
    kappa0, so its answer should not depend on kappa0; the penalty's does)."""
    recs = [r for r in records if r["study"] == AL]
    rows = []
    for r in recs:
        e = r.get("errors", {})
        rows.append({"kappa0": r["params"]["kappa0"], "converged": r["converged"],
                     "iterations": r.get("iterations"), "max_iterations": r.get("max_iterations"),
                     "solves": r.get("solves"), "uzawa": r.get("uzawa", {}).get("total"),
                     "uzawa_gap": r.get("uzawa", {}).get("gap_max"), "p_max": e.get("p_max"),
                     "half_width": e.get("half_width"), "rms": e.get("rms"), "load_balance": e.get("load_balance"),
                     "time_s": r.get("time_s"), "status": r.get("status")})
    ok = [x for x in rows if x["converged"]]
    spread = {k: (max(x[k] for x in ok) - min(x[k] for x in ok)) if ok else None
              for k in ("p_max", "half_width", "rms")}
    conv = [r for r in recs if r["converged"]]
    deviation = None
    if conv:
        ref = conv[len(conv) // 2]
        deviation = max(abs(r[k] / ref[k] - 1.0) for r in conv for k in ("d", "p_max", "half_width"))
    return {"runs": len(rows), "converged": len(ok), "all_converged": bool(rows) and len(ok) == len(rows),
            "error_spread": spread, "max_rel_deviation": deviation,
            "reference_kappa0": conv[len(conv) // 2]["params"]["kappa0"] if conv else None, "rows": rows}


def convective_ratios(records: list[dict], *, main_block: float = 160.0) -> list[dict]:
    """FEM b/b0 at the same load (each half-width over its classical value at its own load) vs theory; the
    ``main_block`` rows first."""
    rows = []
    by = {(r["params"]["nu"], r["params"]["size_factor"], r["params"]["kinematics"]): r
          for r in records if r["study"] == "convective"}
    for nu, size in sorted({k[:2] for k in by}, key=lambda k: (k[1] != main_block, k)):
        s, c = by.get((nu, size, "small")), by.get((nu, size, "convective"))
        if not (s and c and s["converged"] and c["converged"]):
            continue
        fem_ratio = (c["half_width"] / c["half_width_theory"]) / (s["half_width"] / s["half_width_theory"])
        beta = materials.beta_rigid_indenter(nu)
        m = wedge.wedge_slope(s["params"]["wedge_angle"], convention="paper")
        sol = convective.solve(convective.wedge_profile(m), beta=beta)
        rows.append({"nu": nu, "block": size, "beta": beta, "fem": fem_ratio,
                     "converged_theory": sol.b_over_b0_converged,
                     "first_order": sol.b_over_b0_first_order,
                     "rel_error": abs(fem_ratio - sol.b_over_b0_converged) / sol.b_over_b0_converged})
    return rows


def scale_invariance(records: list[dict], *, reference_E: float = 1e3) -> list[dict]:
    """Non-dimensional results of the E sweep relative to the ``reference_E`` (MPa) run (round-off expected)."""
    runs = [r for r in records if r["study"] == "scale" and r["converged"]]
    ref = next((r for r in runs if r["params"]["E"] == reference_E), None)
    if ref is None:
        return []
    return [{"E": r["params"]["E"], **{k: abs(v / ref["nondim"][k] - 1.0) for k, v in r["nondim"].items()},
             "iterations": r["iterations"]} for r in runs]


def run_conformal(cfg: StabilityConfig | None = None, *, comm, progress) -> list[dict]:
    """Close-to-conformal design through its first Table 1 steps d = 0.46, 0.47, 0.48 mm at the defaults
    (``cfg.conformal_d``), through the case pipeline's :func:`workbench.pipeline.run_case.run_one`.

    d = 0.46 is the paper's first row (indentation 0.00043 mm); the primary pair's relative radius is ~228 mm,
    hundreds of times the contact half-width. One record per step (P, peak, patches, Newton iterations).
    """
    from cases.schema import load_case
    from fem.solver import ContactSolveError
    from workbench.pipeline.run_case import run_one

    cfg = StabilityConfig() if cfg is None else cfg
    case = load_case("close_to_conformal")
    run = case.runs(h_contact=case.discretisation.ci_level)[0]
    run = dataclasses.replace(run, loading=dataclasses.replace(run.loading, d=tuple(cfg.conformal_d)))
    t0 = time.perf_counter()
    base = {"study": "conformal", "params": {"design": "close_to_conformal", "h_contact": run.discretisation.h_contact,
                                             "method": run.solver.method, "band": None}}
    try:
        out = run_one(run, name="stability_close_to_conformal", mesh_cache=cfg.cache_dir, comm=comm,
                      progress=progress)
    except ContactSolveError as exc:
        return [base | {"label": "close_to_conformal d=0.46..0.48", "converged": False,
                        "error": run_failure(exc), "warnings": [], "errors": {}, "iterations": None,
                        "time_s": time.perf_counter() - t0}]
    from analytic.hertz import TABLE1

    paper = {row.d: {"P": row.P, "p0": row.p0, "delta": row.delta} for row in TABLE1
             if row.config == "close_to_conformal"}
    recs = []
    for s, snap in zip(out.metrics["steps"], out.result.snapshots, strict=True):
        hw = [e["half_width"] for e in s["patches"]]
        recs.append(base | {"label": f"close_to_conformal d={s['d']:.2f}", "converged": True, "error": None,
                            "iterations": s["iterations"],
                            "time_s": out.metrics["wall_time_s"] / len(out.metrics["steps"]),
                            "warnings": list(snap.warnings),
                            "errors": {"load_balance": abs(s["P"] - s["P_pressure"]) / abs(s["P"])},
                            "d": s["d"], "delta_lcp": s["delta_lcp"], "P": s["P"], "p_max": s["p_max"],
                            "patch_half_widths": hw, "n_patches": s["n_patches"],
                            "width_eq5": [e["width_eq5"][0] if e["width_eq5"] else math.nan for e in s["patches"]],
                            "paper": paper.get(round(s["d"], 2)),
                            "relative_radius": [r for e in s["patches"] for r in e["R_pairs"]]})
    return recs


@dataclass(frozen=True)
class TwoBodySpec:
    """One point of the ``two_body`` study: the case ``cfg.two_body_case`` (two elastic bodies) with the upper body's
    E = ``ratio`` x the lower body's and the given Poisson ratios, at h_c = a / ``h_ratio``.

    Attributes:
        label: Run label.  ratio: E_upper / E_lower.  nu_lower, nu_upper: Poisson's ratios.
        h_ratio: a / h_contact.  band: accuracy band of p_max and the moment half-width against the exact circle
            at the combined modulus and the measured load (relative).  newton: Newton iterations allowed per step.
    """

    label: str
    ratio: float
    nu_lower: float
    nu_upper: float
    h_ratio: float
    band: float
    newton: int

    def params(self) -> dict:
        """The point's parameters for its JSON record."""
        return dataclasses.asdict(self) | {"method": None, "formulation": "displacement"}


def two_body_specs(cfg: StabilityConfig | None = None) -> list[TwoBodySpec]:
    """The ``two_body`` study's points (:attr:`StabilityConfig.two_body_pairs`)."""
    cfg = StabilityConfig() if cfg is None else cfg
    return [TwoBodySpec(f"E2/E1={_decade(r)} nu1={nl:g} nu2={nu:g}", r, nl, nu, cfg.two_body_h_ratio, cfg.band,
                        cfg.two_body_newton) for r, nl, nu in cfg.two_body_pairs]


def _two_body_run(spec: TwoBodySpec, cfg: StabilityConfig):
    """The case's first run with the spec's bodies and mesh level (displacement formulation: the two-body scene has
    no mixed one, so nu = 0.499 locks, and says so)."""
    from cases.schema import load_case

    run = load_case(cfg.two_body_case).runs(h_contact=1.0 / spec.h_ratio)[0]
    lower, upper = run.bodies  # the case's [[body]] tables: the lower body first
    bodies = (dataclasses.replace(lower, nu=spec.nu_lower),
              dataclasses.replace(upper, E=spec.ratio * lower.E, nu=spec.nu_upper))
    return dataclasses.replace(run, bodies=bodies, material=bodies[0].material,
                               solver=dataclasses.replace(run.solver, formulation="displacement"))


def run_two_body_spec(spec: TwoBodySpec, cfg: StabilityConfig, *, comm) -> dict:
    """Run one two-body point through the case pipeline (its scene from the registry: mesh, load path, comparison
    with the exact circle); its record: converged, Newton iterations per step, load balance, errors, warnings."""
    from fem.solver import ContactSolveError
    from workbench.pipeline.run_case import run_one

    run = _two_body_run(spec, cfg)
    rec = {"study": "two_body", "label": spec.label, "params": spec.params()}
    t0 = time.perf_counter()
    try:
        m = run_one(run, name="stability_two_body", mesh_cache=cfg.cache_dir, comm=comm,
                    progress=lambda _: None).metrics
    except (ContactSolveError, ValueError) as exc:  # named: diverged or refused
        return rec | {"converged": False, "error": run_failure(exc), "time_s": time.perf_counter() - t0,
                      "warnings": [], "errors": {}, "iterations": None}
    its = [int(i) for i in m["newton_iterations"]]
    e = m["errors"]
    return rec | {"converged": True, "error": None, "time_s": time.perf_counter() - t0, "ndofs": m["ndofs"],
                  "newton_iterations": its, "iterations": sum(its), "max_iterations": max(its, default=0),
                  "solves": len(its), "warnings": list(m["warnings"]), "P": m["P"], "p_max": m.get("p_max"),
                  "E_star": m["E_star"],
                  "errors": {k: e[k] for k in ("p_max", "half_width", "half_width_moment", "rms", "load_balance")
                             if k in e}}


def classify_two_body(rec: dict) -> str:
    """A two-body point: ``ok`` (converged, p_max and the moment half-width within the band, Newton iterations per
    step within the limit, no warning), ``named: <reason>`` (a failure, a solver warning, e.g. near-incompressible),
    or ``SILENT`` (out of band or over the iterations with nothing named)."""
    par = rec["params"]
    if not rec["converged"]:
        return f"named (failure): {rec['error'].splitlines()[0]}"
    worst = max((rec["errors"].get(k, math.nan) for k in ("p_max", "half_width_moment")), default=math.nan)
    rec["worst_error"] = worst
    slow = rec["max_iterations"] > par["newton"]
    within = worst == worst and worst <= par["band"] and not slow
    its = f", {rec['max_iterations']} Newton its in a step" if slow else ""
    note = "" if within else f" [out of band{its}]"
    if rec["warnings"]:
        return "named (warning): " + "; ".join(dict.fromkeys(w.split(":")[0] for w in rec["warnings"])) + note
    return "ok" if within else "SILENT" + note


@dataclass(frozen=True)
class Point:
    """One point of the sweep for the shared runner: a block ``spec``, a two-body point, or the ``conformal``
    design (spec None)."""

    spec: Spec | TwoBodySpec | None
    cfg: StabilityConfig


def run_stability_point(point: Point) -> dict:
    """The sweep's point function (module level: sent to the workers by name); on ``MPI.COMM_SELF``. A block
    spec returns its record with its ``status``; the conformal design ``{"records": [...]}``."""
    from mpi4py import MPI

    comm = MPI.COMM_SELF
    if point.spec is None:
        recs = run_conformal(point.cfg, comm=comm, progress=lambda _: None)
        for rec in recs:
            rec["status"] = classify(rec)
        return {"records": recs}
    if isinstance(point.spec, TwoBodySpec):
        rec = run_two_body_spec(point.spec, point.cfg, comm=comm)
        rec["status"] = classify_two_body(rec)
        return rec
    rec = run_block_spec(point.spec, comm=comm, mesh_cache=point.cfg.cache_dir)
    rec["status"] = (classify_augmented_lagrangian if point.spec.study == AL else classify)(rec)
    return rec


def run_sweep(cfg: StabilityConfig | None = None, *, executor: ExecutorChoice | None = None,
              progress=print) -> list[dict]:
    """Run the studies of ``cfg`` (default: all) on ``executor`` (default: in this process); returns one record
    per run, each with its ``status`` and where it ran (``worker``)."""
    cfg = StabilityConfig() if cfg is None else cfg
    executor = ExecutorChoice() if executor is None else executor
    ensure_dir(cfg.cache_dir, kind="mesh_cache", kinds=("mesh_cache",))  # the workbench's own, or refused
    todo = [Point(s, cfg) for s in specs(cfg) if s.study in cfg.studies]
    if "conformal" in cfg.studies:
        todo.append(Point(None, cfg))
    if "two_body" in cfg.studies:
        todo += [Point(s, cfg) for s in two_body_specs(cfg)]

    def said(i: int, n: int, rec: dict) -> None:
        for r in rec.get("records", [rec]):
            progress(f"[{i:3d}/{n}] {r['study']:14s} {r['label']:38s} {r['status'][:60]:60s} {r['time_s']:.2f} s")

    records = []
    for rec in run_points(run_stability_point, todo, executor=executor, progress=said):
        for r in rec.get("records", [rec]):
            records.append(r | {"worker": rec["worker"]})
    return records


def _fmt(v, spec=".2e") -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return format(v, spec)


_DESCRIPTIONS = {
    "method": "Method parameters on the Hertz scene (P2, h = a/10): penalty kappa0 and Nitsche gamma0 x theta. "
              "cond_1(J) is the Hager-Higham 1-norm estimate of the free-dof Jacobian at the solution; "
              "ratio = cond_1(J) / cond_1(K) with K the elastic stiffness alone (fem.conditioning).",
    AL: "Augmented Lagrangian (solve_contact(method='augmented_lagrangian')) on the Hertz scene (P2, h = a/10): "
        "p = [lambda - kappa g]_+ with kappa = kappa0 E / h over five decades. At convergence the multiplier "
        "enforces the constraint whatever kappa0, so every run must converge (a failure is FAILED, not named) "
        "and its errors should not move with kappa0 (the penalty's do: method study). its = Newton iterations "
        "summed over all solves (max per solve).",
    "convective": "Wedge theta = pi/5 (face slope theta), h = b/40 (band 3 %), block W = H = 160 b (and 20-80 b at "
                  "nu = 0.499: the finite block's own tangential surface displacement adds a beta-independent "
                  "offset to b/b0), small and convective kinematics (mixed for nu >= 0.45). The classical "
                  "errors of the convective run are not banded (it measures the effect).",
    "incompressible": "nu -> 1/2: P1 (h = a/40, band 4 %) and P2 (h = a/10) displacement formulation against "
                      "Taylor-Hood P2/P1 mixed (solve_contact(formulation='mixed')), Nitsche defaults.",
    "loads": "a/R from 1e-3 to 0.4, i.e. the load P ~ a^2 over 5.2 decades (mesh scaled with a: h = a/10, "
             "block 40 a). Above a/R = 0.1 the exact circle "
             "departs from Hertz's parabola (model limit, shown by the parabola runs).",
    "resolution": "Deliberately coarse meshes at a/R = 0.05: the solver's 'contact unresolved' warning when the patch "
                  "spans fewer than 8 contact facets (fem.solver.MIN_FACETS_ACROSS).",
    "scale": "E over nine decades (1e-3 ... 1e6 MPa), same geometry and a/R: non-dimensional results.",
    "conformal": "Close-to-conformal design, first Table 1 steps (d = 0.46, 0.47, 0.48 mm) at its ci_level mesh "
                 "(h_c = a_est/10), solver defaults, no tuning; relative radius of the primary pair ~234 mm, "
                 "~1500x the first patch half-width.",
    "faults": "Newton divergence: automatic cut-back, and a step that cannot be recovered (named error).",
    "two_body": "Two elastic bodies (issue 24): the elastic_cylinder case (an elastic half disk on an elastic block, "
                "non-matching meshes, penalty mortar, its scene's load path: no analytic predictor) at h_c = a/10 "
                "with E_upper / E_lower from 1e-3 to 1e3 and nu = 0.499 on either side (displacement formulation: "
                "the two-body scene has no mixed one). Errors against the exact circle's half-plane theory at the "
                "combined modulus and the measured load; band on p_max and the moment half-width (the patch "
                "half-width is the last positive node's, within a facet, h = a/10); Newton its per load step "
                "(force corrections included) against the issue's 4.",
}


def _defaults_section(records: list[dict]) -> list[str]:
    """The method defaults read off the ``method`` study: best worst-error run per method, with its cond_1."""
    runs = [r for r in records if r["study"] == "method" and r["converged"]]
    if not runs:
        return []

    def worst(r):
        return max(r["errors"][k] for k in ("p_max", "half_width", "rms"))

    out = ["## Choice of defaults", ""]
    for method in ("nitsche", "penalty"):
        mine = [r for r in runs if r["params"]["method"] == method]
        if not mine:
            continue
        best = min(mine, key=worst)
        clean = [r for r in mine if not r["warnings"]]
        cond = best.get("condition", {}).get("cond_jacobian", math.nan)
        out.append(f"- {method}: smallest worst error {worst(best):.2%} at **{best['label']}** (cond_1(J) = "
                   f"{cond:.2e}); {len(clean)}/{len(mine)} runs without a warning"
                   + (f" ({', '.join(r['label'].split(' ', 1)[1] for r in clean)})" if clean else "") + ".")
    out += ["", "Defaults kept (measured on this sweep, h = a/10, P2): **Nitsche gamma0 = 10, theta = 1** has the "
            "lowest condition number of all runs (cond_1(J) ~ 9e3, 40x below gamma0 = 0.1 or 1e3), the best peak "
            "(0.02 %) and a worst error of 0.4 %; theta = 0 and -1 agree with it within 0.1 % at gamma0 = 10. "
            "gamma0 = 0.1 with theta = -1 reaches 0.30 % but at 45x the condition number. gamma0 >= 1e3 over-"
            "enforces the constraint at the Gauss points ('pressure oscillation', RMS/p0 ~ 2 %), like a stiff "
            "penalty. **Penalty kappa0 = 1e3** is kept for its peak (0.26 %), with a named 'pressure oscillation' "
            "(RMS/p0 2.05 %); kappa0 = 1e2 is the only warning-free penalty value (RMS 1.4 %, peak 1.5 % low "
            "from the penetration p/kappa, cond 10x lower) -- prefer it when the pressure profile matters. "
            "kappa0 <= 10 is named 'penetration' (peak 7-10 % low). Above kappa0 = 1e5 semismooth Newton on the "
            "penalty system itself cycled (DIVERGED_MAX_IT at 1e6, 1e7, 1e8 before): the penalty now solves its "
            "law there by relaxed Uzawa updates of a nodal law with a Newton stiffness of 1e4 (fem.methods.penalty), "
            "which converges for every kappa0 up to 1e10 (table below). Both parameters "
            "scale with E / h, so the choice does not depend on E (scale study).", ""]
    out += _penalty_sweep_section(records)
    return out


def penalty_sweep(records: list[dict]) -> list[dict]:
    """The penalty kappa0 sweep of the ``method`` study: one row per kappa0 (converged, law, iterations, errors)."""
    from fem.methods.penalty import STIFF_KAPPA0

    rows = []
    for r in records:
        if r["study"] != "method" or r["params"]["method"] != "penalty":
            continue
        e = r.get("errors", {})
        k = r["params"]["kappa0"]
        rows.append({"kappa0": k, "law": "nodal (Uzawa)" if k > STIFF_KAPPA0 else "Gauss points (Newton)",
                     "converged": r["converged"], "iterations": r.get("iterations"),
                     "uzawa": r.get("uzawa", {}).get("total"), "p_max": e.get("p_max"),
                     "half_width": e.get("half_width"), "rms": e.get("rms"), "status": r.get("status")})
    return rows


def _penalty_sweep_section(records: list[dict]) -> list[str]:
    rows = penalty_sweep(records)
    if not rows:
        return []
    n_ok = sum(r["converged"] for r in rows)
    lines = [f"Penalty sweep, kappa0 = {rows[0]['kappa0']:g} ... {rows[-1]['kappa0']:g}: **{n_ok} of {len(rows)} "
             "converged**.", "",
             "| kappa0 | law | converged | Newton its | Uzawa solves | p_max err | half-width err | RMS/p0 | status |",
             "|" + "---|" * 9]
    for r in rows:
        lines.append(f"| {r['kappa0']:g} | {r['law']} | {r['converged']} | {r['iterations'] or '-'} | "
                     f"{r['uzawa'] or '-'} | {_fmt(r['p_max'])} | {_fmt(r['half_width'])} | {_fmt(r['rms'])} | "
                     f"{r['status']} |")
    return lines + [""]


def _al_section(al: dict) -> list[str]:
    """The augmented-Lagrangian table: kappa0, convergence, iterations, errors, status; the error spread."""
    lines = ["| kappa0 | converged | Newton its (max) | Uzawa solves | final gap / max abs u | time (s) | "
             "p_max err | half-width err | RMS/p0 | load balance | status |", "|" + "---|" * 11]
    for r in al["rows"]:
        its = f"{r['iterations']} ({r['max_iterations']})" if r["converged"] else "-"
        lines.append(f"| {r['kappa0']:g} | {r['converged']} | {its} | {r['uzawa'] or '-'} | "
                     f"{_fmt(r['uzawa_gap'], '.1e')} | {_fmt(r['time_s'], '.2f')} | {_fmt(r['p_max'])} | "
                     f"{_fmt(r['half_width'])} | {_fmt(r['rms'])} | {_fmt(r['load_balance'])} | {r['status']} |")
    verdict = ("every run converged" if al["all_converged"]
               else f"**{al['runs'] - al['converged']} of {al['runs']} runs did NOT converge**")
    spread = ", ".join(f"{k} {_fmt(v)}" for k, v in al["error_spread"].items())
    dev = (f"; d, p_max and half-width differ from the kappa0 = {al['reference_kappa0']:g} run by at most "
           f"{_fmt(al['max_rel_deviation'], '.1e')} (relative)" if al.get("max_rel_deviation") is not None else "")
    return lines + ["", f"{verdict}; spread (max - min) of the errors over the converged runs: {spread}{dev}.",
                    ""]


def _two_body_section(recs: list[dict]) -> list[str]:
    """The ``two_body`` table: bodies, convergence, Newton its per step, load balance, errors, status; messages."""
    lines = ["| E2/E1 | nu lower | nu upper | converged | Newton its per step | its <= limit | load balance | "
             "p_max err | half-width (moment) err | RMS/p0 | time (s) | status |", "|" + "---|" * 12]
    for r in recs:
        p, e = r["params"], r.get("errors", {})
        its = r.get("newton_iterations")
        lines.append(f"| {_decade(p['ratio'])} | {p['nu_lower']:g} | {p['nu_upper']:g} | {r['converged']} | "
                     f"{its if its is not None else '-'} | "
                     f"{'-' if its is None else ('yes' if r['max_iterations'] <= p['newton'] else '**no**')} | "
                     f"{_fmt(e.get('load_balance'), '.1e')} | {_fmt(e.get('p_max'))} | "
                     f"{_fmt(e.get('half_width_moment'))} | {_fmt(e.get('rms'))} | {r['time_s']:.2f} | "
                     f"{r['status']} |")
    lines.append("")
    return lines + _messages(recs)


def report_markdown(summary: dict, records: list[dict]) -> str:
    """The Markdown report: summary, then one table per study with every run."""
    lines = ["# Numerical stability sweep", "",
             f"{summary['runs']} runs in {summary['wall_time_s']:.0f} s: **{summary['ok']} ok** (converged, errors "
             f"<= {summary['band']:.0%} band, no warning), **{summary['named']} named** (failure, warning or model "
             f"limit, reason given), **{summary['silent']} SILENT** (converged out of band, nothing named)"
             + (f", **{summary['failed']} FAILED** (augmented Lagrangian runs that must converge and did not)"
                if summary.get("failed") else "") + ".", "",
             "Errors: relative, against the classical theory at the measured load (workbench.scenes.block_theory). "
             "its = Newton iterations summed over all solves (max per solve). Status: see "
             "workbench/studies/stability.py.", ""]
    lines += _defaults_section(records)
    for study in STUDIES:
        recs = [r for r in records if r["study"] == study]
        if not recs:
            continue
        lines += [f"## {study}", "", _DESCRIPTIONS[study], ""]
        if study == "conformal":
            lines += ["| run | converged | its | delta LCP (mm) | P (N/mm) | paper P | P/delta (N/mm^2) | paper "
                      "P/delta | p_max (MPa) | paper p0 | 2a FEM (mm) | 2a eq. (5) at FEM load | R pairs (mm) | "
                      "load balance | status |", "|" + "---|" * 15]
            for r in recs:
                pp = r.get("paper") or {}
                stiff = r["P"] / r["delta_lcp"] if r.get("delta_lcp") else math.nan
                lines.append(
                    f"| {r['label']} | {r['converged']} | {r['iterations']} | {_fmt(r.get('delta_lcp'), '.3g')} | "
                    f"{_fmt(r.get('P'), '.4g')} | {_fmt(pp.get('P'), '.4g')} | {_fmt(stiff, '.3g')} | "
                    f"{_fmt(pp['P'] / pp['delta'] if pp else None, '.3g')} | {_fmt(r.get('p_max'), '.4g')} | "
                    f"{_fmt(pp.get('p0'), '.4g')} | "
                    f"{', '.join(f'{2 * h:.3f}' for h in r.get('patch_half_widths', []))} | "
                    f"{', '.join(_fmt(w, '.3f') for w in r.get('width_eq5', []))} | "
                    f"{', '.join(f'{x:.3g}' for x in r.get('relative_radius', []))} | "
                    f"{_fmt(r['errors'].get('load_balance'))} | {r['status']} |")
            lines += ["", "The design is a reconstruction (analytic.designs: the paper publishes no splines); its LCP "
                      "indentation matches Table 1 at d = 0.46 (0.00043 mm). The paper's first row implies a secant "
                      "stiffness P/delta about 5x that of its own second and third rows, whereas a Hertz-type "
                      "contact stiffens with load; the FEM's P/delta rises monotonically.", ""]
            continue
        if study == AL and summary.get(AL):
            lines += _al_section(summary[AL])
            continue
        if study == "two_body":
            lines += _two_body_section(recs)
            continue
        cond = study == "method"
        head = "| run | converged | its (max) | cut-backs | time (s) | p_max err | half-width err | RMS/p0 | "
        head += "cond_1(J) | ratio | " if cond else ""
        head += "status |"
        lines += [head, "|" + "---|" * (head.count("|") - 1)]
        for r in recs:
            e = r.get("errors", {})
            its = f"{r['iterations']} ({r['max_iterations']})" if r["converged"] else "-"
            row = (f"| {r['label']} | {r['converged']} | {its} | {r.get('cutbacks', '-')} | {r['time_s']:.2f} | "
                   f"{_fmt(e.get('p_max', e.get('p_max_vs_classical')))} | "
                   f"{_fmt(e.get('half_width', e.get('half_width_vs_classical')))} | "
                   f"{_fmt(e.get('rms', e.get('rms_vs_classical')))} | ")
            if cond:
                c = r.get("condition", {})
                row += f"{_fmt(c.get('cond_jacobian'))} | {_fmt(c.get('ratio'))} | "
            warn = "; ".join(r.get("warnings", []))
            lines.append(row + r["status"] + (f" -- {warn}" if warn and not r["status"].startswith("named") else "")
                         + " |")
        lines.append("")
        if study == "convective" and summary["convective"]:
            lines += ["FEM b/b0 at the same load against the Ciavarella-Hills theory:", "",
                      "| nu | block (W = H, in b) | beta | FEM b/b0 | converged theory | first order | rel. error |",
                      "|---|---|---|---|---|---|---|"]
            lines += [f"| {c['nu']:g} | {c['block']:g} | {c['beta']:.4g} | {c['fem']:.5f} | "
                      f"{c['converged_theory']:.5f} | "
                      f"{c['first_order']:.5f} | {c['rel_error']:.2e} |" for c in summary["convective"]]
            lines.append("")
        if study == "scale" and summary["scale"]:
            lines += ["Non-dimensional results relative to the E = 1e3 MPa run:", "",
                      "| E (MPa) | p_max/E* | a/R | P/(E* R) | its |", "|---|---|---|---|---|"]
            lines += [f"| {c['E']:g} | {c['p_max/E*']:.1e} | {c['a/R']:.1e} | {c['P/(E* R)']:.1e} | {c['iterations']} |"
                      for c in summary["scale"]]
            lines.append("")
        lines += _messages(recs)
    lines += where_section(wall_time_s=summary.get("wall_time_s"), records=records,
                           label=lambda r: f"{r['study']}: {r['label']}", reference=summary.get("reference"))
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    """CLI ``workbench stability [--study NAME ...] [--out DIR] [--mesh-cache DIR] [--executor local|mpi]
    [--workers N]``; exit 1 if any run is SILENT or an augmented-Lagrangian run FAILED, 2 on a bad option."""
    ap = argparse.ArgumentParser(prog="workbench stability", description=__doc__.splitlines()[0])
    ap.add_argument("--study", action="append", choices=STUDIES, help="run only these studies (repeatable)")
    ap.add_argument("--out", type=Path, default=None, help="output folder (default: <results>/stability)")
    ap.add_argument("--mesh-cache", type=Path, default=None, help="mesh cache (default: <results>/mesh_cache)")
    add_executor_options(ap, workers=1)
    args = ap.parse_args(argv)
    try:
        executor = executor_from_args(args)
    except ValueError as exc:
        print(f"workbench stability: error: {exc}", file=sys.stderr)
        return 2
    cfg = StabilityConfig(studies=tuple(args.study or STUDIES), out=args.out, mesh_cache=args.mesh_cache)
    t0 = time.perf_counter()
    records = run_sweep(cfg, executor=executor)
    where = worker_summary(records)
    wall = time.perf_counter() - t0
    from workbench.studies.reference import measure_reference

    reference = measure_reference(executor=executor, mesh_cache=cfg.cache_dir)
    summary = {
        "runs": len(records),
        "ok": sum(r["status"] == "ok" for r in records),
        "named": sum(r["status"].startswith("named") for r in records),
        "silent": sum(r["status"] == "SILENT" for r in records),
        "failed": sum(r["status"].startswith("FAILED") for r in records),
        "wall_time_s": wall, "reference": reference,
        "executor": executor.kind, "workers": executor.workers, "jit_retries": where["jit_retries"],
        "jit_compiles_on_workers": where["jit_compiles"], "where": where,
        "band": cfg.band,
        "convective": convective_ratios(records, main_block=max((b for _, b in cfg.convective_runs), default=0.0)),
        "scale": scale_invariance(records, reference_E=cfg.scale_reference_E),
        AL: augmented_lagrangian_summary(records) if AL in cfg.studies else None,
    }
    out = cfg.out_dir
    write_json(out / "stability.json", {"config": to_json(cfg), "summary": summary, "records": records})
    write_text(out / "report.md", report_markdown(summary, records))
    from workbench.studies.stability_plot import main as plot_main  # plotting is separate; it reads the JSON back

    plot_main(["--dir", str(out)])
    print(f"stability: {summary['runs']} runs, {summary['ok']} ok, {summary['named']} named, "
          f"{summary['silent']} SILENT, {summary['failed']} FAILED in {summary['wall_time_s']:.0f} s -> {out}")
    return 1 if summary["silent"] or summary["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())
