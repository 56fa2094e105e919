"""The error budget of a case (``make run`` only): the scene's own, and its outputs (the Markdown table, the Hertz
axis samples in ``subsurface.csv``).

Every scene owns its budget (:meth:`workbench.scenes.base.Scene.error_budget`): the block scenes'
:mod:`workbench.scenes.block_budget` (three grids x three block sizes, the Hertz interior and axis), the concave
scenes' :mod:`workbench.scenes.concave_budget`, the two-body ones :mod:`workbench.scenes.two_body_budget` and
:mod:`workbench.scenes.halfplanes_budget`. A scene without a budget returns None (no rows).
"""

from __future__ import annotations

from pathlib import Path

from cases.schema import Case
from workbench.scenes import scene_for

__all__ = ["case_error_budget", "budget_table", "subsurface_csv", "write_subsurface"]


def case_error_budget(case: Case, *, solve, progress=print) -> tuple[dict, dict | None]:
    """The ``error_budget`` of a case (empty without ``budget_levels``) and the Hertz axis samples (or None).

    Args:
        case: The case (its ``[discretisation] budget_levels`` and ``budget_widths``).
        solve: ``solve(run) -> Outcome`` (:func:`workbench.pipeline.run_case.run_one` bound to the mesh
            cache and communicator).

    Returns:
        ``(error_budget, subsurface)``: the JSON dict ``{quantity: row}`` and the axis samples of a Hertz run
        (or None).
    """
    if not case.discretisation.budget_levels:
        return {}, None
    own = scene_for(case.runs()[0]).error_budget(case, solve=solve, progress=progress)
    if own is None:  # a scene with no budget of its own
        return {}, None
    return own.rows, own.subsurface


def subsurface_csv(sub: dict) -> str:
    """``subsurface.csv``: z_mm, the FEM stresses, then the exact ones (MPa)."""
    names = ["z_mm", "sxx_fem", "syy_fem", "szz_fem", "vm_fem", "sxx_exact", "syy_exact", "szz_exact", "vm_exact"]
    cols = sub["columns"]
    lines = [",".join(names)]
    for i in range(len(cols["z_mm"])):
        lines.append(",".join(f"{float(cols[n][i]):.10g}" for n in names))
    return "\n".join(lines) + "\n"


def budget_table(budget: dict) -> list[str]:
    """The budget as Markdown table lines (values dimensionless, over the classical value at the load); the
    band terms are relative: GCI, truncation, iterative, round-off and their sum (the band, times |fine|)."""
    head = ("| quantity | fine | extrapolated | order | status | GCI | truncation | iterative | round-off "
            "| uncertainty | theory | in band | alt. theory | alt. in band |")
    lines = [head, "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]

    def f(v, fmt=".7f"):
        return "n/a" if v is None else format(v, fmt)

    for q, r in budget.items():
        alt = f"{r['alt_theory']} {r['alt_value']:.7f}" if "alt_theory" in r else "-"
        alt_in = ("yes" if r["alt_in_band"] else "no") if "alt_in_band" in r else "-"
        ib = "n/a" if r["theory_in_band"] is None else ("yes" if r["theory_in_band"] else "no")
        if r.get("gci") is None:
            fine = f(r["fine"], ".3e") if isinstance(r["fine"], float) else r["fine"]
            lines.append(f"| {q} | {fine} | n/a | {f(r.get('observed_order'), '.2f')} | {r['status']} | n/a | n/a "
                         f"| n/a | n/a | n/a | {f(r.get('theory'), 'g')} | n/a | - | - |")
            continue
        order = f(r["observed_order"], ".2f")
        if r.get("band_order") is not None and r.get("observed_order") is not None \
                and r["band_order"] != r["observed_order"]:
            order += f" (band at {r['band_order']:g})"
        lines.append(f"| {q} | {f(r['fine'])} | {f(r['extrapolated'])} | {order} | "
                     f"{r['status']} | {f(r['gci'], '.2e')} | {f(r['truncation'], '.2e')} ({r['truncation_status']})"
                     f" | {f(r.get('iterative'), '.1e')} | {f(r.get('roundoff'), '.0e')} "
                     f"| {f(r.get('uncertainty'), '.2e')} | {f(r['theory'])} | {ib} | {alt} | {alt_in} |")
    notes = [f"- {q}: band {r['extrapolated']:.5f} +- {r['uncertainty'] * abs(r['fine']):.1e}; the small-strain "
             "models' extrapolated values: " + ", ".join(
                 f"{c} {v:.5f} ({'in' if r['models_in_band'][c] else 'outside'})" for c, v in r["models"].items())
             for q, r in budget.items() if r.get("models")]
    return lines + ([""] + notes if notes else [])


def write_subsurface(folder: Path, sub: dict) -> None:
    """Write ``subsurface.csv`` into ``folder``."""
    from workbench.atomic import write_text

    write_text(Path(folder) / "subsurface.csv", subsurface_csv(sub))
