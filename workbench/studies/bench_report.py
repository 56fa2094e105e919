"""Markdown report of the performance benchmark: formatting only, no computing, no study code imported.

:func:`to_markdown` turns the benchmark JSON (``<results>/bench/bench.json``, the data of
:func:`workbench.studies.bench.run_bench`) into ``report.md``, with a final table of the targets, each met / not
met with its measured value. The settings (targets, baseline stiffness, box size, ...) are read from the
JSON's ``config`` (:class:`workbench.studies.bench_config.BenchConfig`; its defaults for keys an older JSON lacks).
"""

from __future__ import annotations

import math

from workbench.studies.bench_config import BenchConfig
from workbench.studies.bench_log_events import factor_solves
from workbench.studies.config import from_json
from workbench.studies.where_report import reference_text

__all__ = ["to_markdown"]


def _f(v, fmt=".3g") -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    if isinstance(v, int) and not isinstance(v, bool):
        return str(v)
    return format(v, fmt)


def _met(ok: bool | None) -> str:
    return "n/a" if ok is None else ("met" if ok else "NOT met")


def _events(ev: dict) -> str:
    return f"{ev['MatLUFactorSym']['count']}/{ev['MatLUFactorNum']['count']}"


def _md_accuracy(acc: dict, targets: list, cfg: BenchConfig) -> list[str]:
    base = acc["baseline_reached"]
    L = [
        "## 1. Time to accuracy",
        "",
        f"Baseline: uniform right triangles over the whole half box (W = H = box a, no grading), P2, penalty "
        f"with fixed kappa = {cfg.baseline_kappa:g} E/mm (not scaled by 1/h), force control to "
        f"{cfg.baseline_force_rtol:g} P (the solver's force corrections: tangent of the last state, else secant), "
        "full-step semismooth Newton from zero, no predictor. Ours: the case settings (Hertz predictor, "
        f"active-set predictor, {acc.get('case_steps', '?')} load step(s), force to 1e-10 P) on the graded mesh "
        "of meshes.block (W = H = 40 a). Warm total = mesh (cached) + solve + comparison.",
        "",
        "| config | box/a | h/a | ndofs | warm total (s) | solver (s) | Newton its | rms | p_max err |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    rows = [("baseline", r) for r in acc["baseline"]]
    rows += [(name, r) for name, rs in acc["ours"].items() for r in rs]
    for name, r in rows:
        L.append(
            f"| {name} | {r['box_over_a']:g} | {r['h_over_a']:g} | {r['ndofs']} | {_f(r['total_s'])} | "
            f"{_f(r['solve_s'])} | {r['newton_iterations']} | {_f(r['rms'])} | {_f(r.get('p_max'))} |"
        )
    L += [
        "",
        "| ours | reaches | h/a | ndofs | warm total (s) | baseline/ours total | baseline/ours solver | lower bound |",
        "|---|---|---|---|---|---|---|---|",
    ]
    best = None
    for name, s in acc["summary"].items():
        L.append(
            f"| {name} | {s['reached']} | {_f(s['h_over_a'])} | {_f(s['ndofs'])} | {_f(s['total_s'])} | "
            f"{_f(s['ratio_total'])} | {_f(s['ratio_solve'])} | {_f(s['ratio_total_lower_bound'])} |"
        )
        r = s["ratio_total"] if s["ratio_total"] is not None else s["ratio_total_lower_bound"]
        if r is not None:
            best = max(best or 0.0, r)
    L.append("")
    if base is None:
        last = acc["baseline"][-1]
        L.append(
            f"The baseline did NOT reach rms <= {cfg.rms_target:.1%} on its ladder (finest rung {last['ndofs']} "
            f"dofs: rms {_f(last['rms'])} in {_f(last['total_s'])} s). 'lower bound' = that time / ours "
            "to the target: the baseline needs more than that."
        )
    else:
        L.append(
            f"The baseline reaches the target at box {base['box_over_a']:g} a, h = a*{base['h_over_a']:g} "
            f"({base['ndofs']} dofs) in {_f(base['total_s'])} s warm."
        )
    if acc.get("same_accuracy"):
        L += [
            "",
            "At the baseline's own accuracy (first rung of each configuration of ours with rms <= the baseline's):",
            "",
            "| baseline h/a | ndofs | rms | baseline (s) | ours | h/a | ndofs | ours (s) | ratio total | "
            "ratio solver |",
            "|---|---|---|---|---|---|---|---|---|---|",
        ]
        for r in acc["same_accuracy"]:
            L.append(
                f"| {r['baseline_h_over_a']:g} | {r['baseline_ndofs']} | {_f(r['rms'])} | "
                f"{_f(r['baseline_total_s'])} | {r['ours']} | {r['ours_h_over_a']:g} | {r['ours_ndofs']} | "
                f"{_f(r['ours_total_s'])} | {_f(r['ratio_total'])} | {_f(r['ratio_solve'])} |"
            )
    L.append("")
    tg = cfg.targets
    label = (f">= {tg['speedup_vs_baseline']:g}x faster than the baseline to rms <= {100 * cfg.rms_target:g} % "
             "(best configuration, warm total)")
    if base is None:
        label += " [lower bound]"
    targets.append((label, _f(best), None if best is None else best >= tg["speedup_vs_baseline"]))
    return L


def _md_linear(lin: dict, targets: list, cfg: BenchConfig) -> list[str]:
    ev = lin["events"]
    n = cfg.targets["linear_solves"]
    targets.append(
        (
            f"contact solve <= {n:g} linear solves (default case)",
            _f(lin["linear_solves_equivalent"]),
            lin["linear_solves_equivalent"] <= n,
        )
    )
    return [
        "## 2. Contact solve against one linear solve",
        "",
        f"Default case ({lin['ndofs']} dofs): contact solver {_f(lin['solve_s'])} s warm; one linear elastic "
        f"solve on the same mesh (new problem: assembly, MUMPS symbolic + numeric LU, solve) "
        f"{_f(lin['linear_s'])} s (re-solve of the same problem {_f(lin['linear_resolve_s'])} s): "
        f"**{_f(lin['linear_solves_equivalent'])} linear solves**. Newton iterations "
        f"{lin['newton_iterations']} ({_f(lin['newton_per_step'])} per solve, predictor iteration included). "
        f"PETSc events in one contact solve: LU symbolic/numeric {_events(ev)} (the Hertz predictor's linear "
        f"solve included), Jacobian assemblies {ev['SNESJacobianEval']['count']}, residuals "
        f"{ev['SNESFunctionEval']['count']}; see section 3 for larger sizes.",
        "",
    ]


def _switch(cfg: BenchConfig) -> str:
    if cfg.scale_linear_solver == "auto":
        return ("linear_solver = auto at every size: MUMPS LU (lu_reuse, AMF ordering) up to "
                "fem.linear_solver.AUTO_GAMG_NDOFS dofs, gamg above")
    return f"above {cfg.krylov_threshold} dofs linear_solver = gamg"


def _by_kind(r: dict) -> str:
    b = r.get("linear_by_kind_s") or {}
    return f"{_f(b['lu'])} / {_f(b['gamg'])}" if {"lu", "gamg"} <= set(b) else "-"


def _crossover(sc: dict) -> list[str]:
    """One line per family: where one GAMG linear solve became cheaper than one LU solve (measured rows)."""
    L = []
    for family, fam in sc.items():
        rows = [r for r in fam["rows"] if {"lu", "gamg"} <= set(r.get("linear_by_kind_s") or {})]
        if not rows:
            continue
        faster = [r["ndofs"] for r in rows if r["linear_by_kind_s"]["gamg"] < r["linear_by_kind_s"]["lu"]]
        ratio = ", ".join(f"{r['ndofs']}: {_f(r['linear_by_kind_s']['gamg'] / r['linear_by_kind_s']['lu'])}"
                          for r in rows)
        where = (f"GAMG faster from {min(faster)} dofs" if faster
                 else f"LU faster at every measured size (up to {rows[-1]['ndofs']} dofs)")
        L.append(f"- LU/GAMG crossover ({family}): {where}; one GAMG linear solve in LU solves: {ratio}.")
    return L + ([""] if L else [])


def _why(sc: dict) -> list[str]:
    """Per family, what the measured rows say about the cost above one linear solve: linear solves (Newton and
    tangent solves) and triangular solves per contact solve, and whether the largest three rows mix LU and GAMG."""
    L = []
    for family, fam in sc.items():
        rows = fam["rows"]
        if not rows:
            continue
        parts = []
        for r in rows:
            ev = r.get("events") or {}
            tri = factor_solves(ev)
            parts.append(f"{r['ndofs']}: {sum(r['newton_iterations'])} Newton its"
                         + (f", {tri} triangular solves" if tri and r.get("linear_kind") == "lu" else ""))
        kinds = {r.get("linear_kind", "lu") for r in rows[-3:]}
        mix = (" The largest three rows mix LU and GAMG (the solver switches kind by size), so their exponent "
               "includes the switch." if len(kinds) > 1 else "")
        L.append(f"- Where the cost goes ({family}; first contact solve of each row): " + "; ".join(parts) + "."
                 + mix)
    return L + ([""] if L else [])


def _md_scale(sc: dict, targets: list, cfg: BenchConfig) -> list[str]:
    L = [
        "## 3. Cost growth (P2, the case's Nitsche scene, one process per size)",
        "",
        f"graded: meshes.block at decreasing h_c (W = H = 40 a); uniform: the baseline's half box W = H = "
        f"{cfg.scale_box:g} a. Each row is solved with the row's options (column 'options': the predictor and "
        f"the linear solver; {_switch(cfg)}{_nested_text(cfg)}) and compared with ONE linear "
        "elastic solve on the same mesh with the same kind of linear solver (assembly + factorisation or AMG set-up "
        "+ solve; column 'linear'). 'case' = the case settings (predictor auto: the force-controlled Newton "
        "from the obstacle's zone where it applies; MUMPS LU per Newton iteration) on "
        "the same mesh, in linear solves, and the largest relative difference of P, p_max and the half-width "
        "between the two (below the threshold only). Times: fresh process with warm JIT cache, best of 3 "
        f"in-process solves below {cfg.small_ndofs} dofs, else of 2. Peak RSS = VmHWM of that process "
        "(ru_maxrss is inherited from the parent on Linux): after the mesh, after the first contact solve, and "
        "at the end (reference solves and the linear solve included). 'LU / GAMG linear': one linear solve with "
        "each kind (MUMPS LU with the auto ordering AMF, GAMG), up to crossover_max_ndofs dofs. Only the ratios "
        "inside one row mean something on a shared machine (the rows run at different times).",
        "",
        "| mesh | h/a | ndofs | options | its | solver (s) | linear (s) | solver/linear | case/linear | "
        "max rel diff vs case | LU sym/num | peak RSS mesh / 1st solve / end (MB) | rms | LU / GAMG linear (s) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for family, fam in sc.items():
        for r in fam["rows"]:
            o = r.get("overrides", {})
            case = r.get("case", {})
            diff = r.get("rel_diff_vs_case")
            nest = r.get("nested")
            nest = (f", nested from h x {nest['factor']:g} ({nest['ndofs']} dofs, {_f(nest['solve_s'])} s, its "
                    f"{nest['newton_iterations']})") if nest else ""
            L.append(
                f"| {family} | {r['h_over_a']:.4g} | {r['ndofs']} | {o.get('predictor', 'case')}, "
                f"{o.get('linear_solver', 'lu')}{nest} | {r['newton_iterations']} | "
                f"{_f(r['solve_s'])} | {_f(r['linear_s'])} ({r.get('linear_kind', 'lu')}) | "
                f"{_f(r['linear_solves_equivalent'])} | {_f(case.get('linear_solves_equivalent'))} | "
                f"{_f(max(diff.values()), '.1e') if diff else '-'} | "
                f"{_events(r['events'])} | {_f(r.get('peak_rss_mesh_mb'), '.0f')} / "
                f"{_f(r.get('peak_rss_first_solve_mb'), '.0f')} / "
                f"{_f(r['peak_rss_mb'], '.0f')} | {_f(r['rms'])} | {_by_kind(r)} |"
            )
    L.append("")
    L += _crossover(sc)
    L += _why(sc)
    for family, fam in sc.items():
        f = fam["fits"]
        k = {key: (_f(f[key]["all"]["exponent"]), _f((f[key]["largest3"] or {}).get("exponent"))) for key in f}
        mem = k.get("peak_rss_first_solve_mb", ("-", "-"))
        L.append(
            f"- {family}: t ~ ndofs^k (all sizes / largest 3): solver {k['solve_s'][0]} / {k['solve_s'][1]}, "
            f"one linear solve {k['linear_s'][0]} / "
            f"{k['linear_s'][1]}; peak memory after the first solve {mem[0]} / {mem[1]}."
        )
        for fit in ("all", "largest3"):
            if f["solve_s"][fit] is None:
                continue
            k = f["solve_s"][fit]["exponent"]
            what = "all sizes" if fit == "all" else "largest 3 sizes"
            targets.append((f"cost exponent <= {cfg.targets['exponent']:g} ({family}, row solver, {what})", _f(k),
                            k <= cfg.targets["exponent"]))
        worst = max(fam["rows"], key=lambda r: r["linear_solves_equivalent"])
        targets.append((f"contact solve <= {cfg.targets['linear_solves']:g} linear solves at every size ({family}; "
                        f"worst {worst['ndofs']} dofs)", _f(worst["linear_solves_equivalent"]),
                        worst["linear_solves_equivalent"] <= cfg.targets["linear_solves"]))
        big = fam["rows"][-1]
        if "peak_mb" in cfg.targets and "peak_rss_first_solve_mb" in big:
            peak = big["peak_rss_first_solve_mb"]
            ok = big["ndofs"] >= cfg.targets["largest_ndofs"] and peak < cfg.targets["peak_mb"]
            targets.append((f"largest size >= {cfg.targets['largest_ndofs']} dofs with peak < "
                            f"{cfg.targets['peak_mb']:g} MB after the contact solve ({family})",
                            f"{big['ndofs']} dofs, {_f(big['peak_rss_first_solve_mb'], '.0f')} MB", ok))
    L.append("")
    return L


def _md_mpi(mp: dict) -> list[str]:
    L = [
        "## 4. MPI (`mpiexec -n 2 workbench run hertz_cylinder`)",
        "",
        "| h/a | ndofs | rel diff P | rel diff p0 | rel diff a | <= 1e-8 | solver 1 / 2 procs (s) | speed-up "
        "solver | speed-up process |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in mp["rows"]:
        d = r["rel_diff"]
        L.append(
            f"| {r['h_over_a'] if r['h_over_a'] is not None else 'case'} | {r['serial']['ndofs']} | "
            f"{d['P']:.1e} | {d['p0']:.1e} | {d['half_width']:.1e} | {r['reproduces_1e-8']} | "
            f"{_f(r['serial']['solve_s'])} / {_f(r['np2']['solve_s'])} | {_f(r['speedup_solve'])} | "
            f"{_f(r['speedup_process'])} |"
        )
    return L + [""]


def _md_cache(ca: dict, op: dict | None, targets: list, cfg: BenchConfig) -> list[str]:
    L = ["## 5. Repeated work", ""]
    if ca:
        c, w = ca["cold_process"], ca["disk_warm_process"]
        L += [
            "| | process (s) | imports (s) | mesh (s) | first run (s) | second run, same process (s) |",
            "|---|---|---|---|---|---|",
            f"| cold: fresh FFCx cache (XDG_CACHE_HOME) and mesh cache | {_f(c['process_s'])} | "
            f"{_f(c['import_s'])} | {_f(c['mesh_s'])} | {_f(c['first_total_s'])} | {_f(c['warm_total_s'])} |",
            f"| same caches, new process | {_f(w['process_s'])} | {_f(w['import_s'])} | {_f(w['mesh_s'])} | "
            f"{_f(w['first_total_s'])} | {_f(w['warm_total_s'])} |",
            "",
            f"Whole CLI `workbench run hertz_cylinder` with warm caches (imports, run, plots, VTK, "
            f"report): {_f(ca['cli_warm_process_s'])} s (exit {ca['cli_exit']}).",
            "",
        ]
        targets.append(
            (
                f"default {cfg.case} (rms <= {100 * cfg.rms_target:g} %) in <= "
                f"{cfg.targets['default_warm_s']:g} s warm (whole CLI process)",
                _f(ca["cli_warm_process_s"]),
                ca["cli_warm_process_s"] <= cfg.targets["default_warm_s"],
            )
        )
    if op:
        L += [
            f"Solver options at h_c = a*{op['h_over_a']:g} (graded, {op['rows'][0]['ndofs']} dofs; one "
            "linear "
            f"solve {_f(op['linear']['linear_s'])} s). PETSc options go through the wiring's "
            "`petsc_options` override and reach the Newton solve only (the Hertz predictor's "
            "MUMPS solve keeps its defaults).",
            "",
            "| variant | solver (s) | linear solves | Newton its | LU sym/num | symbolic (s) | numeric (s) | rms |",
            "|---|---|---|---|---|---|---|---|",
        ]
        for r in op["rows"]:
            ev = r["events"]
            L.append(
                f"| {r['variant']} | {_f(r['solve_s'])} | {_f(r['linear_solves_equivalent'])} | "
                f"{r['newton_iterations']} | {_events(ev)} | {_f(ev['MatLUFactorSym']['time_s'])} | "
                f"{_f(ev['MatLUFactorNum']['time_s'])} | {_f(r['rms'])} |"
            )
        L.append("")
    return L


def _md_reuse(lr: dict) -> list[str]:
    L = [
        "Reuse of the LU across Newton solves through PETSc options only (GMRES preconditioned by the LU of "
        "the first Jacobian, `snes_lag_preconditioner -2`, `snes_lag_preconditioner_persists`):",
        "",
        "| mesh | h/a | ndofs | case (s) | reuse (s) | LU numeric case / reuse | triangular solves (reuse) | "
        "rel diff P |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in lr["rows"]:
        c, u = r.get("case", {}), r.get("reuse", {})
        if "failed" in c or "failed" in u:
            L.append(f"| {r['family']} | {r['h_over_a']:g} | - | failed: {c.get('failed', u.get('failed'))} | | | | |")
            continue
        L.append(
            f"| {r['family']} | {r['h_over_a']:g} | {r.get('ndofs')} | {_f(c['solve_s'])} | "
            f"{_f(u['solve_s'])} | {c['lu_numeric']} / {u['lu_numeric']} | {u['triangular_solves']} | "
            f"{_f(r.get('rel_diff_P'), '.1e')} |"
        )
    return L + [
        "",
        "GMRES needs about one triangular solve per contact dof whose state differs from the first "
        "Jacobian, so this wins only when the contact zone holds few dofs (see the comment at "
        "reuse_lu in workbench/studies/bench_config.py, BenchConfig).",
        "",
    ]


def _nested_text(cfg: BenchConfig) -> str:
    if not cfg.scale_nested:
        return ""
    fams = ", ".join(f"{fam} from h x {fac:g} where that h is at most a x {cfg.scale_nested_coarsest:g}"
                     for fam, fac in cfg.scale_nested.items())
    return (f"; nested iteration ({fams}): each such row first solves its family's coarser mesh and starts from "
            "that solution's active set and d; the row's solver time is the sum of both solves (the 'its' column "
            "is the row's mesh's)")


def _md_techniques(tq: dict, cfg: BenchConfig) -> list[str]:
    """Section ``techniques`` (issue 38, items 3 and 4): condensation and solver variants, each with its figure."""
    L = ["## Techniques measured for issue 38 (condensation, Krylov method, forcing, active-set update)", "",
         "Condensation onto the contact cells (item 3): the stiffness factored by MUMPS with the dofs of the cells on "
         f"the contact boundary within |x| <= {cfg.schur_zone:g} a as Schur unknowns, the dense Schur complement "
         "extracted and LU-factored: the floor of a contact solve on the condensed system, in linear solves of the "
         "row's kind. One process per mesh; one run each.", "",
         "| mesh | h/a | ndofs | Schur dofs | dense S (MB) | plain LU (s) | LU with Schur (s) | extract S (s) | "
         "dense LU (s) | total, linear solves | peak RSS (MB) |",
         "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in tq["rows"]:
        c = r["condensation"]
        if "skipped" in c:
            L.append(f"| {r['family']} | {r['h_over_a']:g} | {r['ndofs']} | {c['n_schur']} | {_f(c['dense_mb'])} | "
                     f"{_f(c['plain_factor_s'])} | not run: {c['skipped']} | | | | |")
            continue
        L.append(f"| {r['family']} | {r['h_over_a']:g} | {r['ndofs']} | {c['n_schur']} | {_f(c['dense_mb'])} | "
                 f"{_f(c['plain_factor_s'])} | {_f(c['factor_s'])} | {_f(c['extract_s'])} | {_f(c['dense_lu_s'])} | "
                 f"{_f(c['linear_solves'])} | {_f(c['peak_rss_mb'], '.0f')} |")
    L += ["", "Solver variants (items 3 and 4): the contact solve with the row's options and with each variant "
          "(the second of two solves in the process), in linear solves of the row's kind; 'failed its' = Newton "
          "iterations of solves that did not converge (cut back); 'tri. solves' = passes through the factor "
          "(PETSc MatSolve and MatMatSolve events; for GAMG its coarse-grid solves).", "",
          "| mesh | h/a | ndofs | kind | variant | solver (s) | linear solves | Newton its | failed its | tri. solves "
          "| rel diff P |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in tq["rows"]:
        for v in r["variants"]:
            head = f"| {r['family']} | {r['h_over_a']:g} | {r['ndofs']} | {r['linear_kind']} | {v['variant']} |"
            if "failed" in v:
                L.append(f"{head} failed: {v['failed']} | | | | | |")
                continue
            L.append(f"{head} {_f(v['solve_s'])} | {_f(v['linear_solves_equivalent'])} | {v['newton_iterations']} | "
                     f"{v['failed_iterations']} | {v['triangular_solves']} | {_f(v['rel_diff_P'], '.1e')} |")
    return L + [""]


def _md_predictor_free(pf: dict, targets: list) -> list[str]:
    t = pf["target"]
    L = [
        "## 6. Predictor-free Newton",
        "",
        f"Every run of each scene at its default level with `predictor=\"extrapolate\"` (no analytic predictor) "
        f"and `active_set=\"{pf['active_set']}\"`, `active_set_update=\"{pf.get('active_set_update', 'newton')}\"`"
        f" (total Newton iterations {pf.get('total_newton_iterations')}); reference: today's "
        "`active_set=\"extrapolate\"` (single patches only) and the case default (the Hertz predictor where it "
        "applies). Newton iterations per solve, "
        "the prescribed-active-set iteration included; force corrections and open steps (0 iterations) count "
        "as solves. P: largest relative difference of a run's load from the case default.",
        "",
        f"| scene | {pf['active_set']}: per solve | its | {pf['active_set']} + newton update: per solve | "
        "reference: per solve | case default: per solve | P vs default |",
        "|---|---|---|---|---|---|---|",
    ]
    ref, dflt = pf.get("reference_active_set_extrapolate", {}), pf.get("case_default", {})
    plain = pf.get("active_set_update_newton") or {}
    for name, row in pf["scenes"].items():
        its = "; ".join(f"{k}: {r['newton_iterations']}" for k, r in row["runs"].items())
        L.append(f"| {name} | {_f(row['newton_per_step'])} | {its} | "
                 f"{_f(plain.get(name, {}).get('newton_per_step'))} | {_f(ref.get(name, {}).get('newton_per_step'))} "
                 f"| {_f(dflt.get(name, {}).get('newton_per_step'))} "
                 f"| {_f(row.get('max_rel_diff_P_vs_default'), '.1e')} |")
        targets.append((f"predictor-free Newton <= {t:g} per solve: {name}", _f(row["newton_per_step"]),
                        row["met"]))
    return L + [""]


def two_body_markdown(tb: dict, targets: list) -> list[str]:
    """The ``two_body`` section (:mod:`workbench.studies.bench_two_body`): cost against a rigid case with the same
    dofs, and Newton iterations per load step."""
    cfg = tb.get("config", {})
    ct, nt = tb["cost_target"], tb["newton_target"]
    L = ["## Two elastic bodies against a rigid case with the same dofs", "",
         f"Each two-body run (its scene's load path: no analytic predictor) against `{cfg.get('rigid_case')}` (rigid "
         f"exact circle, as its case file sets it) refined to the same dofs (within {cfg.get('match_rtol')}), timed "
         f"alternately in one process, best of {cfg.get('repeats')} warm runs each. Cost = warm wall time of the "
         f"case pipeline's run (mesh read, solve, comparison). Targets: cost ratio <= {ct:g}, Newton iterations "
         f"<= {nt} in every load step. Load average {_f(tb.get('load_avg', [math.nan])[0], '.2f')}.", "",
         f"A second rigid timing runs without its analytic predictor ({cfg.get('rigid_free')}), as the two-body "
         "load path does: its ratio separates the coupling's cost from the predictor's gain.", "",
         "| two-body run | dofs | rigid h_c | rigid dofs | two-body s (solver) | rigid s (solver) | ratio (solver) | "
         "rigid predictor-free s: ratio | two-body Newton its per step | rigid its (predictor-free) | "
         "numeric LU: two-body / rigid / predictor-free (count, s) |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in tb["rows"]:
        t, g, fr = r["two_body"], r["rigid"], r["rigid_predictor_free"]
        L.append(f"| {r['case']} [{r['run']}] | {t['ndofs']} | {_f(g['h_contact'], '.4g')} | {g['ndofs']} "
                 f"({r['ndofs_rel_diff']:+.1%}) | {_f(t['total_s'])} ({_f(t['solve_s'])}) | {_f(g['total_s'])} "
                 f"({_f(g['solve_s'])}) | {r['ratio_total']:.2f} ({r['ratio_solve']:.2f}) | "
                 f"{_f(fr['total_s'])}: {r['ratio_total_predictor_free']:.2f} | "
                 f"{t['newton_iterations']} | {g['newton_iterations']} ({fr['newton_iterations']}) | "
                 + " / ".join(f"{x.get('lu_numeric', '-')} ({_f(x.get('lu_numeric_s'))})" for x in (t, g, fr)) + " |")
        targets.append((f"two-body cost <= {ct:g} x rigid at equal dofs: {r['case']} [{r['run']}]",
                        f"{r['ratio_total']:.2f}", r["cost_met"]))
        targets.append((f"two-body Newton its <= {nt} per load step: {r['case']} [{r['run']}]",
                        str(r["newton_max"]), r["newton_met"]))
    return L + [""]


def nested_markdown(ne: dict) -> list[str]:
    """The ``nested`` section (:mod:`workbench.studies.bench_nested`): the budget's levels cold and nested."""
    cfg = ne.get("config") or {}
    L = ["## Nested iteration: the error budget's levels (issue 38)", "",
         f"`{cfg.get('case')}` [{cfg.get('run')}] at W = {_f(ne.get('width'), 'g')} of its unit, the levels coarse to "
         f"fine: cold (each from the unloaded state, the case's load path) against nested (each from the coarser "
         f"level's converged state; the coarsest cold). Solver wall time, best of {cfg.get('repeats')}; "
         f"load average {_f(ne['load_avg'][0], '.2f')} at the end. Total nested / cold: "
         f"**{_f(ne.get('ratio'), '.2f')}** ({_f(ne.get('total_nested_s'), '.1f')} s against "
         f"{_f(ne.get('total_cold_s'), '.1f')} s).", "",
         "| h_c | dofs | cold s | cold Newton its (solves) | nested s | nested Newton its (solves) | nested / cold | "
         "moment half-width, nested / cold - 1 |", "|---|---|---|---|---|---|---|---|"]
    for r in ne.get("rows", []):
        c, n = r["cold"], r["nested"]
        L.append(f"| {r['h']:g} | {r['ndofs']} | {c['solve_s']:.2f} | {c['newton_iterations']} ({c['solves']}) | "
                 f"{n['solve_s']:.2f} | {n['newton_iterations']} ({n['solves']}) | {_f(r['ratio'], '.2f')} | "
                 f"{r['moment_rel_diff']:.1e} |")
    return L + [""]


def to_markdown(data: dict) -> str:
    """The benchmark report (Markdown) from the benchmark JSON (its ``config``; defaults where it has none)."""
    cfg = from_json(BenchConfig, data.get("config"))
    L = [
        f"# Performance benchmark ({cfg.case})",
        "",
        f"`workbench bench`: {_f(data.get('bench_wall_time_s'), '.0f')} s"
        f"{reference_text(data.get('bench_wall_time_s'), data.get('reference'))} on "
        f"{data.get('cpu_count')} cores, load average {_f(data['load_avg_start'][0], '.2f')} at start and "
        f"{_f(data.get('load_avg_end', [math.nan])[0], '.2f')} at the end (the CPU is shared: times are the "
        "best "
        f"of the repeats and carry that noise). Error: RMS(p - p_H)/p0 at the measured load; target "
        f"{cfg.rms_target:.1%}. Warm: JIT and mesh caches filled, forms loaded once in the process.",
        "",
    ]
    targets: list = []
    if data.get("accuracy"):
        L += _md_accuracy(data["accuracy"], targets, cfg)
    if data.get("linear"):
        L += _md_linear(data["linear"], targets, cfg)
    if data.get("scale"):
        L += _md_scale(data["scale"], targets, cfg)
    if data.get("mpi"):
        L += _md_mpi(data["mpi"])
    if data.get("cache") or data.get("options"):
        L += _md_cache(data.get("cache"), data.get("options"), targets, cfg)
    if data.get("lu_reuse"):
        L += _md_reuse(data["lu_reuse"])
    if data.get("predictor_free"):
        L += _md_predictor_free(data["predictor_free"], targets)
    if data.get("two_body"):
        L += two_body_markdown(data["two_body"], targets)
    if data.get("nested"):
        L += nested_markdown(data["nested"])
    if data.get("techniques"):
        L += _md_techniques(data["techniques"], cfg)
    if data.get("startup"):
        from workbench.studies.bench_startup_report import startup_markdown

        L += startup_markdown(data["startup"], targets)
    L += ["## Targets", "", "| target | measured | status |", "|---|---|---|"]
    L += [f"| {t} | {v} | {_met(ok)} |" for t, v, ok in targets]
    return "\n".join(L) + "\n"
