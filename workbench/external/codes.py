"""``workbench external <code> CASE ...``: the external codes the workbench runs, by name.

Each code is a module with ``main(argv) -> int`` that parses its own options (``argv`` starts with the code's
name): ``ccx`` (CalculiX, :mod:`workbench.external.ccx`), ``kratos`` (Kratos Multiphysics,
:mod:`workbench.external.kratos`), ``workbench`` (the workbench's own solver, run and scored as an external code
is: :mod:`workbench.external.own_code`). ``compare`` runs them side by side (:mod:`workbench.external.compare`).
A new code is one module and one line here.
"""

from __future__ import annotations

import importlib
import sys

__all__ = ["CODES", "main"]

CODES = {
    "ccx": "workbench.external.ccx",
    "kratos": "workbench.external.kratos",
    "workbench": "workbench.external.own_code",
    "compare": "workbench.external.compare",
}


def main(argv: list[str] | None = None) -> int:
    """Dispatch to the code named first (exit 2, one line, for a missing or unknown code)."""
    argv = sys.argv[1:] if argv is None else list(argv)
    if not argv or argv[0] not in CODES:
        if argv and argv[0] in ("-h", "--help"):
            print(__doc__)
            return 0
        given = f"{argv[0]!r}" if argv else "none"
        print(f"error: external code {given[:60]}; allowed: {', '.join(CODES)} (see workbench external <code> "
              "--help)", file=sys.stderr)
        return 2
    return int(importlib.import_module(CODES[argv[0]]).main(argv) or 0)
