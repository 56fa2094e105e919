"""``workbench score`` per scene on synthetic results whose answer is known by hand (issue 36).

Requirements: three levels of a theory's pressure with a known peak offset extrapolate to that offset with order 2
(two elastic bodies: the exact circle at the combined modulus); a convective pair whose convective run is a Hertz
pressure r times wider carries b/b0 = r exactly (the edges) against Ciavarella-Hills at the bodies' beta; the
classical wedge's own pressure at three levels extrapolates to its half-width and moment (2/sqrt(6)); the patch test's
uniformity is judged against the case's tolerance and the workbench's two pairings (mortar to round-off,
node-to-segment not), never extrapolated; a master body's samples are measured and never judged.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from analytic import circle, hertz, materials, wedge
from workbench.external.score import main as score_main


def _write(path, header: str, rows) -> str:
    path.write_text(header + "\n" + "\n".join(",".join(repr(float(v)) if not isinstance(v, str) else v for v in r)
                                              for r in rows) + "\n")
    return str(path)


def _score(tmp_path, case: str, files: list[str], *extra: str) -> dict:
    assert score_main([case, *files, "--out", str(tmp_path / "out"), *extra]) == 0
    return json.loads((tmp_path / "out" / f"score_{case}" / "score.json").read_text())


def test_two_bodies_exact_circle_offset_extrapolates(tmp_path):
    """elastic_cylinder_dissimilar: the exact circle at E* (steel block, aluminium cylinder) at its target load,
    peak scaled by 1 - 0.003 + 0.5 h^2 (h in mm): p_max/p0 extrapolates to 0.997 with order 2; the cylinder's own
    samples (one level) are measured as the master body."""
    E_star = materials.composite_modulus(210000.0, 0.3, E1=70000.0, nu1=0.33)
    R = 40.0
    P = hertz.hertz_load_from_half_width(0.5, R, E_star)
    ex = circle.circle_contact(P, R, E_star)
    files = []
    for h in (0.04, 0.02, 0.01):
        x = np.arange(-int(round(0.8 / h)), int(round(0.8 / h)) + 1) * h
        p = circle.circle_pressure(x, b=ex.half_width, R=R, E_star=E_star) * (1 - 0.003 + 0.5 * h**2)
        rows = [("block", xi, pi, P) for xi, pi in zip(x, p, strict=True)]
        if h == 0.01:
            rows += [("cylinder", xi, pi, P) for xi, pi in zip(x, p, strict=True)]
        files.append(_write(tmp_path / f"h{h}.csv", "body,x_mm,p_MPa,P_N_per_mm", rows))
    score = _score(tmp_path, "elastic_cylinder_dissimilar", files)
    st = score["studies"]["p_max"]
    assert st["extrapolated"] == pytest.approx(0.997, abs=1e-9) and st["observed_order"] == pytest.approx(2.0, abs=1e-6)
    assert st["theory"] == 1.0 and st["outside_band"] and score["main"] == "p_max"
    assert "-0.300% from the exact circle (combined modulus)" in score["verdict"]
    master = [lv for lv in score["levels"] if lv["role"] == "master"]
    assert len(master) == 1 and master[0]["body"] == "cylinder" and master[0]["p_max"] == pytest.approx(
        max(circle.circle_pressure(np.array([0.0]), b=ex.half_width, R=R, E_star=E_star)) * (1 - 0.003 + 0.5e-4),
        rel=1e-12)
    assert not any(k.startswith("cylinder/") for k in score["studies"])


def test_halfplanes_convective_pair_b_over_b0_by_hand(tmp_path):
    """halfplanes_beta_pos: the small run a Hertz pressure at the target load, the convective run one r = 1.05 times
    wider at the same load: b/b0 from the edges is the ratio of the two square-root edge fits computed by hand at
    every level (near r), and the theory is Ciavarella-Hills converged at beta = +0.3."""
    E_star = materials.bimaterial(E1=52500.0, nu1=0.0, E2=210000.0, nu2=0.0).E_star
    R, r = 10.0, 1.05
    P = hertz.hertz_load_from_half_width(1.0, R, E_star)
    files = []
    for h in (0.08, 0.04, 0.02):
        x = np.arange(-int(round(1.6 / h)), int(round(1.6 / h)) + 1) * h
        rows = []
        for label, b in (("small", 1.0), ("convective", r)):
            p0 = 2.0 * P / (math.pi * b)
            rows += [(label, xi, p0 * math.sqrt(max(0.0, 1 - (xi / b) ** 2)), P) for xi in x]
        files.append(_write(tmp_path / f"h{h}.csv", "run,x_mm,p_MPa,P_N_per_mm", rows))
    score = _score(tmp_path, "halfplanes_beta_pos", files)
    st = score["studies"]["b_over_b0[convective]"]

    def edge(b: float, h: float) -> float:
        """The square-root edge model through the two outermost active nodes; the linear zero crossing where it
        leaves the interval to the first inactive node."""
        n = math.floor(b / h - 1e-12)
        s1, s2, s_out = n * h, (n - 1) * h, (n + 1) * h
        q1, q2 = (math.sqrt(max(0.0, 1 - (v / b) ** 2)) for v in (s1, s2))
        e = s1 + (s1 - s2) * q1**2 / (q2**2 - q1**2)
        return e if s1 <= e <= s_out else s1 + (s_out - s1) * q1 / q1  # q(s_out) = 0

    by_hand = [edge(r, h) / edge(1.0, h) for h in (0.02, 0.04, 0.08)]
    assert st["ratios"] == pytest.approx(by_hand, rel=1e-12) and st["extrapolated"] == pytest.approx(r, abs=3e-3)
    from analytic import convective

    sol = convective.solve(convective.parabola_profile(1.0 / R), beta=0.3, n_plot=801)
    assert st["theory"] == pytest.approx(sol.b_over_b0_converged, rel=1e-9)
    assert st["alt_theory"] == "first order" and st["alt_value"] == pytest.approx(sol.b_over_b0_first_order, rel=1e-9)
    assert score["main"] == "b_over_b0_moment[convective]" and "moment ratio b/b0" in score["headline"]


def test_classical_wedge_at_three_levels(tmp_path):
    """wedge, theta = pi/5: the classical wedge pressure (E* m / pi) arccosh(b/|x|) at nodes offset from the apex;
    the edge half-width extrapolates to b and the moment half-width to 2 b / sqrt(6) within their bands."""
    m = wedge.wedge_slope(math.pi / 5, convention="exact")
    E_star = materials.plane_strain_modulus(210000.0, 0.3)
    b = 0.5
    P = wedge.wedge_load_from_half_width(b, m, E_star)
    files = []
    for h in (0.02, 0.01, 0.005):
        x = (np.arange(0, int(round(0.8 / h))) + 0.5) * h
        p = wedge.wedge_pressure(x, b=b, m=m, E_star=E_star)
        files.append(_write(tmp_path / f"h{h}.csv", "x_mm,p_MPa,P_N_per_mm",
                            [(xi, pi, P) for xi, pi in zip(x, p, strict=True)]))
    score = _score(tmp_path, "wedge", files, "--run", "theta=pi/5")
    edge, mom = score["studies"]["theta=pi/5/half_width"], score["studies"]["theta=pi/5/half_width_moment"]
    assert mom["theory"] == pytest.approx(2.0 / math.sqrt(6.0), rel=1e-15)
    assert abs(edge["extrapolated"] - 1.0) < 2e-3 and abs(mom["extrapolated"] / mom["theory"] - 1.0) < 2e-3
    assert "from the classical wedge" in score["verdict"]


@pytest.mark.parametrize("noise, within, model", [(1e-12, True, "mortar"), (0.1, False, "node-to-segment")])
def test_patch_test_uniformity_bound(tmp_path, noise, within, model):
    """patch_test: P / W everywhere (W = 1 mm) up to a relative ``noise`` at three levels: within or beyond the
    case's tolerance 1e-8, and consistent with the workbench's pairing that behaves the same (its saved band)."""
    files = []
    P = 88.9
    for n in (8, 16, 32):
        x = np.linspace(0.0, 1.0, n + 1)
        p = P * (1 + noise * np.cos(7 * x))
        files.append(_write(tmp_path / f"n{n}.csv", "x_mm,p_MPa,P_N_per_mm", [(xi, pi, P) for xi, pi in zip(x, p,
                                                                                                          strict=True)]))
    score = _score(tmp_path, "patch_test", files)
    st = score["studies"]["uniformity"]
    assert st["kind"] == "bound" and st["within_tolerance"] is within
    assert st["max"] == pytest.approx(noise, rel=1e-3)
    inside = [r["model"] for r in score["models"]["models"] if r["contains"]]
    assert inside == [f"halfplane/small ({model})"], inside
    assert score["verdict"].startswith("max |p / (P/W) - 1| = ")
