"""The number class of every metric, declared by the code that writes it (issue 37).

A key number (:mod:`workbench.pipeline.key_numbers`: ``"case/field..."``) is compared by its class
(:mod:`workbench.pipeline.number_classes`: ``verdict``, ``roundoff``, ``iterations``, ``mesh``, ``theory``,
``physics``, ``error``, ``mesh_sensitive``, ``estimate``, ``excluded``), its kind (which foreign-mesh tolerance:
``load``, ``peak``, ``width`` ...) and its scale (what a move is measured on: ``self``, ``unit``, ``contact_size``,
``run_load``, ``run_peak``). The module that writes a metric declares these beside it with :func:`declare`, by the
section of ``metrics.json`` the metric sits in and its name:

=================  ===========================================================  =========================
section            where in ``metrics.json``                                     written by
=================  ===========================================================  =========================
``case``           a top-level number (``P``, ``pass``)                          the pipeline (run_case)
``case_errors``    ``errors/<name>``: the worst over the runs and the judge's    the scenes' ``judge``
``analytic``       ``analytic/<name>``: the judge's case-level values            the scenes' ``judge``
``band_checks``    ``band_checks/<name>``                                        the pipeline (bands)
``budget``         ``error_budget/<row>/<field>``: a row's values by its          the scenes' budgets
                   quantity (the row name's last word, ``[...]`` dropped)
``budget_fields``  ``error_budget/<row>/<field>``: the row's other fields         the budget rows
``run``            ``runs/<label>/<name>`` (a list's items too)                  :class:`~workbench.scenes.
                                                                                 base.SolveMetrics`, the scenes
``run_errors``     ``runs/<label>/errors/<name>``                                the scenes' ``compare``
``patch``          ``runs/<label>/patches/<i>/<name>``                           :class:`~workbench.scenes.
                                                                                 base.SolveMetrics`
``step``           ``runs/<label>/steps/<i>/<name>``                             the concave scenes
``fingerprint``    ``runs/<label>/mesh_fingerprint/<name>[/...]``                the pipeline (run_case)
=================  ===========================================================  =========================

The name ``"*"`` declares a section's default (e.g. every ``errors/...`` is an ``error`` of unit scale unless its own
name is declared). Declaring a name twice with another class is an error at import (two writers would disagree).
"""

from __future__ import annotations

from typing import NamedTuple

__all__ = ["DECLARED", "SECTIONS", "Number", "declare", "declared"]

SECTIONS = ("case", "case_errors", "analytic", "band_checks", "budget", "budget_fields", "run", "run_errors", "patch",
            "step", "fingerprint")


class Number(NamedTuple):
    """The class of one metric: ``cls`` (comparison class), ``kind`` (foreign-mesh tolerance kind, "" for none),
    ``scale`` (what a move is measured on; :mod:`workbench.pipeline.number_classes`)."""

    cls: str
    kind: str = ""
    scale: str = "self"


# The classes the writers use most (shared so that two writers of one name cannot disagree by a typo).
VERDICT = Number("verdict")
ROUNDOFF = Number("roundoff", scale="unit")
ITERATIONS = Number("iterations", scale="unit")
MESH = Number("mesh")
EXCLUDED = Number("excluded")
THEORY = Number("theory")
FRACTION_THEORY = Number("theory", scale="unit")     # a theory value that is a fraction (0 in a limit)
LOAD = Number("physics", "load")
PEAK = Number("physics", "peak")
WIDTH = Number("physics", "width")
DISPLACEMENT = Number("physics", "displacement")
ERROR = Number("error", "error", "unit")             # an error against theory, a fraction of its reference
MESH_SENSITIVE = Number("mesh_sensitive")
ESTIMATE = Number("estimate")

DECLARED: dict[str, dict[str, Number]] = {s: {} for s in SECTIONS}


def declare(section: str, where: str, **numbers: Number) -> None:
    """Declare the class of the metrics ``numbers`` (name -> :class:`Number`; ``"*"`` via ``**{"*": ...}``: the
    section's default) that the module ``where`` writes into ``section`` (:data:`SECTIONS`)."""
    if section not in DECLARED:
        raise ValueError(f"{where}: number section {section!r} is not one of {SECTIONS}")
    table = DECLARED[section]
    for name, number in numbers.items():
        old = table.get(name)
        if old is not None and old != number:
            raise ValueError(f"{where}: {section}/{name} declared as {number} but already as {old}")
        table[name] = number


def declared(section: str, name: str) -> Number | None:
    """The declared class of ``name`` in ``section``, else the section's default, else None."""
    table = DECLARED[section]
    return table.get(name, table.get("*"))
