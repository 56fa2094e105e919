"""A case file refused in one line: the check the scenes' bad-value tests share."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path


def assert_case_refused(tmp_path: Path, text: str, field: str) -> str:
    """Write ``text`` as ``bad.toml`` and ``workbench run`` it: exit 2, one non-empty stderr line that names
    ``field`` and what is ``allowed``, and nothing in the output folder. Returns the line."""
    f = tmp_path / "bad.toml"
    f.write_text(text)
    proc = subprocess.run([sys.executable, "-m", "workbench", "run", str(f), "--out", str(tmp_path / "out")],
                          capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert proc.returncode == 2, proc.stderr
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and field in lines[0] and "allowed" in lines[0], proc.stderr
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())
    return lines[0]
