"""What every ``workbench external <code>`` command shares: the mesh levels it runs and the score of a geometry's
levels.

Levels: the case's first ``n`` from its ``ci_level`` down (:func:`workbench.external.export.level_sequence`, the levels
``workbench export --levels n`` writes: the case's list, continued by halving). Score: the result files of one
geometry, one per level, read and scored exactly as ``workbench score`` does (:mod:`workbench.external.score`).
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["code_levels", "score_geometry"]


def code_levels(case, n: int, *, error: type[Exception]) -> list[float]:
    """The case's first ``n`` mesh levels from its ``ci_level`` down; ``error`` (one line) outside 1 .. MAX_LEVELS."""
    from workbench.external.export import MAX_LEVELS, level_sequence

    if not 1 <= n <= MAX_LEVELS:
        d = case.runs()[0].discretisation
        raise error(f"--levels {n}; allowed: 1 to {MAX_LEVELS} (the case's levels from ci_level "
                    f"{d.ci_level or d.h_contact:g} down, halving beyond its list)")
    return list(level_sequence(case)[:n])


def score_geometry(case_name: str, files: list[Path], folder: Path) -> str:
    """Score one geometry's levels (one result csv per level) into ``folder``; the headline, or why it was not
    scored (one line)."""
    from workbench.external.results import ResultError
    from workbench.external.score import ScoreError, read_results, score_levels, write_score

    try:
        results = read_results([str(f) for f in files], fmt="csv")
        score = score_levels(case_name, results)
        write_score(score, results, folder)
    except (ScoreError, ResultError, ValueError) as exc:
        return f"not scored: {' '.join(str(exc).split())[:300]}"
    return score.get("headline") or score.get("verdict", "")
