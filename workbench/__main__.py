"""``python -m workbench`` is the same as the console command ``workbench``.

The guard matters under ``mpiexec -n N python -m mpi4py.futures -m workbench <study>``: each worker rank runs
this module once under the name ``__worker__`` (as multiprocessing's spawn does) and must not start the CLI.
"""

import sys

from workbench.cli import main

if __name__ == "__main__":
    sys.exit(main())
