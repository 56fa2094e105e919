"""The concave error budget (issue 12, point 5) on synthetic step metrics (no FEM: fast).

Requirement: every step's P, peak, patch loads and widths carry a GCI over the three grids; the mirror pairs'
load ratio is checked against 1 and fails when the loads differ beyond the band; a pair's first-contact width
is compared with Hertz eq. (5) once, at its activation; a step whose patch count differs between grids is
named, and a non-finite value gives an undefined row, never a silent gap.
"""

from __future__ import annotations

import math

from analytic import hertz
from workbench.scenes.concave_budget import _run_rows

LEVELS = [0.0125, 0.025, 0.05]
E_STAR = 235164.8


def _patch(P, width, s_pair_index):
    return {"P": P, "p_max": 4 * P / (math.pi * width), "width_fem": width, "width_moment": width,
            "width_eq4": width * 1.001, "pairs": [s_pair_index]}


def _step(d, loads, widths, *, pairs):
    patches = [_patch(P, w, k) for k, (P, w) in enumerate(zip(loads, widths, strict=True))]
    P = sum(loads)
    return {"d": d, "P": P, "P_pressure": P * (1 + 1e-15), "p_max": max(p["p_max"] for p in patches),
            "patches": patches, "lcp_pairs": pairs}


PAIRS = [{"s": 12.23, "R": 5.2368, "delta": 0.085}, {"s": 21.25, "R": 5.2368, "delta": 0.085}]


def _levels(asym=0.0):
    """Three grids of a two-step run; the load of patch 1 is off by ``asym`` (relative) on every grid."""
    out = []
    for h in LEVELS:
        e = h**2  # second-order convergence of every quantity
        loads = [7300.0 * (1 + e), 7300.0 * (1 + e) * (1 + asym)]
        out.append([_step(0.6, loads, [0.91 * (1 + e), 0.91 * (1 + e)], pairs=PAIRS),
                    _step(0.8, [27800.0 * (1 + e)] * 2, [1.78 * (1 + e)] * 2,
                          pairs=[dict(p, s=p["s"] + 0.1) for p in PAIRS])])
    return out


def test_every_step_quantity_has_a_gci_and_the_contract_keys():
    rows = _run_rows(LEVELS, _levels(), E_star=E_STAR, pre="")
    for step in ("step1 (d = 0.6 mm)", "step2 (d = 0.8 mm)"):
        for q in ("P", "p_max", "patch_P[0]", "patch_P[1]", "width_fem[0]", "width_moment[1]", "load_symmetry"):
            r = rows[f"{step} {q}"]
            assert {"fine", "extrapolated", "observed_order", "gci", "truncation", "theory",
                    "theory_in_band"} <= set(r), q
            assert r["gci"] is not None and r["truncation"] == 0.0, (step, q, r)
        assert rows[f"{step} P"]["load_balance_by_h"]["0.05"] < 1e-14
    r = rows["step1 (d = 0.6 mm) patch_P[0]"]
    assert abs(r["observed_order"] - 2.0) < 1e-6 and abs(r["extrapolated"] - 7300.0) < 1e-6
    eq5 = hertz.patch_width_eq5(r["extrapolated"], 5.2368, E_STAR)
    assert abs(rows["step1 (d = 0.6 mm) width_moment[0]"]["theory"] - eq5) < 1e-12


def test_load_symmetry_holds_and_fails_beyond_the_band():
    rows = _run_rows(LEVELS, _levels(), E_star=E_STAR, pre="")
    assert rows["step1 (d = 0.6 mm) load_symmetry"]["theory_in_band"] is True
    assert rows["step1 (d = 0.6 mm) load_symmetry"]["theory"] == 1.0
    bad = _run_rows(LEVELS, _levels(asym=1e-3), E_star=E_STAR, pre="")
    assert bad["step1 (d = 0.6 mm) load_symmetry"]["theory_in_band"] is False


def test_first_contact_width_once_per_pair_at_its_activation():
    rows = _run_rows(LEVELS, _levels(), E_star=E_STAR, pre="")
    first = sorted(k for k in rows if "first_contact_width" in k)
    assert first == ["step1 (d = 0.6 mm) first_contact_width[0]", "step1 (d = 0.6 mm) first_contact_width[1]"]
    r = rows[first[0]]
    assert r["alt_theory"] == "eq. (4)" and "alt_in_band" in r


def test_patch_count_change_and_nan_are_named():
    lv = _levels()
    lv[2][1]["patches"] = lv[2][1]["patches"][:1]          # coarse grid: one patch at step 2
    lv[1][0]["patches"][0]["width_moment"] = math.nan       # a failed moment on the middle grid
    rows = _run_rows(LEVELS, lv, E_star=E_STAR, pre="")
    assert "patch count differs" in rows["step2 (d = 0.8 mm) patches"]["status"]
    assert not any(k.startswith("step2 (d = 0.8 mm) width") for k in rows)
    r = rows["step1 (d = 0.6 mm) width_moment[0]"]
    assert r["gci"] is None and r["theory_in_band"] is None and r["by_h"]["0.025"] is None
    assert "undefined" in r["status"]
