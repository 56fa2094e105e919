"""Elastic constants for 2D (plane strain / plane stress) contact between two bodies.

Units: moduli in MPa (N/mm^2); Poisson's ratios dimensionless. Body 1 is the indenter (``E1 = inf``
means rigid), body 2 the deformable body. Every formula lives here once; the other modules call it.

Equations:
    plane-strain modulus       E' = E / (1 - nu^2)
    composite modulus          1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2                (plane strain)
    composite compliance       A = 2 [(1 - nu1^2)/E1 + (1 - nu2^2)/E2] = 2/E*      (Ciavarella & Hills eq. 2)
    Kolosov constant           kappa = 3 - 4 nu (plane strain), (3 - nu)/(1 + nu) (plane stress)
    Dundurs constants          alpha = [Gam (k1 + 1) - (k2 + 1)] / [Gam (k1 + 1) + (k2 + 1)]
                               beta  = [Gam (k1 - 1) - (k2 - 1)] / [Gam (k1 + 1) + (k2 + 1)],
                               Gam = mu2/mu1 (mu = E / (2 (1 + nu)) the shear modulus)
    rigid indenter (Gam = 0)   alpha = -1, beta = -(k2 - 1)/(k2 + 1) = -(1 - 2 nu2)/(2 (1 - nu2)) (plane strain)

Dundurs sign convention (Ciavarella & Hills eq. 6, Johnson's Contact Mechanics): body 1 is the INDENTER (the body
that carries the profile), body 2 the flat block / half-plane, Gam = mu2/mu1. A rigid indenter (mu1 = inf) gives
alpha = -1 and beta = -(1 - 2 nu2)/(2 (1 - nu2)) in [-1/2, 0] (C&H: "body 1 the more rigid, beta < 0"); a rigid
block gives alpha = +1, beta = +(1 - 2 nu1)/(2 (1 - nu1)); exchanging the bodies changes the signs of both;
identical materials give alpha = beta = 0.

Admissible plane-strain values (:func:`bimaterial`, -1 < nu <= 1/2, so 1 <= kappa < 7): alpha runs over [-1, 1]
and, at fixed nu1, nu2, beta increases monotonically with Gam (d beta/d Gam ~ 2 (k1 k2 - 1) >= 0) from
-(1 - 2 nu2)/(2 (1 - nu2)) (rigid indenter) to +(1 - 2 nu1)/(2 (1 - nu1)) (rigid block) (:func:`beta_range`).
For 0 <= nu <= 1/2 that keeps |beta| <= 1/2 and -1 <= alpha - 4 beta <= 1 (Dundurs' parallelogram);
auxetic materials (nu < 0) reach |beta| up to 3/4, beyond the convective theory's -1/2 <= beta <= 1/2.
"""

from __future__ import annotations

import math
from typing import NamedTuple

__all__ = [
    "validate_positive",
    "Bimaterial",
    "Dundurs",
    "beta_range",
    "beta_rigid_indenter",
    "bimaterial",
    "compliance",
    "composite_modulus",
    "dundurs",
    "kolosov",
    "plane_strain_modulus",
    "shear_modulus",
    "validate_modulus",
    "validate_poisson",
]

_PLANES = ("strain", "stress")


class Dundurs(NamedTuple):
    """Dundurs' bimaterial constants (dimensionless); body 1 = indenter, body 2 = deformable body."""

    alpha: float
    beta: float


def validate_modulus(E: float, name: str = "E", *, allow_inf: bool = False) -> float:
    """Return ``E`` as float or raise ``ValueError`` unless 0 < E (< inf unless ``allow_inf``)."""
    E = float(E)
    if math.isnan(E) or E <= 0.0 or (math.isinf(E) and not allow_inf):
        rng = "0 < {n} <= inf (inf = rigid)" if allow_inf else "0 < {n} < inf"
        raise ValueError(f"{name} = {E!r} out of range: need {rng.format(n=name)} (MPa)")
    return E


def validate_positive(value: float, name: str, unit: str) -> float:
    """Return ``value`` as float or raise ``ValueError`` unless 0 < value < inf (``unit`` names its unit)."""
    value = float(value)
    if not (value > 0.0 and math.isfinite(value)):
        raise ValueError(f"{name} = {value!r} out of range: need 0 < {name} < inf ({unit})")
    return value


def validate_poisson(nu: float, name: str = "nu", *, incompressible: bool = False) -> float:
    """Return ``nu`` as float or raise ``ValueError`` unless -1 < nu < 0.5 (nu <= 0.5 if ``incompressible``)."""
    nu = float(nu)
    if incompressible:
        if not (-1.0 < nu <= 0.5):
            raise ValueError(f"{name} = {nu!r} out of range: need -1 < {name} <= 0.5")
        return nu
    if not (-1.0 < nu < 0.5):
        raise ValueError(f"{name} = {nu!r} out of range: need -1 < {name} < 0.5")
    return nu


def _validate_plane(plane: str) -> str:
    if plane not in _PLANES:
        raise ValueError(f"plane = {plane!r} out of range: need one of {_PLANES}")
    return plane


def shear_modulus(E: float, nu: float) -> float:
    """Shear modulus mu = E / (2 (1 + nu)) in MPa (``inf`` for a rigid body)."""
    E = validate_modulus(E, allow_inf=True)
    nu = validate_poisson(nu)
    return E / (2.0 * (1.0 + nu))


def plane_strain_modulus(E: float, nu: float) -> float:
    """Plane-strain modulus E' = E / (1 - nu^2) in MPa."""
    E = validate_modulus(E, allow_inf=True)
    nu = validate_poisson(nu)
    return E / (1.0 - nu * nu)


def _compliance_sum(E1: float, nu1: float, E2: float, nu2: float) -> float:
    """(1 - nu1^2)/E1 + (1 - nu2^2)/E2 = 1/E* (1/MPa, plane strain), on checked values."""
    return (1.0 - nu1 * nu1) / E1 + (1.0 - nu2 * nu2) / E2


def _half_compliance(E1: float, nu1: float, E2: float, nu2: float) -> float:
    """(1 - nu1^2)/E1 + (1 - nu2^2)/E2 in 1/MPa (plane strain); E1 = inf gives a rigid body 1."""
    E1 = validate_modulus(E1, "E1", allow_inf=True)
    E2 = validate_modulus(E2, "E2", allow_inf=True)
    nu1 = validate_poisson(nu1, "nu1")
    nu2 = validate_poisson(nu2, "nu2")
    c = _compliance_sum(E1, nu1, E2, nu2)
    if c <= 0.0:
        raise ValueError("E1, E2 out of range: at least one body must be deformable (finite E)")
    return c


def composite_modulus(E2: float, nu2: float, *, E1: float = math.inf, nu1: float = 0.0) -> float:
    """Composite (effective) plane-strain modulus E* in MPa.

    1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2; the default body 1 is rigid (E1 = inf), so E* = E2/(1 - nu2^2).

    Args:
        E2: Young's modulus of the deformable body (MPa).
        nu2: Poisson's ratio of the deformable body.
        E1: Young's modulus of the indenter (MPa), ``inf`` = rigid.
        nu1: Poisson's ratio of the indenter (irrelevant when rigid).
    """
    return 1.0 / _half_compliance(E1, nu1, E2, nu2)


def compliance(E2: float, nu2: float, *, E1: float = math.inf, nu1: float = 0.0) -> float:
    """Composite compliance A = 2 [(1 - nu1^2)/E1 + (1 - nu2^2)/E2] = 2/E* in 1/MPa (C&H eq. 2)."""
    return 2.0 * _half_compliance(E1, nu1, E2, nu2)


def kolosov(nu: float, *, plane: str = "strain") -> float:
    """Kolosov's constant: 3 - 4 nu (plane strain) or (3 - nu)/(1 + nu) (plane stress)."""
    nu = validate_poisson(nu)
    if _validate_plane(plane) == "strain":
        return 3.0 - 4.0 * nu
    return (3.0 - nu) / (1.0 + nu)


def dundurs(
    E2: float, nu2: float, *, E1: float = math.inf, nu1: float = 0.0, plane: str = "strain"
) -> Dundurs:
    """Dundurs' constants (alpha, beta) for indenter 1 on body 2 (E1 = inf: rigid indenter).

    alpha = [Gam (k1 + 1) - (k2 + 1)] / [Gam (k1 + 1) + (k2 + 1)],
    beta  = [Gam (k1 - 1) - (k2 - 1)] / [Gam (k1 + 1) + (k2 + 1)], Gam = mu2/mu1 (C&H eq. 6).

    With body 1 rigid (Gam = 0) this gives alpha = -1 and beta = -(k2 - 1)/(k2 + 1), which is negative
    for nu2 < 0.5: the sign Ciavarella & Hills use ("body 1 the more rigid, beta < 0").
    """
    E1 = validate_modulus(E1, "E1", allow_inf=True)
    E2 = validate_modulus(E2, "E2")
    k1 = kolosov(validate_poisson(nu1, "nu1"), plane=plane)
    k2 = kolosov(validate_poisson(nu2, "nu2"), plane=plane)
    gam = 0.0 if math.isinf(E1) else (E2 / (2.0 * (1.0 + nu2))) / (E1 / (2.0 * (1.0 + nu1)))
    return _dundurs(gam, k1, k2)


def _dundurs(gam: float, k1: float, k2: float) -> Dundurs:
    """(alpha, beta) from Gam = mu2/mu1 in [0, inf] and the Kolosov constants (C&H eq. 6)."""
    if math.isinf(gam):  # rigid body 2: the limit Gam -> inf
        return Dundurs(alpha=1.0, beta=(k1 - 1.0) / (k1 + 1.0))
    den = gam * (k1 + 1.0) + (k2 + 1.0)
    return Dundurs(
        alpha=(gam * (k1 + 1.0) - (k2 + 1.0)) / den,
        beta=(gam * (k1 - 1.0) - (k2 - 1.0)) / den,
    )


class Bimaterial(NamedTuple):
    """Two bodies in plane strain: 1 the indenter (carries the profile), 2 the flat block (see the module).

    Attributes:
        E1, nu1: Indenter's Young's modulus (MPa, ``inf`` = rigid) and Poisson's ratio.
        E2, nu2: Block's Young's modulus (MPa, ``inf`` = rigid) and Poisson's ratio.
        alpha, beta: Dundurs' constants (Gam = mu2/mu1; rigid indenter: alpha = -1, beta <= 0).
        E_star: Composite plane-strain modulus (MPa), 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2.
    """

    E1: float
    nu1: float
    E2: float
    nu2: float
    alpha: float
    beta: float
    E_star: float


def bimaterial(*, E1: float, nu1: float, E2: float, nu2: float) -> Bimaterial:
    """Dundurs' alpha, beta and the composite modulus E* of indenter 1 on block 2 (plane strain).

    E = ``inf`` makes that body rigid (not both); -1 < nu <= 1/2 (nu = 1/2: incompressible, kappa = 1).
    Convention and admissible ranges: see the module docstring (body 1 = indenter, Gam = mu2/mu1).

    Raises:
        ValueError: one line naming the field (E1, nu1, E2, nu2) and its range.
    """
    E1 = validate_modulus(E1, "E1", allow_inf=True)
    E2 = validate_modulus(E2, "E2", allow_inf=True)
    nu1 = validate_poisson(nu1, "nu1", incompressible=True)
    nu2 = validate_poisson(nu2, "nu2", incompressible=True)
    if math.isinf(E1) and math.isinf(E2):
        raise ValueError("E1, E2 = inf out of range: at least one body must be deformable (finite E)")
    if math.isinf(E1):  # the rigid limits in the same closed form as beta_rigid_indenter (bit-identical)
        d = Dundurs(alpha=-1.0, beta=-_beta_rigid(nu2))
    elif math.isinf(E2):
        d = Dundurs(alpha=1.0, beta=_beta_rigid(nu1))
    else:
        gam = (E2 / (2.0 * (1.0 + nu2))) / (E1 / (2.0 * (1.0 + nu1)))
        d = _dundurs(gam, 3.0 - 4.0 * nu1, 3.0 - 4.0 * nu2)
    E_star = 1.0 / _compliance_sum(E1, nu1, E2, nu2)
    return Bimaterial(E1, nu1, E2, nu2, d.alpha, d.beta, E_star)


def beta_range(*, nu1: float, nu2: float) -> tuple[float, float]:
    """The plane-strain beta interval reachable with these Poisson ratios as E1/E2 runs over (0, inf].

    (-(1 - 2 nu2)/(2 (1 - nu2)), (1 - 2 nu1)/(2 (1 - nu1))): rigid indenter to rigid block (module docstring).
    """
    nu1 = validate_poisson(nu1, "nu1", incompressible=True)
    nu2 = validate_poisson(nu2, "nu2", incompressible=True)
    return -_beta_rigid(nu2), _beta_rigid(nu1)


def _beta_rigid(nu: float) -> float:
    """(1 - 2 nu)/(2 (1 - nu)) = (kappa - 1)/(kappa + 1) in plane strain: |beta| when the other body is rigid."""
    return (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu))


def beta_rigid_indenter(nu2: float) -> float:
    """Dundurs beta for a rigid indenter on a body with Poisson ratio nu2 (plane strain).

    beta = -(1 - 2 nu2) / (2 (1 - nu2)); beta = -1/2 at nu2 = 0 (the extreme of C&H eq. 7), 0 at nu2 = 1/2.
    """
    return -_beta_rigid(validate_poisson(nu2, "nu2"))
