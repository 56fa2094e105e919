"""The techniques section of the benchmark (issue 38, items 3 and 4): the Schur complement helper against a dense
computation, the section's config refusals, and its report from synthetic rows. No timing is asserted."""

from __future__ import annotations

import numpy as np
import pytest

from workbench.studies.bench_config import BenchConfig
from workbench.studies.bench_report import to_markdown
from workbench.studies.config import to_json

# A Schur complement of a well-conditioned 40 x 40 matrix from MUMPS against numpy's: round-off only, so 1e-12
# relative to the largest entry is ~1e4 eps of headroom.
ROUND_OFF = 1e-12


def _spd_matrix(n: int, seed: int = 0):
    rng = np.random.default_rng(seed)
    B = rng.standard_normal((n, n))
    M = B @ B.T
    M[np.abs(M) < 2.0] = 0.0  # sparse-ish, still symmetric
    return 0.5 * (M + M.T) + n * np.eye(n)


def test_schur_complement_equals_the_dense_formula():
    """S = A_cc - A_ci A_ii^-1 A_ic for unknowns given in any order (S is in sorted order of the rows)."""
    import dolfinx_solver  # noqa: F401

    from petsc4py import PETSc

    from fem.schur import schur_complement

    n = 40
    M = _spd_matrix(n)
    A = PETSc.Mat().createAIJ((n, n), comm=PETSc.COMM_SELF)
    A.setUp()
    A.setValues(range(n), range(n), M)
    A.assemble()
    rows = np.array([31, 2, 17, 39, 8])
    c = np.sort(rows)
    i = np.setdiff1d(np.arange(n), c)
    ref = M[np.ix_(c, c)] - M[np.ix_(c, i)] @ np.linalg.solve(M[np.ix_(i, i)], M[np.ix_(i, c)])
    sf = schur_complement(A, rows)
    assert sf.S.shape == (5, 5)
    assert np.abs(sf.S - ref).max() <= ROUND_OFF * np.abs(ref).max()
    assert sf.factor_s >= 0 and sf.extract_s >= 0 and sf.dense_lu_s >= 0
    with pytest.raises(ValueError, match="rows must be distinct"):
        schur_complement(A, np.array([1, 1]))
    with pytest.raises(ValueError, match="rows must be distinct"):
        schur_complement(A, np.array([n]))
    A.destroy()


@pytest.mark.parametrize("kw, msg", [
    ({"technique_meshes": (("coarse", 0.1),)}, "technique_meshes"),
    ({"technique_meshes": (("graded", 0.0),)}, "technique_meshes"),
    ({"schur_zone": 0.0}, "schur_zone must be > 0"),
    ({"schur_max_dofs": 0}, "schur_max_dofs must be an integer >= 1"),
    ({"scale_nested": {"coarse": 8.0}}, "scale_nested must map a family"),
    ({"scale_nested": {"graded": 1.0}}, "scale_nested must map a family"),
    ({"scale_nested_coarsest": 0.0}, r"scale_nested_coarsest must be in \(0, 1\]"),
    ({"scale_nested_coarsest": True}, r"scale_nested_coarsest must be in \(0, 1\]"),
    ({"worker_malloc": 32}, "worker_malloc must be a string of glibc malloc tunables"),
])
def test_the_section_config_refuses_bad_values(kw, msg):
    with pytest.raises(ValueError, match=msg):
        BenchConfig(**kw)


def test_report_lists_every_technique_with_its_figure():
    """A skipped condensation says why with its dense size; a failed variant is named; the others give their
    linear solves and Newton iterations."""
    cond_run = {"n_schur": 152, "zone_over_a": 1.5, "dense_mb": 0.18, "plain_factor_s": 1.0, "factor_s": 1.3,
                "extract_s": 0.001, "dense_lu_s": 0.001, "total_s": 1.302, "linear_solves": 1.66, "peak_rss_mb": 900.0}
    cond_skip = {"n_schur": 21352, "zone_over_a": 1.5, "dense_mb": 3478.0, "plain_factor_s": 0.4,
                 "skipped": "n_c = 21352 > schur_max_dofs = 6000"}
    variant = {"variant": "row's options", "petsc_options": {}, "overrides": {}, "solve_s": 1.2,
               "linear_solves_equivalent": 1.5, "newton_iterations": [2], "failed_iterations": 0,
               "triangular_solves": 3, "rel_diff_P": 0.0}
    rows = [{"family": "uniform", "h_over_a": 0.1, "ndofs": 161202, "linear_kind": "lu_reuse",
             "condensation": cond_run, "variants": [variant]},
            {"family": "graded", "h_over_a": 0.00078125, "ndofs": 88208, "linear_kind": "lu_reuse",
             "condensation": cond_skip,
             "variants": [variant, {"variant": "Eisenstat-Walker forcing (snes_ksp_ew)",
                                    "failed": "ContactSolveError: x"}]}]
    text = to_markdown({"load_avg_start": (1.0, 1.0, 1.0), "cpu_count": 2, "techniques": {"rows": rows},
                        "config": to_json(BenchConfig())})
    assert "| uniform | 0.1 | 161202 | 152 | 0.18 | 1 | 1.3 | 0.001 | 0.001 | 1.66 | 900 |" in text
    assert "not run: n_c = 21352 > schur_max_dofs = 6000" in text
    assert "| graded | 0.00078125 | 88208 | lu_reuse | Eisenstat-Walker forcing (snes_ksp_ew) | failed: " in text
    assert "| uniform | 0.1 | 161202 | lu_reuse | row's options | 1.2 | 1.5 | [2] | 0 | 3 | 0.0e+00 |" in text


def test_a_nested_scale_row_names_its_coarse_solve():
    """Section 3 says which family nests and each nested row gives its coarse mesh's dofs, time and iterations."""
    row = {"family": "graded", "h_over_a": 0.00078125, "ndofs": 88208, "overrides": {"predictor": "hertz_zone",
           "linear_solver": "auto"}, "linear_kind": "lu_reuse", "newton_iterations": [2, 1, 1], "solve_s": 0.63,
           "linear_s": 0.325, "linear_solves_equivalent": 1.94, "rms": 0.0018, "peak_rss_mb": 506.0,
           "events": {"MatLUFactorSym": {"count": 2}, "MatLUFactorNum": {"count": 2}, "MatSolve": {"count": 14}},
           "linear_by_kind_s": {}, "nested": {"factor": 8.0, "ndofs": 11004, "solve_s": 0.05,
                                              "newton_iterations": [2, 0]}}
    fit = {"all": {"exponent": 1.1}, "largest3": None}
    sc = {"graded": {"rows": [row], "fits": {"solve_s": fit, "linear_s": fit}}}
    from workbench.studies.bench_report import _md_scale

    text = "\n".join(_md_scale(sc, [], BenchConfig()))
    assert "nested iteration (graded from h x 16 where that h is at most a x 0.02)" in text
    assert "hertz_zone, auto, nested from h x 8 (11004 dofs, 0.05 s, its [2, 0]) | [2, 1, 1] |" in text


def test_the_cost_workers_run_with_the_malloc_tunables(monkeypatch):
    """The cost-growth and techniques workers get glibc's malloc tunables of the config (none when empty, and a
    GLIBC_TUNABLES the user set wins)."""
    from workbench.studies.bench_measure import malloc_env

    monkeypatch.delenv("GLIBC_TUNABLES", raising=False)
    cfg = BenchConfig()
    assert malloc_env(cfg) == {"GLIBC_TUNABLES": cfg.worker_malloc} and "mmap_threshold" in cfg.worker_malloc
    assert malloc_env(BenchConfig(worker_malloc="")) == {}
    monkeypatch.setenv("GLIBC_TUNABLES", "glibc.malloc.arena_max=1")
    assert malloc_env(cfg) == {}
