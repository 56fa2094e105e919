"""Send a signal to a running ``workbench`` command at a chosen stage (shared by tests/test_signals.py and
tests/fault_campaign.py)."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

__all__ = ["interrupt_at"]


def interrupt_at(argv: list[str], *, when: str, sig: int, delay: float = 0.0, cwd: Path, env: dict,
                 timeout: float = 300.0, wait: float = 60.0) -> tuple[int, str, float | None]:
    """Run ``python -m workbench ARGV``; ``delay`` s after the first stdout line containing ``when``, send ``sig``.

    Returns (exit code, stderr, seconds from the signal to the exit; None when ``when`` never appeared within
    ``timeout`` s of lines, in which case the command is left to finish on its own).
    """
    p = subprocess.Popen([sys.executable, "-m", "workbench", *argv], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, env=env, cwd=cwd)
    t_sig = None
    deadline = time.monotonic() + timeout
    for line in p.stdout:
        if when in line:
            time.sleep(delay)
            p.send_signal(sig)
            t_sig = time.monotonic()
            break
        if time.monotonic() >= deadline:
            break
    p.stdout.read()
    err = p.stderr.read()
    code = p.wait(timeout=wait)
    return code, err, (time.monotonic() - t_sig) if t_sig is not None else None
