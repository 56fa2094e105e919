"""``workbench forcelaw DESIGN``: a force law for multibody and DEM users (issue 40, item 4).

For a design of the family (:mod:`analytic.design_family`: ``symmetric``, ``close_to_conformal``, or a member
given by its numbers, ``KIND:radius_convex=..,radius_concave=..,pair_separation=..,central_gap=..[,depth=..]``),
writes ``<out>/forcelaw_<name>/``:

    forcelaw.csv       d (mm), P (N/mm), the number of patches, and per patch slot x, b (mm), p0 (MPa), share
    forcelaw.json      the same rows, the design's numbers, the model, its constants and its validity limit
    forcelaw_eval.py   the pure-numpy evaluator (:mod:`analytic.force_law_eval`) to copy into your code

from the interacting-patch model (:mod:`analytic.force_law`), from first touch up to ``--d-max`` or, by default, in
steps of ``--step`` up to the region the concave map validated (``workbench/forcelaw_region.json``,
:mod:`workbench.forcelaw_region`).

Which limit refuses: the MEASURED region. A design outside it, or a ``--d-max`` beyond it, is refused. The
model's analytic validity limit (the pairs' tilt against the path, the surface slope over the patches, patch size,
span) does not refuse a design the map validated: the map evaluated the model past that limit against the FEM, so
there the analytic limit is a warning (``forcelaw.json``'s ``warnings``, and one stderr line each). Bad input (a
design, a number, an option): one line naming the field and its range, exit 2, nothing written.
"""

from __future__ import annotations

import argparse
import csv
import io
import math
import sys
from pathlib import Path

__all__ = ["main", "parse_design", "table_json", "table_csv"]

def parse_design(text: str):
    """A paper member's name, or ``KIND:key=value,...`` (:func:`analytic.design_family.parse_family`, the parser a
    case file's ``geometry.family`` uses too; ValueError, one line)."""
    from analytic.design_family import member, parse_family

    if ":" not in text:
        return member(text)
    kind, _, rest = text.partition(":")
    return parse_family(kind, rest, field="DESIGN")


def table_json(table) -> dict:
    """The JSON record of a :class:`analytic.force_law.ForceLawTable`."""
    from dataclasses import asdict

    from analytic.interacting_patches import MAX_PATCH_OVER_RADIUS, MAX_SPAN_OVER_DEPTH, MAX_SURFACE_SLOPE

    return {
        "design": asdict(table.member),
        "model": "interacting_patches (analytic.interacting_patches: all patches together, real gap, half-plane "
                 "log coupling; Flamant's depth convention with r_ref = depth)",
        "units": {"d": "mm", "P": "N/mm", "x": "mm", "b": "mm", "p0": "MPa"},
        "d_touch_mm": table.d_touch,
        "E_star_MPa": table.E_star, "nu": table.nu, "depth_mm": table.depth,
        "validity": {"region": "measured by the concave map (the refusal); the analytic limit below is a warning "
                               "inside it",
                     "max_surface_slope": MAX_SURFACE_SLOPE,
                     "max_patch_over_radius": MAX_PATCH_OVER_RADIUS, "max_span_over_depth": MAX_SPAN_OVER_DEPTH,
                     "d_min_mm": table.rows[0].d, "d_max_mm": table.rows[-1].d},
        "note": table.note,
        "warnings": list(table.warnings),
        "rows": [{"d_mm": r.d, "P_N_per_mm": r.P,
                  "patches": [{"x_mm": x, "b_mm": b, "p0_MPa": p0, "share": sh} for x, b, p0, sh in r.patches]}
                 for r in table.rows],
    }


def table_csv(table) -> str:
    """The rows as csv: d_mm, P_N_per_mm, n_patches, then x_k_mm, b_k_mm, p0_k_MPa, share_k per slot k."""
    slots = max(len(r.patches) for r in table.rows)
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(["d_mm", "P_N_per_mm", "n_patches",
                *[f"{q}_{k}{u}" for k in range(1, slots + 1) for q, u in
                  (("x", "_mm"), ("b", "_mm"), ("p0", "_MPa"), ("share", ""))]])
    for r in table.rows:
        cells = [repr(r.d), repr(r.P), str(len(r.patches))]
        for k in range(slots):
            cells += [repr(v) for v in r.patches[k]] if k < len(r.patches) else ["", "", "", ""]
        w.writerow(cells)
    return out.getvalue()


def _parser() -> argparse.ArgumentParser:
    from workbench.cli import _Parser

    p = _Parser(prog="workbench forcelaw", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("design", metavar="DESIGN", help="symmetric | close_to_conformal | KIND:key=value,...")
    p.add_argument("--d-max", type=float, default=None,
                   help="last displacement (mm along the path); default: the end of the region the concave map "
                        "validated")
    p.add_argument("--rows", type=int, default=41, help="rows from first touch to --d-max, 2 to 1000")
    p.add_argument("--step", type=float, default=0.002, help="row spacing without --d-max (mm), 1e-5 to 0.1")
    p.add_argument("--out", default=None, help="output folder (default: $WORKBENCH_RESULTS, else results/)")
    return p


def main(argv: list[str] | None = None) -> int:
    """``workbench forcelaw`` (exit 0 written, 2 bad input or outside the validity limit, 1 not written)."""
    from workbench import interrupt
    from workbench.owned import check_dir
    from workbench.paths import OutputError, checked_paths

    args = _parser().parse_args(argv)
    try:
        if args.d_max is not None and not math.isfinite(args.d_max):
            raise ValueError(f"--d-max = {args.d_max!r} out of range: need a finite displacement (mm)")
        paths = checked_paths(args.out)  # the output folder's guard, whichever way it was given
        mem = parse_design(args.design)
        folder = paths.inside(f"forcelaw_{mem.name}")
        check_dir(folder, kinds=("forcelaw",))
        interrupt.stage(f"force law of {mem.name}")
        from analytic.force_law import force_law
        from workbench.forcelaw_region import load_region, validated_approach

        region = load_region()
        approach = validated_approach(mem, region)  # outside the map's validated region: refused here
        table = force_law(mem, d_max=args.d_max, n_rows=args.rows, step=args.step, approach_max=approach)
        table = table._replace(note=f"region = where the concave map validated the interacting-patch model within "
                                    f"{100 * region['edge']:g} % of the FEM (widths, p0, P; a point within the "
                                    f"FEM's band counts as within): up to {approach:.4g} mm past first touch; the "
                                    "model's analytic validity limit is a warning there (warnings)")
    except (ValueError, OutputError) as exc:
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    interrupt.stage(f"writing {folder.name}")
    try:
        _write(table, folder)
    except OutputError as exc:
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"error: forcelaw {mem.name}: cannot write the results: {' '.join(str(exc.strerror or exc).split())}; "
              "previous results left intact", file=sys.stderr)
        return 1
    for w in table.warnings:
        print(f"forcelaw {mem.name}: warning: {w}", file=sys.stderr)
    last = table.rows[-1]
    print(f"forcelaw {mem.name}: {len(table.rows)} rows, d = {table.d_touch:.6g} .. {last.d:.6g} mm, "
          f"P up to {last.P:.6g} N/mm (region: validated by the concave map, {approach:.4g} mm past first touch"
          f"{'; past the analytic limit, a warning' if table.warnings else ''}) -> {folder}")
    return 0


def _write(table, folder: Path) -> None:
    import analytic.force_law_eval as evaluator
    from workbench.atomic import atomic_dir, write_json, write_text

    with atomic_dir(folder, kind="forcelaw") as stage:
        write_json(stage / "forcelaw.json", table_json(table))
        write_text(stage / "forcelaw.csv", table_csv(table))
        write_text(stage / "forcelaw_eval.py", Path(evaluator.__file__).read_text(encoding="utf-8"))
