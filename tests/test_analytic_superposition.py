"""Superposition of independent Hertz patches (analytic.superposition)."""

import numpy as np
import pytest
from scipy import integrate

from analytic.hertz import hertz
from analytic.superposition import ContactPair, split_load, superpose

E_STAR = 235000.0


def test_single_pair_is_hertz():
    r = superpose([ContactPair(s=1.5, R=5.23, P=5106.0)], E_star=E_STAR)
    h = hertz(5106.0, 5.23, E_STAR)
    assert r.patches[0] == h
    assert r.p.max() == pytest.approx(h.p0, rel=1e-5)  # grid of 2001 points: nearest point to the peak


def test_sum_integrates_to_total_load():
    pairs = [ContactPair(-0.2, 48.19, 150.0), ContactPair(0.1, 227.8, 58.0)]
    r = superpose(pairs, E_star=E_STAR, s=np.array([0.0]))
    assert r.overlapping  # these two patches overlap: superposition merely adds
    edges = sorted(
        c + sgn * h.half_width for c, h in zip(r.centers, r.patches, strict=True) for sgn in (-1, 1)
    )

    def p(x):
        return superpose(pairs, E_star=E_STAR, s=np.array([x])).p[0]

    total, _ = integrate.quad(p, edges[0], edges[-1], points=edges[1:-1], epsabs=0, epsrel=1e-12, limit=200)
    assert total == pytest.approx(208.0, rel=1e-10)


def test_split_load():
    assert split_load(10.0, 2) == (5.0, 5.0)
    assert split_load(10.0, 3, weights=[1, 1, 2]) == pytest.approx((2.5, 2.5, 5.0), rel=1e-15)
    with pytest.raises(ValueError, match="^weights = .* out of range"):
        split_load(10.0, 2, weights=[1.0])
    with pytest.raises(ValueError, match="^total = .* out of range"):
        split_load(-1.0, 2)
