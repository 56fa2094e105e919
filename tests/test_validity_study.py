"""The validity study's pure parts (no FEM): config validation, bands, the value with its uncertainty, assembling
synthetic runs into points, the report, the summary section and the claims row. The study itself is
``make validity``."""

from __future__ import annotations

import json
import math
from dataclasses import asdict

import pytest

from workbench.studies import validity as v
from workbench.studies import validity_assemble as va
from workbench.studies.config import to_json
from workbench.studies.validity_config import ValidityConfig


@pytest.mark.parametrize("kw", [dict(nu=(0.5,)), dict(nu=()), dict(models=(("halfplane", "finite"),)),
                                dict(h_ratios=(8.0, 4.0, 16.0)), dict(h_ratios=(4.0, 8.0)), dict(workers=0),
                                dict(finite_material="linear"), dict(cylinder_a_over_R=(0.95,)),
                                dict(wedge_theta=(2.0,)), dict(thresholds=(0.05, 0.01)), dict(width_factor_far=100.0),
                                dict(n_steps=1.5), dict(halfplanes_beta=(0.6,)), dict(halfplanes_b0_over_R=(0.9,)),
                                dict(halfplanes_h_ratios=(8.0, 4.0, 16.0)),
                                dict(rigid=False, halfplanes_beta=(), elastic_wedge_theta=()),
                                dict(elastic_wedge_theta=(2.0,)), dict(elastic_wedge_h_ratios=(4.0, 8.0, 12.0)),
                                dict(elastic_wedge_nu=0.49), dict(elastic_wedge_width_far=30.0),
                                dict(halfplanes_finite_laws=("linear",)),
                                dict(halfplanes_finite_laws=("neo_hookean", "neo_hookean")),
                                dict(halfplanes_finite_h_ratios=(10.0, 5.0, 20.0)),
                                dict(elastic_wedge_finite_laws=("linear",)), dict(halfplanes_pairing=1),
                                dict(elastic_wedge_finite_theta=(2.0,))])
def test_config_rejects_bad_values_in_one_line(kw):
    with pytest.raises(ValueError) as exc:
        ValidityConfig(**kw)
    msg = str(exc.value)
    assert "\n" not in msg and "allowed" in msg and next(iter(kw)) in msg


def test_cli_bad_option_is_one_line_exit_2(capsys, tmp_path):
    from workbench.cli import main

    assert main(["validity", "--halfplanes-only", "--elastic-wedge-only", "--out", str(tmp_path / "v")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "--elastic-wedge-only" in err and "allowed" in err and not (tmp_path / "v").exists()
    assert main(["validity", "--workers", "0", "--out", str(tmp_path / "v")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "workers" in err[0]
    assert not (tmp_path / "v").exists()
    with pytest.raises(SystemExit) as exc:
        main(["validity", "--nonsense"])
    assert exc.value.code == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


def test_resume_runs_only_the_tasks_no_saved_record_holds():
    """The study saves its records as it goes; --resume skips the tasks a saved record holds (a failed run too: its
    failure is a measured outcome), whatever order they were saved in."""
    cfg = ValidityConfig(cylinder_a_over_R=(0.1,), wedge_theta=(math.pi / 5,), nu=(0.0,))
    todo, _ = v.tasks(cfg)
    saved = [{"task": json.loads(json.dumps(asdict(t))), "converged": k % 2 == 0} for k, t in enumerate(todo[5:2:-1])]
    rest = v.remaining(todo, saved)
    assert rest == todo[:3] + todo[6:]
    assert v.remaining(todo, []) == todo


def test_resume_refuses_in_one_line_without_matching_saved_runs(capsys, tmp_path):
    """--resume without a saved file, with a file written with other options, or with a file that is not one:
    one line naming --resume, exit 2, and the saved file untouched."""
    from workbench.atomic import write_json
    from workbench.cli import main

    out = tmp_path / "v"
    assert main(["validity", "--tiny", "--resume", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--resume" in err[0] and "no saved runs" in err[0]
    other = to_json(ValidityConfig(out=out, nu=(0.3,)))
    write_json(out / v.PARTIAL, {"config": other, "runs": []})
    before = (out / v.PARTIAL).read_text()
    assert main(["validity", "--tiny", "--resume", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--resume" in err[0] and "other options" in err[0] and "allowed" in err[0]
    assert (out / v.PARTIAL).read_text() == before
    (out / v.PARTIAL).write_text("{not json")
    assert main(["validity", "--tiny", "--resume", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "is not a file of saved validity runs" in err[0]


def test_tasks_cover_every_model_level_and_skip_finite_where_it_locks():
    cfg = ValidityConfig(cylinder_a_over_R=(0.1,), wedge_theta=(math.pi / 5,), nu=(0.0, 0.499))
    todo, skipped = v.tasks(cfg)
    assert len(todo) == 2 * (5 + 4) * 4  # nu = 0: five models; nu = 0.499: four (no finite); four levels each
    assert {s["model"] for s in skipped} == {"obstacle/finite"} and len(skipped) == 2
    assert all("mixed formulation" in s["reason"] for s in skipped)
    far = [t for t in todo if t.level == "far"]
    assert all(t.h_ratio == cfg.h_ratios[1] and t.width_factor == cfg.width_factor_far for t in far)
    assert {t.mesh_name for t in todo} == {f"validity_{s}_h{h:g}_W{w:g}" for s in ("cylinder", "wedge")
                                          for h, w in ((4, 160), (8, 160), (16, 160), (8, 640))}
    assert sum(t.stresses for t in todo) == 4  # wedge, nu = claim_nu, two tractions x (h2, far)


@pytest.mark.parametrize("d, u, band", [(1e-4, 1e-5, "<0.1%"), (5e-3, 1e-4, "<1%"), (0.03, 1e-3, "<5%"),
                                        (0.08, 1e-3, ">5%"), (5e-3, 4e-3, "unresolved"), (0.05, 1e-3, "unresolved"),
                                        (2e-4, 5e-4, "<0.1%")])
def test_classify(d, u, band):
    got, reason = va.classify(d, u, (1e-3, 1e-2, 5e-2), 3.0)
    assert got == band
    assert (reason is None) == (band != "unresolved")


def test_value_extrapolates_and_corrects_the_truncation():
    # f = 1 + 0.01 h^2 (h = 1/ratio) on W, and the far block 3e-4 higher on the middle level
    ratios = (4.0, 8.0, 16.0)
    levels = {f"h{i}": {"moment": 1.0 + 0.01 / r**2} for i, r in enumerate(ratios)}
    levels["far"] = {"moment": levels["h1"]["moment"] + 3e-4}
    out = va.extrapolated_value(levels, "moment", ratios)
    assert out["observed_order"] == pytest.approx(2.0, rel=1e-8)
    assert out["value"] == pytest.approx(1.0 + 4e-4, rel=1e-12)
    assert out["truncation"] == pytest.approx(1e-4 / out["value"], rel=1e-12)
    assert va.extrapolated_value({"h0": {"moment": 1.0}}, "moment", ratios)["value"] is None


def _synthetic_records(cfg: ValidityConfig) -> list[dict]:
    """Runs whose values follow f = c (1 + 0.001 h^2), c per model; finite fails on the wedge."""
    todo, _ = v.tasks(cfg)
    scale = {"halfplane/small": 1.0, "halfplane/convective": 1.02, "obstacle/small": 0.99,
             "obstacle/convective": 1.01, "obstacle/finite": 1.015}
    out = []
    for t in todo:
        rec = {"task": asdict(t), "model": t.model, "converged": True, "error": None, "P": 1.0}
        if t.kinematics == "finite" and t.scene == "wedge":
            rec |= {"converged": False, "error": "diverged: SNES reason -5 (DIVERGED_MAX_IT)"}
        else:
            f = scale[t.model] * (1.0 + 1e-3 / t.h_ratio**2) + (1e-5 if t.level == "far" else 0.0)
            rec |= {"moment": f, "half_width": f, "p_max": 1.0 / f if t.scene == "cylinder" else None}
        out.append(rec)
    return out


def test_assemble_report_summary_and_claims_row(tmp_path):
    cfg = ValidityConfig(cylinder_a_over_R=(0.1,), wedge_theta=(math.pi / 10,), nu=(0.0,), out=tmp_path)
    records = _synthetic_records(cfg)
    points, dropped = va.assemble(cfg, records, [])
    assert len(points) == 2
    cyl = next(p for p in points if p["scene"] == "cylinder")
    wed = next(p for p in points if p["scene"] == "wedge")
    assert cyl["complete_model"] == "obstacle/finite" and wed["complete_model"] == "obstacle/convective"
    s = cyl["split"]
    parts = sum(s[k]["value"] for k in ("profile", "convective", "traction", "finite_strain"))
    assert parts == pytest.approx(s["total"]["value"], abs=1e-12)
    assert s["convective"]["value"] == pytest.approx(0.02, rel=1e-6)
    assert cyl["bands"]["hertz"]["moment"]["band"] == "<5%"
    failed = [d for d in dropped if d["what"] == "run failed"]
    assert len(failed) == 4 and all("DIVERGED" in d["reason"] for d in failed)
    assert any(d["what"] == "value dropped" and d["model"] == "obstacle/finite" for d in dropped)
    data = {"config": to_json(cfg), "summary": {"runs": len(records), "failed": 4, "points": 2, "dropped": 1,
                                                "wall_time_s": 1.0, "workers": 2, "cpu_count": 2,
                                                "cpu_s_workers": 1.0},
            "points": points, "dropped": dropped, "claim": {"rows": [], "verdict": None}, "runs": records}
    md = __import__("workbench.studies.validity_report", fromlist=["x"]).report_markdown(
        json.loads(json.dumps(data, default=float)))
    assert "DIVERGED_MAX_IT" in md and "map_cylinder.png" in md and "No verdict" in md
    folder = tmp_path / "validity"
    folder.mkdir()
    (folder / "validity.json").write_text(json.dumps(data, default=float))
    from workbench.reports.paper_claims import _stress_claim
    from workbench.reports.summary import trust_markdown

    section = "\n".join(trust_markdown(tmp_path))
    assert "validity/map_cylinder.png" in section and "| Hertz | 1 |" in section
    assert "run `make validity`" in "\n".join(trust_markdown(tmp_path / "nothing"))
    assert _stress_claim(tmp_path).verdict == "run `make validity`"
    data["claim"]["verdict"] = {"state": "does not hold", "worst_traction_effect": 0.3, "worst_floor": 0.002,
                                "worst_obstacle_vs_theory": 0.3, "text": "x"}
    (folder / "validity.json").write_text(json.dumps(data, default=float))
    c = _stress_claim(tmp_path)
    assert c.verdict.startswith("not confirmed") and "30.00 %" in c.ours


def test_config_default_folders_and_frozen():
    import dataclasses
    from pathlib import Path

    from workbench.paths import default_paths

    cfg = ValidityConfig()
    assert cfg.out_dir == default_paths().study("validity")
    assert cfg.cache_dir == default_paths().mesh_cache
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.out = Path("x")  # type: ignore[misc]


def test_a_run_whose_jit_compile_timed_out_is_retried_counted_and_then_named(monkeypatch):
    """The shared point runner (workbench.studies.executor.run_point) retries a JIT time-out and counts it; the
    per-worker JIT caches make it unnecessary (tests/test_studies_mpi.py asserts 0 retries in a real study)."""
    from workbench.studies import executor as ex

    task = v.tasks(ValidityConfig())[0][0]
    calls = []

    def timed_out_once(t, cache):
        calls.append(t)
        if len(calls) == 1:
            raise TimeoutError("JIT compilation timed out, probably due to a failed previous compile.")
        return {"task": asdict(t), "model": t.model, "converged": True, "error": None}

    monkeypatch.setattr(v, "_solve_task", timed_out_once)
    rec = ex.run_point(v.run_validity_point, v.Point("solve", task, "unused"), "local")
    assert rec["converged"] and rec["worker"]["jit_retries"] == 1 and len(calls) == 2

    def always_timed_out(t, cache):
        raise TimeoutError("JIT compilation timed out")

    monkeypatch.setattr(v, "_solve_task", always_timed_out)
    rec = ex.run_point(v.run_validity_point, v.Point("solve", task, "unused"), "local")
    assert not rec["converged"] and "JIT compilation timed out" in rec["error"]
    assert rec["worker"]["jit_retries"] == ex.JIT_RETRIES


# --- the two-elastic-half-planes part (issue 25) ---------------------------------------------------------------------


def test_halfplanes_bodies_give_the_asked_beta_of_either_sign_at_one_E_star():
    from analytic import materials
    from workbench.studies.validity_halfplanes import bodies_for

    for beta in (-0.45, -0.3, -0.15, 0.0, 0.15, 0.3, 0.45):
        (E_lo, nu_lo), (E_up, nu_up) = bodies_for(beta, E_star=1000.0)
        bm = materials.bimaterial(E1=E_up, nu1=nu_up, E2=E_lo, nu2=nu_lo)  # body 1 = the upper (profile) body
        assert bm.beta == pytest.approx(beta, abs=1e-14) and bm.E_star == pytest.approx(1000.0, rel=1e-14)
        assert (E_up < E_lo) == (beta > 0)  # beta > 0: the profile body is the softer one


def test_halfplanes_tasks_cover_both_signs_every_kinematics_and_level():
    from workbench.studies.validity_halfplanes import halfplanes_tasks

    cfg = ValidityConfig(halfplanes_beta=(-0.3, 0.3), halfplanes_b0_over_R=(0.1, 0.2))
    every = halfplanes_tasks(cfg)
    todo = [t for t in every if t.kinematics != "finite"]
    assert len(todo) == 2 * 2 * 3 * 4  # small, convective profile, convective pairing
    assert {t.beta for t in todo} == {-0.3, 0.3} and {t.kinematics for t in todo} == {"small", "convective"}
    assert {t.model for t in todo} == {"halfplane/small", "halfplane/convective", "halfplane/convective/pairing"}
    assert {t.convection for t in todo if t.model.endswith("pairing")} == {"pairing"}
    assert not [t for t in halfplanes_tasks(ValidityConfig(halfplanes_pairing=False)) if t.convection == "pairing"]
    assert {t.mesh_name for t in todo} == {f"validity_halfplanes_h{h:g}_W{w:g}"
                                           for h, w in ((6, 160), (10, 160), (16, 160), (10, 640))}
    assert [t.level for t in todo[:4]] == ["h0", "h1", "h2", "far"]  # a chunk of 4 shares its forms
    # finite strain (issue 39): both laws, P1, the obstacle traction, a mesh of its own per b0/R (the meshed parabola)
    finite = [t for t in every if t.kinematics == "finite"]
    assert len(finite) == 2 * 2 * 2 * 4 and {t.material for t in finite} == {"neo_hookean", "saint_venant_kirchhoff"}
    assert {(t.degree, t.traction) for t in finite} == {(1, "obstacle")}
    assert {t.mesh_name for t in finite} == {f"validity_halfplanes_finite_R{R:g}_h{h:g}_W{w:g}" for R in (10, 5)
                                             for h, w in ((10, 160), (16, 160), (25, 160), (16, 640))}
    assert [t.level for t in finite[:4]] == ["h0", "h1", "h2", "far"] and len({t.model for t in finite[:4]}) == 1
    assert not [t for t in halfplanes_tasks(ValidityConfig(halfplanes_finite_laws=())) if t.kinematics == "finite"]
    assert v.tasks(ValidityConfig(rigid=False))[0] == []


def _synthetic_hp_records(cfg: ValidityConfig) -> list[dict]:
    """Small runs f = 1 - 0.01 h^2; convective runs f (1 + 0.08 beta b0/R ...) close to the converged theory's ratio
    (h = 1/ratio); the far run of (b0/R, beta) = (0.1, +0.3, convective) fails."""
    from workbench.studies.validity_halfplanes import halfplanes_tasks, halfplanes_theories

    out = []
    th = {}
    for t in halfplanes_tasks(cfg):
        rec = {"task": asdict(t), "model": t.model, "converged": True, "error": None, "P": 1.0}
        if t.kinematics == "convective" and t.convection == "profile" and t.beta > 0 and t.level == "far":
            out.append(rec | {"converged": False, "error": "diverged: SNES reason -3 (DIVERGED_LINEAR_SOLVE)"})
            continue
        key = (t.param, t.beta)
        th.setdefault(key, halfplanes_theories(t.param, t.beta)["ch_converged"]["moment"])
        f = 1.0 - 0.01 / t.h_ratio**2
        rec["moment"] = f * (th[key] - (0.003 if t.convection == "pairing" else 0.0)
                             if t.kinematics == "convective" else 1.0)
        out.append(rec)
    return out


def test_halfplanes_points_bands_split_report_and_map(tmp_path):
    from workbench.studies.validity_plot import draw_maps
    from workbench.studies.validity_report import report_markdown

    cfg = ValidityConfig(halfplanes_beta=(-0.3, 0.3), halfplanes_b0_over_R=(0.1,), rigid=False, out=tmp_path)
    records = _synthetic_hp_records(cfg)
    points, dropped = va.assemble(cfg, records, [])
    assert [(p["scene"], p["beta"]) for p in points] == [("halfplanes", -0.3), ("halfplanes", 0.3)]
    neg, pos = points
    r = neg["models"][va.HP_COMPLETE]["moment"]
    assert r["value"] == pytest.approx(neg["theories"]["ch_converged"]["moment"], rel=1e-12)  # the ratio cancels f
    b = neg["bands"]["ch_converged"]["moment"]
    assert b["inside"] and b["band"] == "<0.1%"
    assert neg["bands"]["hertz"]["moment"]["band"] == "<5%" and not neg["bands"]["hertz"]["moment"]["inside"]
    assert neg["theories"]["ch_converged"]["moment"] > 1.0 > pos["theories"]["ch_converged"]["moment"]
    s = neg["split"]
    assert s["profile"]["value"] + s["convective"]["value"] == pytest.approx(s["total"]["value"], abs=1e-15)
    assert s["convective"]["theory"] + s["remainder"]["value"] == pytest.approx(s["convective"]["value"], abs=1e-15)
    assert pos["complete_model"] is None and pos["split"] is None  # its far run failed: no ratio, said why
    failed = [d for d in dropped if d["what"] == "run failed"]
    assert len(failed) == 1 and failed[0]["beta"] == 0.3 and "DIVERGED_LINEAR_SOLVE" in failed[0]["reason"]
    assert any(d["what"] == "point unused" and d["beta"] == 0.3 and "wide-block" in d["reason"] for d in dropped)
    data = json.loads(json.dumps({"config": to_json(cfg), "summary": {"runs": len(records), "failed": 1, "points": 2,
                                                                      "dropped": len(dropped), "wall_time_s": 1.0,
                                                                      "workers": 2, "cpu_count": 2},
                                  "points": points, "dropped": dropped, "claim": {"rows": [], "verdict": None},
                                  "runs": records}, default=float))
    md = report_markdown(data)
    assert "Two elastic half-planes" in md and "map_halfplanes.png" in md
    assert "| 0.1 | -0.3 |" in md and "| 0.1 | +0.3 | no value:" in md
    assert "b0/R = 0.1, beta = +0.3" in md and "DIVERGED_LINEAR_SOLVE" in md
    assert [p.name for p in draw_maps(data, tmp_path)] == ["map_halfplanes.png", "map_halfplanes_finite.png"]
    # the finite rows (issue 39): synthetic finite runs equal to the small ones, so F = 1 and the two laws agree:
    # at beta = -0.3 the convective correction (2.4 %) outweighs their spread (0); beta = +0.3 has no R, no split
    assert "### At finite strain" in md and "**Verdict: at 0 of 2 points the spread" in md
    assert neg["finite"]["spread"]["verdict"] == "convective" and "split" not in pos["finite"]["laws"]["neo_hookean"]
    # the pairing model (issue 39): its ratio 3e-3 below profile's (both above 1 at beta < 0): F = 1 is nearer pairing
    pr = neg["models"][va.HP_PAIRING]["moment"]
    assert pr["value"] == pytest.approx(r["value"] - 0.003 / neg["models"]["halfplane/small"]["moment"]["value"],
                                        rel=1e-3)
    assert neg["finite"]["laws"]["neo_hookean"]["follows"]["model"] == "pairing"
    # beta = +0.3 has no profile R: two rows compare both models
    assert "**Which small-strain model: of 2 finite-strain rows" in md and "R pairing +- U" in md
    from workbench.reports.summary import trust_markdown

    (tmp_path / "validity").mkdir()
    (tmp_path / "validity" / "validity.json").write_text(json.dumps(data))
    section = "\n".join(trust_markdown(tmp_path))
    assert "validity/map_halfplanes.png" in section and "Ciavarella-Hills converged (two half-planes) | 1 |" in section
    assert "contains converged Ciavarella-Hills at 1 of 1 points" in section


def test_a_finished_run_frees_its_problem(tmp_path):
    """``fem.solver.solve_problem`` destroys the SNES, whose callbacks otherwise keep every problem (its mesh, spaces
    and MPI communicators) alive: a study worker then ran out of MPICH's 2048 communicators. A small and a finite
    two-body run of the validity study at tiny size: no problem is left alive after them."""
    import gc
    import weakref

    from fem.two_body.problem import TwoBodyProblem
    from workbench.studies.validity_halfplanes import build_mesh, halfplanes_tasks, solve_task

    cfg = ValidityConfig(halfplanes_beta=(0.3,), halfplanes_b0_over_R=(0.1,), rigid=False, elastic_wedge_theta=(),
                         halfplanes_h_ratios=(2.0, 3.0, 4.0), halfplanes_finite_h_ratios=(3.0, 4.0, 5.0),
                         halfplanes_finite_laws=("neo_hookean",), width_factor=20.0, width_factor_far=40.0)
    alive = []
    init = TwoBodyProblem.__init__

    def tracked(self, *a, **k):
        alive.append(weakref.ref(self))
        init(self, *a, **k)

    TwoBodyProblem.__init__ = tracked
    try:
        for t in [t for t in halfplanes_tasks(cfg) if t.level == "h0" and t.kinematics in ("small", "finite")]:
            build_mesh(t, str(tmp_path))
            assert solve_task(t, str(tmp_path))["converged"], t
    finally:
        TwoBodyProblem.__init__ = init
    gc.collect()
    assert len(alive) == 2 and not [w for w in alive if w() is not None]
