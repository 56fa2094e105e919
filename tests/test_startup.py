"""Issue 27, point 5: start-up and output of one case as a whole process.

Requirement: ``workbench run --no-pictures`` (the fast path for scripts) writes the same numbers as the default
run (``metrics.json`` equal except its times; ``pressure.csv`` and ``series.json`` byte for byte), no PNG, and
never imports matplotlib or pyvista; ``workbench ci --no-pictures`` passes it to every case; the bench section
``startup`` returns the whole-process time beside the case's own time and the warm mesh and solve, with the
ratio against the 2x target, and its report states them.
"""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
from pathlib import Path

import pytest

from workbench.reports.case_report import NO_PICTURES

ROOT = Path(__file__).resolve().parents[1]
CASE = "hertz_cylinder"
_TIME = re.compile(r"time")  # a key naming a time (as workbench.pipeline.number_classes excludes them)

# what a --no-pictures run of the case does not need, so does not import (the plots, the renders, xml.sax's
# urllib/http/ssl, scipy.integrate: the case never integrates)
UNNEEDED = ("matplotlib", "pyvista", "vtkmodules", "xml.sax", "urllib.request", "ssl", "scipy.integrate")
_FAST = (
    f"import sys\nUNNEEDED = {UNNEEDED!r}\n"
    "from workbench.cli import main\n"
    "code = main(sys.argv[1:])\n"
    "print('UNNEEDED_MODULES', sorted(m for m in UNNEEDED if m in sys.modules))\n"
    "sys.exit(code)\n"
)


def _differences(a, b, path=""):
    """Paths where ``a`` and ``b`` differ bitwise, leaving out keys that name a time."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = [] if set(a) == set(b) else [f"{path}: keys {sorted(set(a) ^ set(b))}"]
        for k in set(a) & set(b):
            if not _TIME.search(str(k)):
                out += _differences(a[k], b[k], f"{path}/{k}")
        return out
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{path}: length {len(a)} != {len(b)}"]
        return [d for i, (x, y) in enumerate(zip(a, b, strict=True)) for d in _differences(x, y, f"{path}[{i}]")]
    same = a == b or (isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b))
    return [] if same and type(a) is type(b) else [f"{path}: {a!r} != {b!r}"]


def test_no_pictures_writes_the_same_numbers_and_no_picture(tmp_path):
    full, fast = tmp_path / "full", tmp_path / "fast"
    cp = subprocess.run([sys.executable, "-m", "workbench", "run", CASE, "--ci", "--out", str(full)],
                        cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert cp.returncode == 0, cp.stderr[-2000:]
    cp = subprocess.run([sys.executable, "-c", _FAST, "run", CASE, "--ci", "--no-pictures", "--out", str(fast)],
                        cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert cp.returncode == 0, cp.stderr[-2000:]
    assert "UNNEEDED_MODULES []" in cp.stdout  # neither matplotlib nor pyvista (nor the others) was imported
    a, b = (json.loads((d / CASE / "metrics.json").read_text()) for d in (full, fast))
    assert _differences(a, b) == []
    assert a["wall_time_s"] > 0 and b["wall_time_s"] > 0  # the times exist (and differ: left out above)
    for name in ("pressure.csv", "series.json"):
        assert (full / CASE / name).read_bytes() == (fast / CASE / name).read_bytes(), name
    assert {"pressure.png", "render_base.png"} <= {p.name for p in (full / CASE).glob("*.png")}
    assert list((fast / CASE).glob("*.png")) == []
    md = (fast / CASE / "report.md").read_text()
    assert NO_PICTURES in md and ".png)" not in md and "## Checks" in md
    assert (fast / CASE / "view.py").is_file() and (fast / CASE / "report.html").is_file()
    # `workbench report` draws the pictures later from the saved files (what make run relies on)
    from workbench.reports.case_report import write_case_reports

    assert write_case_reports(fast, [CASE]) == [fast / CASE]
    assert {p.name for p in (fast / CASE).glob("*.png")} == {p.name for p in (full / CASE).glob("*.png")}
    assert NO_PICTURES not in (fast / CASE / "report.md").read_text()


def test_ci_passes_no_pictures_to_every_case(tmp_path, monkeypatch):
    import workbench.pipeline.ci as ci
    from workbench.paths import default_paths

    seen = []

    def fake_run(cmd, **_kw):
        seen.append(cmd)
        return subprocess.CompletedProcess(cmd, 0, "", "")

    monkeypatch.setattr(ci.subprocess, "run", fake_run)
    paths = default_paths(tmp_path / "out")
    ci.run_ci(paths, cases=[CASE], pictures=False)
    ci.run_ci(paths, cases=[CASE])
    assert [c[-1] for c in seen] == ["--no-pictures", str(paths.ci.root)]


def test_run_refuses_a_value_for_no_pictures(tmp_path):
    cp = subprocess.run([sys.executable, "-m", "workbench", "run", CASE, "--no-pictures=yes", "--out",
                         str(tmp_path / "o")], capture_output=True, text=True, timeout=120)
    assert cp.returncode == 2 and "--no-pictures" in cp.stderr and len(cp.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "o").exists()


def test_bench_startup_section_reports_both_times_and_the_ratio():
    from workbench.studies.bench_report import to_markdown
    from workbench.studies.bench_startup import TARGET_RATIO, startup_cost

    lines = []
    st = startup_cost(CASE, repeats=1, progress=lines.append)
    assert set(st["modes"]) == {"full", "no_pictures"} and len(lines) == 3
    ch = st["changed_material"]  # issue 34: another E reuses every compiled form (the time ratio is load: reported)
    assert ch["new_modules"] == 0 and ch["pass"] and ch["case"] == f"{CASE}_changed_material", ch
    assert ch["ratio"] == pytest.approx(ch["process_s"]["all"][0] / ch["original_process_s"]["all"][0], rel=1e-12)
    ms = st["mesh_solve_s"]["best"]
    assert ms > 0 and st["mesh_solve_s"]["first_in_process"] > 0  # which is larger is load, not code
    for mode, r in st["modes"].items():
        proc, case_s = r["process_s"]["all"][0], r["case_s"]["all"][0]
        assert 0 < case_s < proc, mode  # the case is a part of its process
        assert r["ratio_to_case"] == pytest.approx(proc / case_s, rel=1e-12)
        assert r["ratio_to_mesh_solve"] == pytest.approx(proc / ms, rel=1e-12)
        assert r["target_met"] == (r["ratio_to_case"] <= TARGET_RATIO) and r["pass"] is True
    assert st["modes"]["no_pictures"]["pngs"] == [] and "pressure.png" in st["modes"]["full"]["pngs"]
    assert st["import_floor_s"]["best"] > 0 and st["floor_ratio"] > 1
    data = {"config": None, "bench_wall_time_s": 1.0, "cpu_count": 2, "load_avg_start": [0.0, 0.0, 0.0],
            "load_avg_end": [0.0, 0.0, 0.0], "startup": st}
    md = to_markdown(data)
    assert "## Start-up and output" in md and f"x its case time | {st['modes']['full']['ratio_to_case']:.1f} x" in md
    assert f"whole CI process (`--no-pictures` (scripts)) <= {TARGET_RATIO:g} x its case time" in md
    assert "**A changed material compiles nothing**" in md and "added 0 FFCx modules" in md


def test_vtk_quoteattr_is_saxutils_quoteattr():
    import itertools
    from xml.sax.saxutils import quoteattr as reference

    from fem.vtk_files import quoteattr

    chars = ("a", "&", "<", ">", '"', "'", "\n", "\r", "\t", "é")
    for k in range(4):
        for t in itertools.product(chars, repeat=k):
            assert quoteattr("".join(t)) == reference("".join(t)), t


def test_fast_exit_only_where_nothing_can_be_lost():
    from workbench.fast_exit import fast_exit_allowed

    class _Comm:
        def __init__(self, n):
            self.n = n

        def Get_size(self):
            return self.n

    class _MPI:
        def __init__(self, n):
            self.COMM_WORLD = _Comm(n)

    ok = {"PETSC_OPTIONS": "-no_signal_handler"}
    assert fast_exit_allowed("run", environ=ok, modules={"mpi4py.MPI": _MPI(1)})
    assert fast_exit_allowed("run", environ={}, modules={})
    assert not fast_exit_allowed("ci", environ=ok, modules={})  # only `run`
    assert not fast_exit_allowed(None, environ=ok, modules={})
    assert not fast_exit_allowed("run", environ=ok, modules={"mpi4py.MPI": _MPI(2)})  # every rank must finalize
    assert not fast_exit_allowed("run", environ={**ok, "PMI_RANK": "0"}, modules={})  # under mpiexec -n 1
    assert not fast_exit_allowed("run", environ=ok, modules={"mpi4py.futures": object()})
    assert not fast_exit_allowed("run", environ=ok, modules={"coverage": object()})
    assert not fast_exit_allowed("run", environ={"PETSC_OPTIONS": "-no_signal_handler -log_view"}, modules={})
    assert not fast_exit_allowed("run", environ={"WORKBENCH_FULL_EXIT": "1"}, modules={})


def test_fast_exit_keeps_the_exit_code_and_runs_atexit(tmp_path):
    script = (
        "import atexit, sys\n"
        "from pathlib import Path\n"
        f"atexit.register(lambda: Path({str(tmp_path / 'atexit_ran')!r}).write_text('yes'))\n"
        f"sys.argv = ['workbench', 'run', 'no_such_case', '--out', {str(tmp_path / 'o')!r}]\n"
        "from workbench.cli import main\n"
        "main()\n"
        "print('AFTER_MAIN')\n"
    )
    env = {k: v for k, v in __import__("os").environ.items() if k != "WORKBENCH_FULL_EXIT"}
    cp = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, env=env, capture_output=True, text=True,
                        timeout=300)
    assert cp.returncode == 2 and "no_such_case" in cp.stderr  # bad input: exit 2, one line
    assert "AFTER_MAIN" not in cp.stdout  # the process ended inside main(), without the teardown
    assert (tmp_path / "atexit_ran").read_text() == "yes"  # the Python atexit handlers still ran
