"""Every report under the results folder has an HTML twin with no raw Markdown; study pages embed their plots.

Requirement (issue 14, item 5): every ``.md`` under ``results/`` has an ``.html`` beside it and none shows raw
Markdown; a study's report shows its own plots and the summary is rebuilt when a study finishes. The folder
test reads ``WORKBENCH_VIZ_RESULTS`` (``make viz-check`` sets it to ``results/`` after ``make run``); without
it that test is skipped with this reason (the case pages are checked in ``make test`` by
``tests/test_cases_end_to_end.py``).
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from pages import raw_markdown

from workbench.reports.study_pages import PLOTS_HEADING, embed_plots, publish_study


def test_raw_markdown_is_detected():
    assert raw_markdown("<body><p>**bold** and ![x](a.png)</p></body>")[:2] == ["bold **", "image ![...]("]
    assert raw_markdown("<body><p><strong>bold</strong> <code>**kept**</code></p></body>") == []


@pytest.mark.skipif(not os.environ.get("WORKBENCH_VIZ_RESULTS"),
                    reason="WORKBENCH_VIZ_RESULTS not set: `make viz-check` checks every page of results/")
def test_every_markdown_report_has_a_clean_html_twin():
    root = Path(os.environ["WORKBENCH_VIZ_RESULTS"])
    reports = [p for p in root.rglob("*.md") if "mesh_cache" not in p.parts]
    assert reports, f"no reports under {root}"
    for md in reports:
        page = md.with_suffix(".html")
        assert page.is_file(), f"{md} has no HTML twin"
        assert not raw_markdown(page.read_text()), (page, raw_markdown(page.read_text()))


def test_study_page_embeds_its_plots_and_rebuilds_the_summary(tmp_path):
    from workbench.owned import make_dirs

    tmp_path = make_dirs(tmp_path / "results")  # an output folder the workbench made (the summary is rebuilt there)
    study = make_dirs(tmp_path / "stability")
    (study / "report.md").write_text("# Stability\n\n| a | b |\n|---|---|\n| **1** | 2 |\n")
    plots = []
    for name in ("method.png", "incompressible.png"):
        (study / name).write_bytes(b"\x89PNG\r\n\x1a\n")
        plots.append(study / name)
    page = publish_study(study, plots)
    md = (study / "report.md").read_text()
    assert "![method](method.png)" in md and "![incompressible](incompressible.png)" in md
    assert '<img src="method.png"' in page.read_text() and not raw_markdown(page.read_text())
    assert embed_plots(md, ["method.png"]).count(PLOTS_HEADING) == 1  # idempotent
    summary = (tmp_path / "report.md").read_text()
    assert "[Numerical stability sweep](stability/report.md)" in summary
