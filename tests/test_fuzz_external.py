"""Property-based fuzzing of external result files (issue 26): ``workbench score`` on any csv or .frd text ends
in exit 0 (score written) or exit 2 with exactly one ``error:`` line naming the file, and nothing written.

Requirement (``make test``: 60 examples, ``make fuzz``: 600): random headers (right, wrong, missing columns),
numbers (NaN, inf, negative, text), loads <= 0, single samples, ragged rows, and random truncations of a
well-formed .frd.
"""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

from fuzz_support import examples, one_error_line
from hypothesis import given
from hypothesis import strategies as st

from workbench.external.score import main as score_main

HEADERS = st.sampled_from([["x_mm", "p_MPa"], ["x_mm", "p_MPa", "P_N_per_mm"], ["x_mm", "p_MPa", "h_mm"],
                           ["coordinate_mm", "p_fem_MPa", "run"], ["x", "q"], ["p_MPa"], [], ["x_mm", "x_mm"]])
CELL = st.one_of(st.floats(allow_nan=True, allow_infinity=True, width=32).map(repr),
                 st.sampled_from(["0", "1", "-1", "0.5", "5000", "nan", "", "abc", "1e400", "base", "other"]))


def _score(tmp_path: Path, f: Path, *extra: str) -> tuple[int, str, Path]:
    out = tmp_path / "out"
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        rc = score_main(["hertz_cylinder", str(f), "--out", str(out), *extra])
    return rc, err.getvalue(), out


@examples(60)
@given(header=HEADERS, rows=st.lists(st.lists(CELL, min_size=0, max_size=4), max_size=8))
def test_any_csv_scores_or_is_one_line_exit_2(tmp_path_factory, header, rows):
    tmp = tmp_path_factory.mktemp("fz")
    f = tmp / "level.csv"
    f.write_text("\n".join(",".join(r) for r in [header, *rows]) + "\n")
    rc, err, out = _score(tmp, f)
    assert rc in (0, 2)
    if rc == 2:
        assert one_error_line(err) and str(f) in err, err
        assert not out.exists() or not any(out.iterdir())
    else:
        assert (out / "score_hertz_cylinder" / "score.json").is_file()


FRD = """    1C
    2C                             3                                     1
 -1         1 0.00000E+00 0.00000E+00 0.00000E+00
 -1         2 1.00000E-01 0.00000E+00 0.00000E+00
 -1         3 2.00000E-01 0.00000E+00 0.00000E+00
 -3
    1PSTEP                         1           1           1
  100CL  101 1.00000E+00           3                     0    1           1
 -4  CONTACT     6    1
 -5  COPEN       1    4    1    1
 -5  CSLIP1      1    4    2    2
 -5  CSLIP2      1    4    3    3
 -5  CPRESS      1    4    1    2
 -5  CSHEAR1     1    4    2    3
 -5  CSHEAR2     1    4    3    1
 -1         1 0.00000E+00 0.00000E+00 0.00000E+00 5.00000E+03 0.00000E+00 0.00000E+00
 -1         2 0.00000E+00 0.00000E+00 0.00000E+00 3.00000E+03 0.00000E+00 0.00000E+00
 -1         3 0.00000E+00 0.00000E+00 0.00000E+00 0.00000E+00 0.00000E+00 0.00000E+00
 -3
 9999
"""


def test_small_frd_is_read(tmp_path):
    f = tmp_path / "r.frd"
    f.write_text(FRD)
    rc, err, out = _score(tmp_path, f, "--format", "frd")
    assert rc == 0, err


@examples(60)
@given(cut=st.integers(min_value=0, max_value=len(FRD) - 2), junk=st.sampled_from(["", "x", " -1  ", "\n -3\n"]))
def test_truncated_frd_is_one_line_exit_2(tmp_path_factory, cut, junk):
    tmp = tmp_path_factory.mktemp("fz")
    f = tmp / "r.frd"
    f.write_text(FRD[:cut] + junk)
    rc, err, out = _score(tmp, f, "--format", "frd")
    assert rc == 2 and one_error_line(err) and str(f) in err, err
    assert not out.exists() or not any(out.iterdir())


VTP = """<?xml version="1.0"?>
<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" header_type="UInt64">
<PolyData>
<FieldData>
<DataArray type="Float64" Name="P_N_per_mm" NumberOfComponents="1" NumberOfTuples="1" format="ascii">4500</DataArray>
</FieldData>
<Piece NumberOfPoints="3" NumberOfVerts="0" NumberOfLines="0" NumberOfStrips="0" NumberOfPolys="0">
<PointData>
<DataArray type="Float64" Name="p_MPa" NumberOfComponents="1" format="ascii">5000 3000 0</DataArray>
</PointData>
<Points>
<DataArray type="Float64" Name="Points" NumberOfComponents="3" format="ascii">0 0 0 0.1 0 0 0.2 0 0</DataArray>
</Points>
</Piece>
</PolyData>
</VTKFile>
"""


def test_small_vtp_is_read(tmp_path):
    f = tmp_path / "r.vtp"
    f.write_text(VTP)
    rc, err, out = _score(tmp_path, f, "--format", "vtu")
    assert rc == 0, err


@examples(60)
@given(cut=st.integers(min_value=0, max_value=len(VTP) - 30), junk=st.sampled_from(["", "x", "<", "nan", "-1 "]))
def test_damaged_vtp_is_exit_0_or_one_line_exit_2(tmp_path_factory, cut, junk):
    tmp = tmp_path_factory.mktemp("fz")
    f = tmp / "r.vtp"
    f.write_text(VTP[:cut] + junk + VTP[cut:] if junk and cut % 2 else VTP[:cut] + junk)
    rc, err, out = _score(tmp, f, "--format", "vtu")
    assert rc in (0, 2)
    if rc == 2:
        assert one_error_line(err) and str(f) in err, err
        assert not out.exists() or not any(out.iterdir())
