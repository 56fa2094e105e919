"""Property-based fuzzing of the command line (issues 15, 23, 28): any arguments end in exit 0, or exit 2 with one
line, and nothing the workbench did not write is ever changed.

Requirement (``make test``: 300 examples, ``make fuzz``: 3000): ``workbench`` with a random subcommand and random
options and values (numbers, NaN/inf, unicode, path-like case names and ``--out`` folders, among them a file, a
folder under a file, a missing parent and a folder no file can be created in) returns 0, or 2 with exactly one
line on stderr that starts with ``error:``; never a traceback.

Collisions (issues 23 and 35): each example plants some of a user's own files and folders in the output folder (a
folder named like a real case, ``logs``, ``analytic``, ``ci``, ``report.md``, ``ci_report.html``, results of an
older workbench, a ``mesh_cache`` that is a symlink out of it or a user's unmarked one holding a file of the cache's
name, ``score_hertz_cylinder`` and ``export_hertz_cylinder``, an empty folder named like a dead process's staging
folder) and writes a case file whose ``[case] name`` and variant labels collide with them, with reserved names, with
the source tree, or with each other; ``--out`` and ``WORKBENCH_RESULTS`` take the checkout, its ``cases/``, the
folder above it, the home folder, a user's folder, or the folder holding the case file. The checkout they take is a
copy of its layout in the sandbox (the guards are pointed at it, and ``HOME`` at a sandbox folder), so a guard that
fails can never write into the real checkout or home; ``/`` is left to ``tests/test_output_safety.py``, with a case
file the schema refuses after the guard. Before and after each command the sandbox, the checkout (its files and
``results/``) and the working directory pytest started in are snapshotted (paths and SHA-256): on exit 2 nothing
changed anywhere; on exit 0 every change lies in a part of the output folder the workbench owned (its marker) and
that it owned before the run, never in a parent of ``--out``; a previous result folder stays byte-identical unless
its own case ran.

The commands are ``run``, ``validate``, ``mesh``, ``report``, ``ci``, ``score`` (a small Hertz level, or a missing
file) and ``export``. The computing steps are replaced by recorders that write where the real ones would, with the
real writers (``atomic_dir``, ``write_root_text``; export's mesh into the mesh cache; score writes its real files
but an empty picture): what is fuzzed is the argument handling and the ownership checks. Nothing is
mounted: as root, the folder no file can be created in is a procfs folder; the read-only tmpfs is tested by
``tests/test_output_safety.py`` in a private mount namespace.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from fuzz_support import changed, examples, one_error_line, outside_changes, owned_change, ownership, snapshot
from hypothesis import event, given
from hypothesis import strategies as st
from probe_cases import PROBE_BLOCK

import workbench.paths as paths_module
import workbench.pipeline.ci as ci_module
import workbench.pipeline.run_case as run_case_module
import workbench.reports.summary as summary_module
from cases.schema import RESERVED_NAMES, label_folder
from workbench.atomic import atomic_dir, write_json, write_root_text, write_text
from workbench.cli import main
from workbench.owned import ensure_dir, make_dirs

CASE_ARGS = ["hertz_cylinder", "wedge", "no_such_case", "../../escaped", "sub/dir", "/etc/passwd", "x" * 300, "ü",
             "", "-", "--", "probe.toml", "cases/wedge.toml", "../cases/hertz_cylinder.toml", "..", ".",
             "case.toml", "case.toml", "proj/probe.toml", "out/previous/c.toml", "twin.toml"]
OUT_ARGS = ["out", "out/sub", "../out2", "../../out3", "a file", "a file/x", "missing/parent/x", "readonly",
            "readonly/new", "/dev/null/x", "ü/ñ", "x" * 300, "", ".",
            # collisions: the source tree (a copy of its layout in the sandbox, see _plant), the home folder, a user's
            # folders, the folder holding a case file
            "@checkout", "@checkout/cases", "@checkout/fem/new", "@checkout/..", "@checkout/.git", "@checkout/results",
            "~", "~/new", "out/hertz_cylinder", "out/previous", "out/logs", "out/mesh_cache", "proj", "out"]
# [case] name of the generated case file: fine, reserved, a user's folder, a source folder, not a path component
NAMES = ["probe", "probe", "previous", "hertz_cylinder", "proj", "wedge", "mesh_cache", "analytic", "logs", "ci",
         "report", "convergence", "validity", "Logs", "cases", "fem", "workbench", "results", ".hidden", "a/b", "..",
         "-", "x" * 65, "score_hertz_cylinder", "export_probe", "External_ccx_x"]
# variant labels of the generated case file: distinct, colliding folders, path-like
LABELS = [(), ("a/b", "a_b"), ("..",), (".", ".."), ("x", "x"), ("ü", "é"), ("theta=pi/20", "theta_pi_20"),
          ("small", "convective"), ("../../up",), ("a" * 64,)]
# a user's own files and folders planted in the sandbox (each example plants some)
USER = ("case_dir", "logs_dir", "report", "ci_report", "analytic", "mesh_link", "ci_dir", "old_results",
        "owned_report", "proj", "score_dir", "export_dir", "staging_like", "mesh_user")
NUMBERS = st.one_of(st.floats(allow_nan=True, allow_infinity=True).map(repr), st.integers().map(str),
                    st.sampled_from(["0", "1", "0.1", "1.5", "-1", "nan", "inf", "1e300", "abc", ""]))
OPTION = st.one_of(
    st.tuples(st.just("--out"), st.sampled_from(OUT_ARGS)),
    st.tuples(st.just("--h-contact"), NUMBERS),
    st.tuples(st.sampled_from(["--ci", "--json", "--help-me", "-x", "--out="]), st.none()),
    st.tuples(st.sampled_from(CASE_ARGS + [""]), st.none()),
    st.tuples(st.text(max_size=12), st.none()),
)
ANY = st.tuples(st.sampled_from(["run", "validate", "mesh", "report", "ci", "list", "bogus", "", "--out", "score",
                                 "export"]),
                st.lists(OPTION, max_size=4))
# mostly well-formed: a subcommand, a case (a real one or a generated file) where it takes one, maybe a second case,
# an output folder (good or bad), maybe --h-contact
_CASE = st.sampled_from(["hertz_cylinder", "wedge", "case.toml", "case.toml", "proj/probe.toml", "out/previous/c.toml"])
_MORE = st.lists(st.one_of(
    st.tuples(st.just("--out"), st.one_of(st.sampled_from(["out", "out2", "out/previous", "~/new"]),
                                        st.sampled_from(OUT_ARGS))),
    st.tuples(st.just("--h-contact"), st.sampled_from(["0.2", "0.5", "1e-300", "nan"])),
    st.tuples(st.sampled_from(["twin.toml", "concave_symmetric"]), st.none())), max_size=2, unique_by=lambda t: t[0])
_HEAD = {"score": lambda case: [("hertz_cylinder" if case.startswith("hertz") else case, None), ("level.csv", None)],
         "export": lambda case: [("hertz_cylinder" if case.startswith("hertz") else case, None), ("--format", "json")]}
WELL_FORMED = st.builds(
    lambda cmd, case, more: (cmd, ([(case, None)] if cmd in ("run", "validate", "mesh") else _HEAD[cmd](case)
                                   if cmd in _HEAD else [])
                             + [m for m in more if cmd == "run" or m[0] == "--out"]),
    st.sampled_from(["run", "run", "run", "validate", "mesh", "report", "report", "ci", "score", "score", "export",
                     "export"]), _CASE, _MORE)
ARGV = st.one_of(ANY, WELL_FORMED, WELL_FORMED)
SCENE = st.fixed_dictionaries({
    "name": st.one_of(st.sampled_from(NAMES), st.sampled_from(RESERVED_NAMES)),
    "twin": st.sampled_from(NAMES[:6]),  # the [case] name of a second case file (twin.toml)
    "labels": st.sampled_from(LABELS),
    "user": st.lists(st.sampled_from(USER), unique=True, max_size=3),
    "results": st.one_of(st.just("out"), st.sampled_from(["out", "home", "checkout", "cases", "above", "out/logs",
                                                          "proj"])),
})


def _flatten(cmd, opts) -> list[str]:
    argv = [cmd] if cmd else []
    for opt, value in opts:
        argv += [opt] if value is None else [opt, value]
    return argv


def _case_text(name: str, labels: tuple[str, ...]) -> str:
    text = PROBE_BLOCK.replace('name = "probe"', f"name = {name!r}".replace("'", '"'))
    return text + "".join(f'[[variant]]\nlabel = "{lb}"\n' for lb in labels)


@pytest.fixture(scope="module")
def readonly_dir(tmp_path_factory):
    """A folder in which no file can be created, without mounting anything: mode 0555 (non-root; root ignores mode
    bits), else a procfs folder (root)."""
    if os.geteuid() == 0:
        yield Path("/proc/self/fdinfo")
        return
    d = tmp_path_factory.mktemp("ro")
    d.chmod(0o555)
    yield d
    d.chmod(0o755)


@pytest.fixture
def recorders(monkeypatch):
    calls = []

    def fake_run_case(case, *, paths, h_contact=None, ci=False, pictures=True):
        calls.append(case.name)
        ensure_dir(paths.mesh_cache, kind="mesh_cache")
        with atomic_dir(paths.case(case.name)) as stage:
            write_json(stage / "metrics.json", {"case": case.name})
            for run in case.runs():
                write_json(stage / "vtk" / label_folder(run.label) / "frames.json", {})
        return {"pass": True}

    def fake_run_ci(paths, *, cases=None, pictures=True):
        ensure_dir(paths.ci.root, kind="ci", kinds=("ci",))
        write_root_text(paths.root, "ci_report.md", "# CI\n")
        write_root_text(paths.root, "ci_report.html", "<p>CI</p>\n")
        return 0

    def fake_summary(root):
        write_root_text(root, "report.md", "# summary\n")
        write_root_text(root, "report.html", "<p>summary</p>\n")
        for twin in ("analytic/convective.md", "ci_report.md"):
            if (Path(root) / twin).is_file():
                html = Path(root) / twin.replace(".md", ".html")
                (write_root_text(root, html.name, "<p/>") if html.parent == Path(root) else write_text(html, "<p/>"))

    monkeypatch.setattr(run_case_module, "run_case", fake_run_case)
    monkeypatch.setattr(ci_module, "run_ci", fake_run_ci)
    monkeypatch.setattr(summary_module, "write_summary", fake_summary)
    import workbench.pipeline.case_mesh as case_mesh_module

    def fake_case_meshes(case, *, mesh_cache, comm, h_contact=None, stats_dir=None):
        return {}

    monkeypatch.setattr(case_mesh_module, "case_meshes", fake_case_meshes)
    import workbench.external.export as export_module
    import workbench.external.score as score_module

    def fake_export_case(case_name, *, fmt, h_contact, folder, mesh_cache, approach=None):
        from meshes.cache import make_cache_dir

        calls.append(f"export {case_name}")
        make_cache_dir(mesh_cache)
        (Path(mesh_cache) / "export_hertz_cylinder_base-7b6bf480fef259fa.msh").write_text("$MeshFormat\n")
        (Path(folder) / f"{Path(case_name).stem}_h0.1.{fmt}").write_text("{}\n")
        return [Path(folder) / f"{Path(case_name).stem}_h0.1.{fmt}"]

    monkeypatch.setattr(export_module, "export_case", fake_export_case)
    monkeypatch.setattr(score_module, "_plot", lambda score, results, path, fem=None: Path(path).write_bytes(b""))
    return calls


SOURCE = ("cases", "fem", "meshes", "analytic", "workbench", "tests", "docs", ".git")
LEVEL = "x_mm,p_MPa\n" + "".join(f"{0.05 * i!r},{5770.0 * max(0.0, 1 - (0.05 * i / 0.5) ** 2) ** 0.5!r}\n"
                                  for i in range(-16, 17))  # one Hertz level of hertz_cylinder (a = 0.5 mm)


def _plant(sandbox: Path, work: Path, scene: dict) -> None:
    """The user's files and folders, a previous result of the workbench, the case files, and the layout of the
    checkout (its source folders, each with a file; the guards are pointed at it, so a failing guard can never
    write into the real checkout, which is snapshotted all the same)."""
    for name in SOURCE:
        (sandbox / "checkout" / name).mkdir(parents=True)
        (sandbox / "checkout" / name / "source.py").write_text(f"# {name}\n")
    (sandbox / "checkout" / "README.md").write_text("the project\n")
    out = work / "out"
    out.mkdir(parents=True)
    make_dirs(out / "previous", kind="case")  # a previous result (the workbench's)
    (out / "previous" / "metrics.json").write_text('{"previous": true}\n')
    (work / "a file").write_text("not a folder\n")
    (work / "notes.txt").write_text("the user's notes in the working directory\n")
    (sandbox / "home").mkdir()
    (sandbox / "home" / "notes.txt").write_text("home\n")
    user = set(scene["user"])
    files = {"case_dir": ["hertz_cylinder/notes.txt"], "logs_dir": ["logs/notes.txt"],
             "report": ["report.md", "report.html"], "ci_report": ["ci_report.html"],
             "analytic": ["analytic/convective.md", "analytic/convective.html"], "ci_dir": ["ci/notes.txt"],
             "old_results": ["wedge/metrics.json"]}
    for key, rels in files.items():
        if key in user:
            for rel in rels:
                (out / rel).parent.mkdir(parents=True, exist_ok=True)
                (out / rel).write_text(f"the user's {rel}\n")
    if "mesh_link" in user:
        (sandbox / "elsewhere").mkdir()
        (sandbox / "elsewhere" / "keep.msh").write_text("a mesh outside --out\n")
        (out / "mesh_cache").symlink_to(sandbox / "elsewhere")
    if "owned_report" in user and "report" not in user:
        write_root_text(out, "report.md", "# an earlier summary\n")
    (work / "case.toml").write_text(_case_text(scene["name"], scene["labels"]))
    (work / "twin.toml").write_text(_case_text(scene["twin"], ()))
    (out / "previous" / "c.toml").write_text(_case_text("previous", ()))
    if "score_dir" in user:
        (out / "score_hertz_cylinder").mkdir()
        (out / "score_hertz_cylinder" / "score.json").write_text("the user's\n")
    if "export_dir" in user:
        (out / "export_hertz_cylinder").mkdir()
        (out / "export_hertz_cylinder" / "hertz_cylinder_h0.1.json").write_text("the user's\n")
    if "staging_like" in user:  # an empty folder of the user's whose name matches a dead process's staging folder
        (out / ".score_hertz_cylinder.staging.4194999.mine").mkdir()
    if "mesh_user" in user and "mesh_link" not in user:
        (out / "mesh_cache").mkdir()
        (out / "mesh_cache" / "export_hertz_cylinder_base-7b6bf480fef259fa.msh").write_text("the user's mesh\n")
    (work / "level.csv").write_text(LEVEL)
    if "proj" in user:
        (work / "proj").mkdir()
        (work / "proj" / "probe.toml").write_text(_case_text("proj", ()))
        (work / "proj" / "notes.txt").write_text("beside the case file\n")


@pytest.fixture(scope="module", autouse=True)
def outside_snapshot():
    """The checkout and the working directory pytest started in, snapshotted before the first example."""
    outside_changes(reset=True)


@examples(300)
@given(argv=ARGV, scene=SCENE)
def test_any_command_line_ends_in_0_or_one_line_2(argv, scene, tmp_path_factory, readonly_dir, recorders, capsys,
                                                  monkeypatch):
    sandbox = tmp_path_factory.mktemp("fuzz_cli")
    work = sandbox / "a" / "b"
    _plant(sandbox, work, scene)
    (work / "readonly").symlink_to(readonly_dir)
    monkeypatch.chdir(work)
    monkeypatch.setenv("HOME", str(sandbox / "home"))
    checkout = sandbox / "checkout"
    monkeypatch.setattr(paths_module, "PROJECT_ROOT", checkout)
    results = {"out": work / "out", "home": sandbox / "home", "checkout": checkout, "cases": checkout / "cases",
               "above": sandbox, "out/logs": work / "out" / "logs", "proj": work / "proj"}[scene["results"]]
    monkeypatch.setenv("WORKBENCH_RESULTS", str(results))
    argv = (argv[0], [(o, v.replace("@checkout", str(checkout)) if v else v) for o, v in argv[1]])
    args = _flatten(*argv)
    outs = [v for o, v in argv[1] if o == "--out" and v is not None]
    root = (work / Path(outs[-1]).expanduser()).resolve() if outs else results.resolve()
    before, own_before = snapshot(sandbox), ownership(root)
    recorders.clear()
    try:
        code = main(args)
    except SystemExit as exc:  # argparse: --help (0) or a usage error (2)
        code = exc.code
    out, err = capsys.readouterr()
    event(f"exit {code}")
    event(f"{args[0] if args else '-'}: exit {code}")
    if args[:1] == ["run"] and "case.toml" in args:
        event(f"run case.toml named {'a reserved name' if scene['name'].lower() in RESERVED_NAMES else 'otherwise'}: "
              f"exit {code}")
    assert code in (0, 2), (args, code, err)
    assert "Traceback" not in err
    diff = changed(before, snapshot(sandbox)) | outside_changes()  # the checkout and start directory: never
    if code == 2:
        assert one_error_line(err), (args, err)
        assert not diff, (args, diff)
        return
    assert not [n for n in recorders if n.lower() in RESERVED_NAMES], recorders  # no case takes a reserved name
    # a run that wrote used an output folder that is not the home folder, the checkout, above it or in its source
    if diff:
        home = (sandbox / "home").resolve()
        inside = checkout in root.parents and root.relative_to(checkout).parts[0] != "results"
        assert not (root in (home, checkout) or root in checkout.parents or inside), (args, scene, root)
    # every change lies in a part of the output folder the workbench owns (and owned before), never above it
    own_after = ownership(root)
    bad = sorted(d for d in diff if not owned_change(d, root, own_before, own_after))
    assert not bad, (args, scene, bad)
    previous = work / "out" / "previous"
    if "previous" not in recorders and root != previous and previous not in root.parents:
        assert not any(d.startswith(str(previous)) for d in diff), diff
