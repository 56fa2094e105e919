"""The FFCx JIT cache as an interrupted or killed process leaves it (issue 34, :mod:`fem.jit_cache`).

Requirement: on a cold cache, ``make run`` (two cases at once) must not fail because another process holds a
module's claim: a live compile is waited for (up to ``WAIT_S``), a claim left by a dead process is taken over, a
claim released by a failed compile is taken at once, and an interrupt (the command line's SIGINT/SIGTERM is a
``KeyboardInterrupt``) during a compile releases its claim, so the next run compiles instead of waiting and failing
("JIT compilation timed out", measured here when a SIGTERM had hit a compile).
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

import threading
import time
from pathlib import Path

import dolfinx
import dolfinx.jit
import ffcx.compiler
import pytest
import ufl
from mpi4py import MPI

from fem.compiled_forms import compile_forms
from fem.jit_cache import POLL_S, WAIT_S


def _form(tag: float):
    """A small form whose module is new to any cache (``tag`` is a literal in it)."""
    mesh = dolfinx.mesh.create_unit_square(MPI.COMM_SELF, 2, 2)
    x = ufl.SpatialCoordinate(mesh)
    return {"f": (x[0] * x[1] + tag) * ufl.dx(domain=mesh)}


@pytest.fixture
def cache(tmp_path, monkeypatch):
    folder = tmp_path / "fenics"
    monkeypatch.setitem(dolfinx.jit.DOLFINX_DEFAULT_JIT_OPTIONS, "cache_dir",
                        (folder, dolfinx.jit.DOLFINX_DEFAULT_JIT_OPTIONS["cache_dir"][1]))
    return folder


def _module_name(tag: float, tmp_path: Path) -> str:
    """The module name of :func:`_form` (compiled once into a scratch cache)."""
    scratch = tmp_path / "scratch"
    old = dolfinx.jit.DOLFINX_DEFAULT_JIT_OPTIONS["cache_dir"]
    dolfinx.jit.DOLFINX_DEFAULT_JIT_OPTIONS["cache_dir"] = (scratch, old[1])
    try:
        compile_forms(_form(tag), comm=MPI.COMM_SELF)
    finally:
        dolfinx.jit.DOLFINX_DEFAULT_JIT_OPTIONS["cache_dir"] = old
    (c_file,) = scratch.glob("*.c")
    return c_file.stem


def _value(compiled) -> float:
    return float(dolfinx.fem.assemble_scalar(compiled["f"]))


def test_the_wait_is_long():
    assert dolfinx.jit.get_options()["timeout"] >= WAIT_S >= 300


def test_a_dead_claim_is_taken_over(cache, tmp_path, monkeypatch):
    name = _module_name(0.125, tmp_path)
    cache.mkdir()
    (cache / f"{name}.c").write_text("")  # a process killed while compiling (SIGKILL): its claim, no marker
    monkeypatch.setitem(dolfinx.jit.DOLFINX_DEFAULT_JIT_OPTIONS, "timeout", (2, ""))
    t0 = time.perf_counter()
    assert _value(compile_forms(_form(0.125), comm=MPI.COMM_SELF)) == pytest.approx(0.25 + 0.125)
    assert time.perf_counter() - t0 >= 2.0  # waited its timeout for the claim, then took it over
    assert (cache / f"{name}.c.cached").exists() and (cache / f"{name}.c.failed").exists()


def test_a_released_claim_is_taken_at_once(cache, tmp_path):
    name = _module_name(0.375, tmp_path)
    cache.mkdir()
    claim = cache / f"{name}.c"
    claim.write_text("")  # another process compiling it ...

    def fail_later():
        time.sleep(1.0)
        claim.rename(claim.with_suffix(".c.failed"))  # ... whose compile failed: FFCx releases the claim

    thread = threading.Thread(target=fail_later)
    thread.start()
    t0 = time.perf_counter()
    assert _value(compile_forms(_form(0.375), comm=MPI.COMM_SELF)) == pytest.approx(0.25 + 0.375)
    thread.join()
    assert time.perf_counter() - t0 < 2 * POLL_S + 30  # not the 600 s wait


def test_an_interrupt_during_a_compile_releases_the_claim(cache, monkeypatch):
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt  # what workbench.interrupt raises on SIGINT / SIGTERM

    with monkeypatch.context() as m:
        m.setattr(ffcx.compiler, "compile_ufl_objects", interrupted)
        with pytest.raises(KeyboardInterrupt):
            compile_forms(_form(0.625), comm=MPI.COMM_SELF)
    assert not [c for c in cache.glob("*.c") if not c.with_suffix(".c.cached").exists()]  # no claim left
    assert list(cache.glob("*.c.failed"))
    t0 = time.perf_counter()
    assert _value(compile_forms(_form(0.625), comm=MPI.COMM_SELF)) == pytest.approx(0.25 + 0.625)
    assert time.perf_counter() - t0 < 60  # compiled, not waited for
