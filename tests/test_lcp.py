"""LCP (analytic/lcp.py, eq. (2) of the close-to-conformal paper) on curves with known answers, and the
default designs (analytic/designs.py) against the paper's reported geometry."""

import json

import numpy as np
import pytest

from analytic.curves import BSpline, CircleArc, Ellipse
from analytic.designs import design, particle_at
from analytic.lcp import cli, find_contact_pairs, relative_radius

TOL = 1e-10  # Newton on eq. (2) converges quadratically: 1e-10 mm is ~1e6 eps on mm-sized curves


def test_ellipse_inside_circle():
    # hole of radius 5 in body A (CCW: left normal points into the hole = out of A); elliptic particle
    # a = 3, b = 2 centred at (0.5, 0), clockwise. Plausible pairs on the major axis: gaps 5 - 3.5 = 1.5
    # and 5 - 2.5 = 2.5; Hertz radii -5 (concave) and b^2/a = 4/3; 1/R = 3/4 - 1/5.
    hole = CircleArc([0.0, 0.0], 5.0, 0.0, 2 * np.pi)
    ell = Ellipse([0.5, 0.0], 3.0, 2.0, angle_start=2 * np.pi, angle_end=0.0)
    res = find_contact_pairs(hole, ell)
    assert [p.gap for p in res.pairs] == pytest.approx([1.5, 2.5], abs=TOL)
    p = res.pairs[0]
    np.testing.assert_allclose(p.point_a, [5.0, 0.0], atol=TOL)
    np.testing.assert_allclose(p.point_b, [3.5, 0.0], atol=TOL)
    np.testing.assert_allclose(p.normal, [-1.0, 0.0], atol=TOL)  # out of A = towards the particle
    assert p.radius_a == pytest.approx(-5.0, rel=1e-12)
    assert p.radius_b == pytest.approx(4.0 / 3.0, rel=1e-12)
    assert p.relative_radius == pytest.approx(1.0 / (0.75 - 0.2), rel=1e-12)
    assert not res.intersections
    # the minor-axis-like pairs (local maxima of the distance to the hole) are non-plausible
    assert any(p.gap > 0 and abs(p.point_a[0]) < 2 for p in res.non_plausible)


def test_two_circles_separated_and_overlapping():
    a = CircleArc([0.0, 0.0], 2.0, 2 * np.pi, 0.0)  # convex bodies: clockwise
    b = CircleArc([4.0, 0.0], 1.0, 2 * np.pi, 0.0)
    res = find_contact_pairs(a, b)
    assert len(res.pairs) == 1
    p = res.pairs[0]
    assert p.gap == pytest.approx(1.0, abs=TOL) and p.delta == 0.0
    assert (p.radius_a, p.radius_b) == pytest.approx((2.0, 1.0), rel=1e-12)
    assert p.relative_radius == pytest.approx(2.0 / 3.0, rel=1e-12)
    # overlapping: centre distance 2.5 -> indentation 0.5, crossings at x = 1.85 (x^2 - (x - 2.5)^2 = 3)
    res = find_contact_pairs(a, b.translated([-1.5, 0.0]))
    assert len(res.pairs) == 1 and res.pairs[0].delta == pytest.approx(0.5, abs=TOL)
    xs = sorted(c.point[1] for c in res.intersections)
    assert len(xs) == 2
    np.testing.assert_allclose([c.point[0] for c in res.intersections], 1.85, atol=TOL)
    np.testing.assert_allclose(xs, [-np.sqrt(4 - 1.85**2), np.sqrt(4 - 1.85**2)], atol=TOL)


def test_bspline_with_two_close_pairs_and_a_non_plausible_one_between():
    # concave body surface (left to right) whose bottom (curvature 0.88 / mm) is more curved than the
    # circular particle (R 1.4) above it: two wall contacts and the non-plausible bottom pair between them.
    cup = BSpline([[-3, 1.5], [-1.5, 0.0], [-0.6, -0.9], [0.6, -0.9], [1.5, 0.0], [3, 1.5]])
    particle = CircleArc([0.0, 1.0], 1.4, 2 * np.pi, 0.0)
    res = find_contact_pairs(cup, particle)
    assert len(res.pairs) == 2 and not res.intersections
    left, right = sorted(res.pairs, key=lambda p: p.point_a[0])
    # mirror symmetry of the data
    np.testing.assert_allclose(left.point_a * [-1, 1], right.point_a, atol=TOL)
    assert left.gap == pytest.approx(right.gap, abs=TOL)
    # each plausible pair is a mutual closest-point pair at distance = gap
    for p in res.pairs:
        np.testing.assert_allclose(particle.project(p.point_a[None]).foot[0], p.point_b, atol=1e-9)
        np.testing.assert_allclose(cup.project(p.point_b[None]).foot[0], p.point_a, atol=1e-9)
        assert np.linalg.norm(p.point_a - p.point_b) == pytest.approx(p.gap, abs=TOL)
        assert np.all(p.hessian_eigs > 0)  # local minimum of the distance
    # the non-plausible pair between them: the cup bottom (t = 1/2) against the particle's lowest point
    # (the cup bottom against the particle's top is non-plausible too, with normals facing the same way)
    mid = [p for p in res.non_plausible if abs(p.point_a[0]) < 1.0 and p.point_b[1] < 0.0]
    assert len(mid) == 1
    np.testing.assert_allclose(mid[0].point_a, cup.point([0.5])[0], atol=TOL)
    np.testing.assert_allclose(mid[0].point_b, [0.0, 1.0 - 1.4], atol=TOL)
    assert mid[0].gap == pytest.approx(-0.4 - cup.point([0.5])[0, 1], abs=TOL)
    assert mid[0].gap > left.gap
    assert left.point_a[0] < mid[0].point_a[0] < right.point_a[0]


def test_relative_radius_formula():
    assert relative_radius(2.96, -6.81) == pytest.approx(1 / (1 / 2.96 - 1 / 6.81), rel=1e-15)
    assert np.isinf(relative_radius(5.0, -5.0))


def test_symmetric_design_reproduces_the_paper_geometry():
    des = design("symmetric")
    for d, delta_paper in zip(des.table1_d, des.table1_delta, strict=True):
        res = find_contact_pairs(des.concave, particle_at(des, d), n_samples=300)
        assert len(res.pairs) == 2
        a, b = res.pairs
        np.testing.assert_allclose(a.point_a * [-1, 1], b.point_a, atol=1e-9)  # symmetric pair
        # radii: designed as arcs R 2.96 / 6.81, fitted by the spline to < 0.2 %
        assert a.radius_b == pytest.approx(2.96, rel=2e-3)
        assert a.radius_a == pytest.approx(-6.81, rel=2e-3)
        assert a.relative_radius == pytest.approx(5.23, rel=3e-3)
        # Table 1 deltas are given to 2 significant digits: agree within 0.003 mm
        assert a.delta == pytest.approx(delta_paper, abs=3e-3)


def test_close_to_conformal_design_reproduces_the_paper_geometry():
    des = design("close_to_conformal")
    res = find_contact_pairs(des.concave, particle_at(des, 0.46), n_samples=300)
    primary = min(res.pairs, key=lambda p: abs(p.point_a[0]))
    assert primary.radius_b == pytest.approx(41.0, rel=0.02)
    assert primary.radius_a == pytest.approx(-50.0, rel=0.02)
    assert primary.delta == pytest.approx(0.00043, abs=2e-5)
    # a secondary pair close by (not yet touching) with a non-plausible pair between them
    secondary = [p for p in res.pairs if p is not primary]
    assert len(secondary) == 1 and 0 < secondary[0].gap < 0.01
    between = [p for p in res.non_plausible if primary.point_a[0] < p.point_a[0] < secondary[0].point_a[0]
               and abs(p.gap) < 0.1]  # (the others face the far side of the particle)
    assert len(between) == 1 and between[0].gap > secondary[0].gap
    # leftmost intersection: radii near 23 (convex) and -44 (concave), relative ~ 50
    left = min(res.intersections, key=lambda c: c.point[0])
    assert left.radius_b == pytest.approx(23.0, rel=0.03)
    assert left.radius_a == pytest.approx(-44.0, rel=0.03)
    # the primary normal is the displacement direction, so delta = d - d0 at every Table 1 step
    for d, delta_paper in zip(des.table1_d, des.table1_delta, strict=True):
        r = find_contact_pairs(des.concave, particle_at(des, d), n_samples=300)
        p = min(r.pairs, key=lambda q: abs(q.point_a[0]))
        assert p.delta == pytest.approx(delta_paper, abs=3e-3)


def test_particles_are_closed_and_tangent_continuous():
    for name in ("symmetric", "close_to_conformal"):
        part = design(name).particle
        assert part.is_closed
        for s in (1.0, 2.0):  # spline -> arc and arc -> spline joints
            before = part.tangent([s - 1e-12])[0]
            after = part.tangent([0.0 if s == 2.0 else s + 1e-12])[0]
            assert before @ after > np.cos(1e-6)


def test_cli_json_and_bad_values(capsys):
    assert cli(["--config", "symmetric", "--d", "0.6", "--json", "--n-samples", "200"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert len(out["pairs"]) == 2 and out["pairs"][0]["delta"] == pytest.approx(0.086, abs=3e-3)
    assert cli(["--config", "symmetric", "--d", "7"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "d must be in" in err[0]
    assert cli(["--config", "nope", "--d", "0.5"]) == 2
