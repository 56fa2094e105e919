"""One scorer per scene: an external code's contact pressure judged with the workbench's own measures and theories.

The registry maps a scene's name (``[geometry] scene`` of a case) to its scorer (:class:`base.SceneScorer`):

=============  ==========================================================================================
block          :mod:`.block`: p_max, edge and moment half-widths, RMS against Hertz, the exact circle or the
               classical wedge; b/b0 of a convective or finite run over the small one (:mod:`.convective`)
concave        :mod:`.concave`: per step and patch P, p0, patch widths against eq. (4)/(5), the Hertz
               superposition, load symmetry (the concave budget's rows)
two_body       :mod:`.two_body`: the exact circle at the combined modulus; the patch test's uniformity
halfplanes     :mod:`.halfplanes`: the classical solution at E* (small run) and b/b0 against Ciavarella-Hills
=============  ==========================================================================================

A new scene's scorer is a class with the protocol's methods and one line ``register_scorer(MyScorer())`` here.
:func:`score_case` runs any of them the same way: assign every group of samples to a (run, step, body) of the case
(:func:`runs.assign`, strict), mirror half models where the case is symmetric, check that the samples lie on the
case's contact surface, measure every level, study the quantities over the three finest levels, apply the
plausibility rules (:func:`base.plausibility`) and only then match the workbench's model bands
(saved by :mod:`workbench.external.models`, passed in) and write the verdict (:mod:`.verdict`). It imports no dolfinx.
"""

from __future__ import annotations

import math

import numpy as np

from workbench.external.results import ExternalResult, mirror_half
from workbench.external.scorers.base import SceneScorer, ScoreError, plausibility
from workbench.external.scorers.runs import assign, schedule

__all__ = ["SCORERS", "register_scorer", "scorer_for", "scoreable", "score_case", "ScoreError"]

SCORERS: dict[str, SceneScorer] = {}


def register_scorer(scorer: SceneScorer) -> SceneScorer:
    """Add a scene's scorer to the registry under ``scorer.scene``."""
    if not isinstance(scorer, SceneScorer):
        raise TypeError(f"{scorer!r} does not implement the SceneScorer protocol")
    SCORERS[scorer.scene] = scorer
    return scorer


def scorer_for(case) -> SceneScorer:
    """The scorer of a case's scene; ScoreError (one line) when its scene has none."""
    scene = case.runs()[0].geometry.scene
    if scene not in SCORERS:
        raise ScoreError(f"case {case.name}: scene {scene!r} has no scorer; allowed: a case of the scenes "
                         f"{', '.join(sorted(SCORERS))}")
    return SCORERS[scene]


def scoreable(case) -> SceneScorer:
    """The case's scorer after its check: ScoreError unless ``score`` can judge the case (before any file is read)."""
    scorer = scorer_for(case)
    scorer.check(case)
    return scorer


def _sizes(records: list[dict], given: bool) -> None:
    """One size h per (file, run): where it was estimated, the median of the estimates of that file's groups of the
    run (one mesh per file and run; the groups' patches differ)."""
    if given:
        return
    by: dict[tuple, list[dict]] = {}
    for rec in records:
        if rec["h_source"].startswith("estimated"):
            by.setdefault((rec["file"], rec["run"]), []).append(rec)
    for recs in by.values():
        hs = [r["h"] for r in recs if math.isfinite(r["h"])]
        if len(recs) > 1 and hs:
            h = float(np.median(hs))
            for r in recs:
                r["h_group_estimate"] = r["h"]
                r["h"] = h


def score_case(case, results: list[list[ExternalResult]], *, h: list[float] | None = None,
               samples_per_element: int = 1, run=None, step=None, body=None, bands: dict | None = None) -> dict:
    """The score of a case's external results (``score.json``'s content, without the verdict's words: see
    :func:`workbench.external.scorers.verdict.judge`).

    Args:
        case: The loaded case.
        results: per RESULT file (one mesh level of the runs it holds), its groups of samples.
        h: the element size on the contact surface per RESULT (mm), or None.
        samples_per_element: samples per element when h is estimated from the sample spacing.
        run, step, body: the ``--run/--step/--body`` values (one per RESULT or one for all) for files without them.
        bands: the case's saved model bands (:func:`workbench.external.models.load_model_bands`), or None.

    Raises:
        ScoreError, ResultError: one line (the command exits 2, nothing written).
    """
    from workbench.external.scorers.verdict import judge

    scorer = scoreable(case)
    if h is not None and len(h) != len(results):
        raise ScoreError(f"--h: {len(h)} sizes for {len(results)} RESULT files; allowed: one per file")
    for name, value in (("run", run), ("step", step), ("body", body)):
        if value is not None and len(value) not in (1, len(results)):
            raise ScoreError(f"--{name}: {len(value)} values for {len(results)} RESULT files; allowed: one, or one "
                             "per file")
    runs = scorer.runs(case)
    steps = {r.label: schedule(r.run, target_load=scorer.target_load(r.run)) for r in runs}
    levels = assign(case, results, runs=runs, steps=steps, bodies=scorer.bodies(case), run_option=run,
                    step_option=step, body_option=body)
    records = []
    with np.errstate(all="ignore"):  # extreme values are named by the checks below, not as numpy warnings
        for i, level in enumerate(levels):
            for g in level:
                res = mirror_half(g.result) if scorer.symmetric(case) else g.result
                g = g._replace(result=res)
                scorer.check_surface(case, g.run, res)
                rec = scorer.measure(case, g, h=None if h is None else h[i], samples_per_element=samples_per_element)
                records.append(rec | {"role": g.body.role, "level": i})
        _sizes(records, h is not None)
        studies = scorer.studies(case, records)
    main = scorer.main_key(case, studies)
    control = case.runs()[0].loading.control
    reasons = plausibility(records, studies, main=main, control=control, load_tolerance=case.tolerances.get("p_max"))
    score = {"case": case.name, "scene": case.runs()[0].geometry.scene,
             "units": {"length": "mm", "load": "N/mm", "pressure": "MPa"},
             "runs": [{"label": r.label, "kinematics": r.kinematics, "aliases": list(r.aliases), "added": r.added,
                       "steps": [s._asdict() for s in steps[r.label]]} for r in runs],
             "bodies": [b._asdict() for b in scorer.bodies(case)],
             "levels": records, "studies": studies, "main": main, "plausibility": reasons}
    return judge(case, score, bands)


from workbench.external.scorers.block import BlockScorer  # noqa: E402  (the registry, after its functions)
from workbench.external.scorers.concave import ConcaveScorer  # noqa: E402
from workbench.external.scorers.halfplanes import HalfplanesScorer  # noqa: E402
from workbench.external.scorers.two_body import TwoBodyScorer  # noqa: E402

register_scorer(BlockScorer())
register_scorer(ConcaveScorer())
register_scorer(TwoBodyScorer())
register_scorer(HalfplanesScorer())
