"""Run a gmsh build in a forked child process, so SIGINT / SIGTERM stop it within milliseconds.

gmsh meshes in native code that does not return to Python for as long as the mesh takes (minutes for a
large one), so a Python signal handler in the same process would only run afterwards. The parent instead
waits on a pipe; a signal's exception interrupts that wait at once, the child is killed (SIGKILL) and reaped,
and its temporary files are removed by the caller. The child returns its result (or its exception) pickled
through the pipe and leaves with ``os._exit`` (no MPI finalisation, no atexit handlers of the parent).

Measured (``tests/test_signals.py``): SIGTERM during a 10 s gmsh build ends the run in well under a second.
"""

from __future__ import annotations

import os
import pickle
import signal
from collections.abc import Callable
from typing import Any

__all__ = ["run_in_child", "MeshChildError"]


class MeshChildError(RuntimeError):
    """The gmsh child process died without a result (killed, e.g. out of memory, or crashed)."""


def run_in_child(fn: Callable[[int], Any]) -> Any:
    """``fn(child_pid)`` run in a forked child; returns its result or re-raises its exception here.

    ``fn`` receives the child's pid (temporary file names use it). With other Python threads running (a
    caller that is a thread pool), ``fn`` runs in this process instead (a fork could deadlock on their locks).
    On any exception in the parent (SIGINT,
    SIGTERM) the child is killed and reaped before the exception propagates.
    """
    import threading
    import warnings

    if threading.active_count() > 1:  # other Python threads may hold locks the child would wait for: in-process
        return fn(os.getpid())
    ppid = os.getpid()
    r, w = os.pipe()
    with warnings.catch_warnings():  # native helper threads (MPI) hold no lock the child needs: it runs gmsh only
        warnings.simplefilter("ignore", DeprecationWarning)
        pid = os.fork()
    if pid == 0:  # child
        status = 0
        try:
            os.close(r)
            for s in (signal.SIGINT, signal.SIGTERM):
                signal.signal(s, signal.SIG_DFL)
            _die_with_parent(ppid)
            try:
                res = ("ok", fn(os.getpid()))
            except BaseException as exc:  # noqa: BLE001 - handed to the parent
                res = ("err", exc)
            try:
                data = pickle.dumps(res)
            except Exception as exc:  # noqa: BLE001 - an unpicklable exception: its text
                data = pickle.dumps(("err", RuntimeError(f"{type(res[1]).__name__}: {res[1]}"[:2000])
                                     if res[0] == "err" else exc))
            with os.fdopen(w, "wb") as f:
                f.write(data)
        except BaseException:  # noqa: BLE001
            status = 1
        finally:
            os._exit(status)
    os.close(w)
    done = False
    try:
        with os.fdopen(r, "rb") as f:
            data = f.read()
        _, status = os.waitpid(pid, 0)
        done = True
    finally:
        if not done:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            os.waitpid(pid, 0)
    if not data:
        why = (f"killed by {signal.Signals(os.WTERMSIG(status)).name}" if os.WIFSIGNALED(status)
               else f"exit status {os.waitstatus_to_exitcode(status)}")
        raise MeshChildError(f"the gmsh process ended without a mesh ({why}; out of memory?)")
    kind, value = pickle.loads(data)
    if kind == "err":
        raise value
    return value


def _die_with_parent(ppid: int) -> None:
    """Linux: the child gets SIGKILL when the parent dies (a SIGKILLed run leaves no gmsh behind)."""
    try:
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGKILL))  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass
    if os.getppid() != ppid:  # the parent died before prctl
        os._exit(1)
