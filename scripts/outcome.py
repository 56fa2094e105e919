"""What a scene run hands to the report writers: its metrics and its pressure series."""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

__all__ = ["Series", "Outcome", "step_printer"]


class Series(NamedTuple):
    """One pressure curve with its analytic predictions (one plot panel, one block of CSV rows).

    Attributes:
        label: Run or step label.
        x: Surface coordinate (mm): material abscissa (block) or arc length of the undeformed concave
            surface (concave scenes).
        p: FEM contact pressure from the contact law (MPa, >= 0).
        sigma_nn: Projected normal stress -sigma_nn (MPa), for comparison.
        predictions: Prediction name -> pressure at ``x`` (MPa).
        xlabel: Axis label of ``x``.
        xlim: Plot range of ``x`` (mm).
    """

    label: str
    x: np.ndarray
    p: np.ndarray
    sigma_nn: np.ndarray
    predictions: dict
    xlabel: str
    xlim: tuple[float, float]


class Outcome(NamedTuple):
    """One FEM run of a case.

    Attributes:
        label: Run label.
        metrics: The run's entry of ``metrics.json["runs"]``.
        series: Pressure curves to plot and to write to ``pressure.csv``.
        theory: Scene-specific analytic prediction (block scenes: :class:`scripts.compare.BlockTheory`).
        result: The :class:`fem.solver.ContactResult` (for VTK output).
    """

    label: str
    metrics: dict
    series: list[Series]
    theory: Any
    result: Any


def step_printer(progress, label: str):
    """An ``on_step`` callback of :func:`fem.solver.solve_contact` that prints one line per converged solve."""

    def on_step(rec: dict) -> None:
        progress(f"[{label}] {rec.get('kind', 'step')}: d = {rec['d']:.6g} mm, P = {rec['P']:.6g} N/mm, "
                 f"{rec['iterations']} Newton its, {rec['time']:.2f} s")

    return on_step
