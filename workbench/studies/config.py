"""Typed, frozen configurations of the studies: what each study runs, its bands, targets and output folder.

One record per study (:class:`ConvergenceConfig`, :class:`StabilityConfig`, :class:`BenchConfig`,
:class:`ConvectiveTableConfig`), like a case record: the defaults are the study as published, a study's
``main(argv)`` builds its record from the command-line options, and ``run_*`` takes it. Every study writes
its record into its JSON (``"config"``: :func:`to_json`), so a report reads what the study ran with from the
JSON alone; :func:`from_json` reads it back (defaults for keys an older JSON lacks).

This module is light (no dolfinx): the studies and their reports both import it, and neither imports the
other. Units: h_c and levels are fractions of the classical contact half-width; kappa0, gamma0 are
dimensionless (kappa = kappa0 E / h); times in s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from vocabulary import (
    ACTIVE_SET_UPDATES,
    ACTIVE_SETS,
    CONVECTIVE,
    FINITE,
    HALFPLANE,
    HYPERELASTIC_MODELS,
    LINEAR_SOLVERS,
    NITSCHE,
    OBSTACLE,
    PENALTY,
    SMALL,
)
from workbench.paths import default_paths
from workbench.studies.rates import N_FINEST

__all__ = ["BenchConfig", "ConvectiveTableConfig", "ConvergenceConfig", "StabilityConfig", "ValidityConfig",
           "VALIDITY_MODELS", "from_json", "to_json"]


def _is_decreasing(values) -> bool:
    return all(b < a for a, b in zip(values, values[1:], strict=False))


def _folder(given: Path | None, default: Path) -> Path:
    """``given`` (absolute), else the workbench default: never the working directory."""
    return Path(given).expanduser().resolve() if given is not None else default


# --- convergence --------------------------------------------------------------------------------------

_BIG = {"width_factor": 640.0, "height_factor": 640.0}


@dataclass(frozen=True)
class ConvergenceConfig:
    """Convergence study (:mod:`workbench.studies.convergence`): error against ndofs and warm run time.

    Attributes:
        cases: Block cases studied.
        levels: h_c of the ``case`` series, coarse to fine, in (0, 1].
        ideal_levels: h_c of the ``ideal`` series (growth 1 + growth_per_h h_c), in [0.025, 0.5].
        growth_per_h: Ideal series: growth - 1 = growth_per_h h_c, so the size field scales with h_c.
        growth_range: The case schema's range of the mesh growth.
        methods, degrees: Contact methods and Lagrange degrees of every series.
        n_finest: Levels in each rate fit (the finest ones).
        rms_target: The issue's target RMS/p_ref of the cheapest configuration.
        inner: ``l2_inner`` band |x| <= inner a.
        metrics: Error columns per case.
        time_of: Time column per metric (default ``time_s``).
        series: Geometry overrides of each series per case.
        expected_rates: ``case/series`` -> metric -> expected slope against h_c (derivation in the report).
        rate_band: |observed - expected| allowed.
        floors: Model-floor decomposition at the finest case level (geometry overrides), per case.
        kappa0_sweep, kappa0_level: Penalty factors of the sweep and its h_c.
        grading_probe: Ideal geometry with the case's fixed growth.
        extension: One ideal level beyond the study (a diagnostic below the schema's growth) and the
            perturbed h_c of the edge-position table.
        repeats: Timed warm solves per run after the warm-up solve (median kept), >= 1.
        diagnostics: Run floors, kappa0 sweep, grading probe and extension.
        plot: Write the plots.
        out: Output folder (default ``<results>/convergence``).  mesh_cache: Mesh cache folder.
    """

    cases: tuple[str, ...] = ("hertz_cylinder", "wedge_convective")
    levels: tuple[float, ...] = (0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625, 0.003125)
    ideal_levels: tuple[float, ...] = (0.4, 0.2, 0.1, 0.05, 0.025)
    growth_per_h: float = 2.0
    growth_range: tuple[float, float] = (1.05, 2.0)
    methods: tuple[str, ...] = (PENALTY, NITSCHE)
    degrees: tuple[int, ...] = (1, 2)
    n_finest: int = N_FINEST
    rms_target: float = 0.005
    inner: float = 0.8
    metrics: dict = field(default_factory=lambda: {
        "hertz_cylinder": ("p_max", "half_width", "rms", "l2", "l2_inner"),
        "wedge_convective": ("b_over_b0", "rms_convective", "half_width", "rms", "l2"),
    })
    time_of: dict = field(default_factory=lambda: {"b_over_b0": "time_pair_s", "rms_convective": "time_pair_s"})
    series: dict = field(default_factory=lambda: {
        "hertz_cylinder": {"case": {}, "ideal": {**_BIG, "indenter": "parabola"}},
        "wedge_convective": {"case": {}, "ideal": dict(_BIG)},
    })
    # The square-root edge of the Hertz pressure caps any L2 pressure error at h^1 (P1 and P2); the log apex
    # singularity of the wedge pressure caps it at h^(1/2). The Hertz case series sits on model floors.
    expected_rates: dict = field(default_factory=lambda: {
        "hertz_cylinder/ideal": {"rms": 1.0, "l2": 1.0},
        "wedge_convective/ideal": {"rms": 0.5, "l2": 0.5},
        "wedge_convective/case": {"rms": 0.5, "l2": 0.5},
    })
    rate_band: float = 0.15
    floors: dict = field(default_factory=lambda: {
        "hertz_cylinder": {"case (W = H = 40 a, circle)": {}, "W = H = 640 a, circle": dict(_BIG),
                           "W = H = 640 a, parabola": {**_BIG, "indenter": "parabola"}},
        "wedge_convective": {"W = H = 40 b0": {"width_factor": 40.0, "height_factor": 40.0},
                             "case (W = H = 160 b0)": {}, "W = H = 640 b0": dict(_BIG)},
    })
    kappa0_sweep: tuple[float, ...] = (1e2, 1e3, 1e4, 1e5)
    kappa0_level: float = 0.0125
    grading_probe: dict = field(default_factory=lambda: {"case": "hertz_cylinder", "series": "ideal",
                                                         "degrees": (1, 2)})
    extension: dict = field(default_factory=lambda: {"case": "hertz_cylinder", "series": "ideal", "level": 0.0125,
                                                     "perturbed": (0.0275, 0.0225, 0.0135, 0.0115)})
    repeats: int = 3
    diagnostics: bool = True
    plot: bool = True
    out: Path | None = None
    mesh_cache: Path | None = None

    @property
    def out_dir(self) -> Path:
        """The output folder: ``out``, else ``<results>/convergence``."""
        return _folder(self.out, default_paths().study("convergence"))

    @property
    def cache_dir(self) -> Path:
        """The mesh cache: ``mesh_cache``, else ``<results>/mesh_cache``."""
        return _folder(self.mesh_cache, default_paths().mesh_cache)

    def __post_init__(self) -> None:
        for key, lv in (("levels", self.levels), ("ideal_levels", self.ideal_levels)):
            if len(lv) < self.n_finest or any(not 0 < v <= 1 for v in lv) or not _is_decreasing(lv):
                raise ValueError(f"{key} must be >= {self.n_finest} strictly decreasing values in (0, 1], "
                                 f"got {list(lv)}")
        for v in self.ideal_levels:
            self.ideal_growth(v)
        if int(self.repeats) != self.repeats or self.repeats < 1:
            raise ValueError(f"repeats must be an integer >= 1, got {self.repeats!r}")
        if not self.rate_band > 0:
            raise ValueError(f"rate_band must be > 0, got {self.rate_band}")

    def ideal_growth(self, h_contact: float) -> float:
        """Mesh growth of the ideal series: 1 + growth_per_h h_c, so the size field scales with h_c.

        Raises:
            ValueError: the growth leaves the case schema's range (h_c outside [0.025, 0.5] by default).
        """
        lo_g, hi_g = self.growth_range
        g = 1.0 + self.growth_per_h * float(h_contact)
        if not lo_g - 1e-12 <= g <= hi_g + 1e-12:
            lo, hi = ((r - 1.0) / self.growth_per_h for r in self.growth_range)
            raise ValueError(f"h_contact must be in [{lo:g}, {hi:g}] for the ideal series, got {h_contact}")
        return float(min(max(g, lo_g), hi_g))


# --- stability ----------------------------------------------------------------------------------------

STABILITY_STUDIES = ("method", "augmented_lagrangian", "incompressible", "convective", "loads", "resolution",
                     "scale", "conformal", "faults", "two_body")


def _two_body_pairs() -> tuple[tuple[float, float, float], ...]:
    """(E_upper / E_lower, nu_lower, nu_upper) of the ``two_body`` study: E ratios 1e-3 ... 1e3 at nu = 0.3, nu =
    0.499 on either side, and both together at the extreme ratios (issue 24)."""
    ratios = tuple(10.0**k for k in range(-3, 4))
    return (tuple((r, 0.3, 0.3) for r in ratios) + ((1.0, 0.499, 0.3), (1.0, 0.3, 0.499))
            + tuple((r, nl, nu) for r in (1e-3, 1e3) for nl, nu in ((0.499, 0.3), (0.3, 0.499))))


@dataclass(frozen=True)
class StabilityConfig:
    """Stability sweep (:mod:`workbench.studies.stability`): stiff and extreme cases.

    Accuracy band: p_max, half-width and RMS/p0 errors <= ``band`` (2 %). At h = a/10 with P2 the edge is
    located within a fraction of one Gauss spacing (a/20 = 5 % of a); the defaults measure 0.02 % (peak) and
    0.4 % (half-width), so 2 % separates a sound run from a degraded one by a factor 5. P1 at h = a/40
    measures 2.0-2.4 % where nothing locks: its band is 4 % (``band_p1``). Wedge: the RMS/p_mean tolerance of
    cases/wedge_convective.toml, 3 % (``band_wedge``).

    Attributes:
        studies: The studies run, in report order.
        band, band_p1, band_wedge: Accuracy bands (relative).
        penalty_kappa0: Penalty factors of the ``method`` study (1e0 ... 1e10; above 1e5 the penalty is solved by
            relaxed Uzawa updates of its nodal law, :mod:`fem.methods.penalty`).
        nitsche_gamma0, nitsche_theta: Nitsche factors x variants of the ``method`` study.
        al_kappa0: Augmented-Lagrangian factors (five decades), every run expected to converge.
        incompressible_nu: Poisson ratios of the ``incompressible`` study.
        incompressible_elements: (degree, formulation, a/h) of that study.
        convective_runs: (nu, block W = H in b) of the ``convective`` study.
        convective_wedge_angle, convective_h_ratio, convective_mixed_from_nu: Its wedge, b/h and the nu from
            which the mixed formulation is used.
        loads_a_over_R, parabola_a_over_R, model_limit_a_over_R: The ``loads`` study (circle beyond the
            model limit is named, the parabola runs show why).
        resolution_h_ratio: a/h_c of the ``resolution`` study.
        scale_E, scale_reference_E: Young's moduli (MPa) of the ``scale`` study and its reference.
        conformal_d: Displacements (mm) of the close-to-conformal steps.
        fault_d: Displacement target (mm) of the ``faults`` study.
        two_body_case, two_body_pairs, two_body_h_ratio: The ``two_body`` study: the case whose scene is run (the
            elastic cylinder, through the scene registry) with (E_upper / E_lower, nu_lower, nu_upper) per point
            (the lower body keeps the case's E), at h_c = a / two_body_h_ratio, displacement formulation.
        two_body_newton: Newton iterations per load step a two-body point may take (issue 24: <= 4).
        out: Output folder (default ``<results>/stability``).  mesh_cache: Mesh cache folder.
    """

    studies: tuple[str, ...] = STABILITY_STUDIES
    band: float = 0.02
    band_p1: float = 0.04
    band_wedge: float = 0.03
    penalty_kappa0: tuple[float, ...] = tuple(10.0**k for k in range(11))
    nitsche_gamma0: tuple[float, ...] = (0.1, 1.0, 10.0, 100.0, 1e3, 1e4)
    nitsche_theta: tuple[int, ...] = (1, 0, -1)
    al_kappa0: tuple[float, ...] = tuple(10.0**k for k in range(1, 6))
    incompressible_nu: tuple[float, ...] = (0.0, 0.3, 0.45, 0.49, 0.499, 0.4999)
    incompressible_elements: tuple[tuple[int, str, float], ...] = ((1, "displacement", 40.0),
                                                                   (2, "displacement", 10.0), (2, "mixed", 10.0))
    convective_runs: tuple[tuple[float, float], ...] = ((0.0, 160.0), (0.3, 160.0), (0.45, 160.0), (0.49, 160.0),
                                                        (0.499, 160.0), (0.499, 20.0), (0.499, 40.0),
                                                        (0.499, 80.0))
    convective_wedge_angle: float = math.pi / 5
    convective_h_ratio: float = 40.0
    convective_mixed_from_nu: float = 0.45
    loads_a_over_R: tuple[float, ...] = (1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.2, 0.4)
    parabola_a_over_R: tuple[float, ...] = (0.2, 0.4)
    model_limit_a_over_R: float = 0.1
    resolution_h_ratio: tuple[float, ...] = (0.5, 1.0, 2.0, 4.0, 8.0, 16.0)
    scale_E: tuple[float, ...] = tuple(10.0**k for k in range(-3, 7))
    scale_reference_E: float = 1e3
    conformal_d: tuple[float, ...] = (0.46, 0.47, 0.48)
    fault_d: float = 0.06
    two_body_case: str = "elastic_cylinder"
    two_body_pairs: tuple[tuple[float, float, float], ...] = field(default_factory=_two_body_pairs)
    two_body_h_ratio: float = 10.0
    two_body_newton: int = 4
    out: Path | None = None
    mesh_cache: Path | None = None

    @property
    def out_dir(self) -> Path:
        """The output folder: ``out``, else ``<results>/stability``."""
        return _folder(self.out, default_paths().study("stability"))

    @property
    def cache_dir(self) -> Path:
        """The mesh cache: ``mesh_cache``, else ``<results>/mesh_cache``."""
        return _folder(self.mesh_cache, default_paths().mesh_cache)

    def __post_init__(self) -> None:
        bad = [s for s in self.studies if s not in STABILITY_STUDIES]
        if bad:
            raise ValueError(f"studies {bad} unknown; allowed: {', '.join(STABILITY_STUDIES)}")
        for key in ("band", "band_p1", "band_wedge"):
            if not getattr(self, key) > 0:
                raise ValueError(f"{key} must be > 0, got {getattr(self, key)}")
        for key in ("penalty_kappa0", "nitsche_gamma0", "al_kappa0", "scale_E"):
            if any(not v > 0 for v in getattr(self, key)):
                raise ValueError(f"every {key} must be > 0, got {list(getattr(self, key))}")
        if any(len(p) != 3 or not 1e-6 <= p[0] <= 1e6 or not all(-1.0 < v < 0.5 for v in p[1:])
               for p in self.two_body_pairs):
            raise ValueError(f"two_body_pairs must be (E ratio in [1e-6, 1e6], nu_lower, nu_upper in (-1, 0.5)) "
                             f"triples, got {list(self.two_body_pairs)[:4]}")


# --- bench --------------------------------------------------------------------------------------------


def _solver_variants() -> dict:
    """label -> (petsc_options, solver overrides) of section 5b."""
    return {
        "case (MUMPS LU per Newton iteration)": ({}, {}),
        "MUMPS ICNTL(7)=5 (METIS ordering)": ({"mat_mumps_icntl_7": 5}, {}),
        "PETSc LU, nd ordering, reuse_ordering": (
            {"pc_factor_mat_solver_type": "petsc", "pc_factor_mat_ordering_type": "nd",
             "pc_factor_reuse_ordering": True},
            {},
        ),
        "3 load steps (n_steps=3, the previous case default)": ({}, {"n_steps": 3}),
    }


BENCH_SECTIONS = ("accuracy", "linear", "scale", "mpi", "cache", "options", "predictor_free", "two_body", "startup")
SCALE_PREDICTORS = ("auto", "hertz_zone")  # the force-control predictors of the cost-growth rows
SCALE_FAMILIES = ("graded", "uniform")


@dataclass(frozen=True)
class BenchConfig:
    """Performance benchmark (:mod:`workbench.studies.bench`).

    Attributes:
        case: The case benchmarked.
        rms_target: The issue's RMS(p - p_H)/p0 target.
        baseline_kappa: Baseline penalty stiffness kappa = baseline_kappa E / (1 mm): fixed, not scaled by 1/h.
        baseline_force_rtol: Baseline force tolerance (ours: the case default 1e-10).
        baseline_ladder: Baseline (W = H in a, uniform h in a) rungs, cheapest first (half model, P2: 41k,
            161k, 642k dofs). W = H = 20 a is the smallest box whose size error alone stays below the target
            (graded Nitsche P2 at W = H = 5, 10, 20, 40 a: rms 3.7 %, 1.1 %, 0.45 %, 0.23 %).
        our_levels: h_c of our ladders.  our_methods, our_degrees: our configurations.
        scale: Cost growth, family -> h / a: ``graded`` (meshes.block, ndofs ~ 1/h_c) and ``uniform`` (the
            baseline's uniform box, ndofs ~ 1/h^2, up to ~1e6 dofs).
        scale_box: W = H of the uniform family (in a).
        small_ndofs: Below this a size is timed 3 times in its process (best kept).
        mpi_levels: h_c of the MPI comparisons (None: the case default).
        option_level: h_c of the solver-options comparison (graded, ~9e4 dofs).
        scale_linear_solver: The ``linear_solver`` of the cost-growth rows up to ``krylov_threshold`` dofs
            (:mod:`fem.linear_solver`; ``"lu"`` is the case default). ``"auto"`` (default): one configuration at
            every size, the solver's own choice by size (``fem.linear_solver.AUTO_GAMG_NDOFS``; then
            ``krylov_threshold`` does not apply), and the row's linear solve uses the same choice.
        crossover_max_ndofs: Cost-growth rows up to this many dofs also time one linear solve with each of the
            two kinds (MUMPS LU with the ``"auto"`` ordering, and GAMG): the measured LU/GAMG crossover; >= 0.
        scale_predictor: The ``predictor`` of the cost-growth rows: ``"auto"`` (the case: the Hertz predictor, a
            stiffness solve) or ``"hertz_zone"`` (the Hertz zone prescribed from the unloaded state, no stiffness
            solve). Each row below ``krylov_threshold`` also runs the case solver, as the reference.
        krylov_threshold: Cost-growth rows with more dofs than this use ``linear_solver="gamg"`` (no LU factor:
            memory ~ ndofs) and compare with a GAMG linear solve; >= 0.
        reuse_lu: PETSc options reusing the LU of the FIRST Jacobian through GMRES for the whole run
            (snes_lag_preconditioner -2). The later Jacobians differ from it only in the rows of the contact
            dofs whose state changed, so GMRES needs about as many triangular solves as there are such dofs: a
            win when the contact zone holds few dofs, a loss when it holds thousands (a graded a/1280 mesh did
            not finish in 3 min). (SNES lag 2 with preonly was measured 10x slower; lag -1 is refused.)
        reuse_meshes: (family, h/a) of the LU-reuse comparison.
        solver_variants: label -> (petsc_options, solver overrides) of the options comparison.
        targets: The issue's targets (stated met / not met).
        predictor_free_cases: Cases of the predictor-free Newton section (every run of each at its default
            level, ``predictor="extrapolate"``: no analytic predictor).
        predictor_free_active_set: The solver's ``active_set`` option of that section (``"geometry"``: the
            first contact from the rigid overlap, several patches; ``"extrapolate"``: single patches only).
            Today's option (``"extrapolate"``) is run too, as the reference row.
        predictor_free_active_set_update: The solver's ``active_set_update`` option of that section
            (``"edge_fit"``: prescribed-active-set iterations with the edges extrapolated from the pressure,
            :mod:`fem.active_set_update`; ``"newton"``: one prescribed iteration, then semismooth Newton). When it
            is not ``"newton"``, the same ``active_set`` with ``"newton"`` is run too, as a second reference row.
        predictor_free_target: The issue's target: mean Newton iterations per solve <= this on every scene.
        repeats: Warm repetitions per timing (best kept), >= 1.
        sections: Sections run.
        out: Output folder (default ``<results>/bench``).  mesh_cache: Mesh cache folder.
    """

    case: str = "hertz_cylinder"
    rms_target: float = 0.005
    baseline_kappa: float = 1e3
    baseline_force_rtol: float = 1e-3
    baseline_ladder: tuple[tuple[float, float], ...] = ((20.0, 0.2), (20.0, 0.1), (20.0, 0.05))
    our_levels: tuple[float, ...] = (0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625, 0.003125, 0.0015625)
    our_methods: tuple[str, ...] = (NITSCHE, PENALTY)
    our_degrees: tuple[int, ...] = (1, 2)
    scale: dict = field(default_factory=lambda: {"graded": (0.05, 0.0125, 0.003125, 0.00078125, 0.000390625),
                                                 "uniform": (0.2, 0.1, 1.0 / 15.0, 0.05, 0.04)})
    scale_box: float = 20.0
    small_ndofs: int = 50_000
    mpi_levels: tuple[float | None, ...] = (None, 0.00078125)
    option_level: float = 0.00078125
    scale_linear_solver: str = "auto"
    crossover_max_ndofs: int = 400_000
    scale_predictor: str = "hertz_zone"
    krylov_threshold: int = 400_000
    reuse_lu: dict = field(default_factory=lambda: {
        "ksp_type": "gmres", "ksp_rtol": 1e-12, "ksp_atol": 0.0, "ksp_gmres_restart": 300, "ksp_max_it": 300,
        "snes_lag_preconditioner": -2, "snes_lag_preconditioner_persists": True,
    })
    reuse_meshes: tuple[tuple[str, float], ...] = (("uniform", 0.2), ("graded", 0.003125))
    solver_variants: dict = field(default_factory=_solver_variants)
    targets: dict = field(default_factory=lambda: {"speedup_vs_baseline": 10.0, "default_warm_s": 3.0,
                                                   "linear_solves": 1.5, "exponent": 1.15, "peak_mb": 2048.0,
                                                   "largest_ndofs": 900_000})
    predictor_free_cases: tuple[str, ...] = ("hertz_cylinder", "wedge", "wedge_convective", "parabola_convective",
                                             "concave_symmetric", "close_to_conformal")
    predictor_free_active_set: str = "geometry"
    predictor_free_active_set_update: str = "edge_fit"
    predictor_free_target: float = 4.0
    repeats: int = 3
    sections: tuple[str, ...] = BENCH_SECTIONS
    out: Path | None = None
    mesh_cache: Path | None = None

    @property
    def out_dir(self) -> Path:
        """The output folder: ``out``, else ``<results>/bench``."""
        return _folder(self.out, default_paths().study("bench"))

    @property
    def cache_dir(self) -> Path:
        """The mesh cache: ``mesh_cache``, else ``<results>/mesh_cache``."""
        return _folder(self.mesh_cache, default_paths().mesh_cache)

    def __post_init__(self) -> None:
        if int(self.repeats) != self.repeats or self.repeats < 1:
            raise ValueError(f"repeats must be an integer >= 1, got {self.repeats!r}")
        for family, levels in self.scale.items():
            if family not in SCALE_FAMILIES:
                raise ValueError(f"scale family must be one of {sorted(SCALE_FAMILIES)}, got {family!r}")
            if any(not 0 < v <= 1 for v in levels) or not _is_decreasing(tuple(levels)):
                raise ValueError(f"scale[{family!r}] must be strictly decreasing values in (0, 1], "
                                 f"got {list(levels)}")
        if self.predictor_free_active_set not in ACTIVE_SETS:
            raise ValueError(f"predictor_free_active_set must be one of {list(ACTIVE_SETS)}, "
                             f"got {self.predictor_free_active_set!r}")
        if self.predictor_free_active_set_update not in ACTIVE_SET_UPDATES:
            raise ValueError(f"predictor_free_active_set_update must be one of {list(ACTIVE_SET_UPDATES)}, "
                             f"got {self.predictor_free_active_set_update!r}")
        if self.scale_linear_solver not in LINEAR_SOLVERS:
            raise ValueError(f"scale_linear_solver must be one of {list(LINEAR_SOLVERS)}, "
                             f"got {self.scale_linear_solver!r}")
        if self.scale_predictor not in SCALE_PREDICTORS:
            raise ValueError(f"scale_predictor must be one of {list(SCALE_PREDICTORS)}, got {self.scale_predictor!r}")
        if isinstance(self.krylov_threshold, bool) or int(self.krylov_threshold) != self.krylov_threshold \
                or self.krylov_threshold < 0:
            raise ValueError(f"krylov_threshold must be an integer >= 0 (dofs), got {self.krylov_threshold!r}")
        if isinstance(self.crossover_max_ndofs, bool) or int(self.crossover_max_ndofs) != self.crossover_max_ndofs \
                or self.crossover_max_ndofs < 0:
            raise ValueError(f"crossover_max_ndofs must be an integer >= 0 (dofs), got {self.crossover_max_ndofs!r}")
        if not self.predictor_free_target > 0:
            raise ValueError(f"predictor_free_target must be > 0, got {self.predictor_free_target!r}")
        if not set(self.sections) <= set(BENCH_SECTIONS):
            raise ValueError(f"sections must be a subset of {sorted(BENCH_SECTIONS)}, got {list(self.sections)}")

    def quick(self) -> BenchConfig:
        """Small sizes only (development): three graded and two uniform sizes, one MPI size, a cheap
        options level, the first baseline rung."""
        return replace(self, scale={"graded": tuple(self.scale["graded"][:3]), "uniform": (0.4, 0.2)},
                       mpi_levels=(None,), option_level=0.0125, baseline_ladder=self.baseline_ladder[:1])


# --- convective table ---------------------------------------------------------------------------------


@dataclass(frozen=True)
class ConvectiveTableConfig:
    """Convective-effect table (:mod:`workbench.studies.convective_table`): b/b0 of Ciavarella & Hills.

    Attributes:
        thetas: Wedge angles (rad) by name.  wedge_betas: Dundurs beta of the wedge rows.
        parabola_b0_over_R, parabola_betas: The parabola rows.
        n_nodes: Gauss-Chebyshev nodes of the table.  self_convergence_nodes: Nodes of the self-convergence.
        out: Output folder (default ``<results>/analytic``).
    """

    thetas: dict = field(default_factory=lambda: {"pi/20": math.pi / 20, "pi/10": math.pi / 10,
                                                  "pi/5": math.pi / 5})
    wedge_betas: tuple[float, ...] = (-0.5, -0.25, -0.1)
    parabola_b0_over_R: tuple[float, ...] = (0.05, 0.1, 0.25, 0.4)
    parabola_betas: tuple[float, ...] = (-0.5, -0.25)
    n_nodes: int = 65536
    self_convergence_nodes: tuple[int, ...] = (1024, 4096, 16384, 65536, 262144)
    out: Path | None = None

    @property
    def out_dir(self) -> Path:
        """The output folder: ``out``, else ``<results>/analytic``."""
        return _folder(self.out, default_paths().analytic)


# --- validity -----------------------------------------------------------------------------------------

# (traction, kinematics) of the model hierarchy, least to most complete (docs/models.md)
VALIDITY_MODELS = ((HALFPLANE, SMALL), (HALFPLANE, CONVECTIVE), (OBSTACLE, SMALL), (OBSTACLE, CONVECTIVE),
                   (OBSTACLE, FINITE))
_HYPERELASTIC = HYPERELASTIC_MODELS


def _bad(name: str, value: Any, allowed: str) -> ValueError:
    text = repr(value)
    return ValueError(f"{name} = {text[:80]} is not allowed; allowed: {allowed}")


@dataclass(frozen=True)
class ValidityConfig:
    """Validity study (:mod:`workbench.studies.validity`): where the half-plane theories hold, model by model.

    Every point is a rigid indenter on a clamped block (half model, W = H = ``width_factor`` a, P2 Nitsche), force
    controlled to the classical load of the target half-width a = 1 mm (so one mesh serves every a/R, theta
    and nu of a scene and level). Each point runs every model of ``models`` (traction x kinematics; ``finite``
    with ``finite_material`` and only below ``mixed_from_nu``: finite strain has no mixed formulation) on the
    three levels a/h_c = ``h_ratios`` and once on the middle level with the block ``width_factor_far``.

    Attributes:
        cylinder_a_over_R: a/R of the exact-circle indenter (1e-3 ... 0.4).
        wedge_theta: Wedge face angles (rad; exact slope tan theta), pi/40 ... pi/4.
        nu: Poisson ratios of the block (beta = -(1 - 2 nu)/(2 (1 - nu)): -1/2 at nu = 0, -> 0 as nu -> 1/2).
        models: (traction, kinematics) pairs, from :data:`VALIDITY_MODELS`.
        finite_material: Hyperelastic law of the ``finite`` runs.
        E: Young's modulus (MPa): every result is scale-free (p/E*, b/a).
        h_ratios: a/h_c of the three levels (coarse to fine); the grading growth - 1 shrinks with h_c.
        growth: Grading of the coarsest level.
        width_factor, width_factor_far: Block sizes W/a of the levels and of the truncation run.
        n_steps: Load steps.  mixed_from_nu: nu from which the (small-strain) runs use the mixed formulation.
        resolve_factor: A model difference is used when it exceeds ``resolve_factor`` x its uncertainty.
        thresholds: The map's bands (relative): 0.1 %, 1 %, 5 %.
        claim_nu: nu of the stress comparison of the paper's claim (beta -> 0, the elastically similar limit).
        claim_bound: The claim's bound (0.5 %).  claim_theta_max: Its angle range theta < pi/5.
        workers: Local processes (2 cores), or the MPI workers of an mpi4py.futures pool (up to 4096).
        out: Output folder (default ``<results>/validity``).  mesh_cache: Mesh cache folder.
        halfplanes_beta: Dundurs beta of the two-elastic-half-planes part (issue 25; body 1 the upper body with
            the profile): both bodies nu = 0, E_lower / E_upper = (1 + 2 beta) / (1 - 2 beta), E* = ``E``; empty:
            no such part.
        halfplanes_b0_over_R: The parabolic gaps b0/R of that part (b0 = 1 mm, Hertz's half-width at the load).
        halfplanes_h_ratios: b0/h_c of its three levels (the far run on the middle one, W as above).
        rigid: Run the rigid-indenter part (the circle and the wedge); False: the two-half-planes part alone.
        elastic_wedge_theta: The paper's theta < pi/5 claim as stated (issue 25,
            :mod:`workbench.studies.validity_elastic_wedge`): the angles (rad, slope tan theta) of the elastic wedge
            on a block of the same material; empty: no such part.
        elastic_wedge_nu: Both bodies' Poisson ratio there (beta = 0 whatever nu).
        elastic_wedge_h_ratios: b/h_c of its three levels (coarse to fine, a constant ratio).
        elastic_wedge_width, elastic_wedge_width_far: W/b of both bodies on the levels and of the truncation run.
    """

    cylinder_a_over_R: tuple[float, ...] = (1e-3, 1e-2, 0.05, 0.1, 0.2, 0.4)
    wedge_theta: tuple[float, ...] = (math.pi / 40, math.pi / 20, math.pi / 10, math.pi / 5, math.pi / 4)
    nu: tuple[float, ...] = (0.0, 0.3, 0.499)
    models: tuple[tuple[str, str], ...] = VALIDITY_MODELS
    finite_material: str = "neo_hookean"
    E: float = 1000.0
    h_ratios: tuple[float, ...] = (4.0, 8.0, 16.0)
    growth: float = 1.3
    width_factor: float = 160.0
    width_factor_far: float = 640.0
    n_steps: int = 3
    mixed_from_nu: float = 0.45
    resolve_factor: float = 3.0
    thresholds: tuple[float, ...] = (1e-3, 1e-2, 5e-2)
    claim_nu: float = 0.499
    claim_bound: float = 5e-3
    claim_theta_max: float = math.pi / 5
    workers: int = 2
    out: Path | None = None
    mesh_cache: Path | None = None
    halfplanes_beta: tuple[float, ...] = (-0.45, -0.3, -0.15, 0.0, 0.15, 0.3, 0.45)
    halfplanes_b0_over_R: tuple[float, ...] = (0.03, 0.1, 0.2)
    halfplanes_h_ratios: tuple[float, ...] = (6.0, 10.0, 16.0)
    rigid: bool = True
    elastic_wedge_theta: tuple[float, ...] = (math.pi / 10, 3 * math.pi / 20, math.pi / 5, math.pi / 4)
    elastic_wedge_nu: float = 0.3
    elastic_wedge_h_ratios: tuple[float, ...] = (4.0, 8.0, 16.0)
    elastic_wedge_width: float = 40.0
    elastic_wedge_width_far: float = 160.0

    @property
    def out_dir(self) -> Path:
        """The output folder: ``out``, else ``<results>/validity``."""
        return _folder(self.out, default_paths().study("validity"))

    @property
    def cache_dir(self) -> Path:
        """The mesh cache: ``mesh_cache``, else ``<results>/mesh_cache``."""
        return _folder(self.mesh_cache, default_paths().mesh_cache)

    def __post_init__(self) -> None:
        def each(name, ok, allowed):
            vals = getattr(self, name)
            if not isinstance(vals, tuple) or not vals or not all(ok(v) for v in vals):
                raise _bad(name, vals, allowed)

        num = (int, float)
        each("cylinder_a_over_R", lambda v: isinstance(v, num) and 1e-5 <= v <= 0.9, "numbers in [1e-5, 0.9]")
        each("wedge_theta", lambda v: isinstance(v, num) and 0 < v < math.pi / 2, "angles in (0, pi/2) rad")
        each("nu", lambda v: isinstance(v, num) and 0.0 <= v < 0.5, "Poisson ratios in [0, 0.5)")
        each("models", lambda v: tuple(v) in VALIDITY_MODELS, f"(traction, kinematics) pairs of {VALIDITY_MODELS}")
        if self.finite_material not in _HYPERELASTIC:
            raise _bad("finite_material", self.finite_material, ", ".join(_HYPERELASTIC))
        each("h_ratios", lambda v: isinstance(v, num) and 1.0 <= v <= 200.0, "three increasing numbers in [1, 200]")
        if len(self.h_ratios) != 3 or not all(b > a for a, b in zip(self.h_ratios, self.h_ratios[1:], strict=False)):
            raise _bad("h_ratios", self.h_ratios, "three increasing numbers in [1, 200]")
        each("thresholds", lambda v: isinstance(v, num) and 0 < v < 1, "increasing numbers in (0, 1)")
        if self.halfplanes_beta:
            each("halfplanes_beta", lambda v: isinstance(v, num) and -0.49 <= v <= 0.49, "numbers in [-0.49, 0.49]")
            each("halfplanes_b0_over_R", lambda v: isinstance(v, num) and 1e-3 <= v <= 0.4, "numbers in [1e-3, 0.4]")
        if self.elastic_wedge_theta:
            each("elastic_wedge_theta", lambda v: isinstance(v, num) and math.pi / 40 <= v <= 0.3 * math.pi,
                 "angles in [pi/40, 0.3 pi] rad")
        ew = self.elastic_wedge_h_ratios
        if (not isinstance(ew, tuple) or len(ew) != 3 or not all(isinstance(v, num) and 1.0 <= v <= 100.0 for v in ew)
                or not ew[1] > ew[0] or abs(ew[2] / ew[1] - ew[1] / ew[0]) > 1e-9 * ew[2] / ew[1]):
            raise _bad("elastic_wedge_h_ratios", ew, "three numbers in [1, 100] in a constant ratio > 1")
        if not isinstance(self.rigid, bool):
            raise _bad("rigid", self.rigid, "True or False")
        if not self.rigid and not self.halfplanes_beta:
            raise _bad("rigid", self.rigid, "True, or False with halfplanes_beta given (else nothing runs)")
        hp = self.halfplanes_h_ratios
        if (not isinstance(hp, tuple) or len(hp) != 3 or not all(isinstance(v, num) and 1.0 <= v <= 100.0 for v in hp)
                or not all(b > a for a, b in zip(hp, hp[1:], strict=False))):
            raise _bad("halfplanes_h_ratios", hp, "three increasing numbers in [1, 100]")
        if list(self.thresholds) != sorted(self.thresholds):
            raise _bad("thresholds", self.thresholds, "increasing numbers in (0, 1)")
        for name, lo, hi in (("E", 1e-6, 1e12), ("growth", 1.0 + 1e-9, 3.0), ("width_factor", 10.0, 1e4),
                             ("width_factor_far", 10.0, 1e5), ("resolve_factor", 1.0, 1e3),
                             ("mixed_from_nu", 0.0, 0.5), ("claim_nu", 0.0, 0.4999999),
                             ("claim_bound", 1e-9, 1.0), ("claim_theta_max", 1e-9, math.pi / 2),
                             ("elastic_wedge_nu", 0.0, 0.45), ("elastic_wedge_width", 10.0, 1e4),
                             ("elastic_wedge_width_far", 10.0, 1e5)):
            v = getattr(self, name)
            if not (isinstance(v, num) and lo <= v <= hi):
                raise _bad(name, v, f"a number in [{lo:g}, {hi:g}]")
        if not self.elastic_wedge_width_far > self.elastic_wedge_width:
            raise _bad("elastic_wedge_width_far", self.elastic_wedge_width_far,
                       f"a number > elastic_wedge_width = {self.elastic_wedge_width:g}")
        if not self.width_factor_far > self.width_factor:
            raise _bad("width_factor_far", self.width_factor_far, f"a number > width_factor = {self.width_factor:g}")
        for name, lo, hi in (("n_steps", 1, 100), ("workers", 1, 4096)):
            v = getattr(self, name)
            if not (isinstance(v, int) and not isinstance(v, bool) and lo <= v <= hi):
                raise _bad(name, v, f"a whole number in [{lo}, {hi}]")


# --- JSON ---------------------------------------------------------------------------------------------


def to_json(cfg) -> dict[str, Any]:
    """The config as a JSON-ready dict (paths as strings; tuples become lists when dumped)."""
    out = {}
    for f in fields(cfg):
        v = getattr(cfg, f.name)
        out[f.name] = str(v) if isinstance(v, Path) else v
    return out


def _tuples(v: Any) -> Any:
    """JSON lists back to tuples, also inside dicts (every sequence of a config is a tuple)."""
    if isinstance(v, list):
        return tuple(_tuples(x) for x in v)
    if isinstance(v, dict):
        return {k: _tuples(x) for k, x in v.items()}
    return v


def from_json(cls: type, data: dict | None, *, strict: bool = False):
    """A config of class ``cls`` from its JSON dict; keys it lacks take their defaults.

    Args:
        cls: One of the config classes.
        data: The ``"config"`` entry of a study JSON (None: the defaults).
        strict: Unknown keys are errors (else they are ignored: a newer JSON read by an older report).

    Raises:
        ValueError: an unknown key (strict), or a value out of range.
    """
    data = data or {}
    known = {f.name: f for f in fields(cls)}
    unknown = sorted(set(data) - set(known))
    if unknown and strict:
        raise ValueError(f"{cls.__name__}: unknown keys {unknown}; allowed keys: {', '.join(known)}")
    kw = {}
    for name, value in data.items():
        if name not in known:
            continue
        if name in ("out", "mesh_cache") and value is not None:
            value = Path(value)
        else:
            value = _tuples(value)
        kw[name] = value
    return cls(**kw)
