"""The elastic wedge of Ciavarella and Hills's theta < pi/5 claim (issue 25, point 4).

* The shaped upper body's contact faces are the wedge itself: every node of ``contact_upper`` lies on y = m |x|,
  the apex a node at the origin; the lower block is the flat block's.
* A shaped wedge of the same material is more compliant than the half-plane it idealises: at theta = pi/5 its
  contact is wider than the classical wedge's at the same load, while the flat twin meets the classical value.
* The claim's arithmetic (:func:`workbench.studies.validity_elastic_wedge.claim_elastic_wedge`): the difference
  of unit stresses, the grid and width uncertainty and the three verdicts, on synthetic records.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401

import math

import numpy as np
import pytest
from mpi4py import MPI

from meshes.two_body import build_profile_blocks
from workbench.mesh_io import read_mesh
from workbench.studies import validity_elastic_wedge as ew
from workbench.studies.validity_config import ValidityConfig


def test_shaped_wedge_mesh_lies_on_its_faces(tmp_path):
    m = math.tan(math.pi / 5)
    files = build_profile_blocks(width=20.0, height=20.0, contact_half_width=1.0, h_contact=0.25, apex_factor=0.25,
                                 wedge_slope=m, out_dir=tmp_path, name="shaped")
    md = read_mesh(files.msh, MPI.COMM_SELF)
    mesh, ft = md.mesh, md.facet_tags
    mesh.topology.create_connectivity(1, 0)
    f2v = mesh.topology.connectivity(1, 0)
    x = mesh.geometry.x

    def nodes(name):
        tag = md.physical_groups[name][1]
        return np.unique(np.concatenate([f2v.links(f) for f in ft.find(tag)]))

    up, low = x[nodes("contact_upper")], x[nodes("contact_lower")]
    assert np.max(np.abs(up[:, 1] - m * np.abs(up[:, 0]))) < 1e-12 * 20.0
    assert np.min(np.hypot(up[:, 0], up[:, 1])) < 1e-12  # the apex is a node
    assert np.max(np.abs(low[:, 1])) < 1e-12 and up[:, 0].min() == pytest.approx(-10.0)
    with pytest.raises(ValueError, match="wedge_slope"):
        build_profile_blocks(width=20.0, height=20.0, contact_half_width=1.0, h_contact=0.25, wedge_slope=m,
                             out_dir=tmp_path, name="no_apex")


def test_shaped_wedge_is_more_compliant_than_its_half_plane(tmp_path):
    """theta = pi/5, nu = 0.3, b/h = 4, W = 20 b. Measured: moment half-width over the classical wedge's, shaped
    1.036, flat 0.993 (the finer grids of the study: 1.043 and 0.999)."""
    cfg = ValidityConfig(elastic_wedge_theta=(math.pi / 5,), elastic_wedge_h_ratios=(4.0, 8.0, 16.0),
                         elastic_wedge_width=20.0, elastic_wedge_width_far=40.0)
    sh, fl = (ew.solve_task(t, str(tmp_path)) for t in ew.elastic_wedge_tasks(cfg) if t.level == "h0")
    assert sh["converged"] and fl["converged"], (sh["error"], fl["error"])
    assert sh["task"]["upper"] == "shaped" and fl["task"]["upper"] == "flat"
    assert abs(fl["moment"] - 1.0) < 0.015 and sh["moment"] - fl["moment"] > 0.025
    assert sh["load_balance"] < 1e-9 and fl["load_balance"] < 1e-9
    # the wedge's own stresses under the apex differ from the mirrored half-plane's by far more than 0.5 %
    d = ew._max_diff(ew._unit(sh), ew._unit(fl))
    assert d["upper"] > 0.1 and d["lower"] > 0.05


def _synthetic(cfg, *, geometry, by_level=None, width=0.0):
    """Records whose unit stresses are the theory's (flat) and the theory's plus ``geometry`` on the block's s_xx
    and twice that on the wedge's (shaped), per level ``by_level`` if given, ``width`` more on the wide blocks."""
    th = ew.theory_unit()
    b, P = 1.0, 2.0  # p_mean = P / (2 b) = 1
    recs = []
    for t in ew.elastic_wedge_tasks(cfg):
        task = {"scene": "elastic_wedge", "param": t.param, "upper": t.upper, "level": t.level,
                "kinematics": t.kinematics}
        if t.kinematics == "finite":  # no probes; its moment 3 % above the small runs' (F = 1.03 on every level)
            recs.append({"task": task, "model": t.model, "converged": True, "P": P, "b": b, "moment": 1.03,
                         "stresses": None})
            continue
        g = 0.0
        if t.upper == "shaped":
            g = (by_level or {}).get(t.level, geometry) + (width if t.level == "far" else 0.0)
        st = {body: {k: list(v) for k, v in th[body].items()} for body in ("lower", "upper")}
        st["lower"]["sxx"] = list(np.asarray(th["lower"]["sxx"]) + g)
        st["upper"]["sxx"] = list(np.asarray(th["upper"]["sxx"]) + 2.0 * g)
        recs.append({"task": task, "model": t.model, "converged": True, "P": P, "b": b, "moment": 1.0,
                     "stresses": st})
    return recs


@pytest.mark.parametrize("geometry, by_level, width, state", [
    (0.02, None, 0.0, "does not hold"),
    (0.002, None, 0.0, "holds"),
    (0.004, {"h0": 0.010, "h1": 0.006, "h2": 0.004, "far": 0.006}, 0.0, "undecided"),  # the GCI straddles 0.5 %
    (0.003, None, 0.004, "undecided"),  # the wide blocks move it by 0.4 %
])
def test_claim_verdicts(geometry, by_level, width, state):
    cfg = ValidityConfig(elastic_wedge_theta=(math.pi / 10, math.pi / 5))
    claim = ew.claim_elastic_wedge(cfg, _synthetic(cfg, geometry=geometry, by_level=by_level, width=width))
    v = claim["verdict"]
    assert v["state"] == state, v
    row = claim["rows"][0]
    assert row["geometry"] == pytest.approx(geometry, abs=1e-12)
    assert row["floor"] == pytest.approx(0.0, abs=1e-12)  # the flat records are the theory itself
    assert row["U_width"] == pytest.approx(width, abs=1e-12)
    assert row["geometry_wedge"] == pytest.approx(2.0 * geometry, abs=1e-12)  # reported, not judged
    assert claim["beta"] == pytest.approx(0.0, abs=1e-15) and not claim["dropped"]
    # the finite rows (issue 39): F = 1.03 / 1.0 with no discretisation error, beyond the 0.5 % bound
    f = row["finite"]["neo_hookean"]
    assert f["ratio"]["value"] == pytest.approx(1.03) and f["ratio"]["uncertainty"] == pytest.approx(0.0, abs=1e-12)
    assert f["beyond_bound"] and f["small"]["value"] == pytest.approx(1.0)


def test_finite_wedge_tasks_and_a_missing_finite_run():
    """The finite runs: per angle and law the shaped pair's four levels at P1, on the shaped pair's meshes; a
    failed finite run leaves its row without a value, says why, and the claim's verdict unchanged."""
    both = (math.pi / 10, math.pi / 5)
    assert {t.param for t in ew.elastic_wedge_tasks(ValidityConfig(elastic_wedge_theta=both))
            if t.kinematics == "finite"} == {math.pi / 10}  # the default: pi/10 alone
    cfg = ValidityConfig(elastic_wedge_theta=both, elastic_wedge_finite_theta=both)
    tasks = ew.elastic_wedge_tasks(cfg)
    fin = [t for t in tasks if t.kinematics == "finite"]
    assert len(fin) == 2 * 1 * 4 and {(t.degree, t.traction, t.material, t.upper) for t in fin} == {
        (1, "obstacle", "neo_hookean", "shaped")}
    assert {t.mesh_name for t in fin} <= {t.mesh_name for t in tasks if t.upper == "shaped" and t.kinematics == "small"}
    assert not [t for t in ew.elastic_wedge_tasks(ValidityConfig(elastic_wedge_finite_laws=())) if t.kinematics
                == "finite"]
    recs = _synthetic(cfg, geometry=0.02)
    recs = [r | ({"converged": False, "error": "diverged: DIVERGED_MAX_IT"} if r["task"]["kinematics"] == "finite"
                 and r["task"]["level"] == "h2" and r["task"]["param"] == math.pi / 5 else {}) for r in recs]
    claim = ew.claim_elastic_wedge(cfg, recs)
    assert claim["verdict"]["state"] == "does not hold"
    f = claim["rows"][1]["finite"]["neo_hookean"]
    assert f["ratio"]["value"] is None and "h2" in f["ratio"]["reason"]
    assert [d["what"] for d in claim["dropped"]] == ["finite row unused"]


def test_claim_names_a_missing_run():
    cfg = ValidityConfig(elastic_wedge_theta=(math.pi / 10, math.pi / 5))
    recs = [r for r in _synthetic(cfg, geometry=0.02)
            if not (r["task"]["param"] == math.pi / 5 and r["task"]["level"] == "far")]
    claim = ew.claim_elastic_wedge(cfg, recs)
    assert len(claim["dropped"]) == 1 and "far" in claim["dropped"][0]["reason"]  # pi/5: no finite rows (default)
    assert claim["verdict"]["angles_tested"] == [math.pi / 10]


def test_report_claims_row_and_summary_say_the_verdict(tmp_path):
    import json

    from workbench.reports.paper_claims import _elastic_wedge_claim, _stress_claim
    from workbench.reports.summary import trust_markdown
    from workbench.studies.config import to_json
    from workbench.studies.validity_report import report_markdown

    cfg = ValidityConfig(elastic_wedge_theta=(math.pi / 10, math.pi / 5),
                         elastic_wedge_finite_theta=(math.pi / 10, math.pi / 5))
    claim = ew.claim_elastic_wedge(cfg, _synthetic(cfg, geometry=0.0175))
    claim.pop("dropped")
    data = json.loads(json.dumps({"config": to_json(cfg), "summary": {"runs": 1, "failed": 0, "points": 0,
                                                                      "dropped": 0, "wall_time_s": 1.0, "workers": 2,
                                                                      "cpu_count": 2},
                                  "points": [], "dropped": [], "claim": {"rows": [], "verdict": None},
                                  "claim_elastic_wedge": claim, "runs": []}, default=float))
    md = report_markdown(data)
    assert "elastic wedge, same material" in md and "**Verdict: does not hold" in md and "| 0.1 pi | 1.75 % |" in md
    assert "### The shaped wedge at finite strain" in md and "| 0.1 pi | neo_hookean | 1.0300 +- 0.0e+00 |" in md
    assert "**Of 2 (angle, law) rows, 2 have a value; at 2 of them" in md
    assert "A rigid wedge: the traction along the face normal" in md
    (tmp_path / "validity").mkdir()
    (tmp_path / "validity" / "validity.json").write_text(json.dumps(data))
    row = _elastic_wedge_claim(tmp_path)
    assert row.verdict.startswith("not confirmed") and "1.75 % +- 0.00 %" in row.ours and "3.50 %" in row.ours
    assert _stress_claim(tmp_path).claim.startswith("Not the paper's problem: a RIGID wedge")
    assert "as it states it: does not hold" in "\n".join(trust_markdown(tmp_path))


def test_the_rigid_claim_ignores_the_elastic_wedge_runs():
    """Both parts' records carry ``stresses`` (of different shapes): the rigid wedge's claim reads only its own
    (a make validity run once failed there, after all its runs)."""
    from workbench.studies import validity_assemble as va

    cfg = ValidityConfig(elastic_wedge_theta=(math.pi / 10, math.pi / 5))
    recs = _synthetic(cfg, geometry=0.02)
    for r in recs:
        r["task"] |= {"traction": "halfplane", "kinematics": "small"}
    # a rigid obstacle-traction run at pi/10 (the elastic records must not stand in for its halfplane twin)
    z = [0.25] * 3
    recs.append({"task": {"scene": "wedge", "param": math.pi / 10, "traction": "obstacle", "level": "h2"},
                 "converged": True, "P": 1.0, "stresses": {"x": [0.0] * 3, "z": z, "sxx": z, "szz": z, "sxz": z}})
    rigid = va.claim_points(cfg, recs)
    assert rigid["verdict"] is None and all("reason" in r["h2"] for r in rigid["rows"])
