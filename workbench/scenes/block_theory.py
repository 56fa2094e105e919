"""FEM pressure against half-plane theory, at the MEASURED load (pure numpy; no dolfinx).

In 2D there is no universal load-indentation law, so every prediction here is evaluated at the load the
FEM actually carries (the virtual-work reaction ``P``), never at an imposed depth.

Error measures (all relative, dimensionless):
    p_max       |max p_fem - p0| / p0                      (Hertz only; the wedge peak is log-singular)
    half_width  |a_fem - a| / a, a_fem from the zero crossing of the contact law at the patch edge
    rms         sqrt( (1/L) int_L (p_fem - p_th)^2 dx ) / p_ref over the sampled patch region
                L = samples with |x - c| <= 1.05 max(a_fem, a); p_ref = p0 (Hertz) or P/(2b) (wedge)
    load_balance |P - P_pressure| / P
    *_vs_exact_circle   the same against the exact circle's half-plane theory (:mod:`analytic.circle`),
                the profile a circle indenter really has (information; the tolerances apply to Hertz)
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from analytic import hertz as hz
from analytic import materials, wedge
from analytic.circle import CircleContact, circle_contact, circle_pressure
from measures.contact import rms_error

__all__ = [
    "BlockTheory",
    "exact_circle",
    "block_theory",
    "compare_block",
    "rms_error",
]


class BlockTheory(NamedTuple):
    """Classical prediction for a block scene at a given load.

    Attributes:
        kind: ``"hertz"`` (circle, parabola) or ``"wedge"``.
        P: Load per unit thickness (N/mm).
        E_star: Plane-strain modulus of the block (rigid indenter), MPa.
        half_width: Classical half-width a or b (mm).
        p_ref: Reference pressure (MPa): Hertz peak p0, or wedge mean pressure P/(2b).
        R: Indenter radius (mm), Hertz only.
        m: Wedge face slope, wedge only.
    """

    kind: str
    P: float
    E_star: float
    half_width: float
    p_ref: float
    R: float | None = None
    m: float | None = None

    def pressure(self, x: np.ndarray) -> np.ndarray:
        """Classical pressure at material abscissa x (mm), MPa."""
        if self.kind == "hertz":
            return hz.hertz_pressure(x, a=self.half_width, p0=self.p_ref)
        return wedge.wedge_pressure(x, b=self.half_width, m=self.m, E_star=self.E_star)


def block_theory(geometry, material, *, P: float | None = None, half_width: float | None = None) -> BlockTheory:
    """Classical half-plane prediction for a block scene, from the load or from the half-width.

    Args:
        geometry: The run's :class:`workbench.scenes.block_schema.BlockGeometry`.
        material: The run's :class:`cases.schema.Material`.
        P: Load per unit thickness (N/mm); give exactly one of ``P`` and ``half_width``.
        half_width: Classical half-width (mm).
    """
    if (P is None) == (half_width is None):
        raise ValueError("block_theory needs exactly one of P and half_width")
    E_star = materials.plane_strain_modulus(material.E, material.nu)
    if geometry.indenter in ("circle", "parabola"):
        R = geometry.radius
        if P is None:
            P = hz.hertz_load_from_half_width(half_width, R, E_star)
        c = hz.hertz(P, R, E_star)
        return BlockTheory("hertz", c.P, E_star, c.half_width, c.p0, R=R)
    if geometry.indenter == "wedge":
        m = wedge.wedge_slope(geometry.wedge_angle, convention=geometry.wedge_slope)
        if P is None:
            P = wedge.wedge_load_from_half_width(half_width, m, E_star)
        b = wedge.wedge_half_width(P, m, E_star)
        return BlockTheory("wedge", float(P), E_star, b, float(P) / (2.0 * b), m=m)
    raise ValueError(f"geometry.indenter = {geometry.indenter!r} has no half-plane prediction")


def compare_block(*, x: np.ndarray, p: np.ndarray, P: float, P_pressure: float, half_width_fem: float,
                  p_max_fem: float, geometry, material) -> tuple[BlockTheory, dict[str, float]]:
    """Errors of one block run against its classical prediction at the measured load ``P``.

    Args:
        x: Material abscissae of the pressure samples (mm).
        p: FEM contact pressure at ``x`` (MPa, >= 0 compressive).
        P: Measured load per unit thickness (virtual-work reaction), N/mm.
        P_pressure: Integral of the FEM pressure, N/mm.
        half_width_fem: FEM half-width of the (central) patch, mm.
        p_max_fem: FEM peak pressure, MPa.
        geometry, material: The run's case records.

    Returns:
        The theory at the measured load, and a dict of relative errors.
    """
    th = block_theory(geometry, material, P=P)
    errors = {
        "half_width": abs(half_width_fem - th.half_width) / th.half_width,
        "rms": rms_error(x, p, th.pressure(x), center=0.0, half_width=max(half_width_fem, th.half_width),
                         p_ref=th.p_ref),
        "load_balance": abs(P - P_pressure) / abs(P),
    }
    if th.kind == "hertz":
        errors["p_max"] = abs(p_max_fem - th.p_ref) / th.p_ref
    if geometry.indenter == "circle":  # the theory of the profile the FEM really has (for information)
        ex = exact_circle(th)
        errors["p_max_vs_exact_circle"] = abs(p_max_fem - ex.p0) / ex.p0
        errors["half_width_vs_exact_circle"] = abs(half_width_fem - ex.half_width) / ex.half_width
        errors["rms_vs_exact_circle"] = rms_error(
            x, p, circle_pressure(x, b=ex.half_width, R=th.R, E_star=th.E_star), center=0.0,
            half_width=max(half_width_fem, ex.half_width), p_ref=ex.p0)
    return th, errors


def exact_circle(th: BlockTheory) -> CircleContact:
    """The exact circle's half-plane contact at the load of ``th`` (:mod:`analytic.circle`; Hertz is its
    parabolic approximation, off by about 3 (a/R)^2 / 16 in the half-width)."""
    return circle_contact(th.P, th.R, th.E_star)
