"""Leave a finished ``workbench run`` process without the interpreter's teardown (issue 27, point 5).

After a run every result is written and closed; what is left at exit is CPython freeing its modules one by one
(scipy, dolfinx, PETSc, gmsh, ...) and the C-level hooks of mpi4py and petsc4py (``MPI_Finalize``,
``PetscFinalize``). Measured here on a CI-level ``hertz_cylinder --no-pictures`` run: 0.1-0.25 s of a 0.9-2 s
process (the more loaded the machine, the more). :func:`exit_now` flushes stdout and stderr, runs the Python
``atexit`` handlers (``tempfile`` and ``weakref.finalize`` clean-ups among them), then ends the process with the
exit code at once (``os._exit``).

It does so only where nothing can be lost (:func:`fast_exit_allowed`): the ``run``, ``score``, ``export`` and
``external`` commands of the program itself (not a call of :func:`workbench.cli.main` from Python), not under an MPI
launcher (``mpiexec``: every rank must reach ``MPI_Finalize``) nor an ``mpi4py.futures`` pool, with no PETSc option
that reports at ``PetscFinalize`` (anything in ``PETSC_OPTIONS`` beyond the command line's own
``-no_signal_handler``), and without coverage measurement (it saves its data at exit). ``WORKBENCH_FULL_EXIT=1``
turns it off.

A signal during the exit (issue 35: a SIGINT 2.90 s into a 3.08 s run ended it with a segmentation fault and no
line) ends it with one line and 130 or 143 like a signal at any other moment: once the work is done the signal
is only recorded (:func:`workbench.interrupt.work_done`), and :func:`finish` reports it, after the ``atexit``
handlers, just before ``os._exit``. Where the interpreter's teardown runs instead (:func:`fast_exit_allowed`
false), :func:`at_teardown`, the last ``atexit`` handler, reports it the same way (and ends the process there,
except under an MPI launcher, where every rank must reach ``MPI_Finalize``: the line is printed and the exit code
stays the command's); a signal after it, in the module teardown and ``MPI_Finalize``, is ignored.
"""

from __future__ import annotations

import atexit
import os
import signal
import sys

from workbench import interrupt

__all__ = ["FAST_EXIT_COMMANDS", "MPI_LAUNCHER_ENV", "at_teardown", "exit_now", "fast_exit_allowed", "finish"]

FAST_EXIT_COMMANDS = ("run", "score", "export", "external")
"""The commands that may end with :func:`exit_now`."""

MPI_LAUNCHER_ENV = ("PMI_RANK", "PMI_SIZE", "PMIX_RANK", "OMPI_COMM_WORLD_SIZE", "MPI_LOCALNRANKS")
"""Environment variables an MPI launcher (MPICH's hydra, PMIx, Open MPI) sets in the processes it starts."""


def fast_exit_allowed(command: str | None, *, environ=None, modules=None) -> bool:
    """Whether a program that ran ``command`` may end with :func:`exit_now` (see the module docstring)."""
    environ = os.environ if environ is None else environ
    modules = sys.modules if modules is None else modules
    if command not in FAST_EXIT_COMMANDS or environ.get("WORKBENCH_FULL_EXIT", "") not in ("", "0"):
        return False
    if any(k in environ for k in MPI_LAUNCHER_ENV) or "mpi4py.futures" in modules or "coverage" in modules:
        return False
    if set(environ.get("PETSC_OPTIONS", "").split()) - {"-no_signal_handler"}:
        return False
    mpi = modules.get("mpi4py.MPI")
    return mpi is None or mpi.COMM_WORLD.Get_size() == 1


_fast: list[bool] = []  # set by exit_now


def _flush() -> None:
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe or stream: nothing more can reach it
            pass


def _with_signal(code: int) -> int:
    """``code``, or 128 + the signal that arrived during the exit (its one line printed here)."""
    signum = interrupt.unreported()
    if signum is None:
        return int(code)
    try:
        print(interrupt.message(signum), file=sys.stderr)
    except (OSError, ValueError):
        pass
    interrupt.reported()
    return interrupt.exit_code(signum)


def exit_now(code: int) -> None:
    """Flush stdout and stderr, run the ``atexit`` handlers, and end the process with ``code`` (no teardown), or
    with 130 / 143 and one line if a signal arrived during the exit."""
    _flush()
    _fast.append(True)  # at_teardown (an atexit handler) leaves the report to the lines below
    interrupt.test_point("atexit")
    atexit._run_exitfuncs()
    interrupt.test_point("os-exit")
    code = _with_signal(code)
    _flush()
    os._exit(code)


def finish(code: int, command: str | None) -> int:
    """End the program that ran ``command``: :func:`exit_now` where :func:`fast_exit_allowed`, else return
    ``code`` to the interpreter's teardown (:func:`at_teardown` reports a signal there)."""
    interrupt.test_point("exit")
    if fast_exit_allowed(command):
        exit_now(code)
    return code


def at_teardown() -> None:
    """The last ``atexit`` handler of the program (registered first): a signal that arrived during the exit is
    reported in one line and ends the process with 130 / 143 (not under MPI: see the module docstring); then
    SIGINT and SIGTERM are ignored for the rest of the teardown."""
    if _fast:
        return
    interrupt.test_point("teardown")
    if interrupt.unreported() is not None:
        code = _with_signal(0)
        if not _under_mpi() and "coverage" not in sys.modules:  # coverage saves its data after this handler
            _flush()
            os._exit(code)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)


def _under_mpi() -> bool:
    """Started by an MPI launcher, or one of several MPI ranks."""
    if any(k in os.environ for k in MPI_LAUNCHER_ENV):
        return True
    mpi = sys.modules.get("mpi4py.MPI")
    return mpi is not None and mpi.COMM_WORLD.Get_size() > 1
