"""Curves (analytic/curves.py): geometry against closed forms, B-spline derivatives against finite
differences, projection against known closest points."""

import numpy as np
import pytest

from analytic.curves import BSpline, CircleArc, CompositeCurve, Ellipse, Line

EPS = np.finfo(float).eps
CP = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, -1.0], [3.0, 0.5], [4.0, 0.0], [5.0, 1.5]])


@pytest.mark.parametrize("ccw", [True, False])
def test_circle_arc_geometry(ccw):
    # C = c + r (cos phi, sin phi); CCW: left normal = -(cos, sin), curvature +1/r; CW: the opposite
    c, r = np.array([1.0, -2.0]), 3.0
    arc = CircleArc(c, r, 0.3, 0.3 + 2.0 if ccw else 0.3 - 2.0)
    t = np.linspace(0.0, 1.0, 7)
    phi = 0.3 + (2.0 if ccw else -2.0) * t
    radial = np.column_stack([np.cos(phi), np.sin(phi)])
    s = 1.0 if ccw else -1.0
    np.testing.assert_allclose(arc.point(t), c + r * radial, atol=1e-14)
    np.testing.assert_allclose(arc.tangent(t), s * np.column_stack([-np.sin(phi), np.cos(phi)]), atol=1e-14)
    np.testing.assert_allclose(arc.normal(t), -s * radial, atol=1e-14)
    np.testing.assert_allclose(arc.curvature(t), s / r, rtol=1e-14)
    np.testing.assert_allclose(arc.radius(t), s * r, rtol=1e-14)


def test_bspline_clamped_ends_and_derivatives_against_finite_differences():
    spl = BSpline(CP)
    # clamped: interpolates the end control points, tangent to the control polygon there:
    # C'(0) = 3 m (P1 - P0) with m knot spans
    np.testing.assert_allclose(spl.point([0.0, 1.0]), CP[[0, -1]], atol=1e-14)
    m = len(CP) - 3  # number of knot spans
    np.testing.assert_allclose(spl.derivative([0.0])[0], 3 * m * (CP[1] - CP[0]), rtol=1e-12)
    # central differences; the points avoid the knots 1/3, 2/3 where C''' jumps.
    # Error of D1: h^2/6 |C'''| ~ 1e-10 * 6^3 ~ 1e-8 (round-off eps/h ~ 1e-11); D2 with h = 1e-4: ~1e-6.
    t = np.array([0.1, 0.25, 0.45, 0.6, 0.8, 0.95])
    h = 1e-5
    fd1 = (spl.point(t + h) - spl.point(t - h)) / (2 * h)
    np.testing.assert_allclose(spl.derivative(t, 1), fd1, rtol=1e-7, atol=1e-7)
    h = 1e-4
    fd2 = (spl.point(t + h) - 2 * spl.point(t) + spl.point(t - h)) / h**2
    np.testing.assert_allclose(spl.derivative(t, 2), fd2, rtol=1e-5, atol=1e-4)
    # curvature: x'y'' - y'x'' over |C'|^3 from the finite-difference derivatives
    k_fd = (fd1[:, 0] * fd2[:, 1] - fd1[:, 1] * fd2[:, 0]) / np.linalg.norm(fd1, axis=1) ** 3
    np.testing.assert_allclose(spl.curvature(t), k_fd, rtol=1e-4)
    # unit tangent / left normal
    tg = spl.tangent(t)
    np.testing.assert_allclose(np.linalg.norm(tg, axis=1), 1.0, atol=1e-15)
    np.testing.assert_allclose(spl.normal(t), np.column_stack([-tg[:, 1], tg[:, 0]]), atol=0)


def test_bspline_of_a_circle_like_quarter_has_positive_curvature_when_turning_left():
    # degree-2 Bezier (a parabola y = x^2 / 2 on [-1, 1]) runs left to right and turns left: kappa(0) = 1
    spl = BSpline([[-1.0, 0.5], [0.0, -0.5], [1.0, 0.5]], degree=2)
    np.testing.assert_allclose(spl.curvature([0.5]), 1.0, rtol=1e-14)
    np.testing.assert_allclose(spl.normal([0.5]), [[0.0, 1.0]], atol=1e-15)


def test_ellipse_curvature_closed_form():
    a, b = 3.0, 2.0
    ell = Ellipse([0.0, 0.0], a, b)
    t = np.linspace(0, 1, 9)
    phi = 2 * np.pi * t
    k = a * b / (a**2 * np.sin(phi) ** 2 + b**2 * np.cos(phi) ** 2) ** 1.5
    np.testing.assert_allclose(ell.curvature(t), k, rtol=1e-13)


def test_projection_onto_bspline_recovers_known_closest_points():
    # x = C(t_k) + s N(t_k) with |s| below the local radius of curvature and far from other branches:
    # the closest point is C(t_k), the signed distance s. Newton converges quadratically: 1e-10 is ~1e5 eps.
    spl = BSpline(CP)
    t_k = np.linspace(0.05, 0.95, 37)
    s = 0.05 * np.sin(np.arange(37))
    x = spl.point(t_k) + s[:, None] * spl.normal(t_k)
    pr = spl.project(x)
    np.testing.assert_allclose(pr.t, t_k, atol=1e-10)
    np.testing.assert_allclose(pr.foot, spl.point(t_k), atol=1e-10)
    np.testing.assert_allclose(pr.distance, s, atol=1e-10)
    np.testing.assert_allclose(pr.normal, spl.normal(t_k), atol=1e-10)
    # t_guess gives the same global answer
    pr2 = spl.project(x, t_guess=np.clip(t_k + 0.01, 0, 1))
    np.testing.assert_allclose(pr2.t, t_k, atol=1e-10)


def test_projection_is_global_against_brute_force():
    spl = BSpline(CP)
    rng = np.random.default_rng(1)
    x = rng.uniform([-1, -2], [6, 3], size=(150, 2))
    pr = spl.project(x)
    tt = np.linspace(0, 1, 200001)
    pts = spl.point(tt)
    brute = np.array([np.min(np.linalg.norm(pts - xi, axis=1)) for xi in x])
    # brute force samples every ~3e-5 mm: its distance exceeds the true one by at most ~1e-9 mm
    assert np.all(np.abs(pr.distance) <= brute + 1e-12)
    assert np.all(np.abs(pr.distance) >= brute - 1e-8)


def test_circle_and_line_projection_signed_distance():
    circle = CircleArc([0.0, 0.0], 2.0, 2 * np.pi, 0.0)  # clockwise: normal points outwards
    pr = circle.project([[3.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    np.testing.assert_allclose(pr.distance, [1.0, -1.0, np.sqrt(2) - 2.0], atol=1e-15)
    np.testing.assert_allclose(pr.foot, [[2.0, 0.0], [0.0, 2.0], [np.sqrt(2), np.sqrt(2)]], atol=1e-15)
    line = Line([0.0, 0.0], [2.0, 0.0])  # left normal +y
    pr = line.project([[1.0, 0.5], [3.0, -1.0]])
    np.testing.assert_allclose(pr.distance, [0.5, -np.sqrt(2)], atol=1e-15)
    np.testing.assert_allclose(pr.t, [0.5, 1.0], atol=1e-15)


def test_composite_curve_parameter_and_translation():
    spl = BSpline([[2.0, 0.0], [1.0, -1.0], [-1.0, -1.0], [-2.0, 0.0]])
    arc = CircleArc([0.0, 0.0], 2.0, np.pi, 0.0)  # clockwise over the top, closes the spline
    comp = CompositeCurve([spl, arc])
    assert comp.t_min == 0.0 and comp.t_max == 2.0 and comp.is_closed
    np.testing.assert_allclose(comp.point([0.3, 1.25]), np.vstack([spl.point([0.3]), arc.point([0.25])]))
    np.testing.assert_allclose(comp.derivative([1.5]), arc.derivative([0.5]))
    moved = comp.translated([0.5, -0.25])
    np.testing.assert_allclose(moved.point([0.7, 1.7]), comp.point([0.7, 1.7]) + [0.5, -0.25], atol=1e-15)
    # closed clockwise curve: distance > 0 outside, < 0 inside
    pr = comp.project([[0.0, 3.0], [0.0, 0.0], [0.0, -2.0]])
    assert pr.distance[0] == pytest.approx(1.0, abs=1e-12)
    assert pr.distance[1] < 0 and pr.distance[2] > 0


def test_bad_arguments_raise_value_error():
    with pytest.raises(ValueError, match="control_points"):
        BSpline([[0.0, 0.0], [1.0, 1.0]])
    with pytest.raises(ValueError, match="radius"):
        CircleArc([0, 0], -1.0, 0.0, 1.0)
    with pytest.raises(ValueError, match="continuous"):
        CompositeCurve([Line([0, 0], [1, 0]), Line([2, 0], [3, 0])])
    with pytest.raises(ValueError, match="points"):
        Line([0, 0], [1, 0]).project(np.zeros((3, 3)))
