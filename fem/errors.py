"""The solver's error type and PETSc's names of SNES converged reasons."""

from __future__ import annotations

__all__ = ["ContactSolveError", "snes_reason_name"]


class ContactSolveError(RuntimeError):
    """A nonlinear contact solve failed (after cut-backs); the message names case, step and SNES reason."""


def snes_reason_name(reason: int) -> str:
    """PETSc's name of a SNES converged reason (e.g. -5 -> ``DIVERGED_MAX_IT``)."""
    from petsc4py import PETSc

    names = {v: k for k, v in vars(PETSc.SNES.ConvergedReason).items() if k.isupper() and isinstance(v, int)}
    return names.get(int(reason), f"UNKNOWN_{int(reason)}")
