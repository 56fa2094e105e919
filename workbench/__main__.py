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
    _matplotlib_config()
    from workbench.cli import main

    return main()


def _matplotlib_config() -> None:
    """Nothing in the home folder: matplotlib creates ``~/.config/matplotlib`` (its config folder) when it is
    missing; then it is pointed at its cache folder instead (``<XDG_CACHE_HOME or ~/.cache>/matplotlib``, where it
    keeps its font cache anyway). A user's existing config folder or ``MPLCONFIGDIR`` is left as it is."""
    import os
    from pathlib import Path

    if os.environ.get("MPLCONFIGDIR"):
        return
    config = Path(os.environ.get("XDG_CONFIG_HOME") or Path.home() / ".config") / "matplotlib"
    if not config.exists():
        cache = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
        os.environ["MPLCONFIGDIR"] = str(cache / "matplotlib")


if __name__ == "__main__":
    sys.exit(program())
