"""Dissimilar materials in the half-plane theory (issue 25, point 1): Dundurs alpha/beta and E* of two bodies,
beta of either sign in the classical and convective theory, and ``python -m analytic halfplane`` with two materials.

Convention pinned here (analytic.materials): body 1 = the indenter, body 2 = the flat block, Gam = mu2/mu1; a rigid
indenter gives alpha = -1, beta = -(1 - 2 nu2)/(2 (1 - nu2)) <= 0 (Ciavarella & Hills eq. 6-7).
"""

import json
import math

import pytest

from analytic import convective, halfplane, hertz
from analytic import materials as mt
from analytic.__main__ import main

INF = math.inf
NUS = (0.0, 0.2, 0.3, 0.45)


# --- Dundurs constants ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("nu2", NUS + (0.49,))
@pytest.mark.parametrize("nu1", (-0.5, 0.0, 0.3, 0.5))
def test_rigid_indenter_gives_todays_beta_exactly(nu1, nu2):
    bm = mt.bimaterial(E1=INF, nu1=nu1, E2=1000.0, nu2=nu2)
    assert bm.alpha == -1.0
    assert bm.beta == mt.beta_rigid_indenter(nu2)  # bit-identical to today's rigid-indenter beta
    assert bm.beta == pytest.approx(mt.dundurs(1000.0, nu2).beta, rel=1e-15, abs=1e-17)  # kappa form
    assert bm.E_star == pytest.approx(mt.composite_modulus(1000.0, nu2), rel=2e-16)


@pytest.mark.parametrize("nu2", NUS)
def test_rigid_limit_is_approached_as_E1_grows(nu2):
    rigid = mt.beta_rigid_indenter(nu2)
    errs = [abs(mt.bimaterial(E1=1000.0 * r, nu1=0.3, E2=1000.0, nu2=nu2).beta - rigid) for r in (1e2, 1e4, 1e6)]
    assert errs[0] > errs[1] > errs[2] and errs[2] < 2e-6  # O(E2/E1)
    far = mt.bimaterial(E1=1e12, nu1=0.3, E2=1.0, nu2=nu2)
    assert far.alpha == pytest.approx(-1.0, abs=1e-11) and far.beta == pytest.approx(rigid, abs=1e-11)


def test_swapping_the_bodies_changes_the_signs_of_alpha_and_beta():
    a = mt.bimaterial(E1=210000.0, nu1=0.3, E2=70000.0, nu2=0.33)
    b = mt.bimaterial(E1=70000.0, nu1=0.33, E2=210000.0, nu2=0.3)
    assert (b.alpha, b.beta) == pytest.approx((-a.alpha, -a.beta), rel=1e-14)
    assert b.E_star == pytest.approx(a.E_star, rel=1e-15)
    assert a.alpha < 0.0 and a.beta < 0.0  # the stiffer indenter: C&H's "body 1 the more rigid, beta < 0"
    rigid_block = mt.bimaterial(E1=1000.0, nu1=0.2, E2=INF, nu2=0.3)
    assert (rigid_block.alpha, rigid_block.beta) == pytest.approx((1.0, -mt.beta_rigid_indenter(0.2)), rel=1e-15)


@pytest.mark.parametrize("E, nu", [(210000.0, 0.3), (1.0, 0.0), (5.0, 0.5), (70.0, -0.4)])
def test_identical_materials_give_alpha_beta_zero(E, nu):
    bm = mt.bimaterial(E1=E, nu1=nu, E2=E, nu2=nu)
    assert bm.alpha == pytest.approx(0.0, abs=1e-15) and bm.beta == pytest.approx(0.0, abs=1e-15)
    assert bm.E_star == pytest.approx(0.5 * E / (1.0 - nu * nu), rel=1e-15)


def test_beta_runs_monotonically_over_its_range_and_stays_in_the_parallelogram():
    for nu1, nu2 in ((0.0, 0.0), (0.3, 0.1), (0.5, 0.2), (0.25, 0.5)):
        lo, hi = mt.beta_range(nu1=nu1, nu2=nu2)
        betas, alphas = [], []
        for r in (1e-9, 1e-3, 0.1, 0.5, 1.0, 2.0, 10.0, 1e3, 1e9):  # E1/E2
            bm = mt.bimaterial(E1=r, nu1=nu1, E2=1.0, nu2=nu2)
            betas.append(bm.beta)
            alphas.append(bm.alpha)
            assert -1.0 <= bm.alpha - 4.0 * bm.beta <= 1.0 and abs(bm.beta) <= 0.5  # 0 <= nu <= 1/2
        assert betas == sorted(betas, reverse=True) and alphas == sorted(alphas, reverse=True)
        assert betas[0] == pytest.approx(hi, abs=1e-8) and betas[-1] == pytest.approx(lo, abs=1e-8)
    assert mt.beta_range(nu1=-0.9, nu2=0.3)[1] > 0.5  # auxetic bodies leave the theory's |beta| <= 1/2


@pytest.mark.parametrize("kw, field", [
    (dict(E1=1.0, nu1=0.6, E2=1.0, nu2=0.3), "nu1"),
    (dict(E1=1.0, nu1=0.3, E2=1.0, nu2=-1.0), "nu2"),
    (dict(E1=0.0, nu1=0.3, E2=1.0, nu2=0.3), "E1"),
    (dict(E1=1.0, nu1=0.3, E2=math.nan, nu2=0.3), "E2"),
    (dict(E1=INF, nu1=0.3, E2=INF, nu2=0.3), "E1, E2"),
])
def test_bad_materials_name_the_field(kw, field):
    with pytest.raises(ValueError, match=rf"^{field} = .* out of range"):
        mt.bimaterial(**kw)


# --- old call signatures: today's numbers, pinned (computed by the code before issue 25) ------------------------

# (nu, profile, half_width, p_max, moment_half_width, b_classical): solve_halfplane(P=8, E* = 1000/(1 - nu^2),
# beta = beta_rigid_indenter(nu)), R = 10 or m = tan(pi/5)
HALFPLANE_PINNED = [
    (0.0, "parabola", 0.322403809522349, 15.731091566693063, 0.3231954622184643, 0.31915382432114614),
    (0.0, "circle", 0.3223432676990074, 15.732067274643528, 0.3231551471659883, 0.319092872372066),
    (0.0, "wedge", 0.013156007375086607, INF, 0.01187363575875802, 0.011011055363769388),
    (0.2, "parabola", 0.31504413282035554, 16.116219436237095, 0.3156142965121129, 0.31270560761786875),
    (0.2, "circle", 0.31498708507098333, 16.11718570512691, 0.3155762966775636, 0.31264827589393684),
    (0.2, "wedge", 0.01204840990210992, INF, 0.010637861257608154, 0.010570613149218611),
    (0.3, "parabola", 0.3061415201719911, 16.597958802966957, 0.30655339449045, 0.3044533443020783),
    (0.3, "circle", 0.3060888032211345, 16.59890680870545, 0.306518271807081, 0.30440043269751155),
    (0.3, "wedge", 0.011052210509693457, INF, 0.009594019775089162, 0.010020060381030142),
    (0.45, "parabola", 0.2854837913276326, 17.827535552322274, 0.2855986909355131, 0.28501347854812653),
    (0.45, "circle", 0.2854404293503223, 17.828436884754044, 0.2855697883364895, 0.2849700688827705),
    (0.45, "wedge", 0.009047402812730433, INF, 0.007540662377496315, 0.008781316652606088),
]
# (nu, profile, first order, first iterate, converged, first order numeric): convective.solve, n_nodes = 4096,
# parabola b0/R = 0.1, wedge m = pi/5, beta = beta_rigid_indenter(nu)
CONVECTIVE_PINNED = [
    (0.0, "parabola", 1.0346558812725015, 1.0305778670970347, 1.0320647013528939, 1.0346558821993113),
    (0.0, "wedge", 1.1609405311997782, 1.1101920646589571, 1.164565704737433, 1.1609405937367097),
    (0.2, "parabola", 1.0254172611332177, 1.0230907482908989, 1.0240053986884672, 1.0254172617972785),
    (0.2, "wedge", 1.1160366484401825, 1.0857975856607858, 1.118648817400897, 1.1160366917847613),
    (0.3, "parabola", 1.0190677917602158, 1.0176915791446173, 1.018266142218808, 1.019067792250485),
    (0.3, "wedge", 1.086032002333154, 1.0674513793230125, 1.087756983069314, 1.0860320336057407),
    (0.45, "parabola", 1.0058727729183001, 1.0057181332544654, 1.005795312668418, 1.005872773064381),
    (0.45, "wedge", 1.0258570890521428, 1.023466091166633, 1.0260694381352469, 1.0258570979303983),
]


def _hp_profile(kind):
    return halfplane.profile("wedge", m=math.tan(math.pi / 5)) if kind == "wedge" else halfplane.profile(kind, R=10.0)


@pytest.mark.parametrize("row", HALFPLANE_PINNED, ids=lambda r: f"{r[1]}-nu{r[0]}")
def test_halfplane_old_signature_and_two_material_form_reproduce_todays_numbers(row):
    nu, kind, *pinned = row
    old = halfplane.solve_halfplane(_hp_profile(kind), P=8.0, E_star=mt.composite_modulus(1000.0, nu),
                                    beta=mt.beta_rigid_indenter(nu))
    bm = mt.bimaterial(E1=INF, nu1=0.25, E2=1000.0, nu2=nu)
    new = halfplane.solve_halfplane(_hp_profile(kind), P=8.0, E_star=bm.E_star, beta=bm.beta)
    for sol in (old, new):
        got = (sol.half_width, sol.p_max, sol.moment_half_width, sol.b_classical)
        assert got == pytest.approx(tuple(pinned), rel=1e-12)


@pytest.mark.parametrize("row", CONVECTIVE_PINNED, ids=lambda r: f"{r[1]}-nu{r[0]}")
def test_convective_old_signature_reproduces_todays_numbers(row):
    nu, kind, *pinned = row
    prof = convective.parabola_profile(0.1) if kind == "parabola" else convective.wedge_profile(math.pi / 5)
    beta = mt.bimaterial(E1=INF, nu1=0.3, E2=1.0, nu2=nu).beta
    s = convective.solve(prof, beta=beta, n_nodes=4096)
    got = (s.b_over_b0_first_order, s.b_over_b0_first_iterate, s.b_over_b0_converged, s.b_over_b0_first_order_numeric)
    assert got == pytest.approx(tuple(pinned), rel=1e-12)


# --- beta of either sign ----------------------------------------------------------------------------------------


@pytest.mark.parametrize("beta, converged, first_order", [(0.3, 0.98099, 0.98176), (-0.3, 1.01918, 1.02007)])
def test_parabola_targets_of_the_issue(beta, converged, first_order):
    s = convective.solve(convective.parabola_profile(0.1), beta=beta)
    assert round(s.b_over_b0_converged, 5) == converged
    assert round(s.b_over_b0_first_order, 5) == first_order
    assert round(s.b_over_b0_first_order_numeric, 5) == first_order
    # the half-plane solver (physical units, N = 4096) gives the same converged ratio
    P = math.pi * 1000.0 * 1.0 / (4.0 * 10.0)  # classical b0 = 1 mm at R = 10 mm, E* = 1000 MPa
    hp = halfplane.solve_halfplane(halfplane.profile("parabola", R=10.0), P=P, E_star=1000.0, beta=beta)
    assert hp.half_width / hp.b_classical == pytest.approx(s.b_over_b0_converged, rel=1e-9)


@pytest.mark.parametrize("kind", ["parabola", "circle", "wedge"])
@pytest.mark.parametrize("beta", [0.1, 0.3, 0.45, 0.5])
def test_sign_of_b_over_b0_minus_one_is_opposite_to_beta(kind, beta):
    prof = halfplane.profile("wedge", m=math.pi / 5) if kind == "wedge" else halfplane.profile(kind, R=10.0)
    r = {}
    for b in (beta, -beta):
        s = halfplane.solve_halfplane(prof, P=math.pi * 1000.0 / 40.0, E_star=1000.0, beta=b)
        r[b] = s.half_width / s.b_classical
    assert r[beta] < 1.0 < r[-beta]
    # odd in beta to leading order; the even part is O(beta^2), positive (|b/b0 - 1| is larger for beta < 0),
    # and under a fifth of the odd part (measured: parabola ~1 %, wedge m = pi/5 up to 18 % at |beta| = 1/2)
    assert 0.0 < r[beta] + r[-beta] - 2.0 < 0.2 * (r[-beta] - r[beta])


def test_first_order_closed_forms_have_the_same_sign_rule():
    for beta in (0.3, 0.45):
        assert convective.wedge_first_order(math.pi / 5, beta) < 1.0 < convective.wedge_first_order(math.pi / 5, -beta)
        assert (convective.parabola_first_order_from_b0(0.1, beta) < 1.0
                < convective.parabola_first_order_from_b0(0.1, -beta))


def test_convective_parabola_refuses_b0_beyond_R():
    P = math.pi * 1000.0 * 3.0**2 / 4.0  # classical b0 = 3 R: the iteration gave NaN before the check
    with pytest.raises(ValueError, match=r"^P = .* out of range: the convective parabola needs .* b0 < R"):
        halfplane.solve_halfplane(halfplane.profile("parabola", R=1.0), P=P, E_star=1000.0, beta=0.3)
    assert halfplane.solve_halfplane(halfplane.profile("parabola", R=1.0), P=P, E_star=1000.0).half_width > 1.0


@pytest.mark.parametrize("kind", ["parabola", "circle", "wedge"])
def test_classical_theory_does_not_depend_on_beta(kind):
    prof = _hp_profile(kind)
    bm = mt.bimaterial(E1=210000.0, nu1=0.3, E2=70000.0, nu2=0.33)
    b0 = {beta: halfplane.solve_halfplane(prof, P=8.0, E_star=bm.E_star, beta=beta).b_classical
          for beta in (-0.45, bm.beta, 0.0, 0.3)}
    assert len(set(b0.values())) == 1  # bit-identical: the classical problem sees E* only
    classical = halfplane.solve_halfplane(prof, P=8.0, E_star=bm.E_star)
    assert classical.half_width == b0[0.0] and classical.iterations == 0
    if kind == "parabola":
        assert classical.half_width == pytest.approx(hertz.hertz(8.0, 10.0, bm.E_star).half_width, rel=1e-10)


# --- command line -------------------------------------------------------------------------------------------------


def _run(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    return code, capsys.readouterr()


def test_cli_two_materials_report_alpha_beta_E_star(capsys):
    code, out = _run(["halfplane", "--profile", "parabola", "--R", "10", "--E1", "210000", "--nu1", "0.3",
                      "--E2", "70000", "--nu2", "0.33", "--P", "100", "--json"], capsys)
    assert code == 0, out.err
    d = json.loads(out.out)
    bm = mt.bimaterial(E1=210000.0, nu1=0.3, E2=70000.0, nu2=0.33)
    assert (d["alpha"], d["beta"], d["E_star"]) == (bm.alpha, bm.beta, bm.E_star)
    sol = halfplane.solve_halfplane(halfplane.profile("parabola", R=10.0), P=100.0, E_star=bm.E_star, beta=bm.beta)
    assert d["half_width"] == sol.half_width and d["b_over_b_classical"] > 1.0  # beta < 0: wider
    code, out = _run(["halfplane", "--profile", "parabola", "--R", "10", "--E1", "210000", "--nu1", "0.3",
                      "--E2", "70000", "--nu2", "0.33", "--P", "100"], capsys)
    names = {line.split()[0] for line in out.out.splitlines()}
    assert code == 0 and {"alpha", "beta", "E_star"} <= names


def test_cli_rigid_pair_equals_old_single_material_form(capsys):
    nu = 0.3
    _, a = _run(["halfplane", "--profile", "circle", "--R", "4", "--E", "100", "--nu", str(nu), "--P", "10",
                 "--beta", repr(mt.beta_rigid_indenter(nu)), "--json"], capsys)
    _, b = _run(["halfplane", "--profile", "circle", "--R", "4", "--E1", "inf", "--nu1", "0.2", "--E2", "100",
                 "--nu2", str(nu), "--P", "10", "--json"], capsys)
    da, db = json.loads(a.out), json.loads(b.out)
    assert da["alpha"] == db["alpha"] == -1.0 and db["E1"] == "inf"
    for key in ("beta", "E_star", "half_width", "p_max", "half_width_classical"):
        assert da[key] == pytest.approx(db[key], rel=1e-15)


def test_cli_E_star_and_beta_directly(capsys):
    code, out = _run(["halfplane", "--profile", "wedge", "--theta", "0.6", "--convention", "paper",
                      "--E-star", "1000", "--beta", "0.3", "--P", "8", "--json"], capsys)
    d = json.loads(out.out)
    assert code == 0 and d["alpha"] is None and d["beta"] == 0.3 and d["E_star"] == 1000.0
    s = convective.solve(convective.wedge_profile(0.6), beta=0.3, n_nodes=4096)
    assert d["b_over_b_classical"] == pytest.approx(s.b_over_b0_converged, rel=1e-12) and d["b_over_b_classical"] < 1


BASE = ["halfplane", "--profile", "parabola", "--R", "10", "--P", "10"]
PAIR = ["--E1", "2000", "--nu1", "0.3", "--E2", "1000", "--nu2", "0.3"]


@pytest.mark.parametrize("extra, option", [
    (["--E1", "2000", "--nu1", "0.6", "--E2", "1000", "--nu2", "0.3"], "--nu1"),
    (["--E1", "2000", "--nu1", "0.3", "--E2", "1000", "--nu2", "-1"], "--nu2"),
    (["--E1", "-1", "--nu1", "0.3", "--E2", "1000", "--nu2", "0.3"], "--E1"),
    (["--E1", "2000", "--nu1", "0.3", "--E2", "0", "--nu2", "0.3"], "--E2"),
    (["--E1", "2000", "--nu1", "0.3", "--E2", "inf", "--nu2", "0.3"], "--E2"),
    (["--E1", "2000", "--nu1", "0.3", "--E2", "nan", "--nu2", "0.3"], "--E2"),
    (["--E1", "2000", "--nu1", "0.3", "--E2", "1000"], "--nu2"),
    ([*PAIR, "--beta", "0.1"], "--beta"),
    ([*PAIR, "--E", "100", "--nu", "0.3"], "materials"),
    (["--E1", "1", "--nu1", "-0.9", "--E2", "1e6", "--nu2", "0.3"], "beta"),  # auxetic: beta = 0.74
    (["--E-star", "-5", "--beta", "0.1"], "--E-star"),
    (["--E-star", "1000", "--beta", "0.6"], "--beta"),
    (["--E-star", "1000", "--beta", "nan"], "--beta"),
    (["--E", "100", "--nu", "0.3", "--beta", "-0.51"], "--beta"),
    (["--E-star", "1e308"], "--E-star"),  # hung before the window
    (["--E1", "1e-300", "--nu1", "0.3", "--E2", "1000", "--nu2", "0.3"], "--E1"),  # NaN before the window
    (["--E1=-inf", "--nu1", "0.3", "--E2", "1000", "--nu2", "0.3"], "--E1"),
    (["--E1", "1e-5", "--nu1", "0.3", "--E2", "1e3", "--nu2", "0.3"], "--P"),  # b0/R = 1.7e3: the b/R range
    (["--E", "100"], "--E, --nu"),
    ([], "materials"),
])
def test_cli_bad_materials_one_line_naming_the_option_exit_2(extra, option, capsys):
    code, out = _run([*BASE, *extra], capsys)
    assert code == 2 and out.out == ""
    lines = out.err.strip().splitlines()
    assert len(lines) == 1, out.err
    assert f": {option} " in lines[0] or f": {option} =" in lines[0], lines[0]
