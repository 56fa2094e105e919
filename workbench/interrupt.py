"""SIGINT / SIGTERM: end a command at any moment with one line, exit 130 (SIGINT) or 143 (SIGTERM).

The handlers record which signal came and raise :class:`Interrupted` (a ``KeyboardInterrupt``) in the main
thread, so every ``with`` block cleans up on the way out (staging folders removed, previous results intact).
Native code can swallow the exception: a Python callback of PETSc's SNES (residual or Jacobian assembly) that
raises makes petsc4py return PETSc error 101, and ``SNES.solve`` then raises ``petsc4py.PETSc.Error`` instead.
So the command line asks :func:`received` whatever the exception is: a run that ends with any exception after a
signal is an interrupted run. The stage (:func:`stage`) names where it was (meshing, the Newton solve, writing).

Where the exception is not raised at once (it is recorded, and raised at the next safe point):

* inside an import (a frame of ``importlib``): an exception in the middle of an extension module's
  initialisation leaves it half made; measured: a SIGTERM during ``import pyvista`` in the case report's
  render made the next VTK import end the process with a segmentation fault (exit -11, no line), or an
  ``ImportError`` the render reported as a second line;
* where Python would only print it ("Exception ignored in ...": a weakref callback, a ``__del__``): the
  :data:`sys.unraisablehook` takes it back and it is raised again at the next safe point;
* inside :func:`held` (the two renames of a swap);
* once the work is done (:func:`work_done`): the exit reports it (:mod:`workbench.fast_exit`).

"At the next safe point": a timer thread sends the signal to the main thread again every :data:`RETRY_S` s
(``pthread_kill``), which runs the handler again there. A second signal within :data:`RERAISE_AFTER_S` s of the
first raised exception only is recorded (the clean-up of the first is under way: a second exception there would cut
it short and print a traceback); later, it raises again (native code swallowed the first).

PETSc's own signal handlers are switched off (``-no_signal_handler`` in ``PETSC_OPTIONS``, set by the command
line before PETSc is imported): they would turn SIGTERM into an MPI abort without clean-up.

Test points (``WORKBENCH_TEST_SIGNAL_AT=<point>:<SIGINT|SIGTERM>``): the process sends itself the signal at a named
point of its exit (:func:`test_point`: ``work-done``, ``exit``, ``atexit``, ``os-exit``, ``teardown``, ``swap``) or
when it starts to import a module (``import:<module>``), so a test reaches those moments every time, not by chance.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
import time

__all__ = ["Interrupted", "early", "install", "received", "stage", "current_stage", "exit_code", "message", "check",
           "replaced", "held", "work_done", "unreported", "reported", "test_point", "RETRY_S", "RERAISE_AFTER_S"]

RETRY_S = 0.02  # seconds between two attempts to raise a recorded signal at a safe point
RERAISE_AFTER_S = 5.0  # a later signal raises again only this long after the first raised exception
TEST_ENV = "WORKBENCH_TEST_SIGNAL_AT"

_state: dict = {"signum": None, "stage": "start-up", "replaced": [], "pending": False, "raised_at": None,
                "hold": 0, "done": False, "reported": False, "timer": None, "hook": None}


class Interrupted(KeyboardInterrupt):
    """SIGINT or SIGTERM arrived (``signum``)."""

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


def _in_import(frame) -> bool:
    """Whether ``frame`` or a caller is the import machinery (``<frozen importlib._bootstrap...>``)."""
    while frame is not None:
        if frame.f_code.co_filename.startswith("<frozen importlib"):
            return True
        frame = frame.f_back
    return False


def _retry() -> None:
    """Timer thread: run the handler again in the main thread while a recorded signal waits for a safe point."""
    _state["timer"] = None
    if _state["pending"] and not _state["hold"] and not _state["done"]:
        # a real signal to the main thread (not _thread.interrupt_main): it also ends a blocking system call
        signal.pthread_kill(threading.main_thread().ident, _state["signum"])


def _defer() -> None:
    """Record that the signal's exception is still to be raised (at the next safe point)."""
    _state["pending"] = True
    if _state["hold"] or _state["done"] or _state["timer"] is not None:
        return  # held: the end of the hold raises it; done: the exit reports it
    timer = threading.Timer(RETRY_S, _retry)
    timer.daemon = True
    _state["timer"] = timer
    timer.start()


def _handler(signum, frame) -> None:
    now = time.monotonic()
    if _state["signum"] is None:
        _state["signum"] = signum
    elif not _state["pending"]:  # a later signal while the first one's exception is on its way
        if _state["done"] or (_state["raised_at"] is not None and now - _state["raised_at"] < RERAISE_AFTER_S):
            return
    if _state["done"] or _state["hold"] or _in_import(frame):
        _defer()
        return
    _state["pending"] = False
    _state["raised_at"] = now
    raise Interrupted(_state["signum"])


def _unraisable(unraisable) -> None:
    """Python could not raise it (a weakref callback, a ``__del__``): raise it again at the next safe point. After a
    signal, any other exception Python cannot raise is dropped: it comes from an object the signal's exception cut
    short (measured: pyvista's ``Renderer.__del__`` of a renderer interrupted in its ``__init__`` printed an
    ``AttributeError`` traceback after the interrupt line), and the command's outcome is the one line."""
    if isinstance(unraisable.exc_value, Interrupted):
        _state["raised_at"] = None
        _defer()
        return
    if _state["signum"] is not None:
        return
    (_state.get("unraisablehook") or sys.__unraisablehook__)(unraisable)


def early() -> None:
    """Record SIGINT and SIGTERM from the program's first line on, before the command line's modules are imported
    (``python -m workbench`` and the console command: :func:`workbench.__main__.program`); :func:`install` keeps
    what arrived, and the command's first :func:`check` raises it."""
    if threading.current_thread() is not threading.main_thread():
        return
    _state.update(signum=None, replaced=[], pending=False, raised_at=None, hold=0, done=True, reported=False,
                  early=True)
    for s in (signal.SIGINT, signal.SIGTERM):
        signal.signal(s, _handler)


def install() -> dict:
    """Install the SIGINT and SIGTERM handlers (main thread only); returns the previous ones. A signal recorded
    since :func:`early` is kept."""
    if threading.current_thread() is not threading.main_thread():
        return {}
    kept = _state["signum"] if _state.get("early") and signal.getsignal(signal.SIGINT) is _handler else None
    _state.update(signum=kept, replaced=[], pending=False, raised_at=None, hold=0, done=False, reported=False,
                  early=False)
    previous = {s: signal.signal(s, _handler) for s in (signal.SIGINT, signal.SIGTERM)}
    previous["unraisablehook"] = sys.unraisablehook
    if sys.unraisablehook is not _unraisable:
        _state["unraisablehook"] = sys.unraisablehook  # what an exception that is not ours goes to
    sys.unraisablehook = _unraisable
    _arm_import_test_point()
    return previous


def restore(previous: dict) -> None:
    """Put back the handlers :func:`install` replaced, and forget what was recorded (a call of the command line
    from Python leaves nothing behind for the next one)."""
    for s, h in previous.items():
        if s == "unraisablehook":
            sys.unraisablehook = h
        else:
            signal.signal(s, h)
    _state.update(signum=None, replaced=[], pending=False, raised_at=None, hold=0, done=False, reported=False,
                  early=False)


def received() -> int | None:
    """The signal number that arrived since :func:`install`, or None."""
    return _state["signum"]


def check() -> None:
    """Raise :class:`Interrupted` if a signal arrived (its exception may have been swallowed by native code)."""
    if _state["signum"] is not None:
        _state["pending"] = False
        raise Interrupted(_state["signum"])


@contextlib.contextmanager
def held():
    """Hold a signal's exception back inside the block (it is recorded); raise it when the block ends."""
    _state["hold"] += 1
    try:
        yield
    finally:
        _state["hold"] -= 1
    installed = signal.getsignal(signal.SIGINT) is _handler  # else the signals are not this module's to raise
    if installed and _state["pending"] and not _state["hold"] and not _state["done"]:
        _state["pending"] = False
        _state["raised_at"] = time.monotonic()
        raise Interrupted(_state["signum"])


def work_done() -> None:
    """The command's work is over (results written, or its refusal or interrupt line printed): from now on a
    signal is only recorded, and the exit reports it (:func:`unreported`)."""
    _state["done"] = True


def reported() -> None:
    """The interrupt line has been printed."""
    _state["reported"] = True


def unreported() -> int | None:
    """A signal that arrived and whose line has not been printed yet (None if none)."""
    return None if _state["reported"] else _state["signum"]


def stage(name: str) -> None:
    """Record the stage the run is in (named in the interrupt line)."""
    _state["stage"] = name


def current_stage() -> str:
    return _state["stage"]


def replaced(folder) -> None:
    """Record that ``folder`` now holds new, complete results (its swap is done): the interrupt line says so
    instead of "previous results kept" (a signal held back during the swap is raised just after it)."""
    _state["replaced"].append(str(folder))
    test_point("swap")


def exit_code(signum: int) -> int:
    """128 + the signal number: 130 for SIGINT, 143 for SIGTERM (the shell's convention)."""
    return 128 + int(signum)


def message(signum: int) -> str:
    """The one line printed for an interrupted command: the stage, and what is on disk (the previous results, or
    the new ones of the folders already swapped in: :func:`replaced`)."""
    head = f"interrupted: {signal.Signals(signum).name} during {_state['stage']}"
    done = _state["replaced"]
    if not done:
        return f"{head}; previous results kept, staging removed"
    from pathlib import Path

    names = ", ".join(dict.fromkeys(Path(f).name for f in done))
    return (f"{head}; the new results of {names[:160]} were already complete and in place (kept); anything "
            "unfinished kept its previous results, staging removed")


def _test_signal(point: str) -> int | None:
    """The signal ``$WORKBENCH_TEST_SIGNAL_AT`` asks for at ``point`` (None: not this point, or not set)."""
    spec = os.environ.get(TEST_ENV, "")
    where, _, name = spec.rpartition(":")
    if where != point or name not in ("SIGINT", "SIGTERM"):
        return None
    return int(getattr(signal, name))


def test_point(point: str) -> None:
    """Send the process the signal ``$WORKBENCH_TEST_SIGNAL_AT`` names for ``point`` (tests only; see the module
    docstring)."""
    sig = _test_signal(point)
    if sig is not None:
        os.kill(os.getpid(), sig)


def _arm_import_test_point() -> None:
    """``import:<module>``: send the signal when the import of ``<module>`` starts (an audit hook: it runs inside
    the import machinery, where the signal then lands)."""
    spec = os.environ.get(TEST_ENV, "")
    if not spec.startswith("import:") or _state["hook"] is not None:
        return
    module = spec[len("import:"):].rpartition(":")[0]
    fired: list[bool] = []

    def hook(event, args):
        if event == "import" and args and args[0] == module and not fired:
            fired.append(True)
            test_point(f"import:{module}")

    _state["hook"] = hook
    sys.addaudithook(hook)
