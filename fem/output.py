"""ParaView output of a contact solution: one time step per converged load or displacement step.

Files in ``out_dir`` (rank 0 writes them; the fields of every rank are gathered first):

* ``body.pvd`` -> ``body_<k>.vtu``: the elastic body, one file per step (time = step number 1, 2, ...), on a
  discontinuous linear (DG1) copy of the mesh so that displacement and stress live on the same points:

  - ``displacement_mm`` (components X Y Z, Z = 0): *Warp By Vector* on it shows the deformed body;
  - ``stress_MPa``: the Cauchy stress as a symmetric tensor, components ``XX YY ZZ XY YZ XZ`` (ZZ is the
    plane-strain out-of-plane stress ``lambda tr eps``, YZ = XZ = 0; a finite-strain run writes the Cauchy
    stress ``P F^T / J`` and ``S_33 / J``, :mod:`fem.hyperelastic`, on the reference mesh);
  - ``von_Mises_MPa`` (plane strain, with sigma_zz);
  - several bodies (:mod:`fem.two_body`): ``body`` (the index of the cell's body in ``frames.json``'s
    ``bodies``, constant on each cell: *Threshold* on it shows one body), ``E_MPa`` and ``nu``;
  - field data ``TimeValue`` (= ``step``), ``step``, ``d_mm`` (rigid displacement), ``P_N_per_mm`` (load,
    full body), ``recorded`` (1 at a ``record_at`` displacement) and ``mirrored``.

* ``contact_surface.pvd`` -> ``contact_surface_<k>.vtp``: the candidate contact surface as one polyline
  through the sample points, ordered by ``s``, at their MATERIAL positions with ``displacement_mm``, so the
  same *Warp By Vector* puts it on the deformed body. Point data ``p_MPa`` (contact law, >= 0),
  ``sigma_nn_MPa`` (stress-based, compressive > 0), ``gap_mm`` (> 0 open), ``s_mm`` (surface coordinate).
* ``contact_surface.csv``: the samples of the last step as a table (:func:`write_samples_csv`).
* ``frames.json``: the steps (time, d, P, kind, files), the contact box of each step (material and deformed
  positions of the samples with p > 0, mm), the peak pressure, the minimum of stress YY and von Mises
  statistics near the contact (percentiles), for view scripts and renders.

Half models (``symmetric_half``) are written as the full body: the half is mirrored about x = 0 (x, u_x and
sigma_xy change sign; s -> -s on the surface) and ``mirrored = 1`` in the field data.

Per-step states come from :class:`FrameRecorder`, a :meth:`fem.stepping.LoadStepper.add_step_callback` hook that
copies the converged unknowns and samples the surface after every converged solve (it reads the state only);
:func:`solve_recording` is :func:`fem.solver.solve_contact` with that hook. Without frames, :func:`write_vtk`
writes the final state as the only step.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

import json
from pathlib import Path
from typing import Any, NamedTuple

import dolfinx
import numpy as np
import ufl

from fem.elasticity import epsilon, sigma, sigma_mixed, von_mises
from fem.hyperelastic import cauchy, cauchy_zz
from fem.vtk_files import SYM_TENSOR_COMPONENTS, VECTOR_COMPONENTS, write_pvd, write_vtp, write_vtu

__all__ = ["Frame", "FrameRecorder", "VtkFiles", "solve_recording", "write_samples_csv", "write_vtk"]


class VtkFiles(NamedTuple):
    """Paths written by :func:`write_vtk`."""

    body: Path
    surface: Path
    surface_csv: Path
    frames: Path


class Frame(NamedTuple):
    """One converged state: step number (1, 2, ...), d (mm), P (N/mm, full body), the solve's kind, the local
    arrays of u (and of the mixed pressure, else None) and the surface samples."""

    step: int
    d: float
    P: float
    kind: str
    u: np.ndarray
    ph: np.ndarray | None
    samples: Any


class FrameRecorder:
    """An ``on_step`` hook of :class:`fem.stepping.LoadStepper` keeping a :class:`Frame` of every converged solve.

    It only reads the problem (copies of the unknowns, :meth:`fem.problem.ContactProblem.sample`), so the
    solution does not depend on whether it is attached.
    """

    def __init__(self, problem):
        self.problem = problem
        self.frames: list[Frame] = []

    def __call__(self, rec: dict) -> None:
        pb = self.problem
        ph = getattr(pb, "ph", None)
        self.frames.append(Frame(len(self.frames) + 1, float(rec["d"]), float(rec["P"]), str(rec.get("kind", "")),
                                 pb.u.x.array.copy(), None if ph is None else ph.x.array.copy(), pb.sample()))


def solve_recording(mesh_data, obstacle, *, options):
    """:func:`fem.solver.solve_contact` with a :class:`FrameRecorder` attached: ``(ContactResult, frames)``;
    ``obstacle`` is any contact partner (a rigid curve or a :class:`fem.two_body.problem.MeshedPartner`)."""
    from fem.partners import contact_problem
    from fem.solver import solve_problem

    problem = contact_problem(mesh_data, obstacle, options)
    recorder = FrameRecorder(problem)
    return solve_problem(problem, step_callbacks=[recorder]), recorder.frames


def write_samples_csv(samples, path) -> Path:
    """Write the surface samples (s, X, Y, x, y, p, sigma_nn, gap, q, weight) as CSV (mm, MPa)."""
    path = Path(path)
    data = np.column_stack([samples.s, samples.X, samples.x, samples.p, samples.sigma_nn, samples.gap, samples.q,
                            samples.weight])
    np.savetxt(path, data, delimiter=",", comments="",
               header="s_mm,X_mm,Y_mm,x_mm,y_mm,p_MPa,sigma_nn_MPa,gap_mm,q_MPa,weight_mm")
    return path


class _BodyFields:
    """DG1 interpolation of u, the stress tensor, sigma_zz and von Mises for a given state (compiled once)."""

    def __init__(self, result):
        u = result.u
        self.mesh = mesh = u.function_space.mesh
        self.u = dolfinx.fem.Function(u.function_space)
        ph = getattr(result, "pressure_field", None)
        self.ph = None if ph is None else dolfinx.fem.Function(ph.function_space)
        lm = result.lame
        Vd = dolfinx.fem.functionspace(mesh, ("DG", 1, (2,)))
        # stress (xx, xy, yx, yy), sigma_zz and von Mises in one DG1 field of six components: one Expression, one
        # compiled module (the components are read apart in at())
        F6 = dolfinx.fem.functionspace(mesh, ("DG", 1, (6,)))
        S = dolfinx.fem.functionspace(mesh, ("DG", 1))
        self.ud, self.fields = dolfinx.fem.Function(Vd), dolfinx.fem.Function(F6)
        stress = sigma(self.u, lm) if self.ph is None else sigma_mixed(self.u, self.ph, lm)
        # a Constant: nu = 0 must not fold sigma_zz to 0.0; two bodies carry cell-wise Lame fields (UFL)
        lmbda = dolfinx.fem.Constant(mesh, float(lm.lmbda)) if np.isscalar(lm.lmbda) else lm.lmbda
        szz = lmbda * ufl.tr(epsilon(self.u)) if self.ph is None else -self.ph
        vm = von_mises(self.u, lm, self.ph)
        model = (getattr(result, "options", None) or {}).get("material_model", "linear")
        if model != "linear":  # finite strain: the Cauchy stress of the current configuration
            stress, szz = cauchy(self.u, model, lm), cauchy_zz(self.u, model, lm, lmbda)
            vm = ufl.sqrt(0.5 * ((stress[0, 0] - stress[1, 1]) ** 2 + (stress[1, 1] - szz) ** 2
                                 + (szz - stress[0, 0]) ** 2) + 3.0 * stress[0, 1] ** 2)
        six = ufl.as_vector([stress[0, 0], stress[0, 1], stress[1, 0], stress[1, 1], szz, vm])
        self.expr = dolfinx.fem.Expression(six, F6.element.interpolation_points)
        self.n_cells = mesh.topology.index_map(mesh.topology.dim).size_local
        self.S = S
        # several bodies (fem.two_body): each cell's body index, E and nu, constant per cell
        forms = getattr(result, "forms", None)
        self.body_names = tuple(getattr(forms, "body_names", ()) or ())
        self.cell_columns = None
        if self.body_names:
            per_cell = [f.x.array[f.function_space.dofmap.list[: self.n_cells, 0]]
                        for f in (forms.body_index, forms.E, forms.nu)]
            self.cell_columns = np.stack(per_cell, axis=1)  # (owned cells, 3): body, E (MPa), nu

    def _per_cell(self, f: dolfinx.fem.Function) -> np.ndarray:
        """(owned cells, 3 vertices, block size) values; the cell-local dof order is the element's for every
        DG1 space, so vertex j of a cell is the same point in all of them."""
        bs = f.function_space.dofmap.index_map_bs
        dofs = f.function_space.dofmap.list[: self.n_cells]
        return f.x.array.reshape(-1, bs)[dofs]

    def geometry(self) -> np.ndarray:
        return self.S.tabulate_dof_coordinates()[self.S.dofmap.list[: self.n_cells]][..., :2]

    def at(self, frame: Frame) -> np.ndarray:
        """(owned cells, 3, 2 + 6 + 1) = u (x, y), stress (XX YY ZZ XY YZ XZ), von Mises of ``frame``."""
        self.u.x.array[:] = frame.u
        self.u.x.scatter_forward()
        if self.ph is not None and frame.ph is not None:
            self.ph.x.array[:] = frame.ph
            self.ph.x.scatter_forward()
        self.ud.interpolate(self.u)
        self.fields.interpolate(self.expr)
        u, six = self._per_cell(self.ud), self._per_cell(self.fields)
        s, szz, vm = six[..., 0:4], six[..., 4:5], six[..., 5:6]
        zero = np.zeros_like(szz)
        # tensor dofs are row-major (xx, xy, yx, yy)
        out = [u, s[..., 0:1], s[..., 3:4], szz, s[..., 1:2], zero, zero, vm]
        if self.cell_columns is not None:
            out.append(np.repeat(self.cell_columns[:, None, :], 3, axis=1))
        return np.concatenate(out, axis=2)


def _bodies(fields: _BodyFields, comm) -> list[dict]:
    """The bodies of a several-body grid for ``frames.json``: index (the ``body`` point array), name, E, nu."""
    cols = fields.cell_columns
    out = []
    for k, name in enumerate(fields.body_names):
        on = cols[cols[:, 0] == k]
        out.append({"index": k, "name": name, "E_MPa": float(on[0, 1]) if len(on) else None,
                    "nu": float(on[0, 2]) if len(on) else None})
    return out


def _gather(comm, arr: np.ndarray) -> np.ndarray | None:
    parts = comm.gather(arr, root=0)
    return None if parts is None else np.concatenate(parts, axis=0)


def _mirror_body(xy: np.ndarray, vals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The half body (x >= 0) and its mirror image about x = 0 (u_x, sigma_xy change sign)."""
    mx, mv = xy.copy(), vals.copy()
    mx[..., 0] *= -1.0
    mv[..., 0] *= -1.0  # u_x
    mv[..., 5] *= -1.0  # XY
    mx, mv = mx[:, ::-1], mv[:, ::-1]  # reversed vertex order keeps the mirrored triangles counter-clockwise
    return np.concatenate([xy, mx]), np.concatenate([vals, mv])


def _surface(smp, mirrored: bool) -> dict:
    """Surface arrays ordered by s (material positions, displacement), the mirror image prepended for a half."""
    order = np.argsort(smp.s, kind="stable")
    X, x = np.asarray(smp.X)[order], np.asarray(smp.x)[order]
    out = {"s": np.asarray(smp.s)[order], "X": X, "u": x - X, "p": np.asarray(smp.p)[order],
           "sigma_nn": np.asarray(smp.sigma_nn)[order], "gap": np.asarray(smp.gap)[order]}
    if mirrored:
        keep = out["s"] > 0
        flip = {k: v[keep][::-1].copy() for k, v in out.items()}
        flip["s"] *= -1.0
        flip["X"][:, 0] *= -1.0
        flip["u"][:, 0] *= -1.0
        out = {k: np.concatenate([flip[k], out[k]]) for k in out}
    return out


def _contact_box(surf: dict, *, deformed: bool = False) -> list[float] | None:
    """[xmin, xmax, ymin, ymax] (mm) of the samples with p > 0, material or deformed positions."""
    on = surf["p"] > 0
    if not on.any():
        return None
    X = surf["X"][on] + (surf["u"][on] if deformed else 0.0)
    return [float(X[:, 0].min()), float(X[:, 0].max()), float(X[:, 1].min()), float(X[:, 1].max())]


def _vm_stats(xy: np.ndarray, vals: np.ndarray, box: list[float] | None) -> dict:
    """Von Mises near the contact (within 3 box widths of it, or everywhere without contact)."""
    pts, vm = xy.reshape(-1, 2), vals[..., 8].ravel()
    if box is not None:
        w = max(box[1] - box[0], box[3] - box[2], 1e-12)
        near = ((pts[:, 0] >= box[0] - 3 * w) & (pts[:, 0] <= box[1] + 3 * w)
                & (pts[:, 1] >= box[2] - 3 * w) & (pts[:, 1] <= box[3] + 3 * w))
        vm = vm[near] if near.any() else vm
    return {"min": float(vm.min()), "p01": float(np.percentile(vm, 1)), "p50": float(np.percentile(vm, 50)),
            "p99": float(np.percentile(vm, 99)), "max": float(vm.max())}


def write_vtk(result, out_dir, *, frames: list[Frame] | None = None,
              record_at: tuple[float, ...] | None = None) -> VtkFiles:
    """Write the body and the contact surface of every frame (time series) of a ContactResult.

    Args:
        result: The :class:`fem.solver.ContactResult`.
        out_dir: The folder (created).
        frames: The converged states of the solve (:func:`solve_recording`); default: the final state only.
        record_at: Displacements (mm) marked ``recorded = 1`` in the field data (the case's snapshots).
    """
    out = Path(out_dir)
    u = result.u
    comm = u.function_space.mesh.comm
    if comm.rank == 0:
        out.mkdir(parents=True, exist_ok=True)
    comm.barrier()
    if not frames:
        ph = getattr(result, "pressure_field", None)
        frames = [Frame(1, float(result.d), float(result.P), "final", u.x.array.copy(),
                        None if ph is None else ph.x.array.copy(), result.samples)]
    mirrored = bool(result.half)
    fields = _BodyFields(result)
    xy = _gather(comm, fields.geometry())
    files = VtkFiles(out / "body.pvd", out / "contact_surface.pvd", out / "contact_surface.csv", out / "frames.json")
    body_entries, surf_entries, steps = [], [], []
    levels = [float(v) for v in (record_at or ())]
    for fr in frames:
        vals = _gather(comm, fields.at(fr))
        if comm.rank != 0:
            continue
        pts, v = _mirror_body(xy, vals) if mirrored else (xy, vals)
        pts, v = pts.reshape(-1, 2), v.reshape(-1, v.shape[-1])
        tri = np.arange(len(pts)).reshape(-1, 3)
        a = pts[tri]
        area = ((a[:, 1, 0] - a[:, 0, 0]) * (a[:, 2, 1] - a[:, 0, 1])
                - (a[:, 2, 0] - a[:, 0, 0]) * (a[:, 1, 1] - a[:, 0, 1]))
        tri[area < 0] = tri[area < 0][:, ::-1]
        recorded = any(abs(fr.d - lv) <= 1e-12 * max(1.0, abs(lv)) for lv in levels)
        field = {"TimeValue": float(fr.step), "step": fr.step, "d_mm": fr.d, "P_N_per_mm": fr.P,
                 "recorded": float(recorded), "mirrored": float(mirrored)}
        disp3 = np.column_stack([v[:, 0:2], np.zeros(len(v))])
        bname, sname = f"body_{fr.step:04d}.vtu", f"contact_surface_{fr.step:04d}.vtp"
        point_data = {"displacement_mm": (disp3, VECTOR_COMPONENTS), "stress_MPa": (v[:, 2:8], SYM_TENSOR_COMPONENTS),
                      "von_Mises_MPa": v[:, 8]}
        if fields.body_names:  # constant on each cell: Threshold on "body" shows one body
            point_data |= {"body": v[:, 9], "E_MPa": v[:, 10], "nu": v[:, 11]}
        write_vtu(out / bname, points=pts, triangles=tri, field=field, point_data=point_data)
        surf = _surface(fr.samples, mirrored)
        n = len(surf["s"])
        write_vtp(out / sname, points=surf["X"], polylines=[list(range(n))] if n > 1 else [], field=field,
                  point_data={"displacement_mm": (np.column_stack([surf["u"], np.zeros(n)]), VECTOR_COMPONENTS),
                              "p_MPa": surf["p"], "sigma_nn_MPa": surf["sigma_nn"], "gap_mm": surf["gap"],
                              "s_mm": surf["s"]})
        body_entries.append((float(fr.step), bname))
        surf_entries.append((float(fr.step), sname))
        box = _contact_box(surf)
        steps.append({"step": fr.step, "time": float(fr.step), "d_mm": fr.d, "P_N_per_mm": fr.P, "kind": fr.kind,
                      "bounds_mm": [float(pts[:, 0].min()), float(pts[:, 0].max()), float(pts[:, 1].min()),
                                    float(pts[:, 1].max())],
                      "recorded": recorded, "body": bname, "surface": sname, "contact_box_mm": box,
                      "contact_box_deformed_mm": _contact_box(surf, deformed=True),
                      "p_max_MPa": float(surf["p"].max()) if n else 0.0,
                      "stress_YY_min_MPa": float(v[:, 3].min()),
                      "von_Mises_near_contact_MPa": _vm_stats(pts.reshape(-1, 3, 2), v[:, :9].reshape(-1, 3, 9),
                                                              box)})
    if comm.rank == 0:
        write_pvd(files.body, body_entries)
        write_pvd(files.surface, surf_entries)
        write_samples_csv(result.samples, files.surface_csv)
        index = {"mirrored": mirrored, "time": "step number (1, 2, ...): one per converged solve",
                 "units": {"length": "mm", "stress": "MPa", "load": "N/mm (per unit thickness, full body)"},
                 "body": files.body.name, "surface": files.surface.name, "steps": steps}
        if fields.body_names:
            index["bodies"] = _bodies(fields, comm)
        files.frames.write_text(json.dumps(index, indent=1) + "\n")
    comm.barrier()
    return files
