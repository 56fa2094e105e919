"""Markdown of the bench section ``startup`` (:mod:`workbench.studies.bench_startup`): formatting only."""

from __future__ import annotations

__all__ = ["startup_markdown"]


def _s(v: float) -> str:
    return f"{v:.2f}" if v >= 0.1 else f"{v:.3f}"


def startup_markdown(st: dict, targets: list) -> list[str]:
    """The section's lines; appends ``(target, measured, met)`` of each process mode to ``targets``."""
    ms, floor, target = st["mesh_solve_s"], st["import_floor_s"], st["target_ratio"]
    L = ["## Start-up and output: one CI-level case as a whole process", "",
         f"`workbench run {st['case']} --ci` ({st['ndofs']} dofs, h_c = {st['h_contact']:g} x half-width) as a "
         f"subprocess, warm (JIT and mesh caches filled by a first process), {st['repeats']} per mode, the modes "
         "alternating. Beside it: the case time each process wrote in its metrics.json (mesh from the cache, forms "
         "loaded from the disk cache, solve, comparison, VTK: the \"PASS in\" time), and the same run's mesh and "
         "solve repeated in one process with its forms loaded (`run_one`, best). Target: the whole process within "
         f"{target:g}x its case time (the ratio of each process to its own case time, median: the load cancels "
         "in part).", "",
         "| mode | whole process (s) | case in that process (s) | process / case | target "
         f"({target:g}x) | warm mesh + solve (s) | process / warm mesh+solve | pictures |",
         "|---|---|---|---|---|---|---|---|"]
    names = {"full": "default (report with pictures)", "no_pictures": "`--no-pictures` (scripts)"}
    for mode, r in st["modes"].items():
        met = "met" if r["target_met"] else "NOT met"
        L.append(f"| {names.get(mode, mode)} | {_s(r['process_s']['best'])} | {_s(r['case_s']['best'])} | "
                 f"{r['ratio_to_case']:.1f} | {met} | {_s(ms['best'])} | {r['ratio_to_mesh_solve']:.1f} | "
                 f"{', '.join(r['pngs']) or 'none'} |")
        targets.append((f"whole CI process ({names.get(mode, mode)}) <= {target:g} x its case time",
                        f"{r['ratio_to_case']:.1f} x", r["target_met"]))
    ch = st.get("changed_material")
    if ch:
        met = "met" if ch["target_met"] else "NOT met"
        L += ["", f"**A changed material compiles nothing** (issue 34): `{ch['case']}`, a copy with every Young's "
              f"modulus x{ch['E_factor']:.4g}, added {ch['new_modules']} FFCx modules to the JIT cache in its first "
              f"process (every number of the forms is a dolfinx Constant). Warm `--no-pictures` processes, alternating "
              f"with the original's: {_s(ch['process_s']['best'])} s against {_s(ch['original_process_s']['best'])} s, "
              f"x{ch['ratio']:.2f} (median of the pairs; target x{ch['target']:g}: {met})."]
        targets.append((f"changed-E copy: no new module, process <= {ch['target']:g} x the original's",
                        f"{ch['new_modules']} modules, {ch['ratio']:.2f} x", ch["target_met"]))
    L += ["", f"The floor: the interpreter and the third-party imports every run of the case needs "
          f"(`python -c \"import {', '.join(floor['imports'])}\"`, ended by `os._exit` as `workbench run` ends) "
          f"take {_s(floor['best'])} s, so no process that solves this case can take less than "
          f"{st['floor_ratio']:.1f}x its case time. The first mesh and solve "
          f"in a fresh process took {_s(ms['first_in_process'])} s (form loading). Load average "
          f"{st['load_avg'][0]:.2f} during the section"
          + ("" if st.get("bytecode_cache", True) else "; Python wrote no bytecode cache (PYTHONDONTWRITEBYTECODE): "
             "the workbench's own modules were compiled in every process") + ".", ""]
    return L
