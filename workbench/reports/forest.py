"""The forest plot's data: every case's judged quantities as value over theory, with their bands (issue 37).

Pure data, no matplotlib (the drawing is :mod:`workbench.reports.forest_plot`). Every row is one judged quantity
of one case, normalised by its theory so that all rows share one axis with the theory at 1:

    ratio = value / theory,    band = half-width / |theory|    (the interval [ratio - band, ratio + band]).

Where the rows come from (``results/<case>/metrics.json``, nothing is recomputed):

* **A case with an error budget** (``make run``): the rows its band checks select
  (``metrics.json["band_checks"][check]["rows"]``, :mod:`workbench.pipeline.bands`), each with the budget row's
  ``extrapolated`` value, band ``uncertainty |fine|`` (older rows: gci + truncation), ``theory`` and ``alt_value``
  (``metrics.json["error_budget"][row]``). A row passes when every band check that selects it passes. A budget
  with no band checks gives its rows with a theory, not judged (``passed`` None).
* **A case without a budget** (CI level, ``--ci``): its tolerance checks of one value against its theory
  (:data:`VALUE_CHECKS`), at the fine (only) grid and with no band; the case's own verdict of that check
  (``value / theory - 1`` against the tolerance, per run where the runs record it). The sign comes from
  ``analytic["<check>_fem"] / analytic["<check>_converged"]`` (b/b0) or a run's ``analytic["signed"]`` when it
  reproduces the checked error; where only the checked error ``|value / theory - 1|`` is recorded the row is drawn
  at ``1 + error`` with ``signed`` False (say so in the picture). An RMS, the load balance or an iteration count
  is no value against a theory: it stays in the summary's table.

A row whose value or theory is missing, NaN or zero (no normalisation) keeps its place with ``ratio`` None and
the reason in ``note``: nothing is dropped silently.
"""

from __future__ import annotations

import math
from typing import NamedTuple

__all__ = ["VALUE_CHECKS", "ForestRow", "case_forest_rows", "forest_caption", "forest_rows"]

VALUE_CHECKS = ("p_max", "half_width", "half_width_moment", "b_over_b0", "b_over_b0_moment")
"""The tolerance checks that compare one measured value with its theory (a CI-level forest row each)."""

_SIGN_TOL = 1e-9  # a recorded signed deviation reproduces the checked error to this (relative) agreement
_THEORY_KEYS = {"p_max": ("p_max", "p0", "p_ref")}  # where a run's analytic record keeps a check's theory value


class ForestRow(NamedTuple):
    """One judged quantity of one case, over its theory.

    Attributes:
        case: The case name.
        quantity: The budget row's name (``b_over_b0_moment``, ``p_max[theta=pi/20]``, ``load_symmetry``) or, at
            CI level, the check's name (with ``[run]`` when the case has several runs).
        ratio: value / theory (the extrapolated value with a budget, the fine value without); None if undefined.
        band: The band's half-width over |theory| (None: no band, CI level or undefined).
        passed: The verdict of the checks that judge the row (None: not judged).
        kinds: Which checks judge it: ``contain_theory``, ``exclude_alt``, ``exclude_theory`` (band checks) or
            ``tolerance`` (with its relative tolerance in ``tolerance``).
        alt_ratio: The alternative theory over the theory (an exclusion's other theory), or None.
        signed: False when only ``|value / theory - 1|`` is recorded (the row sits at ``1 + error``).
        tolerance: The tolerance of a CI-level check (relative), else None.
        note: Why ``ratio`` or ``band`` is undefined, that an exclusion is unresolved (its band holds both
            theories: it passes, :mod:`workbench.pipeline.bands`), or "".
    """

    case: str
    quantity: str
    ratio: float | None
    band: float | None
    passed: bool | None
    kinds: tuple[str, ...]
    alt_ratio: float | None = None
    signed: bool = True
    tolerance: float | None = None
    note: str = ""

    @property
    def has_band(self) -> bool:
        """True for a budget row whose band is defined."""
        return self.band is not None

    @property
    def interval(self) -> tuple[float, float] | None:
        """(low, high) of the band over the theory, or None."""
        if self.ratio is None or self.band is None:
            return None
        return self.ratio - self.band, self.ratio + self.band


def _finite(v) -> float | None:
    """``v`` as a float when it is a finite number, else None (None, NaN, a string)."""
    if isinstance(v, bool) or not isinstance(v, int | float):
        return None
    return float(v) if math.isfinite(v) else None


def _band(row: dict) -> float | None:
    """The absolute band half-width of a budget row (:func:`workbench.pipeline.bands.band_halfwidth`'s rule)."""
    gci, fine = _finite(row.get("gci")), _finite(row.get("fine"))
    if gci is None or fine is None:
        return None
    u = _finite(row.get("uncertainty"))
    if u is None:
        u = gci + (_finite(row.get("truncation")) or 0.0)
    return u * abs(fine)


def _budget_row(case: str, name: str, row: dict, *, passed: bool | None, kinds: tuple[str, ...]) -> ForestRow:
    theory = _finite(row.get("theory"))
    value = _finite(row.get("extrapolated"))
    if theory is None or theory == 0.0:
        why = "no theory" if theory is None else "theory 0: no ratio"
        return ForestRow(case, name, None, None, passed, kinds, note=why)
    if value is None:
        return ForestRow(case, name, None, None, passed, kinds, note="extrapolated value undefined")
    band = _band(row)
    alt = _finite(row.get("alt_value"))
    return ForestRow(case, name, value / theory, None if band is None else band / abs(theory), passed, kinds,
                     alt_ratio=None if alt is None else alt / theory,
                     note="" if band is not None else f"band undefined ({row.get('status', '?')})")


def _row_names(rows) -> list[str]:
    """The row names of a band check's ``rows`` (a dict of verdicts; a list in hand-written metrics)."""
    return list(rows) if isinstance(rows, dict | list | tuple) else []


def _budget_rows(case: str, m: dict) -> list[ForestRow]:
    budget = m.get("error_budget") or {}
    checks = m.get("band_checks") or {}
    judged: dict[str, dict] = {}  # row name -> {"ok": [...], "kinds": [...]} in the checks' order
    for key, c in checks.items():
        rows = c.get("rows") or {}
        kind = c.get("kind") or str(key).split(":", 1)[0]
        for name in _row_names(rows):
            ok = rows[name] if isinstance(rows, dict) else c.get("passed")
            j = judged.setdefault(name, {"ok": [], "kinds": [], "unresolved": False})
            j["ok"].append(bool(ok))
            j["unresolved"] |= name in (c.get("unresolved") or {})
            if kind not in j["kinds"]:
                j["kinds"].append(kind)
    if judged:
        out = []
        for name, j in judged.items():
            row = _budget_row(case, name, budget.get(name) or {}, passed=all(j["ok"]), kinds=tuple(j["kinds"]))
            if j["unresolved"] and not row.note:  # passes, but the band holds the alternative theory too
                row = row._replace(note="unresolved: the band holds the theory and the alternative")
            out.append(row)
        return out
    return [_budget_row(case, name, r, passed=None, kinds=()) for name, r in budget.items()
            if isinstance(r, dict) and _finite(r.get("theory")) not in (None, 0.0)]


def _signed(err: float, candidates) -> tuple[float, bool]:
    """``(value / theory - 1, signed)``: the first candidate signed deviation that reproduces ``err``."""
    for s in candidates:
        s = _finite(s)
        if s is not None and abs(abs(s) - err) <= _SIGN_TOL * max(err, 1e-300) + 1e-15:
            return s, True
    return err, False


def _run_deviations(run: dict, k: str) -> list:
    """Candidate signed deviations ``value / theory - 1`` of check ``k`` in one run's record: its
    ``analytic["signed"][k]``, then its measured value (``k`` or ``patch_k``) over every theory value its analytic
    record keeps (the record itself and its sub-records, e.g. ``exact_circle``). :func:`_signed` keeps the one that
    reproduces the checked error, so a candidate of another theory is never taken."""
    an = run.get("analytic") or {}
    out = [(an.get("signed") or {}).get(k)]
    for d in (an, *[v for v in an.values() if isinstance(v, dict)]):
        for tk in _THEORY_KEYS.get(k, (k,)):
            t = _finite(d.get(tk))
            for v in (_finite(run.get(k)), _finite(run.get(f"patch_{k}"))):
                if t not in (None, 0.0) and v is not None:
                    out.append(v / t - 1.0)
    return out


def _ci_rows(case: str, m: dict) -> list[ForestRow]:
    errors, tol, checks = m.get("errors") or {}, m.get("tolerances") or {}, m.get("checks") or {}
    checked, an, runs = m.get("checked_errors") or {}, m.get("analytic") or {}, m.get("runs") or []
    out = []
    for k in VALUE_CHECKS:
        if k not in checks:
            continue
        e, t = checked.get(k, k), _finite(tol.get(k))
        fem, theory = _finite(an.get(f"{k}_fem")), _finite(an.get(f"{k}_converged"))
        if fem is not None and theory not in (None, 0.0):  # a case-level ratio (b/b0) with both values recorded
            out.append(ForestRow(case, k, fem / theory, None, bool(checks[k]), ("tolerance",), tolerance=t))
            continue
        per_run = [(r.get("label", str(i)), _finite((r.get("errors") or {}).get(e)), r)
                   for i, r in enumerate(runs) if isinstance(r, dict) and e in (r.get("errors") or {})]
        if not per_run:  # the case-level error only
            err = _finite(errors.get(e))
            out.append(ForestRow(case, k, None if err is None else 1.0 + err, None, bool(checks[k]), ("tolerance",),
                                 signed=False, tolerance=t, note="" if err is not None else "error undefined"))
            continue
        for label, err, r in per_run:
            name = k if len(runs) == 1 else f"{k}[{label}]"
            if err is None:
                out.append(ForestRow(case, name, None, None, False, ("tolerance",), tolerance=t,
                                     note="error undefined"))
                continue
            dev, signed = _signed(err, _run_deviations(r, k))
            ok = bool(checks[k]) if t is None else err <= t
            out.append(ForestRow(case, name, 1.0 + dev, None, ok, ("tolerance",), signed=signed, tolerance=t))
    return out


def case_forest_rows(case: str, m: dict) -> list[ForestRow]:
    """The forest rows of one case's metrics (module docstring): its budget's judged rows, else its CI checks."""
    return _budget_rows(case, m) if m.get("error_budget") else _ci_rows(case, m)


def forest_rows(metrics: dict[str, dict]) -> list[ForestRow]:
    """The forest rows of every case of ``metrics`` (case name -> metrics.json), in the cases' order."""
    return [row for name, m in metrics.items() for row in case_forest_rows(name, m)]


def forest_caption(rows: list[ForestRow]) -> str:
    """The caption under the figure: what a marker, a bar and a colour mean, and which rows have no band."""
    no_band = sorted({r.case for r in rows if r.band is None and "tolerance" in r.kinds})
    unsigned = [f"{r.case} {r.quantity}" for r in rows if not r.signed]
    text = ("Every judged quantity of every case over its theory (theory = 1; symmetric-log scale of the deviation). "
            "Circles with a bar: the extrapolated value of the error budget and its band (`make run`); the band "
            "check passes when the bar holds the theory (an `exclude_*` check: when it does not hold that theory). "
            "Green: the verdict passes, red: it fails, grey: not judged; x: the row's alternative theory (an "
            "`exclude_alt` check needs it outside the bar).")
    if no_band:
        text += (" Squares, no band: cases without an error budget (CI level: " + ", ".join(no_band)
                 + "), the fine value against the theory, the check's tolerance shaded around 1.")
    if unsigned:
        text += (" Hollow squares: only |value/theory - 1| is recorded, drawn above 1 (" + ", ".join(unsigned)
                 + ").")
    return text
