"""Band checks: tolerances that are the error budget's own band (``[bands]`` of a case, ``make run`` only).

A budget row (``metrics.json["error_budget"][quantity]``) has the extrapolated value ``x``, the relative GCI
and truncation, and the band half-width ``(gci + truncation) |fine|`` (:mod:`workbench.pipeline.budget`,
:mod:`workbench.scenes.concave_budget`). Two kinds of check (``cases.schema.BAND_KINDS``):

* ``contain_theory``: ``theory_in_band`` (``|theory - x| <= band``): the FEM converges onto the theory the
  scene exists to test;
* ``exclude_alt``: ``not alt_in_band``: the band is tight enough to tell the alternative theory apart (e.g. the
  convective b/b0 against the first-order theory, the exact circle against Hertz);
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

__all__ = ["BandCheck", "band_checks", "band_rows"]


class BandCheck(NamedTuple):
    """One band check over every selected budget row.

    Attributes:
        kind: ``"contain_theory"``, ``"exclude_alt"`` or ``"exclude_theory"``.
        quantity: The listed quantity.
        passed: True when every selected row passes (and at least one row exists).
        rows: ``{row name: verdict}`` (True, False) of every selected row.
        reason: Why the check failed (empty when it passed).
    """

    kind: str
    quantity: str
    passed: bool
    rows: dict
    reason: str


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
    return (not row["alt_in_band"]), "" if not row["alt_in_band"] else "alternative theory inside the band"


def band_checks(bands: dict[str, tuple[str, ...]], budget: dict) -> dict[str, BandCheck]:
    """``{"<kind>:<quantity>": BandCheck}`` for every ``[bands]`` entry of a case against its budget."""
    out = {}
    for kind, quantities in bands.items():
        for q in quantities:
            names = band_rows(budget, q)
            verdicts = {n: _verdict(kind, budget[n]) for n in names}
            bad = [f"{n}: {why}" for n, (ok, why) in verdicts.items() if not ok]
            reason = "no budget row" if not names else "; ".join(bad)
            out[f"{kind}:{q}"] = BandCheck(kind, q, bool(names) and not bad,
                                           {n: ok for n, (ok, _) in verdicts.items()}, reason)
    return out
