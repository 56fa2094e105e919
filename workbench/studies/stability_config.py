"""The stability sweep's configuration (:mod:`workbench.studies.stability`); shared helpers in
:mod:`workbench.studies.config`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import ClassVar

from workbench.studies.config import StudyFolders

__all__ = ["AL", "STABILITY_STUDIES", "StabilityConfig", "decade"]


STABILITY_STUDIES = ("method", "augmented_lagrangian", "incompressible", "convective", "loads", "resolution",
                     "scale", "conformal", "faults", "two_body")
AL = "augmented_lagrangian"  # the method and the study of its stiffness sweep


def decade(v: float) -> str:
    """``1e3`` for a power of ten, else ``%g``."""
    k = round(math.log10(v))
    return f"1e{k}" if v == 10.0**k else f"{v:g}"


def _two_body_pairs() -> tuple[tuple[float, float, float], ...]:
    """(E_upper / E_lower, nu_lower, nu_upper) of the ``two_body`` study: E ratios 1e-3 ... 1e3 at nu = 0.3, nu =
    0.499 on either side, and both together at the extreme ratios (issue 24)."""
    ratios = tuple(10.0**k for k in range(-3, 4))
    return (tuple((r, 0.3, 0.3) for r in ratios) + ((1.0, 0.499, 0.3), (1.0, 0.3, 0.499))
            + tuple((r, nl, nu) for r in (1e-3, 1e3) for nl, nu in ((0.499, 0.3), (0.3, 0.499))))


@dataclass(frozen=True)
class StabilityConfig(StudyFolders):
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

    study: ClassVar[str] = "stability"

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
