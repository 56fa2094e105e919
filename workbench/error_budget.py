"""Solution verification of one quantity over three grids: Richardson extrapolation, observed order, GCI.

Roache's grid convergence index as ASME V&V 20 and Celik et al. (J. Fluids Eng. 130, 078001, 2008) state it.
Grids 1 (fine), 2, 3 (coarse) with representative sizes h1 < h2 < h3 and values f1, f2, f3;
``r21 = h2/h1``, ``r32 = h3/h2``, ``e21 = f2 - f1``, ``e32 = f3 - f2``, ``s = sign(e32/e21)``. The observed order p
solves ``p = |ln|e32/e21| + q(p)| / ln r21`` with ``q(p) = ln((r21^p - s)/(r32^p - s))`` (fixed point; q = 0 for a
constant ratio). Then
    f_ext = (r21^p f1 - f2) / (r21^p - 1),     GCI_fine = Fs |e21 / f1| / (r21^p - 1),   Fs = 1.25.
``s < 0`` means the sequence oscillates: no order and no extrapolation are claimed (:class:`GridStudy` says
``"oscillating"``), and the band falls back to the spread ``Fs max|f_i - f1| / |f1|``.

Two more cases claim no order either (issue 22), with the band ``Fs (max f_i - min f_i) / |f1|`` around the fine
value (Roache's three-grid Fs = 1.25 on the whole range of the three values; Stern et al., J. Fluids Eng. 123,
793 (2001), take half the range, U = (S_U - S_L) / 2, for oscillatory convergence: this band is 2.5 times theirs):

* ``"stalled"``: the fine pair differs by no more than ``floor`` (the absolute iterative and round-off noise of
  one value, measured by the caller): the difference is noise, and an order from it would be noise too;
* ``"crossing"``: ``reference`` (a theory the caller knows) lies strictly between two of the three values, so the
  error against it changes sign between levels. Richardson extrapolation assumes a monotone approach: a limit
  beyond the fine value is not claimed for a sequence that has already crossed the value it is tested against.

Differences that do not shrink on refinement (``|e32/e21| <= ln r32 / ln r21``, no positive order fits) are
``"diverging"``, with the ``max|f_i - f1|`` fallback. An observed order more than 10 % above ``formal_order`` q
keeps its Richardson value, but its GCI is at least ``FS_FORMAL |e21/f1| / (r21^q - 1)`` (Roy's factor-of-safety
rule, applied only above q). An observed order far from the expected one (outside [expected/2, 2 expected]) is
named ``"not asymptotic"``; differences within the noise (``|e21|, |e32| <= max(1e-14 |f1|, floor)``) are
``"converged"`` with GCI 0. All GCIs are relative.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

__all__ = ["FS", "FS_FORMAL", "FORMAL_ORDER", "FORMAL_ORDER_EDGE", "ITERATIVE_FLOOR", "ROUNDOFF_FLOOR", "TIGHTENING",
           "WARM_MAX_IT",
           "GridStudy", "grid_study", "iterative_error", "tight_resolve", "uncertainty"]

FS = 1.25  # safety factor of the GCI for a three-grid study (Roache)
FS_FORMAL = 3.0  # safety factor where the band falls back on the formal order (Roy; Oberkampf & Roy 2010, 8.7)
_ROUNDOFF = 1e-14
# Round-off floor of a budget value (relative). Measured: the same mesh on another CPU (issue 22) moved the
# hertz_cylinder p_max by 1.95e-10 and the load balance (a pure round-off quantity) sits at 1e-14 to 1.2e-13;
# five times the largest cross-machine move of a physics value.
ROUNDOFF_FLOOR = 1e-9
# Formal order the band of a smooth block quantity may rely on (P2; the square-root edge of the pressure limits
# the solution to H^{5/2-eps}: Hild & Renard, SIAM J. Numer. Anal. 50 (2012), h^{3/2} in energy). Measured: the
# moment half-width converges with order 4-5 from h_c = a/20 to a/80, but from a/80 to a/160 with order ~1 and a
# sign change at a/R = 0.17 and 0.25 (docs/error_budget.md): an observed order above 2 is not trusted for the band.
FORMAL_ORDER = 2.0
# The same for a zero crossing of the sampled contact law (the half-width; b/b0): the edge itself, where the
# pressure has its square root, converges no faster than the energy error, h^{3/2}. Measured observed orders on
# the budget grids: 1.17 (hertz_cylinder), 1.64 (wedge), 1.41 (a/R = 0.01 copy), 2.78 (a/R = 0.1 copy, whose fine
# value is then 2.8e-4 off the exact circle against a Roache GCI of 4e-5: that order is not real).
FORMAL_ORDER_EDGE = 1.5
# The iterative error is measured by solving the finest level again with every solver tolerance divided by this.
TIGHTENING = 100.0
# Newton iterations allowed per solve of that re-solve (it starts from the converged state: measured 1-3 where the
# tight tolerances are reachable; where they are not, the round-off floor of the residual, a cold re-solve spent
# 40 iterations and 5 cut-backs per tolerance before failing)
WARM_MAX_IT = 10
# Relative floor of the measured iterative error: the tight solve's own tolerance (default 1e-10 / TIGHTENING).
# Newton converges quadratically, so a default solve often already meets the tight tolerance: then the two
# values are identical and what is known is only that the error is below that tolerance.
ITERATIVE_FLOOR = 1e-12


class GridStudy(NamedTuple):
    """Three-grid verification of one quantity.

    Attributes:
        fine: value on the finest grid.
        extrapolated: Richardson value (the fine value where no order can be claimed).
        observed_order: p, or NaN.
        gci: relative fine-grid uncertainty (dimensionless).
        status: ``"asymptotic"``, ``"not asymptotic"``, ``"oscillating"``, ``"crossing"``, ``"stalled"``,
            ``"diverging"`` or ``"converged"``.
        band_order: the order the GCI was computed with (the observed one, or the formal one where the observed
            order exceeds it; NaN where no order is claimed).
    """

    fine: float
    extrapolated: float
    observed_order: float
    gci: float
    status: str
    band_order: float = math.nan

    def contains(self, value: float) -> bool:
        """True when ``value`` lies in the band ``extrapolated +- gci |fine|``."""
        return abs(value - self.extrapolated) <= self.gci * abs(self.fine)


def _order(e21: float, e32: float, r21: float, r32: float) -> float:
    s = math.copysign(1.0, e32 / e21)
    p = abs(math.log(abs(e32 / e21))) / math.log(r21)
    for _ in range(200):
        q = math.log((r21**p - s) / (r32**p - s))
        p_new = abs(math.log(abs(e32 / e21)) + q) / math.log(r21)
        if abs(p_new - p) <= 1e-13 * max(1.0, p):
            return p_new
        p = p_new
    return p


def grid_study(h: tuple[float, float, float], f: tuple[float, float, float], *,
               expected_order: float | None = None, reference: float | None = None,
               floor: float = 0.0, formal_order: float | None = None) -> GridStudy:
    """Verify one quantity from its values ``f`` on three grids of sizes ``h`` (any order; sorted fine first).

    Args:
        expected_order: Formal order; an observed order outside [expected/2, 2 expected] is "not asymptotic".
        reference: A value the sequence is tested against (the theory): crossing it is ``"crossing"``.
        floor: Absolute noise of one value (iterative error + round-off, >= 0): a fine-pair difference within it
            is ``"stalled"``, and both differences within it ``"converged"``.
        formal_order: The largest order the band may rely on. An observed order more than 10 % above it is kept
            for the Richardson value, but the GCI is the wider of Roache's (Fs = 1.25, observed order) and
            ``FS_FORMAL |e21 / f1| / (r21^q - 1)`` at q = formal_order (Roy's factor-of-safety rule for an
            observed order off the formal one, applied only above it).

    Raises:
        ValueError: fewer or more than three grids, equal or non-positive sizes, a non-finite value or floor.
    """
    if len(h) != 3 or len(f) != 3:
        raise ValueError(f"grid_study needs exactly 3 grids, got {len(h)} sizes and {len(f)} values")
    if not all(math.isfinite(v) for v in (*h, *f)) or min(h) <= 0:
        raise ValueError(f"grid sizes must be > 0 and values finite, got h = {h}, f = {f}")
    (h1, f1), (h2, f2), (h3, f3) = sorted(zip(h, f, strict=True))
    if not h1 < h2 < h3:
        raise ValueError(f"grid sizes must differ, got {sorted(h)}")
    if not (math.isfinite(floor) and floor >= 0.0) or (reference is not None and not math.isfinite(reference)):
        raise ValueError(f"floor must be finite and >= 0 and reference finite, got {floor}, {reference}")
    e21, e32 = f2 - f1, f3 - f2
    scale = max(abs(f1), 1e-300)
    noise = max(_ROUNDOFF * scale, floor)
    if abs(e21) <= noise and abs(e32) <= noise:
        return GridStudy(f1, f1, math.nan, 0.0, "converged")
    if e21 == 0.0 or e32 == 0.0 or e32 / e21 < 0:
        spread = max(abs(f2 - f1), abs(f3 - f1)) / scale
        return GridStudy(f1, f1, math.nan, FS * spread, "oscillating")
    full_range = FS * (max(f1, f2, f3) - min(f1, f2, f3)) / scale
    if abs(e21) <= noise:
        return GridStudy(f1, f1, math.nan, full_range, "stalled")
    r21, r32 = h2 / h1, h3 / h2
    if abs(e32 / e21) <= math.log(r32) / math.log(r21):
        # f = f_ext + C h^p with p > 0 has |e32/e21| = r21^p (r32^p - 1)/(r21^p - 1) > ln r32 / ln r21: the
        # differences do not shrink on refinement (Celik's |ln| would still return an order for them)
        spread = max(abs(e21), abs(f3 - f1)) / scale
        return GridStudy(f1, f1, math.nan, FS * spread, "diverging")
    if reference is not None and min(f1, f2, f3) < reference < max(f1, f2, f3):
        return GridStudy(f1, f1, math.nan, full_range, "crossing")
    p = _order(e21, e32, r21, r32)
    if not (math.isfinite(p) and p > 0):
        return GridStudy(f1, f1, math.nan, FS * max(abs(e21), abs(f3 - f1)) / scale, "not asymptotic")
    rp = r21**p
    f_ext = (rp * f1 - f2) / (rp - 1.0)
    gci = FS * abs(e21 / scale) / (rp - 1.0)
    band_order = p
    if formal_order is not None and p > 1.1 * formal_order:  # Roy: more than 10 % off the formal order
        formal = FS_FORMAL * abs(e21 / scale) / (r21**formal_order - 1.0)
        if formal > gci:
            gci, band_order = formal, float(formal_order)
    status = "asymptotic"
    if expected_order is not None and not (0.5 * expected_order <= p <= 2.0 * expected_order):
        status = "not asymptotic"
    return GridStudy(f1, f_ext, p, gci, status, band_order)


def uncertainty(*terms: float | None) -> float:
    """The numerical uncertainty of a budget row: the sum of its relative terms (None counts 0). Summed, not
    root-summed: the terms (discretisation, truncation, iterative, round-off, theory) are bounds, not standard
    deviations of independent errors."""
    return float(sum(t for t in terms if t is not None))


def iterative_error(value: float, tight: float | None) -> float | None:
    """Relative iterative error of a value: ``max(|tight - value| / |value|, ITERATIVE_FLOOR)`` (None when the
    tight solve failed)."""
    if tight is None or not math.isfinite(tight):
        return None
    return max(abs(tight - value) / max(abs(value), 1e-300), ITERATIVE_FLOOR)


def tight_resolve(solve, run, outcome, *, progress=print):
    """The finest run solved again with the solver tolerances divided by ``TIGHTENING`` (then by 10 if that does
    not converge), warm: ``(outcome, tightening)``, or ``(None, reason)``.

    ``solve(run, **overrides)`` is the pipeline's solve; the tolerances are ``snes_rtol``, ``force_rtol`` and
    ``uzawa_rtol`` (defaults 1e-10) and the SNES absolute tolerance ``1e-13 E L`` (L = the mesh's extent, E the
    stiffest body's Young's modulus, as the problem scales it). The
    re-solve starts from the converged states of ``outcome`` (``warm_start``, :mod:`fem.warm_start`: the final
    state, or every recorded displacement's) on the same mesh, and continues the same Newton (and Uzawa)
    iteration to the tighter tolerances, at most ``WARM_MAX_IT`` Newton iterations per solve: no load path is
    repeated. The difference of a value between the two solves is the iterative error of the stopped one.
    """
    from mpi4py import MPI

    from fem.options import ContactOptions
    from fem.solver import ContactSolveError

    mesh = outcome.result.u.function_space.mesh
    x = mesh.geometry.x
    # every rank must set the same absolute tolerance (the SNES test is collective): the body's extent, as
    # fem/problem.py measures it
    L = mesh.comm.allreduce(float(np.max(np.ptp(x[:, :2], axis=0))) if x.size else 0.0, op=MPI.MAX) or 1.0
    # the problem's own scale (fem/problem.py; two bodies: the stiffer body's E, fem/two_body/problem.py). The
    # first body's E made the "tolerances / 100" of the rigid limit (E ratio 1e6) a tolerance / 1e8, below the
    # residual's round-off: that re-solve could only diverge.
    E = max([b.material.E for b in run.bodies] or [run.material.E])
    d = ContactOptions.defaults()
    warm = {"warm_start": outcome.result.warm_start, "max_it": WARM_MAX_IT}
    last = ""
    for k in (TIGHTENING, 10.0):
        kw = {name: d[name] / k for name in ("snes_rtol", "force_rtol", "uzawa_rtol")}
        try:
            o = solve(run, **kw, **warm, petsc_options={"snes_atol": 1e-13 * E * L / k})
        except ContactSolveError as exc:
            last = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            progress(f"[budget {run.label}] tight re-solve at tolerances / {k:g} did not converge: {last}")
            continue
        its = sum(o.result.newton_iterations)
        progress(f"[budget {run.label}] tight re-solve (warm, tolerances / {k:g}): {its} Newton its in "
                 f"{len(o.result.newton_iterations)} solve(s), {o.result.wall_time_s:.2f} s")
        return o, k
    return None, f"tight re-solve failed: {last}"
