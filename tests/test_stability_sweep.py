"""Stiff and extreme cases: named warnings, locking-free mixed formulation, scale invariance, conditioning.

Scene (workbench.studies.stability.Spec defaults): rigid circle R = 10 mm on a block 40 a x 40 a (half model),
a/R = 0.05, E = 200 GPa, P2, h = a/10, Nitsche gamma0 = 10, theta = 1, force control to the Hertz load; errors
against Hertz at the measured load (workbench.scenes.block_theory). Each solve takes ~0.1 s warm (plus ~1.5 s JIT
per new form).
"""

import dolfinx_solver  # noqa: F401

import dataclasses
import math

import numpy as np
import pytest
import scipy.sparse as sp
from mpi4py import MPI

from fem.conditioning import condition_1norm
from fem.solver import snes_reason_name
from workbench.studies.stability import (
    Spec,
    StabilityConfig,
    classify,
    classify_augmented_lagrangian,
    run_block_spec,
    run_sweep,
    specs,
)

COMM = MPI.COMM_WORLD
BAND = StabilityConfig().band


def _run(**kw):
    """Run a spec; keywords that are not Spec fields are its solver options (ContactOptions fields)."""
    own = {f.name for f in dataclasses.fields(Spec)}
    options = {k: kw.pop(k) for k in list(kw) if k not in own}
    return run_block_spec(Spec("test", "t", options=options, **kw), comm=COMM)


def _names(rec):
    return {w.split(":")[0] for w in rec["warnings"]}


def test_defaults_have_no_warning_and_meet_the_band():
    """Nitsche gamma0 = 10, theta = 1 (the defaults): no warning, errors 0.02 % / 0.4 % / 0.4 % measured."""
    rec = _run()
    assert rec["converged"] and rec["warnings"] == []
    assert max(rec["errors"][k] for k in ("p_max", "half_width", "rms")) <= BAND / 2
    assert classify(rec) == "ok"


def test_contact_unresolved_on_a_coarse_mesh():
    """h_c = 2 a: the patch spans ~2 contact facets (< 8) -> "contact unresolved", named in the status."""
    rec = _run(h_ratio=0.5)
    assert rec["converged"] and "contact unresolved" in _names(rec), rec["warnings"]
    assert classify(rec).startswith("named (warning): contact unresolved")


def test_penalty_warnings_at_both_ends():
    """kappa0 = 1: penetration 2.7 % of d (peak 10 % low) -> "penetration"; kappa0 = 1e5: the constraint is
    over-enforced at the Gauss points (RMS/p0 2.3 % against 0.4 %) -> "pressure oscillation"."""
    soft, stiff = _run(method="penalty", kappa0=1.0), _run(method="penalty", kappa0=1e5)
    assert "penetration" in _names(soft), soft["warnings"]
    assert "pressure oscillation" in _names(stiff), stiff["warnings"]
    assert "penetration" not in _names(stiff)


@pytest.mark.parametrize("nu", [0.3, 0.4999])
def test_mixed_formulation_is_locking_free(nu):
    """Taylor-Hood P2/P1: the same accuracy at nu = 0.3 and 0.4999 (measured p_max 0.08-0.1 %, half-width
    0.46-0.49 %, RMS 0.45-0.47 %); held to half the 2 % band."""
    rec = _run(nu=nu, formulation="mixed")
    assert rec["converged"] and rec["warnings"] == [], rec["warnings"]
    for k in ("p_max", "half_width", "rms"):
        assert rec["errors"][k] <= BAND / 2, (k, rec["errors"])
    assert rec["errors"]["load_balance"] <= 1e-10  # virtual work vs pressure integral: round-off


def test_displacement_formulation_near_incompressible_is_named():
    """P2 displacement at nu = 0.499: RMS/p0 8 % with an oscillating pressure; both causes are named."""
    rec = _run(nu=0.499)
    assert {"near-incompressible", "pressure oscillation"} <= _names(rec), rec["warnings"]
    assert classify(rec).startswith("named")


def test_scale_invariance_over_nine_decades():
    """E = 1e-3 and 1e6 MPa: p_max/E*, a/R and P/(E* R) agree to round-off (measured <= 1.2e-13; 1e-10 allows
    for the force-control stop |P - target| <= 1e-10 target)."""
    lo, hi = _run(E=1e-3), _run(E=1e6)
    for k, v in lo["nondim"].items():
        assert abs(v / hi["nondim"][k] - 1.0) <= 1e-10, (k, v, hi["nondim"][k])


def test_condition_estimate_grows_with_kappa0():
    """cond_1(J) / cond_1(K) ~ kappa0 once the penalty dominates (measured 8.6, 87, 853 at 1e3, 1e4, 1e5)."""
    c3 = _run(method="penalty", kappa0=1e3, condition=True)["condition"]
    c5 = _run(method="penalty", kappa0=1e5, condition=True)["condition"]
    assert 30.0 <= c5["cond_jacobian"] / c3["cond_jacobian"] <= 300.0, (c3, c5)


def test_condition_1norm_is_exact_for_a_diagonal_matrix():
    A = sp.diags([1.0, 10.0, 1e4])
    assert condition_1norm(A) == pytest.approx(1e4, rel=1e-12)


def test_snes_reason_names():
    assert snes_reason_name(-5) == "DIVERGED_MAX_IT" and snes_reason_name(-9) == "DIVERGED_DTOL"


def test_resolution_study_has_no_silent_run():
    """The resolution study end to end: every run ok or named; the coarsest ones are the named ones."""
    recs = run_sweep(StabilityConfig(studies=("resolution",)), progress=lambda _: None)
    status = {r["label"]: r["status"] for r in recs}
    assert not [k for k, v in status.items() if v == "SILENT"], status
    assert status["h_c = a/0.5"].startswith("named") and status["h_c = a/8"] == "ok", status


def test_classify_flags_a_silent_run():
    """Converged, out of band, no warning and no model limit: SILENT (the sweep exits 1 on it)."""
    rec = {"converged": True, "warnings": [], "params": {"band": 0.02},
           "errors": {"p_max": 0.05, "half_width": 0.0, "rms": 0.0, "load_balance": 0.0}}
    assert classify(rec) == "SILENT"
    rec["params"]["model_limit"] = "model limit: test"
    assert classify(rec).startswith("named (model limit)")
    assert math.isclose(rec["worst_error"], 0.05) and np.isfinite(rec["worst_error"])


def test_default_config_reproduces_the_published_sweep():
    """The typed config's defaults are the sweep as published: 88 runs before the AL sweep, labels as before,
    plus five augmented-Lagrangian runs, one per decade of kappa0, and (issue 15) the penalty sweep extended
    from 1e8 to 1e10 (two runs)."""
    all_specs = specs()
    labels = [s.label for s in all_specs]
    assert len(labels) == len(set(labels)) == 88 + 5 + 2
    assert "penalty kappa0=1e8" in labels and "penalty kappa0=1e10" in labels and "E=1e-3" in labels
    assert "nitsche gamma0=0.1 theta=-1" in labels
    al = [s for s in all_specs if s.study == "augmented_lagrangian"]
    k = [s.option("kappa0") for s in al]
    assert [s.option("method") for s in al] == ["augmented_lagrangian"] * 5
    assert math.isclose(math.log10(k[-1] / k[0]), 4.0) and len(k) == 5  # five decades of kappa0
    assert all(s.band == BAND for s in al)


def test_spec_becomes_a_case_run():
    """A spec is a cases.schema.Run (what the wiring reads) plus the study's solver overrides."""
    spec = Spec("test", "t", options=dict(method="penalty", kappa0=1e2, formulation="mixed"), nu=0.49, degree=1,
                h_ratio=40.0)
    run = spec.run()
    assert (run.solver.method, run.solver.kappa0, run.solver.traction) == ("penalty", 1e2, "halfplane")
    assert (run.material.nu, run.discretisation.degree, run.geometry.half_model) == (0.49, 1, True)
    assert run.loading.half_width == spec.a_over_R * spec.R and run.loading.steps == spec.n_steps
    assert spec.solver_overrides()["formulation"] == "mixed"
    fault = Spec("faults", "f", control="displacement", d=0.06, options=dict(active_set_predictor=False)).run()
    assert fault.loading.control == "displacement" and fault.loading.d == (0.06,)


def test_augmented_lagrangian_must_converge():
    """The AL sweep's own classification: a diverged run is FAILED (the sweep exits 1), not a named pass."""
    rec = {"converged": False, "error": "diverged: SNES reason -5 (DIVERGED_MAX_IT)\n...", "warnings": [],
           "params": {"band": BAND}, "errors": {}}
    assert classify(rec).startswith("named (failure)")
    assert classify_augmented_lagrangian(rec) == "FAILED (must converge): diverged: SNES reason -5 (DIVERGED_MAX_IT)"
    ok = {"converged": True, "warnings": [], "params": {"band": BAND},
          "errors": {"p_max": 0.001, "half_width": 0.004, "rms": 0.004, "load_balance": 0.0}}
    assert classify_augmented_lagrangian(ok) == "ok"


def _al_available() -> bool:
    from fem import contact_forms

    return "augmented_lagrangian" in getattr(contact_forms, "METHODS", ())


@pytest.mark.skipif(not _al_available(), reason="fem has no augmented_lagrangian method yet")
@pytest.mark.parametrize("kappa0", [1e1, 1e5])
def test_augmented_lagrangian_converges_at_both_ends(kappa0):
    """kappa0 = 1e1 and 1e5, the ends of the sweep: converged, within the 2 % band, no warning."""
    rec = _run(method="augmented_lagrangian", kappa0=kappa0)
    assert classify_augmented_lagrangian(rec) == "ok", (rec.get("error"), rec["warnings"], rec.get("errors"))
