"""The validity study's configuration (:mod:`workbench.studies.validity`); shared helpers in
:mod:`workbench.studies.config`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar

from vocabulary import CONVECTIVE, FINITE, HALFPLANE, HYPERELASTIC_MODELS, OBSTACLE, SMALL
from workbench.studies.config import StudyFolders

__all__ = ["VALIDITY_MODELS", "ValidityConfig"]


# (traction, kinematics) of the model hierarchy, least to most complete (docs/models.md)
VALIDITY_MODELS = ((HALFPLANE, SMALL), (HALFPLANE, CONVECTIVE), (OBSTACLE, SMALL), (OBSTACLE, CONVECTIVE),
                   (OBSTACLE, FINITE))
_HYPERELASTIC = HYPERELASTIC_MODELS
# the two-half-planes part's measured ratios (model keys of the points): the profile model over small (the complete
# model) and the pairing model over small (issue 39)
HP_COMPLETE = "halfplane/convective over halfplane/small"
HP_PAIRING = "halfplane/convective/pairing over halfplane/small"


def _bad(name: str, value: Any, allowed: str) -> ValueError:
    text = repr(value)
    return ValueError(f"{name} = {text[:80]} is not allowed; allowed: {allowed}")


@dataclass(frozen=True)
class ValidityConfig(StudyFolders):
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
        halfplanes_finite_laws: The hyperelastic laws of that part's finite-strain runs (issue 39: both bodies the
            law, P1, the upper body the meshed parabola capped at 3 b0, the traction along the deformed master
            normal); empty: no finite runs.
        halfplanes_finite_h_ratios: b0/h_c of their three levels (P1; the far run on the middle one).
        halfplanes_pairing: Also run the ``pairing`` convective model at every point of that part (issue 39: which
            small-strain model the finite-strain runs follow); False: ``profile`` alone.
        rigid: Run the rigid-indenter part (the circle and the wedge); False: the two-half-planes part alone.
        elastic_wedge_theta: The paper's theta < pi/5 claim as stated (issue 25,
            :mod:`workbench.studies.validity_elastic_wedge`): the angles (rad, slope tan theta) of the elastic wedge
            on a block of the same material; empty: no such part.
        elastic_wedge_nu: Both bodies' Poisson ratio there (beta = 0 whatever nu).
        elastic_wedge_h_ratios: b/h_c of its three levels (coarse to fine, a constant ratio).
        elastic_wedge_width, elastic_wedge_width_far: W/b of both bodies on the levels and of the truncation run.
        elastic_wedge_finite_laws: The hyperelastic laws of that part's finite-strain runs (issue 39, item 4: the
            shaped wedge and the block both the law, P1, the traction along the deformed interface); empty: none.
            Default neo-Hookean alone: Saint Venant-Kirchhoff softens in strong compression, and the wedge's apex
            compresses it beyond (measured: DIVERGED_MAX_IT at b/8, theta = pi/10).
        elastic_wedge_finite_theta: The angles of those runs (those also in ``elastic_wedge_theta`` run). Default pi/10
            alone: at pi/5 the neo-Hookean run diverged at b/8 (DIVERGED_MAX_IT after 5 cut-backs), and a failing
            finite run costs its cut-backs (docs/models.md).
    """

    study: ClassVar[str] = "validity"

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
    halfplanes_finite_laws: tuple[str, ...] = ("neo_hookean", "saint_venant_kirchhoff")
    halfplanes_finite_h_ratios: tuple[float, ...] = (10.0, 16.0, 25.0)
    halfplanes_pairing: bool = True
    rigid: bool = True
    elastic_wedge_theta: tuple[float, ...] = (math.pi / 10, 3 * math.pi / 20, math.pi / 5, math.pi / 4)
    elastic_wedge_nu: float = 0.3
    elastic_wedge_h_ratios: tuple[float, ...] = (4.0, 8.0, 16.0)
    elastic_wedge_width: float = 40.0
    elastic_wedge_width_far: float = 160.0
    elastic_wedge_finite_laws: tuple[str, ...] = ("neo_hookean",)
    elastic_wedge_finite_theta: tuple[float, ...] = (math.pi / 10,)

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
        for name in ("rigid", "halfplanes_pairing"):
            if not isinstance(getattr(self, name), bool):
                raise _bad(name, getattr(self, name), "True or False")
        if not self.rigid and not self.halfplanes_beta and not self.elastic_wedge_theta:
            raise _bad("rigid", self.rigid, "True, or False with halfplanes_beta or elastic_wedge_theta given (else "
                       "nothing runs)")
        for name in ("halfplanes_h_ratios", "halfplanes_finite_h_ratios"):
            hp = getattr(self, name)
            if (not isinstance(hp, tuple) or len(hp) != 3
                    or not all(isinstance(v, num) and 1.0 <= v <= 100.0 for v in hp)
                    or not all(b > a for a, b in zip(hp, hp[1:], strict=False))):
                raise _bad(name, hp, "three increasing numbers in [1, 100]")
        for name in ("halfplanes_finite_laws", "elastic_wedge_finite_laws"):
            laws = getattr(self, name)
            if (not isinstance(laws, tuple) or not all(v in _HYPERELASTIC for v in laws)
                    or len(set(laws)) != len(laws)):
                raise _bad(name, laws, f"distinct names of {', '.join(_HYPERELASTIC)} (or none)")
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
        if not isinstance(self.elastic_wedge_finite_theta, tuple):
            raise _bad("elastic_wedge_finite_theta", self.elastic_wedge_finite_theta,
                       "angles in [pi/40, 0.3 pi] rad (or none)")
        if self.elastic_wedge_finite_theta:
            each("elastic_wedge_finite_theta", lambda v: isinstance(v, num) and math.pi / 40 <= v <= 0.3 * math.pi,
                 "angles in [pi/40, 0.3 pi] rad (or none)")
        if not self.elastic_wedge_width_far > self.elastic_wedge_width:
            raise _bad("elastic_wedge_width_far", self.elastic_wedge_width_far,
                       f"a number > elastic_wedge_width = {self.elastic_wedge_width:g}")
        if not self.width_factor_far > self.width_factor:
            raise _bad("width_factor_far", self.width_factor_far, f"a number > width_factor = {self.width_factor:g}")
        for name, lo, hi in (("n_steps", 1, 100), ("workers", 1, 4096)):
            v = getattr(self, name)
            if not (isinstance(v, int) and not isinstance(v, bool) and lo <= v <= hi):
                raise _bad(name, v, f"a whole number in [{lo}, {hi}]")
