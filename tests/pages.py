"""Helpers for the page tests: raw Markdown that reached an HTML page."""

from __future__ import annotations

import html
import re

_TAG = re.compile(r"<[^>]+>")
_CODE = re.compile(r"<(pre|code)>.*?</\1>", re.S)
_RAW = [(re.compile(r"\*\*\S"), "bold **"), (re.compile(r"!\[[^\]]*\]\("), "image ![...]("),
        (re.compile(r"\]\([^)]*\)"), "link ](...)"), (re.compile(r"^\s*#{1,6} ", re.M), "heading #"),
        (re.compile(r"^\s*\|?\s*-{3,}\s*\|", re.M), "table rule |---|"), (re.compile(r"(?<!\w)__\S"), "bold __")]


def raw_markdown(page: str) -> list[str]:
    """The kinds of Markdown syntax visible as text in the body of an HTML page (code blocks excluded)."""
    body = page.split("<body>", 1)[-1]
    text = html.unescape(_TAG.sub("", _CODE.sub("", body)))
    return [what for pattern, what in _RAW if pattern.search(text)]
