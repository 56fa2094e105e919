"""The result csv's ``run``, ``step`` and ``body`` columns (issue 36): a file may hold several runs, steps and bodies;
what is not the case's is refused in one line naming the file, exit 2, nothing written (issue 35's promise).

Requirements: a run label that is not one of the case's benchmark runs (nor an alias), a step outside the case's
schedule, a body that is not the case's, a step that is not a whole number, a run column together with ``--run``, a
multi-run case's file without a run column, one (run, step, body) twice under two of its names, a load that varies
inside one group, a concave result without y or off the concave surface: each is one ``error:`` line, exit 2, and the
output folder is not created. A file holding two runs and the case's aliases is read and labelled canonically.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from analytic import hertz as hz
from analytic import materials
from workbench.external.results import read_csv_groups
from workbench.external.score import main as score_main

E_STAR = materials.plane_strain_modulus(210000.0, 0.0)


def _rows(run: str | None, *, step=None, body=None, R=10.0, b0=2.5, h=0.1, P=None) -> list[str]:
    """A Hertz pressure of parabola_convective's scene (b0 = 2.5 mm, R = 10 mm, nu = 0) at nodes of spacing h."""
    P = hz.hertz_load_from_half_width(b0, R, E_STAR) if P is None else P
    c = hz.hertz(P, R, E_STAR)
    x = np.arange(0, int(round(1.6 * c.half_width / h)) + 1) * h
    p = c.p0 * np.sqrt(np.clip(1 - (x / c.half_width) ** 2, 0, None))
    lead = [v for v in (run, step, body) if v is not None]
    return [",".join([*map(str, lead), repr(float(xi)), repr(float(pi)), repr(P)]) for xi, pi in zip(x, p, strict=True)]


def _file(tmp_path, name: str, header: str, rows: list[str]):
    f = tmp_path / name
    f.write_text(header + "\n" + "\n".join(rows) + "\n")
    return f


def _refused(tmp_path, capsys, argv: list[str], *words: str) -> str:
    out = tmp_path / "out"
    assert score_main([*argv, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error: "), err
    for w in words:
        assert w in err[0], (w, err[0])
    assert not out.exists()
    return err[0]


def test_two_runs_in_one_file_are_two_groups(tmp_path):
    f = _file(tmp_path, "both.csv", "run,x_mm,p_MPa,P_N_per_mm", _rows("small") + _rows("convective"))
    groups = read_csv_groups(f)
    assert [(g.run, g.step, g.body) for g in groups] == [("small", None, None), ("convective", None, None)]
    assert all(not g.half for g in groups)  # the scorer mirrors, where the case is symmetric
    assert score_main(["parabola_convective", str(f), "--out", str(tmp_path / "o")]) == 0
    score = json.loads((tmp_path / "o" / "score_parabola_convective" / "score.json").read_text())
    assert sorted((lv["run"], lv["step"], lv["body"]) for lv in score["levels"]) == [("convective", 0, "body"),
                                                                                      ("small", 0, "body")]
    assert all(lv["half_model"] for lv in score["levels"])


def test_case_labels_are_aliases_of_the_benchmark_runs(tmp_path):
    f = _file(tmp_path, "base.csv", "run,x_mm,p_MPa,P_N_per_mm",
              _rows("base", R=10.0, b0=0.5, h=0.02))  # hertz_cylinder's run is "base" in the case, "small" here
    assert score_main(["hertz_cylinder", str(f), "--out", str(tmp_path / "o")]) == 0
    score = json.loads((tmp_path / "o" / "score_hertz_cylinder" / "score.json").read_text())
    assert score["levels"][0]["run"] == "small" and score["runs"][0]["aliases"] == ["base"]


@pytest.mark.parametrize("case, header, rows, words", [
    ("parabola_convective", "run,x_mm,p_MPa,P_N_per_mm", lambda: _rows("sideways"),
     ["run 'sideways' is not a run of case parabola_convective", "allowed: small, convective, finite"]),
    ("parabola_convective", "x_mm,p_MPa,P_N_per_mm", lambda: _rows(None),
     ["no run column", "runs small, convective, finite", "a run column or --run"]),
    ("parabola_convective", "run,step,x_mm,p_MPa,P_N_per_mm", lambda: _rows("small", step=1),
     ["step 1 is outside the schedule of case parabola_convective", "step 0: the target load"]),
    ("parabola_convective", "run,step,x_mm,p_MPa,P_N_per_mm", lambda: _rows("small", step="1.5"),
     ["the step value '1.5' is not allowed", "a whole number >= 0"]),
    ("parabola_convective", "run,body,x_mm,p_MPa,P_N_per_mm", lambda: _rows("small", body="indenter"),
     ["body 'indenter' is not a body of case parabola_convective", "allowed: body (block)"]),
    ("hertz_cylinder", "run,x_mm,p_MPa,P_N_per_mm", lambda: _rows("small", b0=0.5, h=0.02) + _rows("base", b0=0.5,
                                                                                                    h=0.02),
     ["appears twice", "run small, step 0, body body"]),
    ("parabola_convective", "run,x_mm,p_MPa,P_N_per_mm",
     lambda: _rows("small")[:5] + [r.rsplit(",", 1)[0] + ",1.0" for r in _rows("small")[5:]],
     ["column P_N_per_mm varies between rows", "one value per (run, step, body)"]),
    ("patch_test", "body,x_mm,p_MPa", lambda: [f"cylinder,{x},88.9" for x in (0.0, 0.5, 1.0)],
     ["body 'cylinder' is not a body of case patch_test", "lower_block (lower), upper_block (upper)"]),
    ("close_to_conformal", "step,x_mm,y_mm,p_MPa", lambda: [f"6,{x},0.0,1.0" for x in (0.0, 0.1)],
     ["step 6 is outside the schedule of case close_to_conformal", "steps 0 to 5: d = 0.46, 0.47, 0.48, 0.5, 0.7, 1"]),
    ("close_to_conformal", "step,x_mm,p_MPa", lambda: [f"0,{x},1.0" for x in (0.0, 0.1)],
     ["no y column", "x_mm and y_mm"]),
    ("close_to_conformal", "step,x_mm,y_mm,p_MPa", lambda: [f"0,{x},500.0,1.0" for x in (0.0, 0.1)],
     ["off the case's concave surface", "the surface does not match the case"]),
])
def test_what_is_not_the_cases_is_refused_in_one_line(tmp_path, capsys, case, header, rows, words):
    f = _file(tmp_path, "level.csv", header, rows())
    line = _refused(tmp_path, capsys, [case, str(f)], *words)
    assert str(f) in line


def test_run_option_for_a_file_with_a_run_column_is_refused(tmp_path, capsys):
    f = _file(tmp_path, "level.csv", "run,x_mm,p_MPa,P_N_per_mm", _rows("small"))
    _refused(tmp_path, capsys, ["parabola_convective", str(f), "--run", "small"],
             "has a run column and --run was given")


def test_run_option_labels_files_without_the_column(tmp_path):
    a = _file(tmp_path, "small.csv", "x_mm,p_MPa,P_N_per_mm", _rows(None))
    b = _file(tmp_path, "conv.csv", "x_mm,p_MPa,P_N_per_mm", _rows(None))
    assert score_main(["parabola_convective", str(a), str(b), "--run", "small", "convective", "--out",
                       str(tmp_path / "o")]) == 0
    score = json.loads((tmp_path / "o" / "score_parabola_convective" / "score.json").read_text())
    assert [lv["run"] for lv in score["levels"]] == ["small", "convective"]


def test_option_counts_are_checked_before_reading(tmp_path, capsys):
    missing = str(tmp_path / "missing.csv")
    _refused(tmp_path, capsys, ["parabola_convective", missing, missing, missing, "--run", "small", "convective"],
             "--run: 2 values for 3 RESULT files", "one, or one per RESULT")
