"""Where a signal's exception is raised (issue 35; :mod:`workbench.interrupt`), in-process and deterministic.

Requirements: a signal that lands inside an import is raised only once the import has finished (the module is
complete; a half-initialised VTK extension module crashed the next import); one that lands in a ``__del__`` or a
weakref callback (where Python only prints "Exception ignored") is raised again in the main thread, with nothing
printed; one inside :func:`workbench.interrupt.held` is raised when the block ends; a second signal within
``RERAISE_AFTER_S`` of the first raised exception does not cut its clean-up short; after ``work_done`` a signal
is only recorded, for the exit to report. The real command line at those moments: tests/test_issue35_reproducers.py.
"""

from __future__ import annotations

import gc
import importlib
import os
import signal
import sys
import time

import pytest

from workbench import interrupt


@pytest.fixture
def handlers():
    previous = interrupt.install()
    yield
    interrupt.restore(previous)


def _wait_for_interrupt(seconds: float = 5.0) -> None:
    """Run Python bytecode until the deferred exception lands (the timer resends the signal every RETRY_S)."""
    t_end = time.monotonic() + seconds
    while time.monotonic() < t_end:
        sum(range(100))
    raise AssertionError(f"no Interrupted within {seconds} s")


def test_a_signal_inside_an_import_waits_for_the_import_to_finish(handlers, tmp_path, monkeypatch):
    (tmp_path / "signalled_during_import.py").write_text(
        "import os, signal\nos.kill(os.getpid(), signal.SIGINT)\nsteps = []\nfor i in range(1000):\n"
        "    steps.append(i)\nCOMPLETE = True\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    with pytest.raises(interrupt.Interrupted) as exc:
        importlib.import_module("signalled_during_import")
        _wait_for_interrupt()
    assert exc.value.signum == signal.SIGINT
    module = sys.modules.pop("signalled_during_import")
    assert module.COMPLETE and len(module.steps) == 1000  # the whole module body ran


def test_a_signal_in_a_destructor_is_raised_again_in_the_main_thread(handlers, capsys):
    class Signals:
        def __del__(self):
            os.kill(os.getpid(), signal.SIGTERM)
            sum(range(10))  # the handler runs here, inside __del__: Python could only print its exception

    with pytest.raises(interrupt.Interrupted) as exc:
        Signals()
        gc.collect()
        _wait_for_interrupt()
    assert exc.value.signum == signal.SIGTERM
    assert "Exception ignored" not in capsys.readouterr().err


def test_a_signal_inside_held_is_raised_when_the_block_ends(handlers):
    done = []
    with pytest.raises(interrupt.Interrupted):
        with interrupt.held():
            os.kill(os.getpid(), signal.SIGINT)
            for _ in range(1000):
                sum(range(10))
            done.append(True)
    assert done == [True]


def test_a_second_signal_does_not_cut_the_clean_up_of_the_first(handlers):
    cleaned = []
    with pytest.raises(interrupt.Interrupted):
        try:
            os.kill(os.getpid(), signal.SIGINT)
            _wait_for_interrupt()
        finally:
            os.kill(os.getpid(), signal.SIGINT)  # within RERAISE_AFTER_S of the first: recorded only
            sum(range(1000))
            cleaned.append(True)
    assert cleaned == [True] and interrupt.received() == signal.SIGINT


def test_after_the_work_a_signal_is_only_recorded_for_the_exit(handlers):
    interrupt.work_done()
    os.kill(os.getpid(), signal.SIGTERM)
    for _ in range(1000):
        sum(range(10))
    assert interrupt.unreported() == signal.SIGTERM
    assert interrupt.message(signal.SIGTERM).startswith("interrupted: SIGTERM during ")
    interrupt.reported()
    assert interrupt.unreported() is None
