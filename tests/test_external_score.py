"""``workbench score``: an external pressure scored with the workbench's own measures (issue 26).

Requirements: the scorer imports no dolfinx; the workbench's own pressure.csv, scored as an external result,
gives back the case's p_max and half-width (to the csv's 10 significant digits) and, with the load as a column,
its P exactly; three synthetic levels with a known offset extrapolate to it; a bad file is one line naming the
file, exit 2, nothing written.
"""

from __future__ import annotations

import csv
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from analytic import hertz as hz
from analytic import materials
from workbench.external.score import main as score_main

ROOT = Path(__file__).resolve().parents[1]
ENV = {**os.environ, "PYTHONPATH": str(ROOT)}


def _hertz_levels(tmp_path: Path, *, delta: float, c: float = 40.0, hs=(0.04, 0.02, 0.01), half=False,
                  load=True) -> list[str]:
    """Hertz pressures of hertz_cylinder (a = 0.5) at nodes of spacing h, peak scaled by 1 + delta + c h^2."""
    E_star = materials.plane_strain_modulus(210000.0, 0.3)
    P = hz.hertz_load_from_half_width(0.5, 10.0, E_star)
    p0 = hz.hertz(P, 10.0, E_star).p0
    files = []
    for h in hs:
        n = int(round(0.8 / h))
        x = np.arange(0 if half else -n, n + 1) * h
        p = p0 * (1 + delta + c * h**2) * np.sqrt(np.clip(1 - (x / 0.5) ** 2, 0, None))
        f = tmp_path / f"level_{h}.csv"
        with open(f, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["x_mm", "p_MPa", *(["P_N_per_mm"] if load else [])])
            for xi, pi in zip(x, p, strict=True):
                w.writerow([repr(float(xi)), repr(float(pi)), *([repr(P)] if load else [])])
        files.append(str(f))
    return files


def test_score_imports_no_dolfinx(tmp_path):
    files = _hertz_levels(tmp_path, delta=0.0)
    code = ("import sys; from workbench.external.score import main; "
            f"rc = main(['hertz_cylinder', *{files!r}, '--out', {str(tmp_path / 'o')!r}]); "
            "bad = [m for m in ('dolfinx', 'ufl', 'basix', 'petsc4py', 'fem') if m in sys.modules]; "
            "print(rc, bad); sys.exit(rc or len(bad))")
    proc = subprocess.run([sys.executable, "-c", code], env=ENV, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert proc.stdout.strip().splitlines()[-1] == "0 []"


def test_three_levels_extrapolate_the_known_offset(tmp_path):
    files = _hertz_levels(tmp_path, delta=-0.005, c=-5.0)
    assert score_main(["hertz_cylinder", *files, "--out", str(tmp_path)]) == 0
    score = json.loads((tmp_path / "score_hertz_cylinder" / "score.json").read_text())
    assert [lv["h_source"].split(":")[0] for lv in score["levels"]] == ["estimated"] * 3
    assert np.allclose([lv["h"] for lv in score["levels"]], [0.04, 0.02, 0.01], rtol=1e-9)
    st = score["grid_study"]["p_max"]
    assert abs(st["extrapolated"] - 0.995) < 1e-9 and abs(st["observed_order"] - 2.0) < 1e-6
    assert st["outside_band"] and "obstacle" in score["verdict"] and "-0.500%" in score["verdict"]
    assert score["headline"].startswith("The peak extrapolates to -0.52% from the exact circle (-0.50% from Hertz)")
    assert "obstacle/convective" in score["headline"]
    md = (tmp_path / "score_hertz_cylinder" / "report.md").read_text().splitlines()
    assert md[2] == f"**{score['headline']}**" and md[4].startswith("**Verdict.**")  # read first
    for name in ("report.md", "report.html", "pressure.png"):
        assert (tmp_path / "score_hertz_cylinder" / name).stat().st_size > 0
    from workbench.reports.external_summary import scored_markdown

    rows = [ln for ln in scored_markdown(tmp_path) if ln.startswith("| [score_hertz_cylinder]")]
    assert len(rows) == 1 and "0.99500" in rows[0] and "obstacle/convective" in rows[0]


def test_exact_hertz_is_within_band_and_half_model_mirrors(tmp_path):
    (tmp_path / "f").mkdir()
    (tmp_path / "h").mkdir()
    full = _hertz_levels(tmp_path / "f", delta=0.0, c=0.0, hs=(0.01,))
    half = _hertz_levels(tmp_path / "h", delta=0.0, c=0.0, hs=(0.01,), half=True)
    out = []
    for files in (full, half):
        assert score_main(["hertz_cylinder", *files, "--out", str(tmp_path / "o")]) == 0
        out.append(json.loads((tmp_path / "o" / "score_hertz_cylinder" / "score.json").read_text())["levels"][0])
    for key in ("P", "P_integral", "p_max", "half_width", "half_width_moment"):
        assert out[0][key] == pytest.approx(out[1][key], rel=1e-12), key
    assert out[1]["half_model"] and not out[0]["half_model"]
    assert abs(out[0]["errors"]["p_max"]) < 1e-12 and out[0]["errors"]["rms"] < 1e-3


@pytest.mark.parametrize("content, problem", [
    ("x_mm,q\n0,1\n1,2\n", "missing column"),
    ("x_mm,p_MPa\n0,nan\n1,2\n", "NaN"),
    ("x_mm,p_MPa,P_N_per_mm\n0,1,-3\n1,2,-3\n", "<= 0"),
    ("x_mm,p_MPa\n0.5,1\n", "distinct sample position"),
    ("x_mm,p_MPa\n0,-1\n1,2\n", "negative pressure"),
    ("x_mm,p_MPa\n0,1\n1\n", "number of fields"),
    ("", "empty"),
    ("x_mm,p_MPa\n0,1\n50,2\n", "does not match the case"),
])
def test_bad_file_one_line_exit_2_nothing_written(tmp_path, capsys, content, problem):
    f = tmp_path / "bad.csv"
    f.write_text(content)
    out = tmp_path / "out"
    assert score_main(["hertz_cylinder", str(f), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and str(f) in err and problem in err, err
    assert not out.exists() or not any(out.iterdir())


def test_own_pressure_csv_reproduces_the_case_numbers(tmp_path):
    """The FEM's pressure.csv (hertz_cylinder --ci) scored as a csv: p_max and half-width to 1e-9 (the csv has 10
    significant digits); P to 1e-9 from the file alone (its weight_mm column: the integral of the pressure, which
    equals the FEM's virtual-work P to the load balance), to 1e-12 once the run's load is a column. The run's
    contact_surface.csv (weights and pressure argument included): everything to 1e-9 with no load column."""
    run = subprocess.run([sys.executable, "-m", "workbench", "run", "hertz_cylinder", "--ci", "--out",
                          str(tmp_path / "run")], env=ENV, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    m = json.loads((tmp_path / "run" / "hertz_cylinder" / "metrics.json").read_text())["runs"][0]
    rows = list(csv.reader((tmp_path / "run" / "hertz_cylinder" / "pressure.csv").read_text().splitlines()))
    with_load = tmp_path / "with_load.csv"
    with open(with_load, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow([*rows[0], "P_N_per_mm"])
        for r in rows[1:]:
            w.writerow([*r, repr(m["P"])])
    for f in (tmp_path / "run" / "hertz_cylinder" / "pressure.csv", with_load):
        assert score_main(["hertz_cylinder", str(f), "--out", str(tmp_path / "s"), "--fem", str(f)]) == 0
        lv = json.loads((tmp_path / "s" / "score_hertz_cylinder" / "score.json").read_text())["levels"][0]
        assert lv["p_max"] == pytest.approx(m["p_max"], rel=1e-9)
        assert lv["half_width"] == pytest.approx(m["patch_half_width"], rel=1e-9)
        assert lv["P_integral"] == pytest.approx(m["P_pressure"], rel=1e-9)
        assert lv["P"] == pytest.approx(m["P"], rel=1e-9)
    assert lv["P"] == pytest.approx(m["P"], rel=1e-12)
    assert lv["errors"]["rms"] == pytest.approx(m["errors"]["rms"], rel=1e-6)
    # the case's own error numbers (relative errors against Hertz and the exact circle at its load) to 1e-9: as
    # differences of relative errors (the csv's 10 digits leave 1e-10 of p_max, ~5e-7 of a 1.6e-4 error)
    for key in ("p_max", "half_width", "p_max_vs_exact_circle", "half_width_vs_exact_circle", "rms",
                "rms_vs_exact_circle"):
        assert abs(lv["errors"][key]) == pytest.approx(m["errors"][key], rel=0, abs=1e-9), key
    # the run's full-precision samples (vtk/<run>/contact_surface.csv: X_mm, p_MPa, q_MPa, weight_mm; a half
    # model) with no load column: every number of the case to 1e-9 (measured: 0 for p_max, half-width and the
    # pressure integral; the virtual-work P is 1.1e-12 from the integral)
    own = tmp_path / "run" / "hertz_cylinder" / "vtk" / "base" / "contact_surface.csv"
    assert score_main(["hertz_cylinder", str(own), "--out", str(tmp_path / "s2")]) == 0
    lv = json.loads((tmp_path / "s2" / "score_hertz_cylinder" / "score.json").read_text())["levels"][0]
    assert lv["half_model"] and lv["P_source"] == "integral"
    for key, mk in (("P", "P"), ("P_integral", "P_pressure"), ("p_max", "p_max"), ("half_width", "patch_half_width")):
        assert lv[key] == pytest.approx(m[mk], rel=1e-9), key
    assert lv["errors"]["rms"] == pytest.approx(m["errors"]["rms"], rel=1e-9)
    for key in ("p_max", "half_width", "p_max_vs_exact_circle", "half_width_vs_exact_circle", "rms_vs_exact_circle"):
        assert abs(lv["errors"][key]) == pytest.approx(m["errors"][key], rel=1e-9), key
    assert abs(lv["errors"]["load_balance"]) == pytest.approx(m["errors"]["load_balance"], rel=1e-3, abs=1e-11)
    # the run's VTK contact surface (.pvd -> its last .vtp, zlib-compressed binary; P from its FieldData)
    pvd = own.with_name("contact_surface.pvd")
    assert score_main(["hertz_cylinder", str(pvd), "--format", "vtu", "--out", str(tmp_path / "s3")]) == 0
    lv = json.loads((tmp_path / "s3" / "score_hertz_cylinder" / "score.json").read_text())["levels"][0]
    for key, mk in (("P", "P"), ("p_max", "p_max"), ("half_width", "patch_half_width")):
        assert lv[key] == pytest.approx(m[mk], rel=1e-12), key
    bad = tmp_path / "truncated.vtp"
    bad.write_text(own.with_name("contact_surface_0001.vtp").read_text()[:3000])
    assert score_main(["hertz_cylinder", str(bad), "--format", "vtu", "--out", str(tmp_path / "s4")]) == 2
    assert not (tmp_path / "s4").exists()


@pytest.mark.parametrize("levels", ["0", "9"])
def test_external_ccx_levels_out_of_range_one_line_exit_2(tmp_path, levels):
    """``--levels`` outside 1..(the case's levels from ci_level down) is refused with the true range (it said
    "allowed: 1 to 0" for 0), before ccx is looked for or anything is written."""
    proc = subprocess.run([sys.executable, "-m", "workbench", "external", "ccx", "hertz_cylinder", "--levels", levels,
                           "--out", str(tmp_path / "out")], capture_output=True, text=True, env=ENV, timeout=120)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.strip().splitlines() == [f"error: --levels {levels}; allowed: 1 to 6 (the case's levels from "
                                                "ci_level 0.1 down, halving beyond its list)"]
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("model", ["halfplane/convective", "obstacle/convective", "obstacle/finite"])
def test_verdict_names_the_model_whose_band_holds_the_result(tmp_path, model):
    """The verdict is derived from the saved model bands (workbench/external/model_bands/hertz_cylinder.json),
    not a fixed sentence: three levels converging to a model's own extrapolated p_max/p0 are named with it, and
    the traction it shares is put in words."""
    from workbench.external.models import load_model_bands

    bands = {f"{m['traction']}/{m['kinematics']}": m for m in load_model_bands("hertz_cylinder")["models"]}
    target = bands[model]["study"]["p_max"]["extrapolated"]
    from scipy.optimize import brentq

    E_star = materials.plane_strain_modulus(210000.0, 0.3)
    P = hz.hertz_load_from_half_width(0.5, 10.0, E_star)  # one load on every level (issue 35: else no verdict)
    p0 = hz.hertz(P, 10.0, E_star).p0
    files = []
    for h in (0.04, 0.02, 0.01):  # p = r p0 sqrt(1 - x^2/b^2), b such that its trapezoid integral is P exactly
        x = np.arange(-int(round(0.8 / h)), int(round(0.8 / h)) + 1) * h  # (load balance 0), p_max/p0(P) = r
        r = target * (1.0 + math.copysign(5.0, target - 1.0) * h**2)  # away from 1: no "crossing"
        b = brentq(lambda b, x=x, r=r: float(np.trapezoid(r * p0 * np.sqrt(np.clip(1 - (x / b) ** 2, 0, None)), x))
                   - P, 0.3, 0.7, xtol=1e-15)
        p = r * p0 * np.sqrt(np.clip(1 - (x / b) ** 2, 0, None))
        f = tmp_path / f"level_{h}.csv"
        f.write_text("x_mm,p_MPa,P_N_per_mm\n" + "".join(f"{xi!r},{pi!r},{P!r}\n"
                                                          for xi, pi in zip(x.tolist(), p.tolist(), strict=True)))
        files.append(str(f))
    assert score_main(["hertz_cylinder", *files, "--out", str(tmp_path)]) == 0
    score = json.loads((tmp_path / "score_hertz_cylinder" / "score.json").read_text())
    inside = [r["model"] for r in score["models"]["models"] if r["contains"]]
    assert model in inside and "halfplane/small" not in inside
    assert f"Consistent with the workbench's model(s) {', '.join(inside)}" in score["verdict"]
    words = "vertical (half-plane) traction" if model.startswith("halfplane") else "obstacle's normal"
    assert words in score["verdict"]
    assert score["theory"] == "exact circle" and "from the exact circle" in score["verdict"]


def test_circle_theory_is_drawn_as_the_exact_circle():
    """The score plot's theory of a circle indenter is the exact circle (the case's own theory), Hertz beside it."""
    from workbench.external.score import theory_curves

    th = {"kind": "hertz", "P": 4531.143250369892, "E_star": 230769.23076923075, "half_width": 0.5,
          "p0": 5769.230769230768, "R": 10.0,
          "exact_circle": {"p0": 5770.132422825063, "half_width": 0.499765643338218}}
    x = np.linspace(-0.6, 0.6, 241)
    curves = theory_curves(th, x)
    assert [c[0] for c in curves] == ["exact circle", "Hertz (parabola)"]
    assert curves[0][1].max() == pytest.approx(5770.132422825063, rel=1e-4)
    assert [c[0] for c in theory_curves(th | {"exact_circle": None}, x)] == ["hertz"]


def test_saved_model_bands_match_the_case_and_refuse_another_scene():
    """The saved bands were solved on the case as it is now (its scene key), hold every model of the hierarchy
    with finite values, and are not used for a changed case (another E here)."""
    from dataclasses import replace

    from cases import load_case
    from workbench.external.models import load_model_bands
    from workbench.studies.validity_config import VALIDITY_MODELS

    case = load_case("hertz_cylinder")
    bands = load_model_bands("hertz_cylinder", case=case)
    assert bands is not None
    assert [(m["traction"], m["kinematics"]) for m in bands["models"]] == list(VALIDITY_MODELS)
    for m in bands["models"]:
        for st in m["study"].values():
            assert math.isfinite(st["extrapolated"]) and 0 <= st["band"] < 5e-3
    other = replace(case, material=replace(case.material, E=case.material.E * 2))
    assert load_model_bands("hertz_cylinder", case=other) is None
