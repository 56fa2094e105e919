"""What every scene's scorer shares: the protocol, a level's common measures, the grid study of one quantity, the
plausibility rules before a verdict, and the match against the workbench's model bands.

A scorer (one per scene, :mod:`workbench.external.scorers`) turns the samples of one (run, step, body) of one level
into a JSON-ready *level record* (:func:`level_record` fills the common keys: the file, its sizes, the load) with
``quantities`` (name -> value, the numbers the grid study extrapolates), and the level records of a case into
*studies* (:func:`study`: one quantity over the three finest levels, :func:`workbench.error_budget.grid_study`).

The study of a quantity f on levels h1 < h2 < h3 (the three finest of its group): the grid study's extrapolated value
f_ext, observed order, GCI (relative) and named status; ``band`` = GCI |f1| (absolute); ``load_term``: the part of
the uncertainty the level's load carries (the relative load balance |P_integral - P| / P of the finest level times
the quantity's sensitivity to P, e.g. 1/2 for Hertz's p0 ~ sqrt(P)); ``uncertainty`` = band + load_term |f1|;
``deviation`` = f_ext - theory; ``outside_band`` = |deviation| > band, and then ``remainder`` = what the band does not
explain. Units: those of the quantity (ratios are dimensionless; the concave loads N/mm, widths mm).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import NamedTuple, Protocol, runtime_checkable

import numpy as np

from measures.contact import SurfaceSamples, find_patches, trapezoid_weights
from workbench.external.results import ExternalResult, ResultError

__all__ = ["ScoreError", "SceneScorer", "Patches", "samples_of", "main_patch", "level_record", "study", "by_group",
           "three_finest", "plausibility", "HALF_WIDTH_FACTOR", "SPACING_TIE", "fmt_order", "group_key"]

HALF_WIDTH_FACTOR = 2.0  # a level's contact half-width within this factor of the theory's at its load
SPACING_TIE = 0.1  # sample spacings closer than this (relative) do not rank two levels
LOAD_FACTOR_DISPLACEMENT = 2.0  # displacement control: one step's loads over the levels within this factor


class ScoreError(ValueError):
    """Bad input to the scorer (one line)."""


@runtime_checkable
class SceneScorer(Protocol):
    """The protocol of a scene's scorer (see :mod:`workbench.external.scorers`)."""

    scene: str

    def check(self, case) -> None:
        """ScoreError (one line) for a case of the scene that cannot be judged; called before any file is read."""

    def runs(self, case):
        """The benchmark runs (:func:`workbench.external.scorers.runs.benchmark_runs`)."""

    def target_load(self, run) -> float | None:
        """A force-controlled run's target load (N/mm), else None."""

    def bodies(self, case):
        """The bodies whose contact pressure a result may give (:class:`runs.ScoredBody`)."""

    def symmetric(self, case) -> bool:
        """Whether a half model (samples at x >= 0) is mirrored about x = 0."""

    def check_surface(self, case, run, res) -> None:
        """ResultError (one line) when the samples do not lie on the case's contact surface."""

    def measure(self, case, group, *, h: float | None, samples_per_element: int) -> dict:
        """The level record of one group (:func:`level_record` + ``quantities``, ``theory``, ``errors``)."""

    def studies(self, case, records: list[dict]) -> dict:
        """Study key -> study row (:func:`study`) of the case's level records."""

    def main_key(self, case, studies: dict) -> str | None:
        """The study the verdict reads first (None: none was made)."""


class Patches(NamedTuple):
    """The contact patches of a group's samples and its main one (the largest load)."""

    all: list
    main: object


def samples_of(x: np.ndarray, p: np.ndarray, w: np.ndarray, q: np.ndarray, *, X: np.ndarray | None = None
               ) -> SurfaceSamples:
    """Surface samples of an external result (``s`` = x; positions in the reference configuration)."""
    z = np.zeros_like(x)
    pos = np.column_stack([x, z]) if X is None else X
    return SurfaceSamples(s=x, X=pos, x=pos, p=p, q=q, sigma_nn=p, gap=z, weight=w)


def weights_of(res: ExternalResult) -> np.ndarray:
    """The file's quadrature weights (mm), else trapezoid weights in x."""
    return trapezoid_weights(res.x) if res.weight is None else res.weight


def main_patch(res: ExternalResult) -> Patches:
    """The patches of a (flat-surface) group and the one carrying the largest load; ResultError if none."""
    w = weights_of(res)
    q = res.p if res.q is None else res.q
    patches = find_patches(samples_of(res.x, res.p, w, q))
    if not patches:
        raise ResultError(f"{res.path}: no contact patch (no positive pressure between two samples)")
    return Patches(patches, max(patches, key=lambda pt: pt.P))


def level_record(res: ExternalResult, *, P_integral: float, center: float, half_width: float,
                 s: np.ndarray | None = None, h: float | None, samples_per_element: int) -> dict:
    """The common keys of a level record: file, sizes, sample spacing inside the patch ``center +- half_width``
    (in the surface coordinate ``s``, default x), the load (the file's column, else ``P_integral``; ResultError
    unless finite and > 0)."""
    s = res.x if s is None else s
    if not (math.isfinite(P_integral) and P_integral > 0):
        raise ResultError(f"{res.path}: the pressure integrates to P = {P_integral:.6g} N/mm; allowed: a finite load "
                          "> 0 (all weights 0? pressures in MPa?)")
    P = res.load if res.load is not None else P_integral
    inside = np.sort(s[np.abs(s - center) <= half_width])
    dx = np.diff(inside)
    spacing = float(np.median(dx)) if dx.size else math.nan
    if h is not None:
        h_val, h_source = h, "option --h"
    elif res.h is not None:
        h_val, h_source = res.h, "column h_mm"
    else:
        h_val = spacing * samples_per_element
        h_source = f"estimated: median sample spacing in the patch x {samples_per_element} sample(s) per element"
    return {"file": res.path, "run": res.run, "step": res.step, "body": res.body, "half_model": res.half,
            "configuration": res.configuration, "samples": int(res.x.size), "merged_samples": int(res.merged),
            "spacing": spacing, "h": h_val, "h_source": h_source, "P": P,
            "P_source": "file" if res.load is not None else "integral", "P_integral": P_integral}


def group_key(rec: dict) -> tuple:
    return (rec["run"], rec["step"], rec["body"])


def by_group(records: list[dict]) -> dict[tuple, list[dict]]:
    """Level records by (run, step, body), each list sorted fine first (by h)."""
    out: dict[tuple, list[dict]] = {}
    for rec in records:
        out.setdefault(group_key(rec), []).append(rec)
    return {k: sorted(v, key=lambda r: r["h"]) for k, v in out.items()}


def three_finest(levels: list[dict]) -> list[dict]:
    """The three finest level records (fine first); ScoreError unless their sizes h differ and are > 0."""
    fine = levels[:3]
    hs = tuple(lv["h"] for lv in fine)
    if len(set(hs)) < 3 or not all(math.isfinite(v) and v > 0 for v in hs):
        raise ScoreError(f"the three finest levels need three different sizes h > 0, got {hs}; give --h")
    return fine


def study(hs, values, *, formal: float, theory: float | None, theory_name: str, label: str,
          alt: tuple[str, float] | None = None, load_term: float = 0.0, group: dict | None = None) -> dict:
    """The grid study of one quantity (module docstring); ``hs`` and ``values`` fine first."""
    from workbench.error_budget import grid_study

    ref = theory if theory is not None and math.isfinite(theory) else None
    gs = grid_study(tuple(hs), tuple(values), expected_order=formal, reference=ref, formal_order=formal)
    band = gs.gci * abs(gs.fine)
    row = gs._asdict() | {"label": label, "h": list(hs), "ratios": list(values), "band": band,
                          "load_term": load_term, "uncertainty": band + load_term * abs(gs.fine),
                          "theory": ref, "theory_name": theory_name, "group": group or {}}
    if ref is not None:
        dev = gs.extrapolated - ref
        row |= {"deviation": dev, "outside_band": bool(abs(dev) > band),
                "remainder": math.copysign(abs(dev) - band, dev) if abs(dev) > band else 0.0}
    if alt is not None and alt[1] is not None and math.isfinite(alt[1]):
        row |= {"alt_theory": alt[0], "alt_value": alt[1],
                "alt_in_band": bool(abs(alt[1] - gs.extrapolated) <= row["uncertainty"])}
    return row


def plausibility(records: list[dict], studies: dict, *, main: str | None, control: str,
                 load_tolerance: float | None) -> list[str]:
    """Why no verdict may be given (empty: a verdict may be given), the rules of issue 35 for every scene:

    * a level whose contact half-width (a record's ``half_width_ratio``: its edge over the theory's at its load) is
      off by more than a factor :data:`HALF_WIDTH_FACTOR` (positions in m among mm?);
    * one (run, step)'s loads over the levels: force control within twice ``load_tolerance`` (the case's p_max
      tolerance, default 0.5 %: p0 goes as sqrt(P)); displacement control within a factor
      :data:`LOAD_FACTOR_DISPLACEMENT` (its load is a result, but not three orders of magnitude apart);
    * sizes h (given) that rank two levels of one group against their sample spacings;
    * the main study: diverging, a band not finite or not narrower than the quantity, an extrapolation not finite.
    """
    reasons = []
    for lv in records:
        ratio = lv.get("half_width_ratio")
        if ratio is not None and not (math.isfinite(ratio) and 1.0 / HALF_WIDTH_FACTOR <= ratio <= HALF_WIDTH_FACTOR):
            reasons.append(f"{Path(lv['file']).name}: its contact half-width {lv['half_width']:.4g} mm is "
                           f"{ratio:.3g} times the theory's at its load {lv['P']:.6g} N/mm (allowed: within a factor "
                           f"{HALF_WIDTH_FACTOR:g}; positions in mm and pressures in MPa?)")
    for (run, step, _body), levels in by_group(records).items():
        loads = [lv["P"] for lv in levels]
        if len(loads) < 2:
            continue
        spread = max(loads) / min(loads) - 1.0
        where = "" if run is None else f" (run {run}, step {step})"
        if control == "force":
            allowed = 2.0 * (load_tolerance if load_tolerance else 0.005)
            if spread > allowed:
                reasons.append(f"the levels' loads differ by {spread:.3%} ({min(loads):.6g} to "
                               f"{max(loads):.6g} N/mm{where}); the case allows {allowed:.2%} (twice its p_max "
                               "tolerance: p0 goes as sqrt(P)), so they are not one problem at several resolutions")
        elif spread > LOAD_FACTOR_DISPLACEMENT - 1.0:
            reasons.append(f"the levels' loads differ by a factor {max(loads) / min(loads):.3g} "
                           f"({min(loads):.6g} to {max(loads):.6g} N/mm{where}; allowed: within a factor "
                           f"{LOAD_FACTOR_DISPLACEMENT:g} at one displacement): not one problem (units?)")
        given = [lv for lv in levels if not lv["h_source"].startswith("estimated")]
        inverted = next(((a, b) for a in given for b in given if a["h"] < b["h"]
                         and math.isfinite(a["spacing"]) and math.isfinite(b["spacing"])
                         and a["spacing"] > (1.0 + SPACING_TIE) * b["spacing"]), None)
        if inverted is not None:
            a, b = inverted
            reasons.append(f"the sizes h rank {Path(a['file']).name} (h = {a['h']:.4g} mm) finer than "
                           f"{Path(b['file']).name} (h = {b['h']:.4g} mm), but its samples are "
                           f"{a['spacing'] / b['spacing']:.3g} times wider apart: h does not decrease with the levels "
                           "(--h in reverse order?)")
    reasons = list(dict.fromkeys(reasons))
    s = studies.get(main) if main else None
    if s is not None:
        if s["status"] == "diverging":
            reasons.append("the three finest levels diverge (their differences grow on refinement): no order, no "
                           "extrapolation")
        if not (math.isfinite(s["band"]) and s["band"] < abs(s["fine"])):
            reasons.append(f"the discretisation band +-{s['band']:.4g} is not finite or not narrower than the "
                           f"quantity ({s['fine']:.4g})")
        if not math.isfinite(s["extrapolated"]):
            reasons.append("the extrapolated value is not finite")
    return reasons


def fmt_order(v) -> str:
    return "-" if v is None or not math.isfinite(v) else f"{v:.3g}"
