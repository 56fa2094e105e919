"""Command line of the analytic package (python -m analytic)."""

import json
import math

import pytest

from analytic.__main__ import main


def _json(capsys, argv):
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_hertz_json(capsys):
    d = _json(capsys, ["hertz", "--P", "5106", "--R", "5.23", "--E", "214000", "--nu", "0.3", "--json"])
    assert d["E_star"] == pytest.approx(214000 / 0.91, rel=1e-14)
    assert d["full_width"] == pytest.approx(2 * d["half_width"], rel=1e-15)


def test_wedge_json(capsys):
    d = _json(
        capsys,
        [
            "wedge",
            "--P",
            "100",
            "--theta",
            str(math.pi / 5),
            "--E",
            "210000",
            "--nu",
            "0",
            "--convention",
            "paper",
            "--json",
        ],
    )
    assert d["m"] == pytest.approx(math.pi / 5, rel=1e-15)
    assert d["half_width"] == pytest.approx(100 / (210000 * math.pi / 5), rel=1e-14)
    assert d["beta_rigid_indenter"] == -0.5


def test_convective_json_keys(capsys):
    d = _json(
        capsys,
        [
            "convective",
            "--profile",
            "parabola",
            "--b0-over-R",
            "0.25",
            "--beta",
            "-0.5",
            "--nodes",
            "4096",
            "--json",
        ],
    )
    # First order, derived by hand: b/b0 = (1 + 4 beta b/(pi R))^(-1/2) with b/R = (b/b0)(b0/R), i.e. the root x
    # of x^2 (1 - x/(2 pi)) = 1 for b0/R = 1/4, beta = -1/2 (bisection here, 1e-15).
    lo, hi = 1.0, 1.5
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if mid * mid * (1 - mid / (2 * math.pi)) < 1 else (lo, mid)
    assert d["b_over_b0_first_order"] == pytest.approx(lo, rel=1e-12)
    assert d["b_over_b0_first_order_numeric"] == pytest.approx(lo, rel=1e-7)  # quadrature, 4096 nodes: 3e-9
    # the iterate and the converged value differ from first order by second-order terms: eps^2 with
    # eps = 4 |beta| (b/R) / pi = 0.175 (b/R = 0.275), i.e. <= 0.031 (measured 0.027 and 0.020)
    eps = 4 * 0.5 * (lo * 0.25) / math.pi
    for key in ("b_over_b0_first_iterate", "b_over_b0_converged"):
        assert abs(d[key] - lo) <= eps**2, (key, d[key])
    assert d["b_over_b0_converged"] != d["b_over_b0_first_iterate"]


def test_table1_json(capsys):
    d = _json(capsys, ["table1", "--json"])
    assert len(d["rows"]) == 9
    assert round(d["rows"][0]["width_eq4"], 2) == 0.78
    assert d["rows"][1]["eq5"] == "R not published"


@pytest.mark.parametrize(
    "argv, field",
    [
        (["hertz", "--P", "-1", "--R", "1", "--E", "1", "--nu", "0.3"], "P"),
        (["wedge", "--P", "1", "--theta", "2", "--E", "1", "--nu", "0.3"], "theta"),
        (["convective", "--profile", "parabola", "--b0-over-R", "0.2", "--beta", "-0.7"], "beta"),
        (["convective", "--profile", "wedge", "--beta", "-0.5"], "theta"),
        # the command-line field is named (issue 15: it used to say nu2 and E1, the library's names)
        (["hertz", "--P", "1", "--R", "1", "--E", "1", "--nu", "0.7"], "--nu"),
        (["hertz", "--P", "1", "--R", "1", "--E", "1", "--nu", "0.3", "--E2", "-5", "--nu2", "0.3"], "--E2"),
        (["hertz", "--P", "1", "--R", "1", "--E", "1", "--nu", "0.3", "--E2", "5", "--nu2", "0.6"], "--nu2"),
        (["hertz", "--P", "1", "--R", "1", "--E", "-1", "--nu", "0.3"], "--E"),
        (["wedge", "--P", "1", "--theta", "0.1", "--E", "1", "--nu", "0.5"], "--nu"),
    ],
)
def test_bad_values_exit_2_one_line(capsys, argv, field):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"{field} = " in err[0] and "out of range" in err[0]


@pytest.mark.parametrize("extra, given, missing", [(["--nu2", "0.3"], "--nu2", "--E2"),
                                                   (["--E2", "1000"], "--E2", "--nu2")])
def test_half_given_indenter_is_refused(capsys, extra, given, missing):
    """``--nu2`` without ``--E2`` (or the reverse) was silently ignored (a rigid indenter was used): refused."""
    assert main(["hertz", "--P", "1", "--R", "1", "--E", "1", "--nu", "0.3", *extra]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"{given} is given without {missing}" in err[0]


def test_argparse_error_is_one_line(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["hertz", "--P", "x"])
    assert exc.value.code == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
