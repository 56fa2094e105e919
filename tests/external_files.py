"""External result files shared by the score tests (tests/test_fuzz_external.py, tests/test_issue35_reproducers.py):
a small CalculiX .frd and VTK .vtp, the Hertz levels of hertz_cylinder as csv, and a zlib-compressed .vtp."""

from __future__ import annotations

import base64
import struct
import zlib
from pathlib import Path

import numpy as np

from analytic import hertz as hz
from analytic import materials

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

DISP = """    1PSTEP                         2           1           1
  100CL  101 1.00000E+00           3                     0    1           1
 -4  DISP        4    1
 -5  D1          1    2    1    0
 -5  D2          1    2    2    0
 -5  D3          1    2    3    0
 -5  ALL         1    2    0    0    1ALL
 -1         1 0.00000E+00-1.00000E-03 0.00000E+00
 -1         2 1.00000E-05-9.00000E-04 0.00000E+00
 -1         3 2.00000E-05-5.00000E-04 0.00000E+00
 -3
"""
"""A DISP block as CalculiX writes it (``ALL`` is computed by cgx: no value in the records), to insert before
FRD's `` 9999``."""

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


def with_disp(frd: str = FRD) -> str:
    """``frd`` with :data:`DISP` before its end."""
    return frd.replace(" 9999\n", DISP + " 9999\n")


def hertz_levels(folder: Path, *, hs=(0.04, 0.02, 0.01), delta: float = -0.005, c: float = -5.0,
                 scale_x: float = 1.0, scale_p: float = 1.0, load: bool = True, names=None) -> list[str]:
    """Hertz pressures of hertz_cylinder (a = 0.5 mm) sampled at spacing h, peak scaled by 1 + delta + c h^2, one
    csv per h (positions times ``scale_x``, pressures and load times ``scale_p * scale_x``)."""
    E_star = materials.plane_strain_modulus(210000.0, 0.3)
    P = hz.hertz_load_from_half_width(0.5, 10.0, E_star)
    p0 = hz.hertz(P, 10.0, E_star).p0
    files = []
    for i, h in enumerate(hs):
        n = int(round(0.8 / h))
        x = np.arange(-n, n + 1) * h
        p = p0 * (1 + delta + c * h**2) * np.sqrt(np.clip(1 - (x / 0.5) ** 2, 0, None))
        f = folder / (names[i] if names else f"level_{h}.csv")
        head = "x_mm,p_MPa" + (",P_N_per_mm" if load else "")
        rows = [f"{xi * scale_x!r},{pi * scale_p!r}" + (f",{P * scale_p * scale_x!r}" if load else "")
                for xi, pi in zip(x.tolist(), p.tolist(), strict=True)]
        f.write_text("\n".join([head, *rows]) + "\n")
        files.append(str(f))
    return files


def zlib_vtp(*, points: int, declared_points: int | None = None, zeros: int = 0) -> str:
    """A .vtp whose point coordinates are one zlib-compressed binary block (UInt64 header): ``points`` points on
    y = 0 (x = 0.1 i), a pressure field of ascii values; ``zeros`` bytes of zeros appended to the compressed data
    (a zlib bomb: it declares and inflates to that many more bytes); ``declared_points``: the Piece's count."""
    n = declared_points if declared_points is not None else points
    coords = np.zeros((points, 3))
    coords[:, 0] = 0.1 * np.arange(points)
    raw = coords.astype("<f8").tobytes() + b"\0" * zeros
    comp = zlib.compress(raw, 9)
    header = struct.pack("<4Q", 1, len(raw), len(raw), len(comp))
    text = base64.b64encode(header).decode() + base64.b64encode(comp).decode()
    p = " ".join(["5000", "3000"] + ["0"] * (n - 2))
    return (f'<?xml version="1.0"?>\n<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" '
            f'header_type="UInt64" compressor="vtkZLibDataCompressor">\n<PolyData>\n<Piece NumberOfPoints="{n}">\n'
            f'<PointData>\n<DataArray type="Float64" Name="p_MPa" NumberOfComponents="1" format="ascii">{p}'
            '</DataArray>\n</PointData>\n<Points>\n<DataArray type="Float64" Name="Points" NumberOfComponents="3" '
            f'format="binary">{text}</DataArray>\n</Points>\n</Piece>\n</PolyData>\n</VTKFile>\n')
