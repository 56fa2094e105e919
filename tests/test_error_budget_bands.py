"""Issue 22, point 3: the band arithmetic on sequences that converge, cross the limit, oscillate, stall at a
tolerance floor or sit at round-off (workbench/error_budget.py, the rows of workbench/scenes/block_budget.py and
workbench/scenes/concave_budget.py). Synthetic sequences and measured ones; no FEM.
"""

from __future__ import annotations

import math

import pytest

from workbench.error_budget import (
    FS,
    FS_FORMAL,
    ITERATIVE_FLOOR,
    ROUNDOFF_FLOOR,
    grid_study,
    iterative_error,
    uncertainty,
)
from workbench.scenes.block_budget import _study
from workbench.scenes.concave_budget import _row, symmetry_row

H = (0.0125, 0.025, 0.05)  # the budget levels (fine first)


def test_monotone_asymptotic_sequence_keeps_its_order_and_limit():
    f = tuple(1.0 + 0.02 * h**2 for h in H)
    g = grid_study(H, f, reference=1.0, floor=1e-12, formal_order=2.0)
    assert g.status == "asymptotic" and g.observed_order == pytest.approx(2.0, rel=1e-9)
    assert g.extrapolated == pytest.approx(1.0, abs=1e-15) and g.band_order == pytest.approx(2.0)
    assert g.gci == pytest.approx(FS * abs(f[1] - f[0]) / f[0] / 3.0, rel=1e-9) and g.contains(1.0)


def test_sequence_that_crosses_the_theory_is_not_extrapolated():
    """The concave load symmetry of issue 22 (step 2, another machine): 0.9999954, 0.99999921, 1.00000006 from
    the coarse grid to the fine one. Alone it looks asymptotic (order 2.17) and its band excludes 1; told the
    theory, the study sees the error change sign and takes the band from the spread."""
    f = (1.00000006, 0.99999921, 0.9999954)   # fine, middle, coarse
    blind = grid_study(H, f)
    assert blind.status == "asymptotic" and blind.observed_order == pytest.approx(2.17, abs=0.01)
    # it extrapolates away from 1 (1.0000003 with a GCI of 3.05e-7: at the edge of its band, outside on the
    # issue's unrounded values)
    assert blind.extrapolated - 1.0 > f[0] - 1.0 > 0
    g = grid_study(H, f, reference=1.0)
    assert g.status == "crossing" and math.isnan(g.observed_order) and g.extrapolated == f[0]
    assert g.gci == pytest.approx(FS * (max(f) - min(f)) / f[0])
    assert g.contains(1.0)
    # a theory outside the range of the values is not crossed: the same sequence still excludes 1.00001
    far = grid_study(H, f, reference=1.00001)
    assert far.status == "asymptotic" and not far.contains(1.00001)


def test_oscillating_sequence_gets_the_spread():
    f = (0.99999976, 1.0000010, 0.9999954)    # the same step on this machine: the differences change sign
    g = grid_study(H, f, reference=1.0)
    assert g.status == "oscillating" and math.isnan(g.observed_order) and g.extrapolated == f[0]
    assert g.gci == pytest.approx(FS * max(abs(f[1] - f[0]), abs(f[2] - f[0])) / f[0])


def test_sequence_stalled_at_the_tolerance_floor_claims_no_order():
    """The fine pair differs by less than the iterative floor: an order from it would be an order of noise."""
    f = (1.0 + 2e-11, 1.0 + 5e-11, 1.0 + 4e-6)
    noisy = grid_study(H, f)
    assert noisy.status == "asymptotic" and noisy.observed_order > 15   # what the noise would claim
    g = grid_study(H, f, floor=1e-10)
    assert g.status == "stalled" and math.isnan(g.observed_order) and g.extrapolated == f[0]
    assert g.gci == pytest.approx(FS * (max(f) - min(f)) / f[0])
    both = grid_study(H, (1.0, 1.0 + 3e-11, 1.0 - 2e-11), floor=1e-10)   # every difference within the floor
    assert both.status == "converged" and both.gci == 0.0


def test_observed_order_above_the_formal_order_does_not_narrow_the_band():
    """Order 4 on three grids (the Hertz moment half-width): the Richardson value keeps order 4, the GCI is
    Roy's Fs = 3 at the formal order 2 where that is wider."""
    f = tuple(0.99638 - 3e-2 * h**4 for h in H)
    g = grid_study(H, f, formal_order=2.0)
    assert g.observed_order == pytest.approx(4.0, rel=1e-6) and g.extrapolated == pytest.approx(0.99638, abs=1e-12)
    assert g.band_order == 2.0
    assert g.gci == pytest.approx(FS_FORMAL * abs(f[1] - f[0]) / f[0] / 3.0, rel=1e-12)
    assert g.gci > FS * abs(f[1] - f[0]) / f[0] / 15.0
    slow = grid_study(H, tuple(1.0 + 0.1 * h for h in H), formal_order=2.0)   # below it: Roache's GCI as it was
    assert slow.band_order == pytest.approx(1.0) and slow.gci == pytest.approx(FS * 0.1 * 0.0125 / slow.fine)


def test_round_off_floor_and_iterative_terms():
    assert iterative_error(1.0, None) is None
    assert iterative_error(2.0, 2.0) == ITERATIVE_FLOOR                # unchanged by the tight solve
    assert iterative_error(2.0, 2.0 + 2e-8) == pytest.approx(1e-8)
    assert uncertainty(1e-6, None, 2e-7, ROUNDOFF_FLOOR) == pytest.approx(1.2e-6 + ROUNDOFF_FLOOR)
    # a ratio equal on every grid: GCI 0, the band is the round-off floor plus the iterative floor
    r = _row(list(H), [1.0 + 5e-10] * 3, 1.0, tight=1.0 + 5e-10)
    assert r["status"] == "converged" and r["gci"] == 0.0 and r["iterative"] == ITERATIVE_FLOOR
    assert r["uncertainty"] == pytest.approx(ROUNDOFF_FLOOR + ITERATIVE_FLOOR) and r["theory_in_band"]
    off = _row(list(H), [1.0 + 2e-9] * 3, 1.0, tight=1.0 + 2e-9)
    assert not off["theory_in_band"]
    # the iterative error measured by the tight solve widens the band and is recorded as its own term
    it = _row(list(H), [1.0 + 2e-9] * 3, 1.0, tight=1.0 + 2e-9 - 3e-9)
    assert it["iterative"] == pytest.approx(3e-9, rel=1e-6) and it["theory_in_band"]
    assert _row(list(H), [1.0] * 3, 1.0, tight_note="tight re-solve failed: x")["iterative_status"] == (
        "tight re-solve failed: x")


def _loads(u):
    return [{"uncertainty": u}, {"uncertainty": u}]


def test_load_symmetry_passes_on_any_correct_mesh_and_fails_when_asymmetric():
    """Issue 22: the symmetry of an asymmetric mesh is checked on the fine ratio, within the two patch loads'
    uncertainties (measured 1.4e-5 to 1.8e-5 each on concave_symmetric)."""
    for ratios in ((1.00000006, 0.99999921, 0.9999954),    # another machine (monotone, crosses 1)
                   (0.99999976, 1.0000010, 0.9999954),     # this machine (oscillating)
                   (1.0 - 3e-7, 1.0 - 1e-6, 1.0 - 4e-6)):  # a mesh whose asymmetry converges from one side
        r = symmetry_row(list(H), list(ratios), _loads(1.5e-5), tight=ratios[0])
        assert r["theory_in_band"], (ratios, r)
        assert r["extrapolated"] == ratios[0] and r["symmetry_band"] == pytest.approx(3e-5)
    # a genuinely asymmetric solution: the two loads differ by 1e-3 on every grid, far beyond their uncertainty
    bad = symmetry_row(list(H), [1.001, 1.001 + 1e-7, 1.001 + 4e-7], _loads(1.5e-5), tight=1.001)
    assert not bad["theory_in_band"] and bad["error_vs_theory"] == pytest.approx(1e-3)
    # and 1e-4 (a biased contact search) fails too: the check is not wider than the loads' own error
    assert not symmetry_row(list(H), [1.0001, 1.0001, 1.0001 + 1e-6], _loads(1.5e-5))["theory_in_band"]


def test_wide_contact_rows_from_the_measured_sequences():
    """The a/R = 0.17 copy of hertz_cylinder (issue 22), its measured values (h_c = a/80, a/40, a/20 at W = 1e4 a;
    W = 640, 2560, 1e4 a at a/80): p_max crosses the exact circle between a/40 and a/80 (crossing: spread band),
    the moment half-width's order 5.0 is not trusted (band at order 2). Both now contain the exact circle and
    exclude Hertz (1.0), 1.8e-3 and 3.6e-3 away."""
    p = _study([0.0125, 0.025, 0.05], [640.0, 2560.0, 10000.0],
               [1.001813864511879, 1.0018153520837028, 1.0018314410886138],
               [1.0018140895022911, 1.0018137979459916, 1.001813864511879], 1.0018153066162803, ("hertz", 1.0),
               tight=1.001813864511879)
    assert p["status"] == "crossing" and p["theory_in_band"] and not p["alt_in_band"]
    m = _study([0.0125, 0.025, 0.05], [640.0, 2560.0, 10000.0],
               [0.9963805373302168, 0.9963755366394792, 0.9962170321801861],
               [0.9963804343564518, 0.9963805843255931, 0.9963805373302168], 0.99638253820702, ("hertz", 1.0),
               tight=0.9963805373302168)
    assert m["status"] == "asymptotic" and m["band_order"] == 2.0 and abs(m["observed_order"] - 5.0) < 0.05
    assert m["theory_in_band"] and not m["alt_in_band"]
    for r in (p, m):
        assert r["uncertainty"] == pytest.approx(r["gci"] + r["truncation"] + r["iterative"] + r["roundoff"])
        assert r["roundoff"] == ROUNDOFF_FLOOR and r["iterative"] == ITERATIVE_FLOOR


def test_tight_resolve_divides_every_tolerance_and_falls_back():
    """The tight re-solve passes the tolerances / 100 (SNES atol 1e-13 E L / 100), then / 10, then gives up with
    the solver's reason (the row then says so in ``iterative_status``); it starts warm, from the finest run's
    converged states, and scales the atol by the stiffest body's E."""
    from types import SimpleNamespace

    import numpy as np
    from mpi4py import MPI

    from fem.solver import ContactSolveError
    from workbench.error_budget import WARM_MAX_IT, tight_resolve

    mesh = SimpleNamespace(comm=MPI.COMM_SELF, geometry=SimpleNamespace(x=np.array([[0.0, 0.0, 0], [20.0, 5.0, 0]])))
    warm = object()
    outcome = SimpleNamespace(result=SimpleNamespace(u=SimpleNamespace(function_space=SimpleNamespace(mesh=mesh)),
                                                     warm_start=warm))
    run = SimpleNamespace(label="base", material=SimpleNamespace(E=100.0), bodies=())
    tight = SimpleNamespace(result=SimpleNamespace(newton_iterations=[1, 0], wall_time_s=0.1))
    calls = []

    def solve(r, **kw):
        calls.append(kw)
        if len(calls) == 1:
            raise ContactSolveError("load step 1 diverged")
        return tight

    o, how = tight_resolve(solve, run, outcome, progress=lambda m: None)
    assert o is tight and how == 10.0
    assert calls[0]["snes_rtol"] == pytest.approx(1e-12) and calls[0]["force_rtol"] == pytest.approx(1e-12)
    assert calls[0]["uzawa_rtol"] == pytest.approx(1e-12)
    assert calls[0]["petsc_options"]["snes_atol"] == pytest.approx(1e-13 * 100.0 * 20.0 / 100)
    assert calls[1]["snes_rtol"] == pytest.approx(1e-11)
    # warm: from the converged states of the finest run, a few Newton iterations per solve (issue 38)
    assert all(c["warm_start"] is warm and c["max_it"] == WARM_MAX_IT for c in calls)
    # two bodies: the SNES atol scale is the stiffer body's E, as the problem's own (fem/two_body/problem.py)
    calls.clear()
    stiff = SimpleNamespace(material=SimpleNamespace(E=1e8))
    two = SimpleNamespace(label="small", material=SimpleNamespace(E=100.0),
                          bodies=(SimpleNamespace(material=SimpleNamespace(E=100.0)), stiff))
    tight_resolve(lambda r, **kw: calls.append(kw) or tight, two, outcome, progress=lambda m: None)
    assert calls[0]["petsc_options"]["snes_atol"] == pytest.approx(1e-13 * 1e8 * 20.0 / 100)

    def never(r, **kw):
        raise ContactSolveError("diverged: SNES reason -5")

    o, how = tight_resolve(never, run, outcome, progress=lambda m: None)
    assert o is None and how == "tight re-solve failed: diverged: SNES reason -5"
