"""The ``two_body`` bench section (issue 24: a two-body case against a rigid case with the same dofs, side by side)
on a small mesh: both timings are there, the rigid mesh matches the two-body dofs, the ratio is theirs, and the
report names the targets. No timing is asserted (the benchmark reports times, it does not test them)."""

from __future__ import annotations

import math

import pytest

from workbench.owned import ensure_dir
from workbench.studies.bench_report import to_markdown, two_body_markdown
from workbench.studies.bench_two_body import TwoBodyBench, run_two_body_bench


@pytest.fixture(scope="module")
def section(tmp_path_factory):
    cache = ensure_dir(tmp_path_factory.mktemp("tb") / "mesh_cache", kind="mesh_cache")
    cfg = TwoBodyBench(cases=(("patch_test", 0.05),), repeats=1, mesh_cache=cache)
    return cfg, run_two_body_bench(cfg, progress=lambda _: None)


def test_both_timings_at_equal_dofs(section):
    cfg, data = section
    assert [(r["case"], r["run"]) for r in data["rows"]] == [("patch_test", "mortar"),
                                                             ("patch_test", "node-to-segment")]
    for r in data["rows"]:
        two, rigid = r["two_body"], r["rigid"]
        for side in (two, rigid, r["rigid_predictor_free"]):
            assert side["total_s"] > 0 and side["solve_s"] > 0 and side["repeats"] == 1
            assert side["lu_numeric"] >= 1 and side["lu_numeric_s"] > 0  # where a Newton iteration's cost goes
        assert rigid["ndofs"] == r["rigid_predictor_free"]["ndofs"]
        assert abs(rigid["ndofs"] / two["ndofs"] - 1.0) <= cfg.match_rtol  # dofs of the solves, not the estimate
        assert math.isclose(r["ratio_total"], two["total_s"] / rigid["total_s"])
        assert math.isclose(r["ratio_solve"], two["solve_s"] / rigid["solve_s"])
        assert r["cost_met"] == (r["ratio_total"] <= cfg.cost_target)
        assert r["newton_max"] == max(two["newton_iterations"]) and r["newton_met"] == (r["newton_max"] <= 4)
        assert rigid["h_contact"] < 0.05  # the rigid case's own level (0.05) has fewer dofs: it was refined


def test_report_lists_the_targets(section):
    _, data = section
    targets: list = []
    text = "\n".join(two_body_markdown(data, targets))
    assert "patch_test [node-to-segment]" in text
    assert len(targets) == 4 and {ok for *_, ok in targets} <= {True, False}
    assert "two-body cost <= 2 x rigid" in to_markdown({"two_body": data, "load_avg_start": [0.0]})


def test_unreachable_dofs_are_refused_in_one_line(tmp_path):
    from mpi4py import MPI

    import workbench.scenes  # noqa: F401
    from cases import load_case
    from workbench.studies.bench_two_body import match_rigid

    cache = ensure_dir(tmp_path / "mesh_cache", kind="mesh_cache")
    with pytest.raises(ValueError, match=r"no h_contact in \(0, 1\] of rigid gives 100 dofs") as err:
        match_rigid(load_case("hertz_cylinder").runs()[0], 100, name="rigid", mesh_cache=cache, comm=MPI.COMM_SELF,
                    rtol=0.03)
    assert "\n" not in str(err.value)
