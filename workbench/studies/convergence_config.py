"""The convergence study's configuration (:mod:`workbench.studies.convergence`); shared helpers in
:mod:`workbench.studies.config`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import ClassVar

from vocabulary import NITSCHE, PENALTY
from workbench.studies.config import StudyFolders, is_decreasing
from workbench.studies.rates import N_FINEST

__all__ = ["ConvergenceConfig"]


_BIG = {"width_factor": 640.0, "height_factor": 640.0}


@dataclass(frozen=True)
class ConvergenceConfig(StudyFolders):
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

    study: ClassVar[str] = "convergence"

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

    def __post_init__(self) -> None:
        for key, lv in (("levels", self.levels), ("ideal_levels", self.ideal_levels)):
            if len(lv) < self.n_finest or any(not 0 < v <= 1 for v in lv) or not is_decreasing(lv):
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
