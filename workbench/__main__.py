"""``python -m workbench`` is the same as the console command ``workbench`` (both call :func:`program`).

The guard matters under ``mpiexec -n N python -m mpi4py.futures -m workbench <study>``: each worker rank runs
this module once under the name ``__worker__`` (as multiprocessing's spawn does) and must not start the CLI.
"""

import sys


def program() -> int:
    """The program: SIGINT / SIGTERM are recorded from here on (:func:`workbench.interrupt.early`, before the
    command line's modules are imported), then :func:`workbench.cli.main` runs the command."""
    from workbench import interrupt

    interrupt.early()
    from workbench.cli import main

    return main()


if __name__ == "__main__":
    sys.exit(program())
