"""The PETSc log events the benchmark counts around a solve, and what the report reads from them (plain data: the
report layer imports this, not the measuring code)."""

from __future__ import annotations

__all__ = ["LOG_EVENTS", "factor_solves"]

LOG_EVENTS = ("MatLUFactorSym", "MatLUFactorNum", "MatSolve", "MatMatSolve", "SNESJacobianEval", "SNESFunctionEval")


def factor_solves(events: dict) -> int:
    """Passes through a factor (or, GAMG, its coarse-grid solver) in the log counts ``events`` ({name: {"count":
    n, ...}}): PETSc's MatSolve events plus its MatMatSolve events (several right-hand sides in one pass: the
    force-controlled Newton's z and w, :mod:`fem.force_newton`)."""
    return sum(int((events.get(name) or {}).get("count", 0)) for name in ("MatSolve", "MatMatSolve"))
