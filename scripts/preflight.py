"""Checks that need the geometry, run before anything is written (bad input -> CaseError -> exit 2)."""

from __future__ import annotations

import math

from cases import Case, CaseError

__all__ = ["preflight"]


def _overlaps(des, d: float) -> bool:
    from analytic.designs import particle_at
    from analytic.lcp import find_contact_pairs

    res = find_contact_pairs(des.concave, particle_at(des, d), n_samples=300)
    return any(pr.plausible and pr.gap < 0 and 0 < pr.relative_radius < math.inf for pr in res.pairs)


def preflight(case: Case) -> None:
    """Reject loads that cannot be reached: concave displacement paths that never touch the body."""
    for run in case.runs():
        if run.geometry.scene != "concave":
            continue
        from analytic.designs import design

        des = design(run.geometry.design)
        if not _overlaps(des, run.loading.d[-1]):
            raise CaseError(
                f"{case.path.name}: variant {run.label!r}: loading.d = {list(run.loading.d)!r} never brings the "
                "particle into contact with the concave body; allowed: a largest displacement beyond first contact "
                f"(Table 1 of the paper starts at d = {min(des.table1_d)} mm)")
