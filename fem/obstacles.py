"""Rigid analytic obstacles for frictionless contact (never meshed).

Conventions (units: mm):

* An obstacle is a rigid body moved by ``d * direction`` (``direction`` a unit vector, default ``(0, -1)``:
  pressing down on the block top ``y = 0``). Moving the obstacle by ``s = d * direction`` is the same as
  evaluating the unmoved obstacle at ``x - s``.
* ``signed_distance(x1, x2, d=..., xp=...)`` returns ``Gap(g, n1, n2)``: the signed gap ``g`` (> 0 outside the
  obstacle, i.e. open; < 0 penetration) and the unit OUTWARD normal ``n`` of the obstacle (the gradient of
  ``g`` with respect to ``x``). The traction that the obstacle exerts on the body is ``t = p n`` with the
  contact pressure ``p >= 0``.
* ``lower_surface(x1, d=..., xp=...)`` is the height ``phi(x1) - d`` of the obstacle's lower surface at abscissa
  ``x1`` (half-plane mode: vertical gap ``g = phi(x1) - d - x2``, traction along ``-e_y``).

Every formula is written once with a math-module argument ``xp`` (``numpy`` or ``ufl``) so the UFL weak form
and the numpy post-processing share the same line.

:class:`CurveObstacle` wraps a general :class:`analytic.curves.Curve` (closed, clockwise, so its left normal is
the outward normal): numpy only, evaluated at nodes through ``curve.project``.
"""

from __future__ import annotations

import copy
import math
from typing import Any, ClassVar, NamedTuple

import numpy as np

__all__ = [
    "Gap",
    "math_ops",
    "AnalyticObstacle",
    "CircleObstacle",
    "ParabolaObstacle",
    "WedgeObstacle",
    "PlaneObstacle",
    "CurveObstacle",
]


class Gap(NamedTuple):
    """Signed gap ``g`` (mm, > 0 open) and outward obstacle normal ``(n1, n2)`` at the evaluation points."""

    g: Any
    n1: Any
    n2: Any


class _Ops(NamedTuple):
    sqrt: Any
    sign: Any
    maximum: Any
    abs: Any


def math_ops(xp) -> _Ops:
    """Elementary functions for the math module ``xp`` (``numpy`` or ``ufl``)."""
    if xp is np:
        return _Ops(np.sqrt, np.sign, np.maximum, np.abs)
    import ufl

    if xp is ufl:
        return _Ops(ufl.sqrt, ufl.sign, ufl.max_value, abs)
    raise ValueError(f"xp must be numpy or ufl, got {xp!r}")


def _unit(direction) -> tuple[float, float]:
    v = np.asarray(direction, dtype=float).reshape(2)
    n = float(np.hypot(*v))
    if not np.isfinite(n) or n == 0.0:
        raise ValueError(f"direction must be a non-zero 2-vector, got {direction!r}")
    return float(v[0] / n), float(v[1] / n)


class AnalyticObstacle:
    """Base of the analytic obstacles: translation by ``d * direction`` and the two gap formulas.

    ``geometry``: the names of the attributes (floats, or tuples of floats) that size and place the obstacle;
    :meth:`with_constants` turns them into dolfinx Constants for the UFL forms (:mod:`fem.coefficients`). The
    loading ``direction`` stays a Python vector (it decides the form's structure).
    """

    analytic = True
    geometry: ClassVar[tuple[str, ...]] = ()

    def __init__(self, direction=(0.0, -1.0)):
        self.direction = _unit(direction)

    def with_constants(self, mesh) -> AnalyticObstacle:
        """A copy whose :attr:`geometry` attributes are dolfinx Constants on ``mesh`` (same values), for the UFL
        forms: another radius or apex then reuses the compiled form (:mod:`fem.coefficients`). The numpy
        formulas keep using ``self``."""
        from fem.coefficients import scalar

        out = copy.copy(self)
        for name in self.geometry:
            value = getattr(self, name)
            setattr(out, name, tuple(scalar(mesh, v) for v in value) if isinstance(value, tuple)
                    else scalar(mesh, value))
        return out

    # -- to implement (obstacle at d = 0) ------------------------------------------------------------------
    def _distance0(self, x1, x2, xp) -> Gap:
        raise NotImplementedError

    def _phi0(self, x1, xp):
        raise NotImplementedError

    # -- public -----------------------------------------------------------------------------------------------
    def signed_distance(self, x1, x2, *, d, xp=np) -> Gap:
        """Signed gap and outward normal of the obstacle moved by ``d * direction`` at point ``(x1, x2)``."""
        s1, s2 = self.direction
        return self._distance0(x1 - d * s1, x2 - d * s2, xp)

    def lower_surface(self, x1, *, d, xp=np):
        """Height (mm) of the moved obstacle's lower surface at abscissa ``x1`` (graph ``y = phi(x1)``)."""
        s1, s2 = self.direction
        return self._phi0(x1 - d * s1, xp) + d * s2

    def halfplane_gap(self, x1, x2, *, d, xp=np):
        """Vertical gap ``g = phi(x1) - d - x2`` of half-plane theory (mm, > 0 open)."""
        return self.lower_surface(x1, d=d, xp=xp) - x2


class CircleObstacle(AnalyticObstacle):
    """Rigid circle (the exact circle): ``g = |x - c| - R``, ``n = (x - c) / |x - c|``.

    Args:
        center: centre (mm) at d = 0; ``(0, R)`` touches the block top ``y = 0`` at the origin.
        radius: R (mm) > 0.
        direction: unit loading direction of the rigid body.
    """

    geometry = ("center", "radius")

    def __init__(self, *, center, radius: float, direction=(0.0, -1.0)):
        super().__init__(direction)
        if not radius > 0:
            raise ValueError(f"radius must be > 0, got {radius}")
        self.center = tuple(float(c) for c in center)
        self.radius = float(radius)

    def __repr__(self) -> str:
        return f"CircleObstacle(center={self.center}, radius={self.radius}, direction={self.direction})"

    def hertz_contact(self) -> tuple[float, float, float]:
        """(x_c, y_lowest, R): abscissa and height of the lowest point at d = 0, radius (Hertz predictor)."""
        return self.center[0], self.center[1] - self.radius, self.radius

    def half_plane_half_width(self, P: float, E_star: float) -> float:
        """Contact half-width (mm) of this exact circle on an elastic half-plane under the load P (N/mm), plane
        strain modulus E_star (MPa): :func:`analytic.circle.circle_half_width` (smaller than Hertz's by about
        3 (a/R)^2 / 16)."""
        from analytic.circle import circle_half_width

        return circle_half_width(P, self.radius, E_star)

    def _distance0(self, x1, x2, xp) -> Gap:
        ops = math_ops(xp)
        r1, r2 = x1 - self.center[0], x2 - self.center[1]
        r = ops.sqrt(r1 * r1 + r2 * r2)
        return Gap(r - self.radius, r1 / r, r2 / r)

    def _phi0(self, x1, xp):
        ops = math_ops(xp)
        r1 = x1 - self.center[0]
        return self.center[1] - ops.sqrt(ops.maximum(self.radius**2 - r1 * r1, 0.0))


class _GraphObstacle(AnalyticObstacle):
    """Obstacle above the graph ``y = phi(x1)``; gap ``g = (phi - x2) / sqrt(1 + phi'^2)``.

    That gap is the first-order normal distance to the graph: exact at ``g = 0`` with gradient equal to the
    outward normal ``n = (phi', -1) / sqrt(1 + phi'^2)`` there (exact everywhere for straight faces).
    """

    def _dphi0(self, x1, xp):
        raise NotImplementedError

    def _distance0(self, x1, x2, xp) -> Gap:
        ops = math_ops(xp)
        dphi = self._dphi0(x1, xp)
        s = ops.sqrt(1.0 + dphi * dphi)
        return Gap((self._phi0(x1, xp) - x2) / s, dphi / s, -1.0 / s)


class ParabolaObstacle(_GraphObstacle):
    """Rigid parabola ``y = v2 + (x - v1)^2 / (2 R)`` (the Hertz approximation of a circle of radius R)."""

    geometry = ("radius", "vertex")

    def __init__(self, *, radius: float, vertex=(0.0, 0.0), direction=(0.0, -1.0)):
        super().__init__(direction)
        if not radius > 0:
            raise ValueError(f"radius must be > 0, got {radius}")
        self.radius = float(radius)
        self.vertex = tuple(float(v) for v in vertex)

    def __repr__(self) -> str:
        return f"ParabolaObstacle(radius={self.radius}, vertex={self.vertex}, direction={self.direction})"

    def hertz_contact(self) -> tuple[float, float, float]:
        """(x_c, y_lowest, R): vertex abscissa and height at d = 0, radius (Hertz predictor)."""
        return self.vertex[0], self.vertex[1], self.radius

    def half_plane_half_width(self, P: float, E_star: float) -> float:
        """Contact half-width (mm) of this parabola on an elastic half-plane under the load P (N/mm), plane strain
        modulus E_star (MPa): Hertz's, exact for the parabola."""
        from analytic.hertz import hertz

        return hertz(P, self.radius, E_star).half_width

    def _phi0(self, x1, xp):
        r1 = x1 - self.vertex[0]
        return self.vertex[1] + r1 * r1 / (2.0 * self.radius)

    def _dphi0(self, x1, xp):
        return (x1 - self.vertex[0]) / self.radius


class WedgeObstacle(_GraphObstacle):
    """Rigid wedge ``y = v2 + m |x - v1|`` with face slope ``m`` (``m = tan(theta)`` for external angle theta).

    The gap is the distance to the nearer face (exact for points whose foot is on a face, i.e. outside the
    apex's normal cone; at and inside contact it is exact).
    """

    geometry = ("slope", "apex")

    def __init__(self, *, slope: float, apex=(0.0, 0.0), direction=(0.0, -1.0)):
        super().__init__(direction)
        if not (slope > 0 and math.isfinite(slope)):
            raise ValueError(f"slope must be finite and > 0, got {slope}")
        self.slope = float(slope)
        self.apex = tuple(float(v) for v in apex)

    def __repr__(self) -> str:
        return f"WedgeObstacle(slope={self.slope}, apex={self.apex}, direction={self.direction})"

    def _phi0(self, x1, xp):
        return self.apex[1] + self.slope * math_ops(xp).abs(x1 - self.apex[0])

    def _dphi0(self, x1, xp):
        return self.slope * math_ops(xp).sign(x1 - self.apex[0])


class PlaneObstacle(_GraphObstacle):
    """Rigid half-plane (flat punch wider than the body) with lower surface ``y = height`` at d = 0."""

    geometry = ("height",)

    def __init__(self, *, height: float = 0.0, direction=(0.0, -1.0)):
        super().__init__(direction)
        self.height = float(height)

    def __repr__(self) -> str:
        return f"PlaneObstacle(height={self.height}, direction={self.direction})"

    def _phi0(self, x1, xp):
        return self.height + 0.0 * x1

    def _dphi0(self, x1, xp):
        return 0.0 * x1


class CurveObstacle:
    """Rigid body bounded by a general closed curve (e.g. a B-spline particle), clockwise oriented.

    The gap is ``curve.project(x).distance`` (> 0 outside) and the normal the projection's left normal
    (outward). numpy only: the solver evaluates it at the contact boundary nodes every Newton iteration.
    """

    analytic = False

    def __init__(self, curve, *, direction=(0.0, -1.0)):
        self.curve = curve
        self.direction = _unit(direction)

    def __repr__(self) -> str:
        return f"CurveObstacle({self.curve!r}, direction={self.direction})"

    def signed_distance(self, x1, x2, *, d, xp=np) -> Gap:
        """Signed gap and outward normal of the moved curve at points ``(x1, x2)`` (numpy arrays)."""
        if xp is not np:
            raise ValueError("CurveObstacle supports xp=numpy only")
        s = d * np.asarray(self.direction)
        pts = np.column_stack([np.ravel(x1) - s[0], np.ravel(x2) - s[1]])
        pr = self.curve.project(pts)
        return Gap(pr.distance, pr.normal[:, 0], pr.normal[:, 1])
