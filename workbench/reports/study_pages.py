"""A study's pages once its plots are drawn: plots embedded in ``report.md``, ``report.html``, summary rebuilt.

:func:`publish_study` is called by each study's plot module when it has drawn its plots
(:mod:`workbench.studies.convergence_plot`, :mod:`workbench.studies.stability_plot`,
:mod:`workbench.studies.bench_plot`), so a finished study always has an HTML page showing its own plots and
the summary (``<out>/report.{md,html}``) lists it without waiting for ``workbench report``.
"""

from __future__ import annotations

import re
from pathlib import Path

from workbench.atomic import write_text
from workbench.reports.markdown import markdown_to_html

__all__ = ["PLOTS_HEADING", "embed_plots", "publish_study"]

PLOTS_HEADING = "## Plots"


def embed_plots(md: str, plots: list[str]) -> str:
    """``md`` with every plot of ``plots`` (file names) that it does not show yet in a final Plots section."""
    md = md.split(f"\n{PLOTS_HEADING}\n", 1)[0].rstrip("\n") + "\n"
    shown = set(re.findall(r"!\[[^\]]*\]\(([^)]+)\)", md))
    missing = [p for p in plots if p not in shown]
    if not missing:
        return md
    return md + f"\n{PLOTS_HEADING}\n\n" + "\n\n".join(f"![{Path(p).stem}]({p})" for p in missing) + "\n"


def publish_study(folder: Path, plots: list[Path], *, report: str = "report.md") -> Path | None:
    """Embed ``plots`` in ``folder/report``, write its HTML twin and rebuild the summary of ``folder.parent``.

    Returns the HTML page, or None when the study has no report (yet).
    """
    folder = Path(folder)
    md_file = folder / report
    if not md_file.is_file():
        return None
    md = embed_plots(md_file.read_text(), [Path(p).name for p in plots if Path(p).is_file()])
    write_text(md_file, md)
    page = md_file.with_suffix(".html")
    write_text(page, markdown_to_html(md, title=folder.name, link_suffixes={".md": ".html"}))
    from workbench.owned import read_marker
    from workbench.paths import OutputError
    from workbench.reports.summary import write_summary

    # the summary is rebuilt only in a workbench output folder (a study's --out elsewhere writes nothing above it)
    if read_marker(folder.parent) is None:
        print(f"summary not rebuilt: {folder.parent} is not a workbench output folder (run `workbench report`)")
        return page
    try:
        write_summary(folder.parent, case_reports=False)
    except OutputError as exc:
        print(f"summary not rebuilt: {exc}")
    return page
