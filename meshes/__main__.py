"""``python -m meshes build NAME [--h-contact H] [--half] [--out-dir DIR] [--stats-dir DIR] [--json]``.

NAME is one of the built-in defaults (hertz_default: a = 0.5 mm, W = H = 40 a, h_c = a/20;
wedge_default: the same block with apex refinement; concave_symmetric / symmetric and close_to_conformal:
the designs of :mod:`analytic.designs`, h_c = 0.05 mm). Prints the mesh statistics. Bad values: one stderr
line, exit code 2. The meshes of a case, exactly as the case runs them, come from ``workbench mesh CASE``
(this layer knows nothing of cases).
"""

from __future__ import annotations

import argparse
import json
import math
import sys

from meshes.cache import DEFAULT_CACHE_DIR

__all__ = ["main"]

BLOCK_DEFAULTS = {"hertz_default": dict(a=0.5, apex=False), "wedge_default": dict(a=0.5, apex=True)}
CONCAVE_DEFAULTS = {"concave_symmetric": "symmetric", "symmetric": "symmetric",
                    "close_to_conformal": "close_to_conformal"}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m meshes", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    b = sub.add_parser("build", help="build one mesh and print its statistics")
    b.add_argument("name", help=f"one of {sorted({*BLOCK_DEFAULTS, *CONCAVE_DEFAULTS})}")
    b.add_argument("--h-contact", type=float, default=None, help="contact element size (mm), > 0")
    b.add_argument("--half", action="store_true", help="half model (block scenes)")
    b.add_argument("--out-dir", default=str(DEFAULT_CACHE_DIR), help="mesh cache directory")
    b.add_argument("--stats-dir", default=None, help="also write <dir>/mesh.json")
    b.add_argument("--no-xdmf", action="store_true", help="skip the XDMF file")
    b.add_argument("--json", action="store_true", help="print the statistics as JSON")
    args = parser.parse_args(argv)
    from meshes.portable import perturb_amplitude

    try:
        perturb_amplitude()
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    if args.h_contact is not None and not (math.isfinite(args.h_contact) and args.h_contact > 0):
        print(f"error: --h-contact must be > 0 (mm), got {args.h_contact}", file=sys.stderr)
        return 2
    try:
        if args.name in BLOCK_DEFAULTS:
            from meshes.block import build_block_mesh

            spec = BLOCK_DEFAULTS[args.name]
            a = spec["a"]
            files = build_block_mesh(width=40 * a, height=40 * a, contact_half_width=a,
                                     h_contact=args.h_contact or a / 20, half_model=args.half,
                                     apex_refinement=spec["apex"], out_dir=args.out_dir, name=args.name,
                                     write_xdmf=not args.no_xdmf, stats_dir=args.stats_dir)
        else:
            if args.name not in CONCAVE_DEFAULTS:
                print(f"error: name must be one of {sorted({*BLOCK_DEFAULTS, *CONCAVE_DEFAULTS})}, "
                      f"got {args.name!r}", file=sys.stderr)
                return 2
            design_name, h_c = CONCAVE_DEFAULTS[args.name], 0.05
            from meshes.concave import build_concave_mesh

            files = build_concave_mesh(design=design_name, h_contact=args.h_contact or h_c,
                                       out_dir=args.out_dir, name=args.name, write_xdmf=not args.no_xdmf,
                                       stats_dir=args.stats_dir)
    except ValueError as exc:
        print(f"error: {str(exc).splitlines()[0]}", file=sys.stderr)
        return 2
    out = {"msh": str(files.msh), "xdmf": None if files.xdmf is None else str(files.xdmf), "key": files.key,
           "cached": files.cached, **{k: v for k, v in files.stats.items() if k != "params"}}
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        for k, v in out.items():
            print(f"{k:28s} {v:.6g}" if isinstance(v, float) else f"{k:28s} {v}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
