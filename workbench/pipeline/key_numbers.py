"""The key numbers of a results folder, and their comparison with a saved set (refactors change no result).

``key_numbers(root)`` flattens every case's ``metrics.json`` into ``{"case/field": value}``: the load ``P`` and
``P_pressure``, every error, the case-level analytic values (b/b0 ...), and per run ``P``, ``d``, ``p_max``,
the patch half-width, the patches, the errors, ``ndofs`` and the Newton iterations; per concave step its
load, peak and superposition errors. From ``make run`` (issue 12) also every error-budget row's results
contract (``fine``, ``extrapolated``, ``observed_order``, ``gci``, ``truncation``, ``theory``,
``theory_in_band``; ``alt_value`` and ``alt_in_band`` where the row has an alternative theory) and every band
check's verdict. Times are left out.

Each run's ``mesh_fingerprint`` (node and cell counts, hash of the rounded coordinates), when the run has one,
is a key number too: it says whether two sets of numbers come from the same mesh.

Two comparisons, for two questions:

* **same machine, refactor check** (``compare``, ``make check-numbers``): every number at ``rtol`` = 1e-10 of its
  scale (itself, the contact size for a centre, 1 for a fraction) against a baseline saved on this machine
  (``make save-baseline`` -> ``results/baseline/``, not under version control). Any change of a result shows; it
  says nothing about another machine.
* **portable regression** (``portable``, ``tests/test_cases_end_to_end.py``): every number against the saved
  set ``tests/data/key_numbers_{ci,run}.json`` at the tolerance of its class
  (:mod:`workbench.pipeline.number_classes`: verdicts exact, round-off against an absolute ceiling,
  iterations within a margin, physics relative to what the solver and the mesh can decide). The saved
  files carry the class of every key next to its number (``{"classes": {...}, "numbers": {...}}``).

``python -m workbench.pipeline.key_numbers save RESULTS FILE`` writes them; ``... update RESULTS FILE`` replaces the
entries of the cases under RESULTS and keeps every other case's (a case added or changed alone); ``... compare RESULTS
FILE [--rtol 1e-10]`` prints every number that moved by more than ``rtol`` (relative) and exits 1 if any did;
``... portable RESULTS FILE`` prints every number outside its class tolerance and exits 1 if any is.
A missing FILE is refused with one line (exit 2).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

from workbench.atomic import write_text
from workbench.pipeline.number_classes import MESH_SENSITIVE_SAME, classify, compare_portable, scale_kind, scale_of

__all__ = ["AMPLIFIED", "key_numbers", "compare_numbers", "saved_file", "load_saved"]

_RUN_FIELDS = ("P", "P_pressure", "d", "p_max", "patch_half_width", "ndofs", "newton_iterations",
               "mesh_fingerprint")
_BUDGET_FIELDS = ("fine", "extrapolated", "observed_order", "gci", "truncation", "theory", "theory_in_band",
                  "alt_value", "alt_in_band")
_STEP_FIELDS = ("d", "P", "P_pressure", "p_max", "n_patches", "superposition_independent_rms_over_p0",
                "superposition_best_rms_over_p0")


def _flat(prefix: str, value, out: dict) -> None:
    if isinstance(value, dict):
        for k, v in value.items():
            _flat(f"{prefix}/{k}", v, out)
    elif isinstance(value, (list, tuple)):
        for i, v in enumerate(value):
            _flat(f"{prefix}/{i}", v, out)
    elif isinstance(value, bool) or value is None or isinstance(value, str):
        out[prefix] = value
    elif isinstance(value, (int, float)):
        out[prefix] = float(value)


def key_numbers(root: Path) -> dict:
    """Key numbers of every ``<root>/<case>/metrics.json`` (see the module docstring)."""
    out: dict = {}
    for f in sorted(Path(root).glob("*/metrics.json")):
        m = json.loads(f.read_text())
        c = m["case"]
        for k in ("P", "P_pressure", "errors", "pass"):
            _flat(f"{c}/{k}", m.get(k), out)
        _flat(f"{c}/analytic", {k: v for k, v in m.get("analytic", {}).items() if k != "runs"}, out)
        for q, row in (m.get("error_budget") or {}).items():
            _flat(f"{c}/error_budget/{q}", {k: row[k] for k in _BUDGET_FIELDS if k in row}, out)
        for k, chk in (m.get("band_checks") or {}).items():
            out[f"{c}/band_checks/{k}"] = bool(chk["passed"])
        for r in m.get("runs", []):
            pre = f"{c}/runs/{r['label']}"
            for k in _RUN_FIELDS:
                _flat(f"{pre}/{k}", r.get(k), out)
            _flat(f"{pre}/errors", r.get("errors"), out)
            _flat(f"{pre}/patches", r.get("patches"), out)
            for i, s in enumerate(r.get("steps", [])):
                _flat(f"{pre}/steps/{i}", {k: s.get(k) for k in _STEP_FIELDS}, out)
    return out


AMPLIFIED = ("estimate", "mesh_sensitive")
"""Classes whose numbers amplify round-off, compared at their same-mesh class tolerance (3.4e-2 of themselves) by
``compare``: an error budget's GCI, truncation and observed order are differences and log-ratios of nearly equal
grid values (issue 34 measured up to 1.1e-5 of themselves after a change that moved the grid values by round-off),
the best superposition's rms is an optimiser's result (1.8e-4)."""


def compare_numbers(new: dict, old: dict, *, rtol: float = 1e-10, allow_new: bool = False) -> list[str]:
    """One line per key number that is missing, new (unless ``allow_new``: e.g. a case added since the saved
    set), or moved by more than ``rtol`` of its scale (:func:`workbench.pipeline.number_classes.scale_of`: the
    number itself where it is bounded away from zero, the contact size for a patch centre, 1 for a fraction, never
    a quantity that is zero in theory against itself); a number of the :data:`AMPLIFIED` classes by more than the
    larger of ``rtol`` and 3.4e-2 of itself."""
    bad = []
    for k in sorted(set(old) | set(new)):
        if k not in old and allow_new:
            continue
        if k not in new or k not in old:
            bad.append(f"{k}: {'missing now' if k not in new else 'new'}")
            continue
        a, b = old[k], new[k]
        if isinstance(a, float) and isinstance(b, float):
            if math.isnan(a) and math.isnan(b):
                continue
            scale = scale_of(k, old, new)
            tol = max(rtol, MESH_SENSITIVE_SAME) if classify(k)[0] in AMPLIFIED else rtol
            if not abs(b - a) <= tol * scale:
                bad.append(f"{k}: {a!r} -> {b!r} (moved {abs(b - a) / scale if scale > 0 else math.inf:.3g} of "
                           f"its scale {scale:.6g}, {scale_kind(k)})")
        elif a != b:
            bad.append(f"{k}: {a!r} -> {b!r}")
    return bad


def saved_file(numbers: dict) -> dict:
    """The saved form of ``numbers``: each key's class next to its number (see the module docstring)."""
    return {"about": "key numbers; classes and tolerances: workbench/pipeline/number_classes.py",
            "classes": {k: classify(k)[0] for k in sorted(numbers)}, "numbers": dict(sorted(numbers.items()))}


def load_saved(path: Path) -> dict:
    """The numbers of a saved file (the ``saved_file`` form, or a plain ``{key: number}`` of older sets)."""
    data = json.loads(Path(path).read_text())
    return data["numbers"] if isinstance(data.get("numbers"), dict) else data


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m workbench.pipeline.key_numbers", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("action", choices=("save", "update", "compare", "portable"),
                   help="update: replace the entries of the cases under RESULTS in FILE, keep every other case's")
    p.add_argument("results", type=Path)
    p.add_argument("file", type=Path)
    p.add_argument("--rtol", type=float, default=1e-10)
    p.add_argument("--allow-new", action="store_true", help="numbers absent from FILE (new cases) are not errors")
    args = p.parse_args(argv)
    numbers = key_numbers(args.results)
    if not numbers:
        print(f"error: no */metrics.json under {args.results}", file=sys.stderr)
        return 2
    if args.action == "update":
        if not args.file.is_file():
            print(f"error: no saved key numbers at {args.file} to update; allowed: an existing file (save writes a "
                  "new one)", file=sys.stderr)
            return 2
        cases = {k.split("/", 1)[0] for k in numbers}
        kept = {k: v for k, v in load_saved(args.file).items() if k.split("/", 1)[0] not in cases}
        write_text(args.file, json.dumps(saved_file(kept | numbers), indent=1) + "\n")
        print(f"updated {', '.join(sorted(cases))} ({len(numbers)} key numbers) in {args.file}")
        return 0
    if args.action == "save":
        args.file.parent.mkdir(parents=True, exist_ok=True)
        write_text(args.file, json.dumps(saved_file(numbers), indent=1) + "\n")
        print(f"wrote {len(numbers)} key numbers to {args.file}")
        return 0
    if not args.file.is_file():
        print(f"error: no saved key numbers at {args.file}; `make save-baseline` saves them from this machine's "
              "`make run` (results/baseline/key_numbers.json)", file=sys.stderr)
        return 2
    saved = load_saved(args.file)
    if args.action == "portable":
        moves = compare_portable(numbers, saved, allow_new=args.allow_new)
        bad = [mv for mv in moves if not mv.ok]
        for mv in bad:
            print(f"{mv.key} [{mv.cls}]: {mv.old!r} -> {mv.new!r} (moved {mv.moved:.3g}, tolerance "
                  f"{mv.tolerance:.3g}{', ' + mv.note if mv.note else ''})")
        print(f"{len(moves)} key numbers, {len(bad)} outside their class tolerance")
        return 1 if bad else 0
    bad = compare_numbers(numbers, saved, rtol=args.rtol, allow_new=args.allow_new)
    if args.allow_new and (added := sorted(set(numbers) - set(saved))):
        print(f"{len(added)} key numbers are new (not in {args.file.name}), e.g. {added[0]}")
    for line in bad:
        print(line)
    print(f"{len(numbers)} key numbers, {len(bad)} moved by more than {args.rtol:g} of their scale "
          f"({', '.join(AMPLIFIED)}: {MESH_SENSITIVE_SAME:g} of themselves)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
