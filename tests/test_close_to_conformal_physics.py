"""Issue 28: the close-to-conformal case's physics at CI level, with tolerances that hold on any correct mesh.

One CI-level run of ``cases/close_to_conformal.toml`` (module fixture), and once more with the case's h_contact
scaled by 0.97 (emulates another machine's gmsh mesh: the CI meshes of the concave cases differ between machines,
e.g. 11800 against 11856 dofs for concave_symmetric). Every check below is a physical statement of the paper
(/work/shared/papers/001_...) or of this design (docs/concave_design.md), with a band derived from what the
quantity is, not from one machine's number:

1. Patch topology: one patch at d = 0.46 (the secondary pair's rigid gap is still 0.0056 mm), two separate
   patches at d = 0.47, 0.48, 0.50 (each holding its own LCP pair), one merged patch holding both pairs from
   d = 0.70 on (merge step 0.70). Margins: at d = 0.50 the patches are 1.2 mm apart (~40 contact elements);
   in the merged patch at d = 0.70 the pressure between the pairs stays above 32 % of the peak (measured).
2. P-delta curve against an independent estimate: the Richardson-extrapolated (grid-converged) P of each
   step from the make-run error budget (h_c = 0.1, 0.07, 0.05 x the patch estimate; observed orders 2.2 to
   3.1). Band: the CI level's own discretisation error (measured 0.39 % at d = 0.46, where the patch spans the
   fewest elements, h/a = 0.2; <= 0.033 % at every later step where the patches are 3 to 40x wider) times 2.5,
   i.e. 1 % at the first step and 0.1 % after. The 0.97 mesh moved P by 2.5e-4 at most.
3. Hertz where the paper finds it, not where it does not:
   - the isolated secondary patch (d = 0.47, R = 23.8 mm, a/R = 0.003) follows Hertz eq. (5): its moment
     width 4 sqrt(M2/M0) equals eq. (5)'s 2a at the patch's own load within 3 % (half-plane error O(a/R) =
     0.3 %, quadrature error of the moments at h/a ~ 0.45 measured 0.6 % on the 0.97 mesh);
   - the close-to-conformal primary patch does not: eq. (5) with its R = 234 mm over-predicts the width
     by a factor 1.8 to 2.1 at d = 0.47 to 0.50 (measured on both meshes): the check asks > 1.5;
4. The non-elliptic pressure: even the best least-squares superposition of the pairs' Hertz patches misses
   the merged patch by RMS/p0 = 0.24 (d = 0.70) and 0.32 (d = 1.00), while at d = 0.46 (one small Hertzian
   patch) the superposition at the FEM patch load matches to 0.022 (the h/a = 0.2 discretisation). The check:
   merged > 0.15, first step < 0.05: the gap between them is 5x the discretisation level on both sides.
   While the patches are apart, the superposition at the FEM patch loads is within 0.005 (0.015 at d = 0.50)
   of the best one.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401

from pathlib import Path

import pytest
from mpi4py import MPI

from cases import load_case
from workbench.pipeline.run_case import run_one

D_STEPS = [0.46, 0.47, 0.48, 0.50, 0.70, 1.00]
N_PATCHES = [1, 2, 2, 2, 1, 1]
MERGE_D = 0.70
# Grid-converged P (N/mm) of each step: Richardson extrapolation of the make-run error budget over
# h_c = 0.1, 0.07, 0.05 (main 7402bd3, tests/data/key_numbers_run.json "error_budget/stepK ... P/extrapolated";
# the extrapolated value is mesh-independent to ~1e-4, far inside the bands below).
P_CONVERGED = [30.0775, 992.730, 2365.758, 5435.815, 47139.96]
P_BAND = [1e-2, 1e-3, 1e-3, 1e-3, 1e-3]
SECONDARY_HERTZ_TOL = 0.03
PRIMARY_EQ5_OVER_FEM_MIN = 1.5
MERGED_BEST_RMS_MIN = 0.15
FIRST_RMS_MAX = 0.05
SUPERPOSITION_GAP_MAX = (0.005, 0.005, 0.005, 0.015)


@pytest.fixture(scope="module", params=[1.0, 0.97], ids=["ci-mesh", "ci-mesh-x0.97"])
def steps(request, tmp_path_factory):
    """The per-step metrics of one CI-level run (h_contact = ci_level x the parameter)."""
    case = load_case("close_to_conformal")
    run = case.runs(h_contact=case.discretisation.ci_level * request.param)[0]
    o = run_one(run, name="close_to_conformal", mesh_cache=Path(tmp_path_factory.mktemp("mesh")),
                comm=MPI.COMM_WORLD, progress=lambda _m: None)
    return o.metrics["steps"]


def test_steps_are_table1(steps):
    assert [s["d"] for s in steps] == pytest.approx(D_STEPS, abs=1e-12)


def test_patches_separate_then_merge(steps):
    assert [s["n_patches"] for s in steps] == N_PATCHES
    for s in steps:
        pairs = [e["pairs"] for e in s["patches"]]
        if s["n_patches"] == 2:  # each patch holds its own pair: primary (0) left, secondary (1) right
            assert pairs == [[0], [1]], (s["d"], pairs)
            gap = (s["patches"][1]["center"] - s["patches"][1]["half_width"]) - \
                  (s["patches"][0]["center"] + s["patches"][0]["half_width"])
            assert gap > 0, (s["d"], gap)
        elif s["d"] >= MERGE_D:  # merged: one patch spanning both pairs
            assert pairs == [[0, 1]], (s["d"], pairs)
    merge = next(s["d"] for k, s in enumerate(steps) if k > 0 and s["n_patches"] < steps[k - 1]["n_patches"])
    assert merge == pytest.approx(MERGE_D)


def test_p_delta_against_the_grid_converged_curve(steps):
    deltas = [s["delta_lcp"] for s in steps]
    P = [s["P"] for s in steps]
    assert all(b > a for a, b in zip(deltas, deltas[1:], strict=False))
    assert all(b > a for a, b in zip(P, P[1:], strict=False))
    for s, ref, band in zip(steps, P_CONVERGED, P_BAND, strict=False):
        assert abs(s["P"] / ref - 1.0) <= band, (s["d"], s["P"], ref, band)
    # the contact stiffens as the patches grow and merge: the secant stiffness dP/d(delta) rises at every step
    k = [(P[i + 1] - P[i]) / (deltas[i + 1] - deltas[i]) for i in range(len(P) - 1)]
    assert all(b > a for a, b in zip(k, k[1:], strict=False)), k


def test_isolated_secondary_patch_is_hertzian(steps):
    s = steps[1]  # d = 0.47: the secondary patch has just formed, far from the primary
    sec = s["patches"][1]
    (w5,) = sec["width_eq5"]
    assert abs(sec["width_moment"] / w5 - 1.0) <= SECONDARY_HERTZ_TOL, (sec["width_moment"], w5)


def test_close_to_conformal_primary_is_not_hertzian(steps):
    for s in steps[1:4]:
        prim = s["patches"][0]
        (w5,) = prim["width_eq5"]
        assert w5 / prim["width_moment"] > PRIMARY_EQ5_OVER_FEM_MIN, (s["d"], w5, prim["width_moment"])


def test_superposition_at_the_patch_loads_is_the_best_while_the_patches_are_apart(steps):
    """While each pair has its own patch (d <= 0.50), the paper's superposition (each Hertz patch at its FEM
    patch's load) is as close to the FEM as the best least-squares choice of the loads: equilibrium fixes each
    patch's load. Measured: independent - best RMS/p0 = 0.0012, 0.0020, 0.0020, 0.0067 (both meshes); bands
    0.005 at the first three steps and 0.015 at d = 0.50 (where the secondary patch has grown less Hertzian, fit
    RMS/p0 0.125): 2.2 to 4x the measured. A superposition sum that scales the Hertz pressures by 1.1 fails it
    (tools/mutations.py); one that keeps only the last patch does not (the best fit uses the same sum): that one is
    caught by tests/test_analytic_superposition.py."""
    for s, band in zip(steps[:4], SUPERPOSITION_GAP_MAX, strict=True):
        gap = s["superposition_independent_rms_over_p0"] - s["superposition_best_rms_over_p0"]
        assert -1e-9 <= gap <= band, (s["d"], gap, band)


def test_merged_pressure_is_not_a_hertz_superposition(steps):
    first = steps[0]
    assert first["superposition_independent_rms_over_p0"] < FIRST_RMS_MAX
    assert first["superposition_best_rms_over_p0"] < FIRST_RMS_MAX
    for s in steps:
        if s["d"] >= MERGE_D:
            assert s["superposition_best_rms_over_p0"] > MERGED_BEST_RMS_MIN, s["d"]
            assert s["superposition_independent_rms_over_p0"] > MERGED_BEST_RMS_MIN, s["d"]
