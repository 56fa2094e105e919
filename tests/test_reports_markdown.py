"""Markdown to HTML for every report (markdown-it-py, CommonMark with GFM tables).

Requirement: the HTML twin of every report renders what its Markdown says (bold, emphasis, code, links,
images, lists, tables), never shows raw Markdown syntax, escapes raw HTML, and keeps wide tables inside the
page. Known bug this guards: ``analytic/convective.html`` showed raw ``**...**`` when the bold text held a
``*`` (``theta*beta``).
"""

from __future__ import annotations

import re

from workbench.atomic import write_text
from workbench.reports.markdown import fmt, markdown_to_html
from workbench.reports.summary import write_summary

# The paper-figures list of analytic/convective.md as `workbench convective-table` writes it (abridged).
CONVECTIVE_MD = """# Convective effect (Ciavarella & Hills): b/b0 at fixed load

- load: fixed P; b0 = classical half-width at that load; b in material coordinates
- converged: fixed point of the full equations H' = h'(x - g) (1 + beta A p)

## Wedge

| m convention | theta | m | beta | first order | first iterate | converged | iterations |
|---|---|---|---|---|---|---|---|
| paper | pi/5 | 0.628319 | -0.5 | 1.160941 | 1.110192 | 1.164566 | 28 |

## The paper's printed figures

- **eq. (7): rigid indenter, nu2 = 0 -> beta = -1/2** (printed -0.500): beta_rigid_indenter(0) = -0.500000. \
Verdict: confirmed.
- **parabola: 'the correction is about 16 %' (beta = -0.5)** (printed 0.160): 4|beta|(b/R)/pi at b/R=1/4 = 0.159155.
- **wedge: correction depends on the product theta*beta only** (printed ): converged(pi/10, -0.5) = 1.075856, \
converged(pi/5, -0.25) = 1.075856. Verdict: confirmed.
"""


def _body(html: str) -> str:
    return html.split("<body>", 1)[1]


def test_inline_markup_renders():
    html = markdown_to_html("Verdict: **PASS**, *emphasis*, `code`, [metrics](metrics.json), "
                            "![pressure](pressure.png)\n", title="t")
    assert html.startswith("<!doctype html>") and "<title>t</title>" in html
    body = _body(html)
    assert '<strong><span class="pass">PASS</span></strong>' in body
    assert "<em>emphasis</em>" in body and "<code>code</code>" in body
    assert '<a href="metrics.json">metrics</a>' in body and '<img src="pressure.png" alt="pressure"' in body
    assert "*" not in body


def test_table_and_list_render():
    md = "- one\n- **two**\n\n| run | P (N/mm) | verdict |\n|---|---|---|\n| base | 4531.1 | FAIL |\n| | | |\n"
    body = _body(markdown_to_html(md))
    assert "<ul>" in body and "<li><strong>two</strong></li>" in body
    assert '<div class="table-wrap">\n<table>' in body and "</table>\n</div>" in body  # wide tables scroll
    assert "<th>P (N/mm)</th>" in body and '<td><span class="fail">FAIL</span></td>' in body
    assert body.count("<tr>") == 3 and "|" not in body


def test_raw_html_is_escaped_not_passed_through():
    body = _body(markdown_to_html("a <script>alert(1)</script> b\n\n<div>x</div>\n", title="<x>"))
    assert "<script>" not in body and "&lt;script&gt;" in body and "<div>x</div>" not in body
    assert "<title>&lt;x&gt;</title>" in markdown_to_html("", title="<x>")


def test_convective_table_renders_without_raw_markdown():
    body = _body(markdown_to_html(CONVECTIVE_MD, title="analytic"))
    assert "**" not in body
    assert "<strong>wedge: correction depends on the product theta*beta only</strong>" in body
    assert "<strong>eq. (7): rigid indenter, nu2 = 0 -&gt; beta = -1/2</strong>" in body
    assert body.count("<strong>") == 3
    assert "<td>1.164566</td>" in body


def test_stylesheet_keeps_wide_tables_in_the_page():
    html = markdown_to_html("x")
    assert re.search(r"\.table-wrap\{[^}]*overflow-x:auto", html)
    assert re.search(r"th,td\{[^}]*text-align:left", html)


def test_links_to_markdown_reports_can_point_at_their_html_twins():
    md = "[a](case/report.md) [b](analytic/convective.md#wedge) [c](https://example.org/x.md) [d](data.csv)\n"
    body = _body(markdown_to_html(md, link_suffixes={".md": ".html"}))
    assert 'href="case/report.html"' in body and 'href="analytic/convective.html#wedge"' in body
    assert 'href="https://example.org/x.md"' in body and 'href="data.csv"' in body
    assert 'href="case/report.md"' in _body(markdown_to_html(md))


def test_summary_links_html_twins_and_renders_convective_table(tmp_path):
    write_text(tmp_path / "analytic" / "convective.md", CONVECTIVE_MD)  # as the study writes it: a marked folder
    write_summary(tmp_path)
    assert "[Analytic convective table](analytic/convective.md)" in (tmp_path / "report.md").read_text()
    summary = (tmp_path / "report.html").read_text()
    assert 'href="analytic/convective.html"' in summary and "convective.md" not in summary
    twin = (tmp_path / "analytic" / "convective.html").read_text()
    assert "**" not in _body(twin) and twin.count("<strong>") == 3


def test_fmt_cells():
    assert fmt(None) == "-" and fmt(0.123456789) == "0.12346" and fmt(0.123456789, 3) == "0.123"
    assert fmt(7) == "7" and fmt("nitsche") == "nitsche"
