"""The workbench's own runs written as an external result: the csv schema of :mod:`workbench.external.results`, so
that ``workbench score`` judges the workbench's own solver with exactly the code it judges another one with (the
round-trip tests, the model bands of :mod:`workbench.external.models`, and ``external compare``).

One group per reported step of a run (:func:`workbench.external.scorers.runs.schedule`): a displacement-controlled
run's snapshots (one per ``record_at`` displacement), else its final state (step 0). A group holds the slave surface's
samples (the facet quadrature points, :class:`measures.contact.SurfaceSamples`) at their reference positions
``x_mm = X1``, ``y_mm = X2``, the contact law's pressure ``p_MPa``, its argument ``q_MPa``, the quadrature weight
``weight_mm`` and the run's virtual-work load ``P_N_per_mm`` (full body). Half models are written as they are
(x >= 0): the scorer mirrors them. A finite-strain run's pressure (force per deformed length) is written per
reference length, ``p dx1/dX1`` (the surface stretch from the samples' current positions, :func:`numpy.gradient`),
the schema's convention. Numbers have 17 significant digits (the csv round-trips every double). Units: mm, N/mm, MPa.
"""

from __future__ import annotations

import csv
import io

import numpy as np

from workbench.external.results import ExternalResult

__all__ = ["COLUMNS", "outcome_groups", "groups_csv", "reference_pressure"]

COLUMNS = ("run", "step", "body", "x_mm", "y_mm", "p_MPa", "q_MPa", "weight_mm", "P_N_per_mm")


def reference_pressure(samples, *, finite: bool) -> np.ndarray:
    """The pressure per reference length (MPa): as sampled for small strain; a finite-strain run's Cauchy pressure
    times the stretch dx1/dX1 of the (flat) surface at each sample."""
    if not finite:
        return np.asarray(samples.p, dtype=float)
    X1, x1 = samples.X[:, 0], samples.x[:, 0]
    order = np.argsort(X1, kind="stable")
    stretch = np.empty_like(X1)
    stretch[order] = np.gradient(x1[order], X1[order])
    return np.asarray(samples.p, dtype=float) * stretch


def _group(samples, *, P: float, label: str, step: int, body: str, path: str, finite: bool) -> ExternalResult:
    X = np.asarray(samples.X, dtype=float)
    return ExternalResult(path, X[:, 0].copy(), reference_pressure(samples, finite=finite), float(P), None, False,
                          weight=np.asarray(samples.weight, dtype=float), q=np.asarray(samples.q, dtype=float),
                          run=label, step=step, body=body, y=X[:, 1].copy())


def outcome_groups(outcome, *, label: str, body: str, path: str = "workbench") -> list[ExternalResult]:
    """The groups of one :class:`workbench.scenes.base.Outcome` (module docstring): run ``label``, slave ``body``."""
    result = outcome.result
    finite = outcome.run.solver.kinematics == "finite"
    if outcome.run.loading.control == "displacement" and result.snapshots:
        return [_group(snap.samples, P=snap.P, label=label, step=i, body=body, path=path, finite=finite)
                for i, snap in enumerate(result.snapshots)]
    return [_group(result.samples, P=result.P, label=label, step=0, body=body, path=path, finite=finite)]


def groups_csv(groups: list[ExternalResult]) -> str:
    """The csv text of groups (:data:`COLUMNS`; ``y_mm`` empty where a group has none)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(COLUMNS)
    for g in groups:
        y = g.y if g.y is not None else [None] * g.x.size
        q = g.q if g.q is not None else g.p
        wt = g.weight if g.weight is not None else [None] * g.x.size
        for i in range(g.x.size):
            w.writerow([g.run, g.step, g.body, repr(float(g.x[i])), "" if y[i] is None else repr(float(y[i])),
                        repr(float(g.p[i])), repr(float(q[i])), "" if wt[i] is None else repr(float(wt[i])),
                        repr(float(g.load))])
    return buf.getvalue()
