"""Where a study's points run: one shared point runner and two executors (issue 27).

A study is a typed config plus a list of points (picklable records); :func:`run_points` hands the points to an
executor and returns one record per point, in the points' order, each with where it ran:

* ``local`` (default): a process pool on this machine (``spawn``), ``workers`` processes; ``workers = 1`` runs the
  points in this process, one after the other (no pool: what a timing study wants on a quiet core).
* ``mpi``: an ``mpi4py.futures`` pool of the MPI ranks the study was started on, without any dynamic process
  spawn (disabled or hanging on several cluster MPIs)::

      mpiexec -n 9 python -m mpi4py.futures -m workbench validity     # 1 master + 8 workers

  Under ``python -m mpi4py.futures`` with more than one rank, ``mpi`` is the default; started any other way,
  ``--executor mpi`` is refused (exit 2) instead of spawning.

Every point runs in a worker on ``MPI.COMM_SELF`` (its mesh and forms are its own): the worker initialises PETSc
on ``COMM_SELF`` before dolfinx is imported. PETSc's default ``PETSC_COMM_WORLD`` is ``MPI_COMM_WORLD``, which in
an ``mpi4py.futures`` pool holds the master too, so ``import dolfinx`` on a worker hung in PETSc's initialisation
(measured here: mpiexec -n 3, the first task never returned).

JIT compiles without races: each worker process compiles its FFCx forms into its own cache folder, a *slot*
``<jit cache>/<host>-<i>`` that it holds with an exclusive ``flock`` for its life (:func:`claim_jit_slot`); a later
worker (next run, next study) takes a free slot and finds the forms compiled there. No two processes ever compile
into the same folder, so FFCx never waits for another's compile: the 10-s ``JIT compilation timed out`` of the
shared cache cannot happen. The jit cache is ``$WORKBENCH_JIT_CACHE``, else ``<XDG_CACHE_HOME or ~/.cache>/
fenics-workbench`` (put it on a node-local disk on a cluster). Before each point a slot takes every finished module
of the shared cache (dolfinx's own, ``$XDG_CACHE_HOME/fenics``) it lacks, and after a point that compiled it gives
its new modules back (:func:`share_modules`: hard links, FFCx's claim file first and its ready marker last), so on a
cold cache a form is compiled once, not once per worker (issue 34). The runner still retries a point that reports a JIT
time-out (at most :data:`JIT_RETRIES` times) and counts it: every study's summary prints the count (0 expected).

Each point record gains ``worker``: executor, host, MPI rank (0 for local processes), pid, jit slot, forms
compiled during the point (``jit_compiles``: FFCx cache misses in that worker), JIT retries and the point's wall
time (s).
"""

from __future__ import annotations

import contextlib
import errno
import os
import shutil
import socket
import sys
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

__all__ = ["EXECUTORS", "JIT_RETRIES", "ExecutorChoice", "add_executor_options", "claim_jit_slot", "share_modules",
           "executor_from_args", "jit_cache_root", "mpi_pool_size", "petsc_on_self", "run_point", "run_points",
           "worker_summary"]

EXECUTORS = ("local", "mpi")
JIT_RETRIES = 2  # a point that still reports a JIT time-out after these retries keeps its error
_JIT_TIMEOUT = "JIT compilation timed out"


@dataclass(frozen=True)
class ExecutorChoice:
    """How a study runs its points.

    Attributes:
        kind: ``local`` or ``mpi``.
        workers: Local processes (``local``; 1: in this process); for ``mpi`` the pool's ranks (size - 1).
    """

    kind: str = "local"
    workers: int = 1

    def __post_init__(self) -> None:
        if self.kind not in EXECUTORS:
            raise ValueError(f"--executor = {self.kind!r} is not allowed; allowed: {', '.join(EXECUTORS)}")
        if isinstance(self.workers, bool) or not isinstance(self.workers, int) or not 1 <= self.workers <= 4096:
            raise ValueError(f"--workers = {self.workers!r} is not allowed; allowed: a whole number in [1, 4096]")


def mpi_pool_size() -> int | None:
    """Workers of the ``python -m mpi4py.futures`` pool this process is the master of (None: not started so)."""
    if "mpi4py.futures" not in sys.modules:  # only ``python -m mpi4py.futures`` (or a pool user) loaded it
        return None
    from mpi4py.futures import _core

    if _core.SharedPool is None:
        return None
    from mpi4py import MPI

    return max(MPI.COMM_WORLD.Get_size() - 1, 1)  # -n 1: mpi4py runs the tasks in a thread of the master


def add_executor_options(parser, *, workers: int) -> None:
    """``--executor local|mpi`` and ``--workers N`` (local processes) on a study's argument parser."""
    parser.add_argument("--executor", default=None, choices=EXECUTORS,
                        help="where the points run: local processes (default) or the ranks of "
                             "`mpiexec -n N python -m mpi4py.futures -m workbench ...` (default there)")
    parser.add_argument("--workers", type=int, default=workers,
                        help=f"local processes (default {workers}; 1: in this process)")


def executor_from_args(args) -> ExecutorChoice:
    """The executor of parsed ``--executor``/``--workers``.

    Raises:
        ValueError: one line naming the option and what is allowed (the study exits 2, nothing written).
    """
    local = ExecutorChoice("local", args.workers)  # --workers is checked whichever executor runs
    pool = mpi_pool_size()
    kind = args.executor or ("mpi" if pool is not None and pool > 0 and _world_size() > 1 else "local")
    if kind == "mpi":
        if pool is None:
            raise ValueError("--executor mpi needs the MPI ranks of `mpiexec -n N python -m mpi4py.futures -m "
                             "workbench ...` (N >= 2: 1 master + N-1 workers); allowed without it: --executor "
                             "local (dynamic process spawn is not used)")
        petsc_on_self()  # the master too: a later import of dolfinx here must not wait for the busy workers
        return ExecutorChoice("mpi", pool)
    return local


def _world_size() -> int:
    from mpi4py import MPI

    return MPI.COMM_WORLD.Get_size()


# --- the worker side ------------------------------------------------------------------------------------------


def jit_cache_root() -> Path:
    """The parent of the workers' JIT slots: ``$WORKBENCH_JIT_CACHE``, else ``<XDG_CACHE_HOME|~/.cache>/
    fenics-workbench``."""
    given = os.environ.get("WORKBENCH_JIT_CACHE")
    if given:
        return Path(given).expanduser()
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache").expanduser() / "fenics-workbench"


_STATE: dict = {}  # this process's worker state: slot, its lock file, the compile counter


def claim_jit_slot(root: Path | None = None, *, limit: int = 4096) -> Path:
    """Take the first free JIT slot ``<root>/<host>-<i>`` of this host (an exclusive ``flock`` held until this
    process exits) and point dolfinx's JIT cache at it; returns the slot folder. Idempotent per process."""
    import fcntl

    if "slot" in _STATE:
        return _STATE["slot"]
    root = jit_cache_root() if root is None else Path(root)
    root.mkdir(parents=True, exist_ok=True)
    host = socket.gethostname().split(".")[0] or "host"
    for i in range(limit):
        slot = root / f"{host}-{i}"
        fd = os.open(root / f"{host}-{i}.lock", os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            os.close(fd)
            continue
        slot.mkdir(exist_ok=True)
        import dolfinx.jit

        shared, doc = dolfinx.jit.DOLFINX_DEFAULT_JIT_OPTIONS["cache_dir"]
        _STATE.update(slot=slot, lock_fd=fd, shared=Path(shared))
        dolfinx.jit.DOLFINX_DEFAULT_JIT_OPTIONS["cache_dir"] = (slot, doc)
        return slot
    raise RuntimeError(f"no free JIT slot among {limit} in {root}")


def petsc_on_self() -> None:
    """Make ``MPI.COMM_SELF`` PETSc's world in this process, before PETSc is first imported (after: nothing to do).

    In an ``mpi4py.futures`` pool ``MPI_COMM_WORLD`` holds the master and every worker; PETSc's initialisation on
    it is collective, so a process importing dolfinx alone waits for ever (measured: mpiexec -n 3, the first
    task never returned)."""
    opts = os.environ.get("PETSC_OPTIONS", "")
    if "-no_signal_handler" not in opts:  # as the CLI: Python's signal handlers, not PETSc's MPI_Abort
        os.environ["PETSC_OPTIONS"] = (opts + " -no_signal_handler").strip()
    import dolfinx_solver  # noqa: F401  (MPI ordering, before petsc4py/dolfinx)

    import petsc4py
    from mpi4py import MPI

    if "petsc4py.PETSc" not in sys.modules:
        petsc4py.init(sys.argv[:1], comm=MPI.COMM_SELF)


def _init_worker() -> None:
    """Once per worker process: PETSc on COMM_SELF, the JIT slot, the compile counter."""
    if _STATE.get("ready"):
        return
    petsc_on_self()
    from mpi4py import MPI

    claim_jit_slot()
    _count_compiles()
    _STATE.update(ready=True, rank=MPI.COMM_WORLD.Get_rank(), host=MPI.Get_processor_name())


def _count_compiles() -> None:
    """Count FFCx cache misses (calls of its private ``_compile_objects``; left alone if FFCx renames it)."""
    import ffcx.codegeneration.jit as fj

    _STATE["compiles"] = 0
    inner = getattr(fj, "_compile_objects", None)
    if inner is None or getattr(inner, "_workbench_counted", False):
        return

    def counted(*args, **kwargs):
        _STATE["compiles"] += 1
        return inner(*args, **kwargs)

    counted._workbench_counted = True  # type: ignore[attr-defined]
    fj._compile_objects = counted


def share_modules(src: Path, dst: Path) -> int:
    """Hard-link (or copy) every finished FFCx module of the cache folder ``src`` that ``dst`` lacks; returns how
    many. A module is finished when FFCx's ready marker ``<name>.c.cached`` exists; its ``<name>.c`` is linked first
    (FFCx's own claim: a process that finds it waits for the marker, a concurrent claimant skips), then its
    compiled ``.so``, then the marker. So a worker's slot starts with what the shared cache (dolfinx's own,
    ``$XDG_CACHE_HOME/fenics``) has, and gives back what it compiled: on a cold cache a form is compiled once per
    study and test run, not once per worker and run."""
    if not src.is_dir():
        return 0
    dst.mkdir(parents=True, exist_ok=True)
    have = {e.name for e in os.scandir(dst)}
    files = [e.name for e in os.scandir(src)]
    libs = {f.split(".", 1)[0]: f for f in files if f.endswith(".so")}
    n = 0
    for ready in (f for f in files if f.endswith(".c.cached")):
        name = ready[: -len(".c.cached")]
        if name not in libs or f"{name}.c" in have:
            continue
        try:
            _link(src / f"{name}.c", dst / f"{name}.c")
        except OSError:  # FileExistsError: claimed meanwhile by a compiling process or another sharer
            continue
        try:
            _link(src / libs[name], dst / libs[name])
            _link(src / ready, dst / ready)
            n += 1
        except OSError:  # leave no claim without its module: FFCx would wait for it, then compile again
            for f in (dst / f"{name}.c", dst / libs[name]):
                with contextlib.suppress(OSError):
                    f.unlink()
    return n


def _link(src: Path, dst: Path) -> None:
    """``dst`` as a hard link of ``src`` (a copy across file systems); FileExistsError if it exists."""
    try:
        os.link(src, dst)
    except OSError as exc:
        if isinstance(exc, FileExistsError) or exc.errno not in (errno.EXDEV, errno.EPERM, errno.EMLINK):
            raise
        fd = os.open(dst, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
        with os.fdopen(fd, "wb") as out, open(src, "rb") as inp:
            shutil.copyfileobj(inp, out)


def _jit_timed_out(rec) -> bool:
    return isinstance(rec, dict) and _JIT_TIMEOUT in str(rec.get("error"))


def run_point(fn: Callable, point, kind: str):
    """The shared point runner (in the worker): ``fn(point)``, retried after a JIT time-out, with ``worker``."""
    _init_worker()
    before, retries = _STATE.get("compiles", 0), 0
    t0 = time.perf_counter()
    share_modules(_STATE["shared"], _STATE["slot"])  # what the shared cache has, this slot need not compile
    while True:
        try:
            rec = fn(point)
        except Exception as exc:  # noqa: BLE001  (a JIT time-out raised rather than recorded)
            if _JIT_TIMEOUT not in str(exc) or retries == JIT_RETRIES:
                raise
            retries += 1
            continue
        if not _jit_timed_out(rec) or retries == JIT_RETRIES:
            break
        retries += 1
    if _STATE.get("compiles", 0) > before:  # compiled here: given back to the shared cache
        share_modules(_STATE["slot"], _STATE["shared"])
    where = {"executor": kind, "host": _STATE["host"], "rank": _STATE["rank"], "pid": os.getpid(),
             "jit_slot": _STATE["slot"].name, "jit_compiles": _STATE.get("compiles", 0) - before,
             "jit_retries": retries, "wall_s": time.perf_counter() - t0}
    if isinstance(rec, dict):
        return rec | {"worker": where}
    return rec, where


# --- the master side ------------------------------------------------------------------------------------------


def _pool(choice: ExecutorChoice):
    if choice.kind == "mpi":
        from mpi4py.futures import MPIPoolExecutor

        return MPIPoolExecutor()
    from concurrent.futures import ProcessPoolExecutor
    from multiprocessing import get_context

    return ProcessPoolExecutor(max_workers=choice.workers, mp_context=get_context("spawn"))


def run_points(fn: Callable, points: Sequence, *, executor: ExecutorChoice, chunksize: int = 1,
               progress: Callable[[int, int, object], None] | None = None) -> list:
    """Run ``fn(point)`` for every point on ``executor``; the results in the points' order.

    Args:
        fn: A module-level function (picklable) of one point returning a dict (gains ``worker``) or any value
            (then ``(value, worker)``).
        points: Picklable points.
        executor: Where they run.
        chunksize: Points sent to a worker at a time.
        progress: Called with (done, total, the point's result) after each point, in the points' order.
    """
    os.environ.setdefault("OMP_NUM_THREADS", "1")  # inherited by the local pool (mpiexec: set it in the job)
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    total, out = len(points), []
    if executor.kind == "local" and executor.workers == 1:
        results: Iterable = (run_point(fn, p, "local") for p in points)
        for i, r in enumerate(results, 1):
            out.append(r)
            if progress:
                progress(i, total, r)
        return out
    with _pool(executor) as pool:
        for i, r in enumerate(pool.map(run_point, [fn] * total, points, [executor.kind] * total,
                                       chunksize=max(1, chunksize)), 1):
            out.append(r)
            if progress:
                progress(i, total, r)
    return out


def worker_summary(records: Iterable[dict]) -> dict:
    """Where the points ran: per ``host:rank:pid`` the points and their summed wall time (s); the forms compiled
    on workers and the JIT retries in all."""
    per: dict = {}
    compiles = retries = 0
    executor = None
    for r in records:
        w = r.get("worker") if isinstance(r, dict) else None
        if not w:
            continue
        executor = w["executor"]
        key = f"{w['host']}:{w['rank']}:{w['pid']}"
        e = per.setdefault(key, {"host": w["host"], "rank": w["rank"], "pid": w["pid"], "points": 0,
                                 "wall_s": 0.0, "jit_compiles": 0})
        e["points"] += 1
        e["wall_s"] += w["wall_s"]
        e["jit_compiles"] += w["jit_compiles"]
        compiles += w["jit_compiles"]
        retries += w["jit_retries"]
    return {"executor": executor, "workers": list(per.values()), "jit_compiles": compiles, "jit_retries": retries}
