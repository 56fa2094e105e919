"""SIGINT / SIGTERM: end a run at any stage with one line, exit 130 (SIGINT) or 143 (SIGTERM).

The handlers record which signal came and raise :class:`Interrupted` (a ``KeyboardInterrupt``) in the main
thread, so every ``with`` block cleans up on the way out (staging folders removed, previous results intact).
Native code can swallow the exception: a Python callback of PETSc's SNES (residual or Jacobian assembly) that
raises makes petsc4py return PETSc error 101, and ``SNES.solve`` then raises ``petsc4py.PETSc.Error`` instead.
So the command line asks :func:`received` whatever the exception is: a run that ends with any exception after a
signal is an interrupted run. The stage (:func:`stage`) names where it was (meshing, the Newton solve, writing).

PETSc's own signal handlers are switched off (``-no_signal_handler`` in ``PETSC_OPTIONS``, set by the command
line before PETSc is imported): they would turn SIGTERM into an MPI abort without clean-up.
"""

from __future__ import annotations

import signal
import threading

__all__ = ["Interrupted", "install", "received", "stage", "current_stage", "exit_code", "message", "check"]

_state: dict = {"signum": None, "stage": "start-up"}


class Interrupted(KeyboardInterrupt):
    """SIGINT or SIGTERM arrived (``signum``)."""

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


def _handler(signum, frame) -> None:
    first = _state["signum"] is None
    if first:
        _state["signum"] = signum
    raise Interrupted(_state["signum"])


def install() -> dict:
    """Install the SIGINT and SIGTERM handlers (main thread only); returns the previous ones."""
    if threading.current_thread() is not threading.main_thread():
        return {}
    _state["signum"] = None
    return {s: signal.signal(s, _handler) for s in (signal.SIGINT, signal.SIGTERM)}


def restore(previous: dict) -> None:
    for s, h in previous.items():
        signal.signal(s, h)


def received() -> int | None:
    """The signal number that arrived since :func:`install`, or None."""
    return _state["signum"]


def check() -> None:
    """Raise :class:`Interrupted` if a signal arrived (its exception may have been swallowed by native code)."""
    if _state["signum"] is not None:
        raise Interrupted(_state["signum"])


def stage(name: str) -> None:
    """Record the stage the run is in (named in the interrupt line)."""
    _state["stage"] = name


def current_stage() -> str:
    return _state["stage"]


def exit_code(signum: int) -> int:
    """128 + the signal number: 130 for SIGINT, 143 for SIGTERM (the shell's convention)."""
    return 128 + int(signum)


def message(signum: int) -> str:
    """The one line printed for an interrupted run."""
    return (f"interrupted: {signal.Signals(signum).name} during {_state['stage']}; previous results kept, "
            "staging removed")
