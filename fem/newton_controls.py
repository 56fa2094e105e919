"""What the load stepper asks of every contact problem's Newton solve (:class:`fem.stepping.LoadStepper`).

A contact problem (the rigid obstacle's :class:`fem.problem.ContactProblem`, the two bodies'
:class:`fem.two_body.problem.TwoBodyProblem`) owns a PETSc SNES (``self.snes``), its options
(``self.options.max_it``), a Newton solve ``newton()`` and a context ``prescribed_active_set(zones)``; this mixin
adds the two controls built on them, the same for every partner.
"""

from __future__ import annotations

from collections.abc import Sequence
from contextlib import contextmanager

__all__ = ["NewtonControls"]


class NewtonControls:
    """Mixin: temporary iteration limits and the prescribed-active-set predictor iteration."""

    @contextmanager
    def max_iterations(self, n: int):
        """Temporarily limit the SNES to ``n`` iterations."""
        self.snes.setTolerances(max_it=n)
        try:
            yield
        finally:
            self.snes.setTolerances(max_it=self.options.max_it)

    def predictor_iteration(self, zones: Sequence[tuple[float, float]]) -> None:
        """One Newton iteration with the prescribed active set ``lo_k < X1 < hi_k``; the law is the true one
        afterwards."""
        with self.prescribed_active_set(zones), self.max_iterations(1):
            self.newton()
