"""The performance benchmark's configuration (:mod:`workbench.studies.bench`); shared helpers in
:mod:`workbench.studies.config`.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import ClassVar

from vocabulary import ACTIVE_SET_UPDATES, ACTIVE_SETS, LINEAR_SOLVERS, NITSCHE, PENALTY
from workbench.studies.config import StudyFolders, is_decreasing

__all__ = ["ACTIVE_SETS", "ACTIVE_SET_UPDATES", "BENCH_SECTIONS", "BenchConfig", "LINEAR_SOLVERS", "SCALE_FAMILIES",
           "SCALE_PREDICTORS"]


def _technique_variants() -> dict:
    """label -> (petsc_options, solver overrides) of the techniques section (issue 38, items 3 and 4)."""
    return {
        "ksp_type gmres (left-preconditioned)": ({"ksp_type": "gmres"}, {}),
        "ksp_type fgmres (right-preconditioned)": ({"ksp_type": "fgmres"}, {}),
        "Eisenstat-Walker forcing (snes_ksp_ew)": ({"snes_ksp_ew": True}, {}),
        "active_set_update edge_fit": ({}, {"active_set_update": "edge_fit"}),
    }


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


BENCH_SECTIONS = ("accuracy", "linear", "scale", "mpi", "cache", "options", "predictor_free", "two_body", "startup",
                  "nested", "techniques")
SCALE_PREDICTORS = ("auto", "hertz_zone")  # the force-control predictors of the cost-growth rows
SCALE_FAMILIES = ("graded", "uniform")


@dataclass(frozen=True)
class BenchConfig(StudyFolders):
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
            baseline's uniform box, ndofs ~ 1/h^2, up to ~1e6 dofs; h = 0.06 a, 448k dofs, makes the largest three
            sizes one configuration, GAMG, under ``"auto"``).
        scale_box: W = H of the uniform family (in a).
        small_ndofs: Below this a size is timed 3 times in its process (best kept; else twice), its linear solve 3
            times (else once): every LU row of the cost growth (up to ``krylov_threshold``). With 50k (the LU rows
            above it timed twice, their linear solve once) two runs of the graded family's largest three rows gave
            contact solve exponents 1.20 and 1.07 (one row's time moved by 10-35 % between runs); with 400k, three
            runs gave 1.20, 1.20 and 1.18. The scale section took 4 min 00 s - 4 min 15 s against 3 min 39 s.
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
        scale_nested: Nested iteration in the cost-growth rows (issue 38, item 1, "for a single level, a coarse
            mesh of the same geometry built for it"), family -> factor > 1: each row of that family first solves its
            family's mesh at ``h * factor`` and starts from that solution's active set and d
            (:func:`workbench.studies.bench_scale.worker_scale`); a family not named is solved cold. Default: the
            graded family only, from h x 16. Measured (make bench, h x 8, before the force-controlled Newton of
            :mod:`fem.force_newton`): graded 88k and 173k dofs 1.9 and 1.7 linear solves nested against 3.8 and
            5.9 cold, its 2.6k-23k rows 2.1-2.2 against 1.5-1.8; uniform 40k and 161k dofs 3.2 and 1.7 against 1.4
            and 1.3 (their coarse mesh, h = 0.8-1.6 a, does not resolve the contact: the Hertz zone is the better
            start), GAMG rows 642k and 1M 3.1 and 2.3 against 2.3 and 2.7. With the force-controlled Newton (one run
            each, quiet machine), graded 23k, 88k, 173k dofs: h x 16: 2.3, 1.23, 1.29 linear solves (Newton
            iterations [4], [1], [2]); h x 8: 1.6, 1.26, 1.48; h x 4: 1.5, 1.4, 1.8; cold from the Hertz zone:
            1.35-1.47, 3.3 ([5]), 5.5 ([6]).
        scale_nested_coarsest: A row nests only when its coarse mesh has ``h / a`` at most this (a coarser one
            resolves the contact edge worse than the Hertz zone does, above): graded a/80 (88k dofs, coarse
            6.9k) nests, a/320 (23k, coarse h = a/20: 4 Newton iterations against 2 from the Hertz zone) does
            not.
        worker_malloc: glibc's malloc tunables (``GLIBC_TUNABLES``) of the cost-growth and techniques workers: a
            freed block up to 32 MB stays in the heap for the next solve instead of going back to the kernel, so a
            solve does not pay its pages' first-touch faults again. Without it the same contact solve measured
            0.083-0.17 s in one process (graded 23k dofs, by what ran before it: the first four solves 0.13-0.17 s,
            after a linear solve 0.083-0.086 s, after the case's solves 0.10-0.12 s) and the linear solve 0.067-0.094
            s; with it 0.081-0.11 s and 0.064-0.066 s. Both kinds of solve run under the same setting. "": none.
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
        technique_meshes: (family, h_c / a) of the techniques section (:mod:`workbench.studies.bench_techniques`),
            each a size of ``scale``'s families.
        schur_zone: Half-width of the contact zone condensed onto in that section, in units of a (> 0).
        schur_max_dofs: The condensation is measured up to this many Schur dofs (its dense complement takes
            8 n^2 bytes), >= 1.
        technique_variants: label -> (petsc_options, solver overrides) of that section's contact solves.
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

    study: ClassVar[str] = "bench"

    case: str = "hertz_cylinder"
    rms_target: float = 0.005
    baseline_kappa: float = 1e3
    baseline_force_rtol: float = 1e-3
    baseline_ladder: tuple[tuple[float, float], ...] = ((20.0, 0.2), (20.0, 0.1), (20.0, 0.05))
    our_levels: tuple[float, ...] = (0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625, 0.003125, 0.0015625)
    our_methods: tuple[str, ...] = (NITSCHE, PENALTY)
    our_degrees: tuple[int, ...] = (1, 2)
    scale: dict = field(default_factory=lambda: {"graded": (0.05, 0.0125, 0.003125, 0.00078125, 0.000390625),
                                                 "uniform": (0.2, 0.1, 1.0 / 15.0, 0.06, 0.05, 0.04)})
    scale_box: float = 20.0
    small_ndofs: int = 400_000
    mpi_levels: tuple[float | None, ...] = (None, 0.00078125)
    option_level: float = 0.00078125
    scale_linear_solver: str = "auto"
    crossover_max_ndofs: int = 400_000
    scale_predictor: str = "hertz_zone"
    scale_nested: dict = field(default_factory=lambda: {"graded": 16.0})
    scale_nested_coarsest: float = 0.02
    worker_malloc: str = "glibc.malloc.mmap_threshold=33554432:glibc.malloc.trim_threshold=1073741824"
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
    technique_meshes: tuple[tuple[str, float], ...] = (("graded", 0.0125), ("graded", 0.00078125), ("uniform", 0.1),
                                                       ("uniform", 0.05))
    schur_zone: float = 1.5
    schur_max_dofs: int = 6000
    technique_variants: dict = field(default_factory=_technique_variants)
    predictor_free_cases: tuple[str, ...] = ("hertz_cylinder", "wedge", "wedge_convective", "parabola_convective",
                                             "concave_symmetric", "close_to_conformal")
    predictor_free_active_set: str = "geometry"
    predictor_free_active_set_update: str = "edge_fit"
    predictor_free_target: float = 4.0
    repeats: int = 3
    sections: tuple[str, ...] = BENCH_SECTIONS
    out: Path | None = None
    mesh_cache: Path | None = None

    def __post_init__(self) -> None:
        if int(self.repeats) != self.repeats or self.repeats < 1:
            raise ValueError(f"repeats must be an integer >= 1, got {self.repeats!r}")
        for family, levels in self.scale.items():
            if family not in SCALE_FAMILIES:
                raise ValueError(f"scale family must be one of {sorted(SCALE_FAMILIES)}, got {family!r}")
            if any(not 0 < v <= 1 for v in levels) or not is_decreasing(tuple(levels)):
                raise ValueError(f"scale[{family!r}] must be strictly decreasing values in (0, 1], "
                                 f"got {list(levels)}")
        for family, factor in self.scale_nested.items():
            if family not in SCALE_FAMILIES or isinstance(factor, bool) or not float(factor) > 1:
                raise ValueError(f"scale_nested must map a family of {sorted(SCALE_FAMILIES)} to a factor > 1, got "
                                 f"{family!r}: {factor!r}")
        if not isinstance(self.worker_malloc, str):
            raise ValueError("worker_malloc must be a string of glibc malloc tunables (GLIBC_TUNABLES, e.g. "
                             f"'glibc.malloc.mmap_threshold=33554432'; '' for none), got {self.worker_malloc!r}")
        if isinstance(self.scale_nested_coarsest, bool) or not 0 < float(self.scale_nested_coarsest) <= 1:
            raise ValueError(f"scale_nested_coarsest must be in (0, 1] (h / a), got {self.scale_nested_coarsest!r}")
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
        if isinstance(self.small_ndofs, bool) or int(self.small_ndofs) != self.small_ndofs or self.small_ndofs < 0:
            raise ValueError(f"small_ndofs must be an integer >= 0 (dofs), got {self.small_ndofs!r}")
        if isinstance(self.crossover_max_ndofs, bool) or int(self.crossover_max_ndofs) != self.crossover_max_ndofs \
                or self.crossover_max_ndofs < 0:
            raise ValueError(f"crossover_max_ndofs must be an integer >= 0 (dofs), got {self.crossover_max_ndofs!r}")
        for pair in self.technique_meshes:
            if len(pair) != 2 or pair[0] not in SCALE_FAMILIES or not 0 < float(pair[1]) <= 1:
                raise ValueError(f"technique_meshes must be (family, h_c / a) pairs, family one of "
                                 f"{sorted(SCALE_FAMILIES)} and h_c / a in (0, 1], got {pair!r}")
        if not self.schur_zone > 0:
            raise ValueError(f"schur_zone must be > 0 (in units of a), got {self.schur_zone!r}")
        if isinstance(self.schur_max_dofs, bool) or int(self.schur_max_dofs) != self.schur_max_dofs \
                or self.schur_max_dofs < 1:
            raise ValueError(f"schur_max_dofs must be an integer >= 1, got {self.schur_max_dofs!r}")
        if not self.predictor_free_target > 0:
            raise ValueError(f"predictor_free_target must be > 0, got {self.predictor_free_target!r}")
        if not set(self.sections) <= set(BENCH_SECTIONS):
            raise ValueError(f"sections must be a subset of {sorted(BENCH_SECTIONS)}, got {list(self.sections)}")

    def quick(self) -> BenchConfig:
        """Small sizes only (development): three graded and two uniform sizes, one MPI size, a cheap
        options level, the first baseline rung."""
        return replace(self, scale={"graded": tuple(self.scale["graded"][:3]), "uniform": (0.4, 0.2)},
                       technique_meshes=(("graded", 0.05), ("uniform", 0.4)),
                       mpi_levels=(None,), option_level=0.0125, baseline_ladder=self.baseline_ladder[:1])
