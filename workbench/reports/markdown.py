"""Markdown to HTML for every workbench report: CommonMark plus GFM tables, by markdown-it-py.

One parser (:data:`MD`) renders every report, so what a Markdown viewer shows and what the browser shows
agree: bold, emphasis, code, links, images, lists, headings and pipe tables. Raw HTML in the Markdown is
escaped, not passed through (the reports quote paper text, which may contain ``<`` and ``>``).

The page has a small stylesheet: readable fonts, left-aligned table cells, and a table wider than the page
scrolls horizontally in its own box instead of overflowing it. ``PASS`` and ``FAIL`` are coloured.
"""

from __future__ import annotations

import html
import re
from collections.abc import Mapping

from markdown_it import MarkdownIt

__all__ = ["MD", "fmt", "markdown_to_html"]

_CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,"Helvetica Neue",Arial,sans-serif;font-size:16px;
  line-height:1.5;max-width:1100px;margin:2em auto;padding:0 1em;color:#222;background:#fff}
h1,h2,h3{line-height:1.25;margin:1.4em 0 .5em}h1{font-size:1.8em}h2{font-size:1.4em;border-bottom:1px solid #ddd}
h3{font-size:1.15em}
code,pre{font-family:ui-monospace,SFMono-Regular,Menlo,Consolas,"Liberation Mono",monospace;font-size:90%}
code{background:#f4f4f4;padding:0 3px;border-radius:3px}pre{background:#f6f6f6;padding:.6em;overflow-x:auto}
pre code{background:none;padding:0}
.table-wrap{max-width:100%;overflow-x:auto;margin:1em 0}
table{border-collapse:collapse;font-size:90%;font-variant-numeric:tabular-nums}
th,td{border:1px solid #bbb;padding:3px 7px;text-align:left;vertical-align:top}th{background:#eee}
tbody tr:nth-child(even){background:#fafafa}
img{max-width:100%;height:auto}a{color:#0550ae}
.pass{color:#070;font-weight:bold}.fail{color:#b00;font-weight:bold}
"""

_VERDICT = re.compile(r"\b(PASS|FAIL)\b")
_SCHEME = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")


def _parser() -> MarkdownIt:
    md = MarkdownIt("commonmark", {"html": False, "linkify": False, "typographer": False}).enable("table")
    md.add_render_rule("table_open", lambda self, tokens, idx, options, env:
                       '<div class="table-wrap">\n' + self.renderToken(tokens, idx, options, env))
    md.add_render_rule("table_close", lambda self, tokens, idx, options, env:
                       self.renderToken(tokens, idx, options, env) + "</div>\n")
    md.add_render_rule("text", _render_text)
    return md


def _render_text(self, tokens, idx, options, env) -> str:
    """Plain text, escaped, with ``PASS``/``FAIL`` coloured."""
    text = html.escape(tokens[idx].content, quote=False)
    return _VERDICT.sub(lambda m: f'<span class="{m.group(1).lower()}">{m.group(1)}</span>', text)


MD: MarkdownIt = _parser()
"""The one Markdown parser of the reports (CommonMark, GFM tables, raw HTML escaped)."""


def fmt(value, digits: int = 5) -> str:
    """A table cell: ``-`` for None, ``digits`` significant digits for floats."""
    if value is None:
        return "-"
    if isinstance(value, float):
        return f"{value:.{digits}g}"
    return str(value)


def _rewrite_links(tokens, suffixes: Mapping[str, str]) -> None:
    """Change the suffix of relative link targets in place (e.g. ``case/report.md`` -> ``case/report.html``)."""
    for tok in tokens:
        for child in tok.children or ():
            if child.type != "link_open":
                continue
            href = str(child.attrGet("href") or "")
            if not href or _SCHEME.match(href) or href.startswith(("/", "#")):
                continue
            path, hash_, fragment = href.partition("#")
            for old, new in suffixes.items():
                if path.endswith(old):
                    child.attrSet("href", path[: -len(old)] + new + hash_ + fragment)
                    break


def markdown_to_html(md: str, *, title: str = "report", link_suffixes: Mapping[str, str] | None = None) -> str:
    """Render the report Markdown ``md`` as a standalone HTML page.

    Args:
        md: CommonMark with GFM pipe tables (raw HTML in it is escaped).
        title: The page title.
        link_suffixes: Old -> new suffix of relative link targets, e.g. ``{".md": ".html"}`` so that links
            between reports point at their HTML twins. Absolute URLs are left alone.
    """
    env: dict = {}
    tokens = MD.parse(md, env)
    if link_suffixes:
        _rewrite_links(tokens, link_suffixes)
    body = MD.renderer.render(tokens, MD.options, env)
    return (f"<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
            f"<title>{html.escape(title)}</title>\n<style>{_CSS}</style></head>\n<body>\n{body}</body></html>\n")
