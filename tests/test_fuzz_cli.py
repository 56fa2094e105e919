"""Property-based fuzzing of the command line (issue 15): any arguments end in exit 0, or exit 2 with one line.

Requirement (``make test``: 300 examples, ``make fuzz``: 3000): ``workbench`` with a random subcommand and random
options and values (numbers, NaN/inf, unicode, path-like case names and ``--out`` folders, among them a file, a
folder under a file, a missing parent and, when one can be made, a read-only folder) returns 0, or 2 with exactly
one ``error:`` line on stderr; never a traceback; nothing is written outside the output folder it was given, and
a previous result folder stays byte-identical. The computing steps are replaced by recorders that write where the
real ones would (inside ``paths.case`` / the output folder), so what is fuzzed is the argument handling.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from fuzz_support import changed, examples, one_error_line, tree
from hypothesis import event, given
from hypothesis import strategies as st

import workbench.pipeline.ci as ci_module
import workbench.pipeline.run_case as run_case_module
import workbench.reports.summary as summary_module
from workbench.atomic import atomic_dir, write_json
from workbench.cli import main

CASE_ARGS = ["hertz_cylinder", "wedge", "no_such_case", "../../escaped", "sub/dir", "/etc/passwd", "x" * 300, "ü",
             "", "-", "--", "probe.toml", "cases/wedge.toml", "../cases/hertz_cylinder.toml", "..", "."]
OUT_ARGS = ["out", "out/sub", "../out2", "../../out3", "a file", "a file/x", "missing/parent/x", "readonly",
            "readonly/new", "/dev/null/x", "ü/ñ", "x" * 300, "", "."]
NUMBERS = st.one_of(st.floats(allow_nan=True, allow_infinity=True).map(repr), st.integers().map(str),
                    st.sampled_from(["0", "1", "0.1", "1.5", "-1", "nan", "inf", "1e300", "abc", ""]))
OPTION = st.one_of(
    st.tuples(st.just("--out"), st.sampled_from(OUT_ARGS)),
    st.tuples(st.just("--h-contact"), NUMBERS),
    st.tuples(st.sampled_from(["--ci", "--json", "--help-me", "-x", "--out="]), st.none()),
    st.tuples(st.sampled_from(CASE_ARGS + [""]), st.none()),
    st.tuples(st.text(max_size=12), st.none()),
)
ANY = st.tuples(st.sampled_from(["run", "validate", "mesh", "report", "ci", "list", "bogus", "", "--out"]),
                st.lists(OPTION, max_size=4))
# mostly well-formed: a subcommand, a real case and an output folder (good or bad), maybe --h-contact
WELL_FORMED = st.tuples(
    st.sampled_from(["run", "validate", "mesh", "report", "ci"]),
    st.tuples(st.tuples(st.sampled_from(["hertz_cylinder", "wedge", "concave_symmetric"]), st.none()),
              st.tuples(st.just("--out"), st.sampled_from(OUT_ARGS)),
              st.tuples(st.just("--h-contact"), NUMBERS)).map(list).flatmap(
                  lambda opts: st.lists(st.sampled_from(opts), min_size=1, max_size=3, unique=True)))
ARGV = st.one_of(ANY, WELL_FORMED)


def _flatten(cmd, opts) -> list[str]:
    argv = [cmd] if cmd else []
    for opt, value in opts:
        argv += [opt] if value is None else [opt, value]
    return argv


@pytest.fixture(scope="module")
def readonly_dir(tmp_path_factory):
    """A real read-only folder: a read-only tmpfs (root ignores mode bits), else mode 0555 (non-root)."""
    d = tmp_path_factory.mktemp("ro")
    if os.geteuid() == 0:
        if os.system(f"mount -t tmpfs -o ro,size=64k tmpfs {d} 2>/dev/null") != 0:
            pytest.skip("running as root without permission to mount a read-only tmpfs: no read-only folder to test")
        yield d
        os.system(f"umount {d}")
    else:
        d.chmod(0o555)
        yield d
        d.chmod(0o755)


@pytest.fixture
def recorders(monkeypatch):
    def fake_run_case(case, *, paths, h_contact=None, ci=False):
        with atomic_dir(paths.case(case.name)) as stage:
            write_json(stage / "metrics.json", {"case": case.name})
        return {"pass": True}

    def fake_run_ci(paths):
        write_json(paths.ci.root / "ci_summary.json", {})
        return 0

    def fake_summary(root):
        write_json(Path(root) / "summary.json", {})

    monkeypatch.setattr(run_case_module, "run_case", fake_run_case)
    monkeypatch.setattr(ci_module, "run_ci", fake_run_ci)
    monkeypatch.setattr(summary_module, "write_summary", fake_summary)
    import workbench.pipeline.case_mesh as case_mesh_module

    def fake_case_meshes(case, *, mesh_cache, comm, h_contact=None, stats_dir=None):
        return {}

    monkeypatch.setattr(case_mesh_module, "case_meshes", fake_case_meshes)


@examples(300)
@given(argv=ARGV)
def test_any_command_line_ends_in_0_or_one_line_2(argv, tmp_path_factory, readonly_dir, recorders, capsys,
                                                  monkeypatch):
    sandbox = tmp_path_factory.mktemp("fuzz_cli")
    work = sandbox / "a" / "b"
    (work / "out" / "previous").mkdir(parents=True)
    write_json(work / "out" / "previous" / "metrics.json", {"previous": True})
    (work / "a file").write_text("not a folder\n")
    (work / "readonly").symlink_to(readonly_dir)
    monkeypatch.chdir(work)
    monkeypatch.setenv("WORKBENCH_RESULTS", str(work / "out"))
    args = _flatten(*argv)
    before = tree(sandbox)
    try:
        code = main(args)
    except SystemExit as exc:  # argparse: --help (0) or a usage error (2)
        code = exc.code
    out, err = capsys.readouterr()
    event(f"exit {code}")
    assert code in (0, 2), (args, code, err)
    assert "Traceback" not in err
    diff = changed(before, tree(sandbox))
    if code == 2:
        assert one_error_line(err), (args, err)
        assert not diff, (args, diff)
    # every write lies inside the output folder the command used (--out, else $WORKBENCH_RESULTS)
    outs = [v for o, v in argv[1] if o == "--out" and v is not None]
    root = (work / outs[-1]).resolve() if outs else (work / "out").resolve()
    for d in diff:
        p = (sandbox / d).resolve()
        assert p == root or root in p.parents or p in root.parents, (args, d)
    assert not any(d.startswith("a/b/out/previous") for d in diff), diff
