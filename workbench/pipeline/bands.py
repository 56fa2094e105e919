"""Band checks: tolerances that are the error budget's own band (``[bands]`` of a case, ``make run`` only).

A budget row (``metrics.json["error_budget"][quantity]``) has the extrapolated value ``x`` and the band
half-width ``uncertainty |fine|``, ``uncertainty`` = gci + truncation + iterative + roundoff (+ the theory's own
uncertainty where the row has one) (:mod:`workbench.scenes.block_budget`, :mod:`workbench.scenes.concave_budget`;
a row written before issue 22 has no ``uncertainty``: gci + truncation). Three kinds of check
(``cases.schema.BAND_KINDS``):

* ``contain_theory``: ``theory_in_band`` (``|theory - x| <= band``): the FEM converges onto the theory the
  scene exists to test;
* ``exclude_alt``: ``not alt_in_band``: the band is tight enough to tell the alternative theory apart (e.g. the
  convective b/b0 against the first-order theory, the exact circle against Hertz). Where the alternative AND the
  theory both lie inside the band, the band cannot decide between them: the row is **unresolved**, which does
  not fail the check (issue 22: Hertz and the exact circle at small a/R); the check's ``unresolved`` names the
  band half-width that would separate them (``|theory - alt| / 2``) and, where the row has an order, the
  finest h_c that would give it (``h_fine (needed / band)^(1/order)``). It fails only when the alternative is
  inside and the theory is not;
* ``exclude_theory``: ``not theory_in_band``: the FEM tells the row's theory apart (e.g. Hertz with the primary
  LCP pair of a close-to-conformal contact, which the paper finds does not hold).

A listed quantity selects every row named ``q``, ``q[run]`` (block variants) or ``<step> q`` / ``<step> q[k]``
(concave steps and patches); ``q[k]`` selects the concave rows of patch k only. No row, a row without the
theory, or a band that could not be computed (NaN, null) fails the check and says why: nothing is dropped
silently.
"""

from __future__ import annotations

import re
from typing import NamedTuple

from workbench.scenes.numbers import VERDICT, declare

__all__ = ["BandCheck", "band_checks", "band_halfwidth", "band_rows"]

declare("band_checks", __name__, **{"*": VERDICT})  # a band check's verdict (workbench.scenes.numbers)


class BandCheck(NamedTuple):
    """One band check over every selected budget row.

    Attributes:
        kind: ``"contain_theory"``, ``"exclude_alt"`` or ``"exclude_theory"``.
        quantity: The listed quantity.
        passed: True when every selected row passes (and at least one row exists).
        rows: ``{row name: verdict}`` (True, False) of every selected row.
        reason: Why the check failed (empty when it passed).
        unresolved: ``{row name: what resolution it would need}`` of the ``exclude_alt`` rows whose band holds
            both the theory and the alternative (they pass: module docstring).
    """

    kind: str
    quantity: str
    passed: bool
    rows: dict
    reason: str
    unresolved: dict = {}


def band_rows(budget: dict, quantity: str) -> list[str]:
    """The budget rows of ``quantity`` (module docstring)."""
    pat = re.compile(r"(?:^|\s)" + re.escape(quantity) + r"(?:\[[^\]]*\])?$")
    return [name for name in budget if pat.search(name)]


def _verdict(kind: str, row: dict) -> tuple[bool, str]:
    if kind in ("contain_theory", "exclude_theory"):
        if row.get("theory") is None:
            return False, "no theory"
        if row.get("theory_in_band") is None:
            return False, "band undefined"
        if kind == "exclude_theory":
            return (not row["theory_in_band"]), "theory inside the band" if row["theory_in_band"] else ""
        return bool(row["theory_in_band"]), "" if row["theory_in_band"] else "theory outside the band"
    if "alt_in_band" not in row or row["alt_in_band"] is None:
        return False, "no alternative theory"
    if not row["alt_in_band"]:
        return True, ""
    if row.get("theory_in_band"):
        return True, _needed(row)
    return False, "alternative theory inside the band"


def band_halfwidth(row: dict) -> float | None:
    """The band half-width of a budget row (absolute): ``uncertainty |fine|`` (older rows: gci + truncation)."""
    if row.get("gci") is None or row.get("fine") is None:
        return None
    u = row.get("uncertainty")
    if u is None:
        u = row["gci"] + (row.get("truncation") or 0.0)
    return u * abs(row["fine"])


def _needed(row: dict) -> str:
    """What an unresolved exclusion would need: the band half-width that separates theory and alternative, and
    the h_c that the row's order predicts for it."""
    need = abs(row["theory"] - row["alt_value"]) / 2.0
    band = band_halfwidth(row)
    text = (f"unresolved: theory and {row.get('alt_theory', 'alternative')} both inside the band "
            f"+-{band:.2e}; separating them needs a band below {need:.2e}")
    order = row.get("band_order") or row.get("observed_order")
    by_h = row.get("by_h") or {}
    if order and by_h and band and need > 0:
        h_fine = min(float(h) for h in by_h)
        text += f" (h_c ~ {h_fine * (need / band) ** (1.0 / order):.3g} at order {order:.2f})"
    else:
        text += " (no order claimed: a finer grid, or a smoother quantity)"
    return text


def band_checks(bands: dict[str, tuple[str, ...]], budget: dict) -> dict[str, BandCheck]:
    """``{"<kind>:<quantity>": BandCheck}`` for every ``[bands]`` entry of a case against its budget."""
    out = {}
    for kind, quantities in bands.items():
        for q in quantities:
            names = band_rows(budget, q)
            verdicts = {n: _verdict(kind, budget[n]) for n in names}
            bad = [f"{n}: {why}" for n, (ok, why) in verdicts.items() if not ok]
            reason = "no budget row" if not names else "; ".join(bad)
            unresolved = {n: why for n, (ok, why) in verdicts.items() if ok and why}
            out[f"{kind}:{q}"] = BandCheck(kind, q, bool(names) and not bad,
                                           {n: ok for n, (ok, _) in verdicts.items()}, reason, unresolved)
    return out
