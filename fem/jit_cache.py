"""The FFCx JIT cache as several processes and an interrupted one leave it: wait long, never wait for the dead.

FFCx claims a module by creating ``<cache>/<module>.c`` exclusively, compiles it, and marks it ready with
``<module>.c.cached``; another process that finds the claim waits for the marker, one second at a time, for
dolfinx's jit option ``timeout`` (10 s by default), then raises "JIT compilation timed out". Two ways this broke
runs on a cold cache (measured here, issue 34):

* **A live compile longer than the wait.** ``make run`` solves two cases at once; on a loaded machine one
  compiling a form the other needs took more than 10 s, and the other failed. :func:`configure` sets the wait to
  :data:`WAIT_S`.
* **A dead claim.** FFCx releases its claim (renames it ``.c.failed``) on an ``Exception`` only. A SIGINT or
  SIGTERM during a compile is the command line's :class:`workbench.interrupt.Interrupted`, a ``KeyboardInterrupt``,
  so the claim stayed, and every later run that needed the module waited and failed (``make run``: two cases,
  "JIT compilation timed out, probably due to a failed previous compile"). :func:`configure` wraps FFCx's compile
  step so that any exception releases the claim; a claim left by a killed process (SIGKILL, a crash) is taken over
  when the wait for it runs out: it is renamed ``.c.failed`` (as FFCx names a failed compile) and compiled again.
  A waiter looks every :data:`POLL_S` seconds whether the claim is still there: one released by a failed compile
  is claimed at once (and the compile's own error reported), not waited for.

Both wrappers keep FFCx's behaviour otherwise (the same arguments, return values and files). They are installed
once per process by :func:`configure`, which every module that compiles forms calls at import.
"""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["WAIT_S", "configure", "release_claim"]

WAIT_S = 600
"""Seconds a process waits for another's compile of the same module (a compile takes seconds; 600 s is dead)."""

POLL_S = 5
"""Seconds between looks at a claim being waited for: a claim released by a failed compile is taken at once."""


def release_claim(cache_dir, module_name: str) -> bool:
    """Rename an unfinished claim ``<module>.c`` (no ``.c.cached`` marker) to ``<module>.c.failed``; True if one was
    released."""
    c_file = Path(cache_dir) / f"{module_name}.c"
    if c_file.with_suffix(".c.cached").exists():
        return False
    try:
        os.replace(c_file, c_file.with_suffix(".c.failed"))
    except FileNotFoundError:
        return False
    return True


def configure() -> None:
    """Install the wait and the two claim wrappers (idempotent; see the module docstring)."""
    import dolfinx.jit
    import ffcx.codegeneration.jit as fj

    opts = dolfinx.jit.DOLFINX_DEFAULT_JIT_OPTIONS
    if opts["timeout"][0] < WAIT_S:
        opts["timeout"] = (WAIT_S, opts["timeout"][1])
    if not getattr(fj._compile_objects, "_workbench_releases", False):
        fj._compile_objects = _releasing(fj._compile_objects)
    if not getattr(fj.get_cached_module, "_workbench_takes_over", False):
        fj.get_cached_module = _taking_over(fj.get_cached_module)


def _releasing(compile_objects):
    def compile_releasing(decl, ufl_objects, object_names, module_name, options, cache_dir, *args, **kwargs):
        try:
            return compile_objects(decl, ufl_objects, object_names, module_name, options, cache_dir, *args, **kwargs)
        except BaseException:  # an interrupt too: FFCx itself releases the claim on an Exception only
            release_claim(cache_dir, module_name)
            raise

    compile_releasing._workbench_releases = True  # type: ignore[attr-defined]
    for attr in ("_workbench_counted",):  # keep a counting wrapper's mark (workbench.studies.executor)
        if getattr(compile_objects, attr, False):
            setattr(compile_releasing, attr, True)
    return compile_releasing


def _taking_over(get_cached_module):
    def get_or_take_over(module_name, object_names, cache_dir, timeout):
        waited = 0
        while True:
            step = max(1, min(POLL_S, int(timeout) - waited))
            try:
                return get_cached_module(module_name, object_names, cache_dir, step)
            except TimeoutError:
                waited += step
                if not (Path(cache_dir) / f"{module_name}.c").exists():
                    continue  # released by its compiler (a failed compile): claim and compile it here
                if waited >= timeout and not release_claim(cache_dir, module_name):
                    raise

    get_or_take_over._workbench_takes_over = True  # type: ignore[attr-defined]
    return get_or_take_over
