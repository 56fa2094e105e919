"""The literate examples run and their numbers hold (as scikit-fem's test_examples.py): an example cannot rot."""

from __future__ import annotations

import runpy
from pathlib import Path

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def test_hertz_contact_example(tmp_path, monkeypatch):
    """Hertz at a/R = 0.05, Nitsche P2, h_c = a/20: within the hertz_cylinder case tolerances (0.5 % peak and
    half-width, 1 % RMS/p0), and its outputs stay in its own folder."""
    monkeypatch.setenv("EXAMPLE_OUT", str(tmp_path))
    ns = runpy.run_path(str(EXAMPLES / "hertz_contact.py"), run_name="__main__")
    assert ns["error_p0"] < 5e-3
    assert ns["error_a"] < 5e-3
    assert ns["rms"] < 1e-2
    assert abs(ns["result"].P - ns["P"]) <= 1e-9 * ns["P"]  # force control reached the target load
    assert (tmp_path / "pressure.png").stat().st_size > 10_000
    assert {f.name for f in tmp_path.iterdir()} == {"mesh", "pressure.png"}
