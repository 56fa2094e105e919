"""The report section every study shares: its wall time, and where its points ran (issue 27).

Reads only the study JSON (the ``worker`` of each record, :mod:`workbench.studies.executor`), like the rest of a
study's report. Light: no dolfinx.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

__all__ = ["reference_text", "where_section"]


def _f(v, spec=".1f") -> str:
    return "-" if v is None else format(v, spec)


def reference_text(wall_time_s: float | None, reference: dict | None) -> str:
    """``= N reference solves (...)``: the wall time over the reference solve of the same run
    (:mod:`workbench.studies.reference`), or empty when there is none."""
    if not reference or not reference.get("solve_s") or wall_time_s is None:
        return ""
    return (f" = {wall_time_s / reference['solve_s']:.0f} reference solves (the reference, {reference['case']} at "
            f"h_c = {reference['h_contact']:g}, {reference['ndofs']} dofs, warm: {reference['solve_s']:.3f} s, "
            "measured in the same run: on a loaded machine compare this ratio, not the seconds)")


def where_section(*, wall_time_s: float | None, records: Iterable[dict], label: Callable[[dict], str],
                  reference: dict | None = None, title: str = "Time, and where the points ran") -> list[str]:
    """Markdown lines: the study's wall time (and its ratio to the ``reference`` solve), the executor, one row per
    worker (host, MPI rank, pid, points, their wall time, forms compiled there), the JIT retries, then one row per
    point (``label(record)``: host, rank, wall time). Records without ``worker`` (run before the executor
    existed) are listed as ``-``."""
    records = list(records)
    workers: dict = {}
    retries = compiles = 0
    executor = None
    for r in records:
        w = r.get("worker")
        if not w:
            continue
        executor = w["executor"]
        e = workers.setdefault((w["host"], w["rank"], w["pid"]), [0, 0.0, 0])
        e[0] += 1
        e[1] += w["wall_s"]
        e[2] += w["jit_compiles"]
        retries += w["jit_retries"]
        compiles += w["jit_compiles"]
    md = [f"## {title}", "",
          f"Wall time of the study: {_f(wall_time_s)} s{reference_text(wall_time_s, reference)}. "
          f"Executor: {executor or 'not recorded'}; "
          f"{len(workers)} worker process(es); JIT retries: {retries} (each worker compiles into its own FFCx "
          f"cache, so no compile waits for another: 0 expected); forms compiled on the workers: {compiles}.", ""]
    if not workers:
        return md
    md += ["| host | MPI rank | pid | points | their wall time (s) | forms compiled |", "|---|---|---|---|---|---|"]
    for (host, rank, pid), (n, wall, comp) in sorted(workers.items(), key=lambda kv: (kv[0][0], kv[0][1], kv[0][2])):
        md.append(f"| {host} | {rank} | {pid} | {n} | {wall:.1f} | {comp} |")
    md += ["", "| point | host | MPI rank | wall time (s) |", "|---|---|---|---|"]
    for r in records:
        w = r.get("worker") or {}
        md.append(f"| {label(r)} | {w.get('host', '-')} | {w.get('rank', '-')} | {_f(w.get('wall_s'), '.2f')} |")
    return md
