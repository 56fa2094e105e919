"""Property-based fuzzing of the readers of external results (issues 26 and 35): ``workbench score`` on any csv,
.frd, .vtu/.vtp or .pvd ends in exit 0 (score written) or exit 2 with exactly one ``error:`` line naming the file;
never a traceback, never a hang, nothing written outside ``--out``.

Requirement (``make test``: 1060 examples, ``make fuzz``: ten times as many): malformed files drawn by hypothesis:

* csv: headers right, wrong, missing or repeated; cells of any float (NaN, inf, 1e300, subnormal), text, empty,
  quoted, very long (up to 200,000 characters), NUL bytes, non-UTF-8 bytes; ragged rows; repeated positions;
* frd: a well-formed CalculiX result (with a DISP block as CalculiX writes it) mutated: lines deleted,
  repeated, cut, swapped, a fixed-width field replaced (NaN, inf, blank, text, a number run into the next one), a
  component count changed, junk inserted; and its truncations;
* vtu/vtp: an ascii .vtp and a zlib-compressed binary one mutated: attributes changed (NumberOfPoints,
  NumberOfComponents, type, format, header_type, compressor), base64 corrupted, the zlib header's sizes changed
  (a bomb that declares more than it may), a DTD inserted, cut;
* pvd: DataSet entries with a good file, no file, an absolute path, ``..`` out of the folder, a symlink out of it,
  a FIFO, a missing file, several entries.

Each example runs in-process under a time limit (``LIMIT_S``: SIGALRM; a FIFO opened for reading without a writer
would block forever) in its own sandbox; the sandbox outside ``--out``, the checkout and the working directory are
snapshotted before and after. The report's picture is replaced by an empty file (what is fuzzed is the reading;
the picture is drawn by tests/test_external_score.py).
"""

from __future__ import annotations

import contextlib
import io
import os
import signal
from pathlib import Path

import pytest
from external_files import FRD, VTP, with_disp, zlib_vtp
from fuzz_support import changed, examples, one_error_line, outside_changes, snapshot
from hypothesis import event, given
from hypothesis import strategies as st

import workbench.external.score as score_module
from workbench.external.score import main as score_main

LIMIT_S = 20.0  # seconds per example (measured: 0.01-0.3 s; the limit catches a hang, not a slow example)


@contextlib.contextmanager
def time_limit(seconds: float):
    """Fail the example if it runs longer than ``seconds`` (SIGALRM interrupts a blocking open or read too)."""
    def alarm(signum, frame):
        raise TimeoutError(f"the example ran longer than {seconds} s (a hang)")

    previous = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


@pytest.fixture(scope="module", autouse=True)
def outside_snapshot():
    outside_changes(reset=True)


@pytest.fixture(autouse=True)
def no_picture(monkeypatch):
    monkeypatch.setattr(score_module, "_plot", lambda score, results, path, fem=None: Path(path).write_bytes(b""))


def _score(sandbox: Path, f: Path, *extra: str) -> tuple[int, str]:
    """``workbench score hertz_cylinder F --out <sandbox>/out`` in-process, under the time limit; checks that
    nothing outside ``--out`` changed (the sandbox, the checkout, the working directory)."""
    out = sandbox / "out"
    before = {k: v for k, v in snapshot(sandbox).items() if not k.startswith(str(out))}
    err = io.StringIO()
    with time_limit(LIMIT_S), contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        rc = score_main(["hertz_cylinder", str(f), "--out", str(out), *extra])
    after = {k: v for k, v in snapshot(sandbox).items() if not k.startswith(str(out))}
    assert not changed(before, after), changed(before, after)
    assert not outside_changes()
    return rc, err.getvalue()


def _check(rc: int, err: str, f: Path, out: Path) -> None:
    event(f"exit {rc}")
    assert rc in (0, 2), (rc, err)
    assert "Traceback" not in err
    if rc == 2:
        assert one_error_line(err) and str(f) in err, err
        assert not out.exists() or not any(p for p in out.rglob("*") if p.name != ".workbench-owned"), \
            list(out.rglob("*"))
    else:
        assert (out / "score_hertz_cylinder" / "score.json").is_file()
        assert err == "", err


# --- csv --------------------------------------------------------------------------------------------------------

HEADERS = st.sampled_from([["x_mm", "p_MPa"], ["x_mm", "p_MPa", "P_N_per_mm"], ["x_mm", "p_MPa", "h_mm"],
                           ["coordinate_mm", "p_fem_MPa", "run"], ["x_mm", "p_MPa", "weight_mm", "q_MPa"],
                           ["x", "q"], ["p_MPa"], [], ["x_mm", "x_mm"], ["root:x:0:0:root:/root:/bin/bash"],
                           ["\ufeffx_mm", "p_MPa"], ['"x_mm"', "p_MPa"]])
NUMBER = st.one_of(st.floats(allow_nan=True, allow_infinity=True).map(repr),
                   st.sampled_from(["0", "1", "-1", "0.5", "5000", "nan", "inf", "-inf", "1e300", "1e-320", "4.9e-324",
                                    "1e400", "0x10", "1_000", " 2 ", "+3"]))
CELL = st.one_of(NUMBER, NUMBER, st.sampled_from(["", "abc", "base", "other", '"1,5"', '"', "\x00", "é"]),
                 st.text(max_size=8), st.integers(1, 200_000).map(lambda n: "1" * n))
ROW = st.lists(CELL, min_size=0, max_size=5)
GOOD_ROWS = st.lists(st.tuples(st.integers(-40, 40), st.floats(0, 6000, allow_nan=False)), min_size=2, max_size=30)


def _csv_text(header, rows, good, ending, junk) -> bytes:
    lines = [",".join(header), *(",".join(r) for r in rows), *(f"{0.02 * x!r},{p!r}" for x, p in good)]
    return ending.join(lines).encode("utf-8", "surrogatepass") + junk


@examples(330)
@given(header=HEADERS, rows=st.lists(ROW, max_size=8), good=st.one_of(st.just([]), GOOD_ROWS),
       ending=st.sampled_from(["\n", "\r\n", "\r"]), junk=st.sampled_from([b"", b"\n", b"\xff\xfe", b"\x00\n"]))
def test_any_csv_scores_or_is_one_line_exit_2(tmp_path_factory, header, rows, good, ending, junk):
    box = tmp_path_factory.mktemp("fz_csv")
    f = box / "level.csv"
    f.write_bytes(_csv_text(header, rows, good, ending, junk))
    rc, err = _score(box, f)
    _check(rc, err, f, box / "out")


# --- frd --------------------------------------------------------------------------------------------------------

FIELD = st.sampled_from(["        NaN", "        inf", "           ", "       abc ", "1.00000E+03-2.0E+03",
                         "1.0E+999999", "-0.00000E+00", "12345678901234567890"])
MUTATION = st.one_of(
    st.tuples(st.just("delete"), st.integers(0, 40)),
    st.tuples(st.just("repeat"), st.integers(0, 40)),
    st.tuples(st.just("cut"), st.integers(0, 40), st.integers(0, 90)),
    st.tuples(st.just("swap"), st.integers(0, 40), st.integers(0, 40)),
    st.tuples(st.just("field"), st.integers(0, 40), st.integers(0, 6), FIELD),
    st.tuples(st.just("ncomp"), st.sampled_from(["CONTACT", "DISP"]), st.sampled_from(["    0", "   -1", "  999",
                                                                                       "    3", "   12", " abcd"])),
    st.tuples(st.just("junk"), st.integers(0, 40), st.sampled_from([" -1", " -3", " -4", " -5  X", "\x00", " 9999",
                                                                     "    2C", " -1         1"])),
)


def _mutate_frd(text: str, mutations) -> str:
    lines = text.splitlines()
    for m in mutations:
        n = len(lines)
        if not n:
            break
        kind, i = m[0], m[1] % n if isinstance(m[1], int) else 0
        if kind == "delete":
            del lines[i]
        elif kind == "repeat":
            lines.insert(i, lines[i])
        elif kind == "cut":
            lines[i] = lines[i][:m[2]]
        elif kind == "swap":
            j = m[2] % n
            lines[i], lines[j] = lines[j], lines[i]
        elif kind == "field":
            start = 13 + 12 * m[2]
            line = lines[i].ljust(start + 12)
            lines[i] = line[:start] + " " + m[3] + line[start + 12:]
        elif kind == "ncomp":
            lines = [ln[:13] + m[2] + ln[18:] if ln.startswith(" -4") and m[1] in ln else ln for ln in lines]
        elif kind == "junk":
            lines.insert(i, m[2])
    return "\n".join(lines) + "\n"


@examples(330)
@given(base=st.sampled_from([FRD, with_disp()]), mutations=st.lists(MUTATION, min_size=1, max_size=4),
       cut=st.one_of(st.none(), st.integers(0, len(with_disp()))), configuration=st.sampled_from(["reference",
                                                                                                 "current"]))
def test_any_frd_scores_or_is_one_line_exit_2(tmp_path_factory, base, mutations, cut, configuration):
    box = tmp_path_factory.mktemp("fz_frd")
    f = box / "r.frd"
    text = _mutate_frd(base, mutations)
    f.write_text(text if cut is None else text[:cut], errors="surrogateescape")
    rc, err = _score(box, f, "--format", "frd", "--configuration", configuration)
    _check(rc, err, f, box / "out")


def test_small_frd_is_read(tmp_path):
    for name, text in (("r.frd", FRD), ("d.frd", with_disp())):
        f = tmp_path / name
        f.write_text(text)
        rc, err = _score(tmp_path, f, "--format", "frd")
        assert rc == 0, err


# --- vtu / vtp ----------------------------------------------------------------------------------------------------

ATTRIBUTE = st.one_of(
    st.tuples(st.just("NumberOfPoints"), st.sampled_from(["0", "2", "3", "4", "-1", "x", "4000001", "1e3",
                                                          "99999999999999999999"])),
    st.tuples(st.just("NumberOfComponents"), st.sampled_from(["0", "1", "2", "3", "4", "-3", "x"])),
    st.tuples(st.just("type"), st.sampled_from(["Float64", "Float32", "Int8", "UInt64", "String", ""])),
    st.tuples(st.just("format"), st.sampled_from(["ascii", "binary", "appended", "raw", ""])),
    st.tuples(st.just("header_type"), st.sampled_from(["UInt32", "UInt64", "Int8"])),
    st.tuples(st.just("compressor"), st.sampled_from(["vtkZLibDataCompressor", "vtkLZ4DataCompressor", ""])),
    st.tuples(st.just("Name"), st.sampled_from(["p_MPa", "Points", "pressure", ""])),
)
VTK_MUTATION = st.one_of(
    st.tuples(st.just("attribute"), ATTRIBUTE, st.integers(0, 5)),
    st.tuples(st.just("base64"), st.integers(0, 4000), st.sampled_from(["!", "=", "A", "\n", "===="])),
    st.tuples(st.just("cut"), st.integers(0, 4000)),
    st.tuples(st.just("dtd"), st.sampled_from(['<!DOCTYPE x [<!ENTITY a "aaaaaaaaaa">]>',
                                               '<!DOCTYPE x SYSTEM "file:///etc/passwd">'])),
    st.tuples(st.just("text"), st.sampled_from(["5000 3000 0", "nan nan nan", "1 2", "1 2 3 4", "-5 0 0", "", "x y z",
                                               "1e400 0 0"])),
    st.tuples(st.just("sizes"), st.integers(0, 3), st.sampled_from([0, 1, 71, 72, 73, 2**20, 2**40, 2**63])),
)


def _mutate_vtk(text: str, mutations) -> str:
    import base64
    import re
    import struct

    for m in mutations:
        kind = m[0]
        if kind == "attribute":
            (name, value), k = m[1], m[2]
            hits = [h for h in re.finditer(rf'{name}="[^"]*"', text)]
            if hits:
                h = hits[k % len(hits)]
                text = text[:h.start()] + f'{name}="{value}"' + text[h.end():]
            elif name in ("compressor", "header_type"):
                text = text.replace("<VTKFile ", f'<VTKFile {name}="{value}" ', 1)
        elif kind == "base64":
            i = m[1] % max(len(text), 1)
            text = text[:i] + m[2] + text[i + 1:]
        elif kind == "cut":
            text = text[:m[1] % max(len(text), 1)]
        elif kind == "dtd":
            text = text.replace("<VTKFile", m[1] + "\n<VTKFile", 1)
        elif kind == "text":
            text = re.sub(r'(Name="p_MPa"[^>]*>)[^<]*', lambda mm, new=m[1]: mm.group(1) + new, text, count=1)
        elif kind == "sizes":  # one of the zlib header's four UInt64 of the binary Points array
            hit = re.search(r'(Name="Points"[^>]*format="binary">)([^<]*)', text)
            if hit:
                head = base64.b64decode(hit.group(2)[:44])
                if len(head) == 32:
                    vals = list(struct.unpack("<4Q", head))
                    vals[m[1]] = m[2]
                    new = base64.b64encode(struct.pack("<4Q", *vals)).decode() + hit.group(2)[44:]
                    text = text[:hit.start(2)] + new + text[hit.end(2):]
    return text


@examples(300)
@given(base=st.sampled_from(["ascii", "zlib"]), mutations=st.lists(VTK_MUTATION, min_size=1, max_size=3),
       suffix=st.sampled_from([".vtp", ".vtu"]))
def test_any_vtk_file_scores_or_is_one_line_exit_2(tmp_path_factory, base, mutations, suffix):
    box = tmp_path_factory.mktemp("fz_vtk")
    f = box / f"r{suffix}"
    f.write_text(_mutate_vtk(VTP if base == "ascii" else zlib_vtp(points=3), mutations))
    rc, err = _score(box, f, "--format", "vtu")
    _check(rc, err, f, box / "out")


def test_small_vtp_is_read(tmp_path):
    for name, text in (("r.vtp", VTP), ("z.vtp", zlib_vtp(points=3))):
        f = tmp_path / name
        f.write_text(text)
        rc, err = _score(tmp_path, f, "--format", "vtu")
        assert rc == 0, err


def test_a_zlib_bomb_is_refused_before_it_is_inflated(tmp_path):
    """64 MB of zeros declared by a .vtp of 3 points (about 90 KB): refused from the header, with at most a few MB
    allocated (measured with tracemalloc)."""
    import tracemalloc

    from workbench.external.results import ResultError
    from workbench.external.vtk_xml import read_vtk_result

    f = tmp_path / "bomb.vtp"
    f.write_text(zlib_vtp(points=3, zeros=64 * 2**20))
    tracemalloc.start()
    try:
        with pytest.raises(ResultError, match="refused before inflating"):
            read_vtk_result(f)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 8 * 2**20, peak


# --- pvd ----------------------------------------------------------------------------------------------------------

DATASET = st.sampled_from(["good", "none", "empty", "absolute", "up", "link_out", "fifo", "missing", "folder",
                           "itself"])


@examples(100)
@given(entries=st.lists(DATASET, min_size=0, max_size=3))
def test_any_pvd_scores_or_is_one_line_exit_2(tmp_path_factory, entries):
    box = tmp_path_factory.mktemp("fz_pvd")
    run = box / "run"
    run.mkdir()
    (run / "good.vtp").write_text(VTP)
    (box / "outside.vtp").write_text(VTP)
    (run / "link.vtp").symlink_to(box / "outside.vtp")
    os.mkfifo(run / "fifo.vtp")
    (run / "sub").mkdir()
    files = {"good": 'file="good.vtp"', "none": "", "empty": 'file=""', "absolute": f'file="{run / "good.vtp"}"',
             "up": 'file="../outside.vtp"', "link_out": 'file="link.vtp"', "fifo": 'file="fifo.vtp"',
             "missing": 'file="missing.vtp"', "folder": 'file="sub"', "itself": 'file="r.pvd"'}
    sets = "".join(f'<DataSet timestep="{i}" {files[e]}/>' for i, e in enumerate(entries))
    f = run / "r.pvd"
    f.write_text(f'<?xml version="1.0"?>\n<VTKFile type="Collection"><Collection>{sets}</Collection></VTKFile>\n')
    rc, err = _score(box, f, "--format", "vtu")
    _check(rc, err, f, box / "out")
    if entries and entries[-1] in ("absolute", "up", "link_out", "fifo", "none", "empty"):
        assert rc == 2, (entries, err)
