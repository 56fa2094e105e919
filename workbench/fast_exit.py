"""Leave a finished ``workbench run`` process without the interpreter's teardown (issue 27, point 5).

After a run every result is written and closed; what is left at exit is CPython freeing its modules one by one
(scipy, dolfinx, PETSc, gmsh, ...) and the C-level hooks of mpi4py and petsc4py (``MPI_Finalize``,
``PetscFinalize``). Measured here on a CI-level ``hertz_cylinder --no-pictures`` run: 0.1-0.25 s of a 0.9-2 s
process (the more loaded the machine, the more). :func:`exit_now` flushes stdout and stderr, runs the Python
``atexit`` handlers (``tempfile`` and ``weakref.finalize`` clean-ups among them), then ends the process with the
exit code at once (``os._exit``).

It does so only where nothing can be lost (:func:`fast_exit_allowed`): the ``run`` command of the program itself
(not a call of :func:`workbench.cli.main` from Python), not under an MPI launcher (``mpiexec``: every rank must
reach ``MPI_Finalize``) nor an ``mpi4py.futures`` pool, with no PETSc option that reports at ``PetscFinalize``
(anything in ``PETSC_OPTIONS`` beyond the command line's own ``-no_signal_handler``), and without coverage
measurement (it saves its data at exit). ``WORKBENCH_FULL_EXIT=1`` turns it off.
"""

from __future__ import annotations

import atexit
import os
import sys

__all__ = ["FAST_EXIT_COMMANDS", "MPI_LAUNCHER_ENV", "exit_now", "fast_exit_allowed"]

FAST_EXIT_COMMANDS = ("run",)
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


def exit_now(code: int) -> None:
    """Flush stdout and stderr, run the ``atexit`` handlers, and end the process with ``code`` (no teardown)."""
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe or stream: nothing more can reach it
            pass
    atexit._run_exitfuncs()
    os._exit(int(code))
