"""Command line: ``python -m analytic {hertz,wedge,convective,halfplane,table1,lcp} ... [--json]``.

Units: mm, N/mm, MPa, rad. A bad value prints ONE line on stderr, starting with ``error:``, naming the field and
its range, and exits with code 2. Computing lives in the modules; this file only parses and formats.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Sequence
from typing import Any, NoReturn

import numpy as np

__all__ = ["main"]


class _Parser(argparse.ArgumentParser):
    """ArgumentParser whose errors are one stderr line and exit code 2."""

    def error(self, message: str) -> NoReturn:
        print(f"error: {self.prog}: {' '.join(message.split())}", file=sys.stderr)
        raise SystemExit(2)


def _emit(data: dict[str, Any], as_json: bool) -> None:
    if as_json:
        print(json.dumps(data, indent=2))
        return
    for key, value in data.items():
        if isinstance(value, float):
            print(f"{key:32s} {value:.10g}")
        elif isinstance(value, dict):
            for sub, seq in value.items():
                print(f"{key + '.' + sub:32s} " + " ".join(f"{v:.10g}" for v in seq))
        else:
            print(f"{key:32s} {value}")


# Magnitudes (--P, --E, --R, --E2, --E-star): every command forms products such as P / (E* R) and p0 b; inside
# [1e-100, 1e100] they stay far from the double range (1e-308 ... 1e308) whatever the combination.
MAGNITUDE = (1e-100, 1e100)
# b/R of the circle and the parabola (b the classical half-width): the half-plane theory needs b/R < 1 (the
# contact cannot be wider than the circle) and its solve needs b/R above round-off (E = 1e308 gave b/R = 1e-153
# and hung for more than 60 s; R = 1e-300 gave b/R = 1e151 and a NaN answer with exit 0).
B_OVER_R = (1e-8, 1.0)


def _magnitudes(args: argparse.Namespace) -> None:
    """The dimensional inputs within MAGNITUDE (one line naming the option)."""
    lo, hi = MAGNITUDE
    for attr, name in (("P", "--P"), ("E", "--E"), ("R", "--R"), ("E2", "--E2"), ("E_star", "--E-star")):
        v = getattr(args, attr, None)
        if v is not None and not (math.isfinite(v) and lo <= v <= hi):
            raise ValueError(f"{name} = {v!r} out of range: need {lo:g} <= {name} <= {hi:g} (units of mm, N/mm, "
                             "MPa; beyond that the theory's products leave the floating-point range)")


def _body(args: argparse.Namespace) -> None:
    """Check the deformable body's --E and --nu under their command-line names (ValueError, one line)."""
    from analytic import materials

    materials.validate_modulus(args.E, "--E")
    materials.validate_poisson(args.nu, "--nu")


def _cmd_hertz(args: argparse.Namespace) -> dict[str, Any]:
    from analytic import hertz, materials

    _body(args)
    if (args.E2 is None) != (args.nu2 is None):
        given, missing = ("--E2", "--nu2") if args.nu2 is None else ("--nu2", "--E2")
        raise ValueError(f"{given} is given without {missing}: an elastic indenter needs both --E2 (MPa, > 0) "
                         "and --nu2 (-1 < --nu2 < 0.5); omit both for a rigid indenter")
    if args.E2 is not None:
        materials.validate_modulus(args.E2, "--E2")
        materials.validate_poisson(args.nu2, "--nu2")
    E1 = math.inf if args.E2 is None else args.E2
    nu1 = 0.0 if args.nu2 is None else args.nu2
    E_star = materials.composite_modulus(args.E, args.nu, E1=E1, nu1=nu1)
    c = hertz.hertz(args.P, args.R, E_star)
    return {
        "P": c.P,
        "R": c.R,
        "E_star": c.E_star,
        "half_width": c.half_width,
        "full_width": c.full_width,
        "p0": c.p0,
        "indenter": "rigid" if math.isinf(E1) else "elastic",
    }


def _cmd_wedge(args: argparse.Namespace) -> dict[str, Any]:
    from analytic import materials, wedge

    _body(args)
    m = wedge.wedge_slope(args.theta, convention=args.convention)
    E_star = materials.composite_modulus(args.E, args.nu)
    c = wedge.wedge(args.P, m, E_star)
    return {
        "P": c.P,
        "theta": args.theta,
        "convention": args.convention,
        "m": c.m,
        "E_star": c.E_star,
        "half_width": c.half_width,
        "full_width": c.full_width,
        "beta_rigid_indenter": materials.beta_rigid_indenter(args.nu),
    }


def _cmd_convective(args: argparse.Namespace) -> dict[str, Any]:
    from analytic import convective, wedge

    if args.profile == "wedge" and args.theta is None:
        raise ValueError("theta = None out of range: --profile wedge needs 0 < --theta < pi/2")
    m = wedge.wedge_slope(args.theta, convention=args.convention) if args.profile == "wedge" else None
    prof = convective.profile_from_args(args.profile, m=m, b0_over_R=args.b0_over_R, n=args.n)
    sol = convective.solve(prof, beta=args.beta, n_nodes=args.nodes)
    return {
        "profile": prof.kind,
        "label": prof.label,
        "n": prof.n,
        "lam": prof.lam,
        "beta": sol.beta,
        "b_over_b0_first_order": sol.b_over_b0_first_order,
        "b_over_b0_first_order_numeric": sol.b_over_b0_first_order_numeric,
        "b_over_b0_first_iterate": sol.b_over_b0_first_iterate,
        "b_over_b0_converged": sol.b_over_b0_converged,
        "iterations": sol.iterations,
        "n_nodes": sol.n_nodes,
    }


E_WINDOW = (1e-6, 1e12)  # MPa: the moduli the two-material options accept (beyond it the solver over/underflows)


def _modulus_window(value: float, name: str, *, rigid: bool = False) -> None:
    """ValueError (one line) unless E_WINDOW[0] <= value <= E_WINDOW[1] MPa (``rigid``: the message offers inf)."""
    lo, hi = E_WINDOW
    if not lo <= value <= hi:
        extra = " or inf (rigid)" if rigid else ""
        raise ValueError(f"{name} = {value!r} out of range: need {lo:g} <= {name} <= {hi:g} (MPa){extra}")


def _halfplane_materials(args: argparse.Namespace) -> dict[str, Any]:
    """The halfplane command's materials: E_star, alpha, beta (ValueError naming the option, one line).

    Three forms: ``--E --nu [--beta]`` (the old one: a rigid indenter on that block, beta as given, default 0),
    ``--E1 --nu1 --E2 --nu2`` (indenter 1 on block 2, plane strain: alpha, beta, E* from
    :func:`analytic.materials.bimaterial`), or ``--E-star [--beta]`` (E* and beta directly, alpha not known).
    """
    from analytic import materials

    pair = (args.E1, args.nu1, args.E2, args.nu2)
    forms = [args.E is not None or args.nu is not None, any(v is not None for v in pair), args.E_star is not None]
    if sum(forms) != 1:
        raise ValueError("materials out of range: give exactly one of --E with --nu (rigid indenter), "
                         "--E1 --nu1 --E2 --nu2 (indenter 1 on block 2), or --E-star (with --beta)")
    beta = 0.0 if args.beta is None else args.beta
    if not (math.isfinite(beta) and -0.5 <= beta <= 0.5):
        raise ValueError(f"--beta = {beta!r} out of range: need -0.5 <= --beta <= 0.5")
    if forms[0]:
        if args.E is None or args.nu is None:
            raise ValueError("--E, --nu out of range: the rigid-indenter form needs both --E (MPa, 0 < --E < inf) "
                             "and --nu (-1 < --nu < 0.5)")
        _body(args)
        return {"materials": "rigid indenter on the block (--E, --nu)", "alpha": -1.0, "beta": beta,
                "beta_rigid_indenter": materials.beta_rigid_indenter(args.nu),
                "E_star": materials.composite_modulus(args.E, args.nu)}
    if forms[2]:
        _modulus_window(args.E_star, "--E-star")
        return {"materials": "E* and beta given (--E-star, --beta)", "alpha": None, "beta": beta,
                "E_star": float(args.E_star)}
    for name, value in zip(("--E1", "--nu1", "--E2", "--nu2"), pair, strict=True):
        if value is None:
            raise ValueError(f"{name} = None out of range: two materials need all of --E1 --nu1 --E2 --nu2")
    if args.beta is not None:
        raise ValueError("--beta is given with --E1 --nu1 --E2 --nu2: beta follows from the two materials; "
                         "give --beta with --E-star instead")
    if args.E1 != math.inf:
        _modulus_window(args.E1, "--E1", rigid=True)
    _modulus_window(args.E2, "--E2")
    materials.validate_poisson(args.nu1, "--nu1", incompressible=True)
    materials.validate_poisson(args.nu2, "--nu2", incompressible=True)
    bm = materials.bimaterial(E1=args.E1, nu1=args.nu1, E2=args.E2, nu2=args.nu2)
    if not -0.5 <= bm.beta <= 0.5:
        raise ValueError(f"beta = {bm.beta:.6g} out of range: the convective theory needs -0.5 <= beta <= 0.5 "
                         "(auxetic --nu1/--nu2 < 0 can exceed it)")
    lo, hi = materials.beta_range(nu1=args.nu1, nu2=args.nu2)
    return {"materials": "indenter 1 on block 2 (plane strain)", "E1": bm.E1 if math.isfinite(bm.E1) else "inf",
            "nu1": bm.nu1, "E2": bm.E2, "nu2": bm.nu2, "alpha": bm.alpha, "beta": bm.beta,
            "beta_range_for_these_nu": [lo, hi], "E_star": bm.E_star}


def _cmd_halfplane(args: argparse.Namespace) -> dict[str, Any]:
    from analytic import halfplane, wedge

    mats = _halfplane_materials(args)
    if args.profile == "wedge":
        if args.R is not None:
            raise ValueError("--R is given with --profile wedge: the wedge takes --theta (0 < --theta < pi/2), not --R")
        if args.theta is None or not 0.0 < args.theta < 0.5 * math.pi:
            raise ValueError(f"--theta = {args.theta!r} out of range: --profile wedge needs 0 < --theta < pi/2 (rad)")
        prof = halfplane.profile("wedge", m=wedge.wedge_slope(args.theta, convention=args.convention))
    else:
        if args.theta is not None:
            raise ValueError(f"--theta is given with --profile {args.profile}: it takes --R (mm, > 0), not --theta")
        if args.R is None or not (math.isfinite(args.R) and args.R > 0.0):
            raise ValueError(f"--R = {args.R!r} out of range: --profile {args.profile} needs --R > 0 (mm)")
        prof = halfplane.profile(args.profile, R=args.R)
    if not (math.isfinite(args.P) and args.P > 0.0):
        raise ValueError(f"--P = {args.P!r} out of range: need --P > 0 (N/mm)")
    if args.pressure is not None and not 2 <= args.pressure <= 100000:
        raise ValueError(f"--pressure = {args.pressure!r} out of range: need 2 <= --pressure <= 100000 (points)")
    E_star = mats.pop("E_star")
    if prof.kind in ("circle", "parabola"):
        g = math.sqrt(4.0 * args.P / (math.pi * E_star * args.R))
        if not B_OVER_R[0] <= g < B_OVER_R[1]:
            raise ValueError(f"--P = {args.P!r}, --R = {args.R!r} and the moduli (E* = {E_star:.6g}) give a classical "
                             f"half-width b/R = {g:.3g}; allowed: {B_OVER_R[0]:g} <= b/R < {B_OVER_R[1]:g} (the "
                             "half-plane theory's range, above round-off)")
    sol = halfplane.solve_halfplane(prof, P=args.P, E_star=E_star, beta=mats["beta"])
    out: dict[str, Any] = {
        "profile": prof.kind,
        "label": prof.label,
        "P": sol.P,
        "E_star": E_star,
        **mats,
        "beta": sol.beta,
        "half_width": sol.half_width,
        "p_max": sol.p_max if math.isfinite(sol.p_max) else None,
        "p_max_note": "log-singular at the wedge apex" if prof.kind == "wedge" else "at x = 0",
        "moment_half_width": sol.moment_half_width,
        "half_width_classical": sol.b_classical,
        "b_over_b_classical": sol.half_width / sol.b_classical,
        "iterations": sol.iterations,
        "n_nodes": sol.n_nodes,
    }
    if prof.kind in ("circle", "parabola"):
        from analytic import hertz

        h = hertz.hertz(args.P, args.R, E_star)
        out |= {"hertz_half_width": h.half_width, "hertz_p0": h.p0,
                "half_width_over_hertz": sol.half_width / h.half_width, "p_max_over_hertz": sol.p_max / h.p0}
    if args.pressure is not None:
        x = np.linspace(-sol.half_width, sol.half_width, int(args.pressure))
        out["pressure"] = {"x": x.tolist(), "p": sol.pressure(x).tolist()}
    return out


def _cmd_table1(args: argparse.Namespace) -> dict[str, Any]:
    from analytic import hertz

    rows = []
    for t in hertz.table1_patch_sizes(E_star=args.E_star):
        rows.append(
            {
                **t.row._asdict(),
                "width_eq4": t.width_eq4,
                "eq5": [e._asdict() for e in t.eq5] if t.eq5 else "R not published",
            }
        )
    return {"E_star": args.E_star, "note": "widths are FULL patch widths 2a (mm)", "rows": rows}


def _print_table1(data: dict[str, Any]) -> None:
    print(f"E* = {data['E_star']:.6g} MPa; {data['note']}")
    head = f"{'config':20s} {'d':>5s} {'P':>7s} {'p0':>7s} {'2a eq4':>8s}"
    print(f"{head}  eq5 (pair: R printed -> 2a | R computed -> 2a)")
    for r in data["rows"]:
        eq5 = r["eq5"]
        txt = (
            eq5
            if isinstance(eq5, str)
            else "; ".join(
                f"{e['pair']}: R={e['R_printed']:g} -> {e['width_eq5_R_printed']:.3f} | "
                f"R={e['R_computed']:.4g} -> {e['width_eq5_R_computed']:.3f} (printed {e['width_printed']:g})"
                for e in eq5
            )
        )
        print(f"{r['config']:20s} {r['d']:5.2f} {r['P']:7.0f} {r['p0']:7.0f} {r['width_eq4']:8.4f}  {txt}")


def _build_parser() -> _Parser:
    parser = _Parser(prog="python -m analytic", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    p = sub.add_parser("hertz", help="2D Hertz line contact")
    p.add_argument("--P", type=float, required=True, help="load per unit thickness (N/mm)")
    p.add_argument("--R", type=float, required=True, help="relative radius (mm)")
    p.add_argument("--E", type=float, required=True, help="Young's modulus of the deformable body (MPa)")
    p.add_argument("--nu", type=float, required=True, help="Poisson's ratio of the deformable body")
    p.add_argument("--E2", type=float, default=None, help="Young's modulus of the indenter (default rigid)")
    p.add_argument("--nu2", type=float, default=None, help="Poisson's ratio of the indenter")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=_cmd_hertz)

    p = sub.add_parser("wedge", help="classical rigid wedge on a half-plane")
    p.add_argument("--P", type=float, required=True, help="load per unit thickness (N/mm)")
    p.add_argument("--theta", type=float, required=True, help="external wedge angle (rad)")
    p.add_argument("--E", type=float, required=True)
    p.add_argument("--nu", type=float, required=True)
    p.add_argument(
        "--convention",
        choices=("paper", "exact"),
        default="exact",
        help="slope m = theta (paper) or tan(theta) (exact)",
    )
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=_cmd_wedge)

    p = sub.add_parser("convective", help="Ciavarella-Hills convective correction b/b0 at fixed load")
    p.add_argument("--profile", choices=("wedge", "parabola", "power"), required=True)
    p.add_argument("--theta", type=float, default=None, help="wedge angle (rad)")
    p.add_argument("--convention", choices=("paper", "exact"), default="paper")
    p.add_argument("--b0-over-R", dest="b0_over_R", type=float, default=None, help="classical b0/R")
    p.add_argument("--n", type=float, default=None, help="power-profile exponent")
    p.add_argument("--beta", type=float, required=True, help="Dundurs beta (rigid indenter: <= 0)")
    p.add_argument("--nodes", type=int, default=65536, help="Gauss-Chebyshev nodes")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=_cmd_convective)

    p = sub.add_parser("halfplane", help="circle / parabola / wedge on a half-plane at a load, one or two materials")
    p.add_argument("--profile", choices=("circle", "parabola", "wedge"), required=True)
    p.add_argument("--R", type=float, default=None, help="radius (mm): circle, parabola")
    p.add_argument("--theta", type=float, default=None, help="external wedge angle (rad): wedge")
    p.add_argument("--convention", choices=("paper", "exact"), default="exact",
                   help="wedge slope m = theta (paper) or tan(theta) (exact)")
    p.add_argument("--E", type=float, default=None, help="Young's modulus of the block, rigid indenter (MPa)")
    p.add_argument("--nu", type=float, default=None, help="Poisson's ratio of the block, rigid indenter")
    p.add_argument("--E1", type=float, default=None, help="indenter (body 1) Young's modulus (MPa, inf = rigid)")
    p.add_argument("--nu1", type=float, default=None, help="indenter (body 1) Poisson's ratio, -1 < nu1 <= 0.5")
    p.add_argument("--E2", type=float, default=None, help="block (body 2) Young's modulus (MPa)")
    p.add_argument("--nu2", type=float, default=None, help="block (body 2) Poisson's ratio, -1 < nu2 <= 0.5")
    p.add_argument("--E-star", dest="E_star", type=float, default=None, help="composite modulus E* (MPa), with --beta")
    p.add_argument("--P", type=float, required=True, help="load per unit thickness (N/mm)")
    p.add_argument("--beta", type=float, default=None,
                   help="Dundurs beta, -0.5..0.5, with --E/--nu or --E-star (default 0: classical)")
    p.add_argument("--pressure", type=int, default=None, metavar="N", help="also print p(x) at N points")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=_cmd_halfplane)

    p = sub.add_parser("table1", help="eq. (4)/(5) patch sizes of Table 1 (close-to-conformal paper)")
    p.add_argument("--E-star", dest="E_star", type=float, default=235000.0, help="E* (MPa)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=_cmd_table1)

    sub.add_parser("lcp", help="local contact problem (delegated to analytic.lcp)", add_help=False)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code (2 for a bad value)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] == "lcp":
        from analytic import lcp

        return lcp.cli(argv[1:], parser_class=_Parser)
    parser = _build_parser()
    args = parser.parse_args(argv)
    try:
        _magnitudes(args)
        data = args.func(args)
    except ValueError as exc:
        print(f"error: python -m analytic {args.command}: {str(exc).splitlines()[0]}", file=sys.stderr)
        return 2
    if args.command == "table1" and not args.json:
        _print_table1(data)
    else:
        _emit(data, args.json)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
