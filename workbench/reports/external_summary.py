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


def _main(s: dict) -> tuple[str, dict]:
    """The main study of a score (``main`` of issue 36; a Hertz score of issue 26 read its ``p_max``)."""
    key = s.get("main")
    if key and (s.get("studies") or {}).get(key):
        return key, s["studies"][key]
    return "p_max", (s.get("grid_study") or {}).get("p_max") or {}


def scored_markdown(results: Path) -> list[str]:
    """Markdown lines: one row per scored external result set (empty when none)."""
    rows = _scores(Path(results))
    if not rows:
        return []
    lines = ["## Scored external codes", "",
             "| scored | case | levels | main quantity | extrapolated | from theory | band | verdict |",
             "|---|---|---|---|---|---|---|---|"]
    for folder, _f, s in rows:
        levels = s.get("levels") or []
        key, st = _main(s)
        ext = st.get("extrapolated")
        ext_text = f"{ext:.5f}" if isinstance(ext, float) else "-"
        th = st.get("theory")
        dev = f"{ext / th - 1.0:+.3%}" if isinstance(ext, float) and isinstance(th, float) and th else "-"
        band = st.get("band")
        fine = st.get("fine")
        band_text = f"+-{band / abs(fine):.3%}" if isinstance(band, float) and isinstance(fine, float) and fine else "-"
        if s.get("plausibility"):
            verdict = "no verdict: " + s["plausibility"][0]
        elif not st:
            verdict = "fewer than three levels"
        else:
            inside = [m["model"] for m in (s.get("models") or {}).get("models", []) if m.get("contains")]
            verdict = ("within the discretisation band of the theory" if st.get("outside_band") is False
                       else f"remainder {st.get('remainder', 0.0):+.3%} outside the band" if st.get("outside_band")
                       else "no closed-form theory")
            verdict += f"; within the band of the workbench's {', '.join(inside)}" if inside else (
                "; no model of the workbench holds it" if s.get("models") else "")
        lines.append(f"| [{folder}]({folder}/report.md) | {s.get('case')} | {len(levels)} | {key} | {ext_text} | "
                     f"{dev} | {band_text} | {verdict} |")
    return [*lines, ""]
