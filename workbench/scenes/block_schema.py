"""What a case file of the block scene may say: its geometry record and checks (:class:`cases.schema.SceneSchema`).

An elastic block under a rigid circle, parabola or wedge, force-controlled, compared with half-plane theory
(:mod:`workbench.scenes.block`). Registered with the case schema by :func:`workbench.scenes.base.register_scene`
(``BlockScene.schema``). Units: mm, N, MPa; angles in rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from cases.schema import MAX_SIZE_FACTOR, Case, CaseError, Geometry, Run, SceneSchema
from cases.schema import short_repr as _r

__all__ = ["BLOCK_SCHEMA", "BlockGeometry", "HALF_WIDTH_RANGE", "MAX_ASPECT", "MIN_A_OVER_R"]

# A block contact: the approach d ~ a^2 / R must stay far above the round-off of the coordinates (~1e-16 R).
# Measured on hertz_cylinder (P2, h = a/20): a/R = 1e-5 within the case tolerances (p_max 0.05 %), 1e-6
# p_max 1 % with an oscillating pressure, 1e-7 round-off noise (13 patches, p_max 87 % off).
MIN_A_OVER_R = 1e-5
# The classical half-width (mm) the mesh is sized from: measured sound from 5e-8 mm (R = 1e-6 mm) upwards.
HALF_WIDTH_RANGE = (1e-8, 1e8)
# Block size over the half-width: W/H is kept within 1e3 (far-field elements too stretched for load balance);
# width and height beyond MAX_SIZE_FACTOR a are refused (cases.schema).
MAX_ASPECT = 1e3


@dataclass(frozen=True)
class BlockGeometry(Geometry):
    """Geometry of a block scene (``scene = "block"``): an elastic block under a rigid indenter.

    Attributes:
        indenter: ``"circle"``, ``"parabola"`` or ``"wedge"``.
        radius: Indenter radius R in mm (circle, parabola).
        wedge_angle: External wedge angle theta in rad, 0 < theta < pi/2.
        wedge_slope: ``"exact"`` (face slope tan(theta), the true geometry) or ``"paper"`` (slope
            theta, the small-angle profile of Ciavarella & Hills).
        width_factor: Block width W over the classical contact half-width (>= 10).
        height_factor: Block height H over the classical contact half-width (>= 10).
        half_model: Mesh half the block with a symmetry edge.
        far_field: Outer boundary of the block: ``"clamped"`` (bottom clamped, sides free) or ``"halfplane"``
            (bottom and sides moved as the half-plane under the line load P, Flamant's field:
            :mod:`fem.far_field`; force control). The error budget always uses ``"halfplane"``.
    """

    radius: float | None = None
    wedge_angle: float | None = None
    wedge_slope: str = "exact"
    width_factor: float = 40.0
    height_factor: float = 40.0
    half_model: bool = True
    far_field: str = "clamped"


_BODY = {"width_factor", "height_factor", "half_model", "far_field"}


def _check_geometry(run: Run, where: str) -> None:
    """The indenter's own geometry field is required; a circle cannot make a contact wider than itself."""
    g, ld = run.geometry, run.loading
    if g.indenter in ("circle", "parabola") and g.radius is None:
        raise CaseError(f"{where}: geometry.radius is required for a {g.indenter}; allowed: radius > 0 (mm)")
    if g.indenter == "wedge" and g.wedge_angle is None:
        raise CaseError(
            f"{where}: geometry.wedge_angle is required for a wedge; allowed: 0 < wedge_angle < pi/2 (rad)"
        )
    if g.indenter == "circle" and ld.control == "force" and (ld.P is None) != (ld.half_width is None):
        _check_circle_reachable(run, where)


def _check_load(run: Run, where: str) -> None:
    """Magnitudes of a force-controlled block run (after the loading's own checks)."""
    ld = run.loading
    if ld.control == "force" and (ld.P is None) != (ld.half_width is None):
        _check_block_scale(run, where)


def _check_case(case: Case, runs: tuple[Run, ...], where: str) -> None:
    """The ``convective`` prediction compares a small and a convective run of the case."""
    if "convective" in case.analytic.predictions:
        kinematics = {r.solver.kinematics for r in runs}
        if not {"small", "convective"} <= kinematics:
            raise CaseError(f"{where}: analytic.predictions lists 'convective', which compares a small and a "
                            f"convective run; got kinematics {sorted(kinematics)}; allowed: [[variant]] runs with "
                            "solver.kinematics = 'small' and 'convective' (finite runs may be added)")


def _classical_half_width(run: Run) -> float:
    """The classical half-width (mm) of a force-controlled block run (Hertz or wedge)."""
    from analytic import hertz, materials, wedge

    g, ld = run.geometry, run.loading
    if ld.half_width is not None:
        return ld.half_width
    E_star = materials.plane_strain_modulus(run.material.E, run.material.nu)
    if g.indenter == "wedge":
        return wedge.wedge(ld.P, wedge.wedge_slope(g.wedge_angle, convention=g.wedge_slope), E_star).half_width
    return hertz.hertz_half_width(ld.P, g.radius, E_star)


def _check_block_scale(run: Run, where: str) -> None:
    """Magnitudes a double-precision solve resolves: the contact against the radius and in absolute size."""
    g, ld = run.geometry, run.loading
    field_ = "loading.half_width" if ld.half_width is not None else "loading.P"
    value = ld.half_width if ld.half_width is not None else ld.P
    try:
        a = _classical_half_width(run)
    except (ValueError, ArithmeticError):
        a = math.nan
    if g.indenter == "parabola" and a >= 0.5 * g.radius:
        raise CaseError(f"{where}: {field_} = {_r(value)} gives a contact half-width a = {a:.4g} mm against "
                        f"radius {g.radius:g} mm: strains of order a/R, beyond the small-strain model; allowed: "
                        f"half-width < radius/2 = {0.5 * g.radius:.4g} mm")
    if g.indenter in ("circle", "parabola") and math.isfinite(a) and a < MIN_A_OVER_R * g.radius:
        raise CaseError(f"{where}: {field_} = {_r(value)} gives a contact half-width a = {a:.3g} mm, a/R = "
                        f"{a / g.radius:.2g}: the approach a^2/R is at the round-off of the coordinates (the "
                        f"pressure would be noise, not a mesh-resolution problem); allowed: a/R >= {MIN_A_OVER_R:g} "
                        "(raise the load)")
    lo, hi = HALF_WIDTH_RANGE
    if not (math.isfinite(a) and lo <= a <= hi):
        raise CaseError(f"{where}: {field_} = {_r(value)} with material.E = {run.material.E!r} gives a contact "
                        f"half-width of {a:.3g} mm; allowed: {lo:g} <= half-width <= {hi:g} mm (change the load or "
                        "E, or the units)")
    if max(g.width_factor / g.height_factor, g.height_factor / g.width_factor) > MAX_ASPECT:
        raise CaseError(f"{where}: geometry.width_factor / height_factor = {g.width_factor:g} / {g.height_factor:g} "
                        f"makes far-field elements too stretched for load balance; allowed: a ratio within "
                        f"1/{MAX_ASPECT:g} ... {MAX_ASPECT:g}")


def _check_circle_reachable(run: Run, where: str) -> None:
    """A rigid circle cannot make a contact wider than itself: the Hertz half-width must stay below R/2
    (the half-plane theory and the case's comparison mean nothing beyond that)."""
    from analytic import hertz, materials

    g, ld = run.geometry, run.loading
    limit = 0.5 * g.radius
    if ld.half_width is not None:
        a = ld.half_width
    else:
        a = hertz.hertz_half_width(ld.P, g.radius, materials.plane_strain_modulus(run.material.E, run.material.nu))
    if a >= limit:
        field_ = "loading.half_width" if ld.half_width is not None else "loading.P"
        value = ld.half_width if ld.half_width is not None else ld.P
        raise CaseError(f"{where}: {field_} = {_r(value)} cannot be reached by a circle of radius {g.radius} mm "
                        f"(Hertz half-width {a:.4g} mm); allowed: half-width < radius/2 = {limit:.4g} mm")


BLOCK_SCHEMA = SceneSchema(
    name="block",
    geometry=BlockGeometry,
    indenters={"circle": frozenset({"radius"} | _BODY), "parabola": frozenset({"radius"} | _BODY),
               "wedge": frozenset({"wedge_angle", "wedge_slope"} | _BODY)},
    predictions={"circle": ("hertz", "convective"), "parabola": ("hertz", "convective"),
                 "wedge": ("wedge", "convective")},
    controls=("force",),
    choices={"wedge_slope": ("exact", "paper"), "far_field": ("clamped", "halfplane")},
    ranges={
        "radius": (0.0, math.inf, False, False, "radius > 0 (mm)"),
        "wedge_angle": (0.0, math.pi / 2, False, False, "0 < wedge_angle < pi/2 (rad)"),
        "width_factor": (10.0, MAX_SIZE_FACTOR, True, True, f"10 <= width_factor <= {MAX_SIZE_FACTOR:g}"),
        "height_factor": (10.0, MAX_SIZE_FACTOR, True, True, f"10 <= height_factor <= {MAX_SIZE_FACTOR:g}"),
    },
    tolerances={
        "p_max": "relative error of the peak pressure",
        "half_width": "relative error of the contact half-width",
        "rms": "RMS(p_fem - p_theory) / p0",
        "load_balance": "|P - P_pressure| / P",
        "b_over_b0": "relative error of the FEM convective ratio b/b0 against the converged theory",
        "rms_convective": "RMS(p_fem - p_convective)/p_ref of the convective run against the converged theory",
    },
    band_quantities=("p_max", "half_width", "half_width_moment", "b_over_b0", "b_over_b0_moment"),
    finite=True,
    mixed=True,
    budget_widths=None,
    check_geometry=_check_geometry,
    check_load=_check_load,
    check_case=_check_case,
)
