"""ParaView output of a contact solution (VTK .pvd/.vtu + surface samples .vtp/.csv).

Files in ``out_dir`` (rank 0 writes the surface files; the .pvd files are parallel):

* ``displacement.pvd``: u (mm), on the solution's Lagrange space.
* ``stress.pvd``: Cauchy stress (MPa, interpolated into DG 1 tensors) and von Mises
  (MPa, same space, plane strain with sigma_zz).
* ``contact_surface.vtp``: the contact quadrature samples at their current positions with point data p
  (contact law, MPa), sigma_nn (stress-based, MPa), gap (mm), s (mm).
* ``contact_surface.csv``: the same samples as a table.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

from pathlib import Path
from typing import NamedTuple

import dolfinx
import numpy as np

from fem.elasticity import sigma, sigma_mixed, von_mises

__all__ = ["VtkFiles", "write_vtk", "write_samples_csv"]


class VtkFiles(NamedTuple):
    """Paths written by :func:`write_vtk`."""

    displacement: Path
    stress: Path
    surface_vtp: Path
    surface_csv: Path


def write_samples_csv(samples, path) -> Path:
    """Write the surface samples (s, X, Y, x, y, p, sigma_nn, gap, q, weight) as CSV (mm, MPa)."""
    path = Path(path)
    data = np.column_stack([samples.s, samples.X, samples.x, samples.p, samples.sigma_nn, samples.gap, samples.q,
                            samples.weight])
    np.savetxt(path, data, delimiter=",", comments="",
               header="s_mm,X_mm,Y_mm,x_mm,y_mm,p_MPa,sigma_nn_MPa,gap_mm,q_MPa,weight_mm")
    return path


def write_vtk(result, out_dir) -> VtkFiles:
    """Write displacement, stress, von Mises and the contact-pressure samples of a ContactResult."""
    out = Path(out_dir)
    u = result.u
    mesh = u.function_space.mesh
    comm = mesh.comm
    if comm.rank == 0:
        out.mkdir(parents=True, exist_ok=True)
    comm.barrier()
    disp = out / "displacement.pvd"
    with dolfinx.io.VTKFile(comm, str(disp), "w") as f:
        f.write_function(u, 0.0)

    T = dolfinx.fem.functionspace(mesh, ("DG", 1, (2, 2)))
    S = dolfinx.fem.functionspace(mesh, ("DG", 1))
    s = dolfinx.fem.Function(T, name="stress")
    ph = getattr(result, "pressure_field", None)
    stress_u = sigma(u, result.lame) if ph is None else sigma_mixed(u, ph, result.lame)
    s.interpolate(dolfinx.fem.Expression(stress_u, T.element.interpolation_points))
    vm = dolfinx.fem.Function(S, name="von_mises")
    vm.interpolate(dolfinx.fem.Expression(von_mises(u, result.lame, ph), S.element.interpolation_points))
    stress = out / "stress.pvd"
    with dolfinx.io.VTKFile(comm, str(stress), "w") as f:
        f.write_function([s, vm], 0.0)

    vtp, csv = out / "contact_surface.vtp", out / "contact_surface.csv"
    if comm.rank == 0:
        smp = result.samples
        write_samples_csv(smp, csv)
        _write_vtp(vtp, smp)
    comm.barrier()
    return VtkFiles(displacement=disp, stress=stress, surface_vtp=vtp, surface_csv=csv)


def _write_vtp(path: Path, smp) -> None:
    """Minimal ASCII VTK PolyData of the sample points (no extra dependency)."""
    n = len(smp.s)
    pts = np.column_stack([smp.x, np.zeros(n)])
    lines = ['<?xml version="1.0"?>', '<VTKFile type="PolyData" version="0.1" byte_order="LittleEndian">',
             "<PolyData>", f'<Piece NumberOfPoints="{n}" NumberOfVerts="{n}">', "<PointData>"]
    for name, arr in (("p", smp.p), ("sigma_nn", smp.sigma_nn), ("gap", smp.gap), ("s", smp.s)):
        lines.append(f'<DataArray type="Float64" Name="{name}" format="ascii">')
        lines.append(" ".join(f"{v:.17g}" for v in arr))
        lines.append("</DataArray>")
    lines += ["</PointData>", "<Points>", '<DataArray type="Float64" NumberOfComponents="3" format="ascii">',
              " ".join(f"{v:.17g}" for v in pts.ravel()), "</DataArray>", "</Points>", "<Verts>",
              '<DataArray type="Int64" Name="connectivity" format="ascii">', " ".join(map(str, range(n))),
              "</DataArray>", '<DataArray type="Int64" Name="offsets" format="ascii">',
              " ".join(map(str, range(1, n + 1))), "</DataArray>", "</Verts>", "</Piece>", "</PolyData>",
              "</VTKFile>"]
    path.write_text("\n".join(lines) + "\n")
