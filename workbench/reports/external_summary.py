"""The summary's table of scored external codes: every ``<out>/score_<case>/score.json`` and
``<out>/external_ccx_<case>/score/score.json`` (reads JSON only; issue 26)."""

from __future__ import annotations

import json
from pathlib import Path

__all__ = ["scored_markdown"]


def _scores(results: Path) -> list[tuple[str, Path, dict]]:
    out = []
    for f in sorted([*results.glob("score_*/score.json"), *results.glob("external_*_*/score/score.json")]):
        try:
            out.append((f.parent.relative_to(results).as_posix(), f, json.loads(f.read_text())))
        except (OSError, ValueError):
            continue
    return out


def scored_markdown(results: Path) -> list[str]:
    """Markdown lines: one row per scored external result set (empty when none)."""
    rows = _scores(Path(results))
    if not rows:
        return []
    lines = ["## Scored external codes", "",
             "| scored | case | levels | finest p_max err | finest RMS/p0 | extrapolated p_max/p0 | verdict |",
             "|---|---|---|---|---|---|---|"]
    for folder, _f, s in rows:
        levels = s.get("levels") or []
        fine = min(levels, key=lambda lv: lv.get("h") or 0.0) if levels else {}
        err = fine.get("errors", {})
        st = (s.get("grid_study") or {}).get("p_max") or {}
        ext = f"{st['extrapolated']:.5f}" if "extrapolated" in st else "-"
        pm = f"{err['p_max']:+.3%}" if isinstance(err.get("p_max"), float) else "-"
        rms = f"{err['rms']:.3%}" if isinstance(err.get("rms"), float) else "-"
        if not st:
            verdict = "fewer than three levels"
        elif not st.get("outside_band"):
            verdict = "within the discretisation band"
        else:
            inside = [m["model"] for m in (s.get("models") or {}).get("models", []) if m.get("contains")]
            verdict = f"remainder {st.get('remainder', 0.0):+.3%} outside the band" + (
                f"; within the band of the workbench's {', '.join(inside)}" if inside else "")
        lines.append(f"| [{folder}]({folder}/report.md) | {s.get('case')} | {len(levels)} | {pm} | {rms} | {ext} | "
                     f"{verdict} |")
    return [*lines, ""]
