"""The half-plane theory of a two-half-planes run (:mod:`workbench.scenes.halfplanes`): the bodies' Dundurs
constants, the classical solution at the measured load (Hertz or the classical wedge at E*), and the
Ciavarella-Hills solution at the bodies' beta. Shared by the scene and its error budget
(:mod:`workbench.scenes.halfplanes_budget`). Units mm, N/mm, MPa.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from analytic import convective, materials, wedge
from analytic.hertz import hertz, hertz_pressure
from cases.schema import Run

__all__ = ["HalfplanesComparison", "HalfplanesTheory", "bimaterial_of", "classical_theory", "convective_theory",
           "profile_size"]


class HalfplanesTheory(NamedTuple):
    """The classical solution at a run's measured load and E* (mm, N/mm, MPa).

    Attributes:
        kind: the profile, ``"parabola"`` (Hertz) or ``"wedge"``.
        P: load (N/mm).  R: the parabola's radius (mm; None for the wedge).  m: the wedge's face slope (None for
            the parabola).  E_star: E* (MPa).  half_width: b0 (mm).
        p_ref: Hertz's peak p0, or the wedge's mean pressure P / (2 b0) (the RMS reference; MPa).
        beta: Dundurs' beta of the bodies.
        moment: the classical moment half-width 2 sqrt(M2/M0) (mm): b0 (Hertz), 2 b0 / sqrt(6) (wedge).
    """

    kind: str
    P: float
    R: float | None
    E_star: float
    half_width: float
    p_ref: float
    beta: float
    m: float | None = None
    moment: float = math.nan

    def pressure(self, x: np.ndarray) -> np.ndarray:
        """The classical pressure (MPa) at x (mm); the wedge's is +inf at its apex."""
        if self.kind == "wedge":
            return wedge.wedge_pressure(x, b=self.half_width, m=self.m, E_star=self.E_star)
        return hertz_pressure(x, a=self.half_width, p0=self.p_ref)

    @property
    def name(self) -> str:
        """The classical solution's name (plots and tables)."""
        return "classical wedge" if self.kind == "wedge" else "Hertz"


def profile_size(run: Run) -> float:
    """The profile's size, as :class:`fem.two_body.geometry.ProfileSurface` takes it: R (mm) or the slope m."""
    g = run.geometry
    if g.indenter == "wedge":
        return wedge.wedge_slope(g.wedge_angle, convention=g.wedge_slope)
    return g.radius


def classical_theory(run: Run, P: float) -> HalfplanesTheory:
    """The classical solution of a run's profile at load P (N/mm) and the bodies' E* (small kinematics: beta does
    not enter)."""
    bm, kind = bimaterial_of(run), run.geometry.indenter
    if kind == "wedge":
        m = profile_size(run)
        b = wedge.wedge_half_width(P, m, bm.E_star)
        return HalfplanesTheory(kind, P, None, bm.E_star, b, P / (2.0 * b), bm.beta, m,
                                2.0 * wedge.wedge_moment_half_width(b))
    hz = hertz(P, run.geometry.radius, bm.E_star)
    return HalfplanesTheory(kind, P, run.geometry.radius, bm.E_star, hz.half_width, hz.p0, bm.beta, None,
                            hz.half_width)


class HalfplanesComparison(NamedTuple):
    """One run's measured contact: ``half_width`` (the edge, mm), ``moment`` (sqrt(M2/M0), mm), ``p_max`` (MPa)."""

    half_width: float
    moment: float
    p_max: float

    def signed(self, theory: HalfplanesTheory) -> dict:
        """FEM over the classical ``theory`` minus 1: ``p_max`` (parabola only: the wedge's peak is log-singular),
        ``half_width`` (the edge) and ``half_width_moment`` (2 sqrt(M2/M0))."""
        signed = {"half_width": self.half_width / theory.half_width - 1.0,
                  "half_width_moment": 2.0 * self.moment / theory.moment - 1.0}
        if theory.kind == "parabola":
            signed = {"p_max": self.p_max / theory.p_ref - 1.0} | signed
        return signed


def bimaterial_of(run: Run) -> materials.Bimaterial:
    """Dundurs' alpha, beta and E* of a run: body 1 the upper (profile) body, body 2 the lower (flat) one."""
    lower, upper = run.bodies
    return materials.bimaterial(E1=upper.E, nu1=upper.nu, E2=lower.E, nu2=lower.nu)


def convective_theory(theory: HalfplanesTheory, *, n_plot: int = 8001) -> convective.ConvectiveSolution:
    """Ciavarella-Hills at a run's beta and profile: the wedge's m, or the parabola's b0/R (b0 classical at its
    measured load)."""
    profile = (convective.wedge_profile(theory.m) if theory.kind == "wedge"
               else convective.parabola_profile(theory.half_width / theory.R))
    return convective.solve(profile, beta=theory.beta, n_plot=n_plot)
