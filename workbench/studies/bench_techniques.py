"""Benchmark section ``techniques`` (issue 38, items 3 and 4): what each candidate technique costs on the
cost-growth meshes, measured, so that the ones that did not pay stay in the report with their figure.

One subprocess per mesh (:func:`worker_techniques`; memory measured per mesh, as in section 3), each mesh of
``BenchConfig.technique_meshes`` (family, h_c / a) of :func:`workbench.studies.bench_measure.family_mesh`:

* **Condensation onto the contact cells** (item 3, :mod:`fem.schur`): the dofs of every cell with a facet on the
  contact boundary within ``|x| <= schur_zone a`` of the axis (Nitsche's terms reach every dof of those cells).
  The elastic stiffness is factored by MUMPS with those dofs as Schur unknowns; the dense Schur complement is
  extracted and factored by LAPACK. That is the floor of a contact solve on the condensed system (its active-set
  iterations would then be dense solves of size n_c), against one plain factorisation and one linear solve of
  the row's kind. Above ``schur_max_dofs`` Schur dofs it is not run (the dense ``S`` alone takes ``8 n_c^2``
  bytes); the row says so with that size.
* **Solver variants** (items 3 and 4): the contact solve with the row's options (:func:`scale_overrides`) and
  with each of ``technique_variants`` (extra PETSc options and solver overrides): the Krylov method, the
  Eisenstat-Walker forcing of the Newton steps' linear tolerance, the edge-fit active-set update. Each variant is
  solved once (JIT, factor pattern) and then timed once; time = the solver's ``wall_time_s``, in linear solves of
  the row's kind on the same mesh, with its Newton iterations, triangular solves (passes through the factor:
  PETSc's MatSolve and MatMatSolve events, :func:`factor_solves`; for GAMG these are its coarse-grid solves) and
  the relative difference of P from the row's own solve.
"""

from __future__ import annotations

import time

from workbench.studies.bench_config import BenchConfig
from workbench.studies.bench_log_events import factor_solves
from workbench.studies.bench_measure import (
    block_space,
    count_dofs,
    family_mesh,
    linear_solve,
    log_counts,
    log_delta,
    malloc_env,
    peak_rss_mb,
    rel_diff,
    scale_overrides,
    solve_case,
    subprocess_json,
)

__all__ = ["techniques", "worker_techniques"]


def _contact_cell_dofs(md, V, zone: float):
    """Dof indices (both components; one process: local = global) of the cells with a facet on the contact
    boundary within ``|x| <= zone`` (mm) of the axis."""
    import dolfinx
    import numpy as np

    mesh = md.mesh
    facets = md.facet_tags.find(md.physical_groups["contact"].tag)
    mid = dolfinx.mesh.compute_midpoints(mesh, 1, facets)
    facets = facets[np.abs(mid[:, 0]) <= zone]
    mesh.topology.create_connectivity(1, 2)
    f2c = mesh.topology.connectivity(1, 2)
    cells = np.unique(np.concatenate([f2c.links(f) for f in facets])) if facets.size else np.zeros(0, np.int32)
    nodes = np.unique(V.dofmap.list[cells].reshape(-1))
    bs = V.dofmap.index_map_bs
    return np.sort(np.concatenate([nodes * bs + k for k in range(bs)]))


def _stiffness(md, run):
    """The elastic stiffness of the case's body with its supports (:func:`block_space`), assembled; and its space."""
    import dolfinx
    import dolfinx.fem.petsc
    import ufl

    from fem.elasticity import lame, sigma

    V, bcs = block_space(md, run)
    v, du = ufl.TestFunction(V), ufl.TrialFunction(V)
    lm = lame(E=run.material.E, nu=run.material.nu)
    A = dolfinx.fem.petsc.assemble_matrix(dolfinx.fem.form(ufl.inner(sigma(du, lm), ufl.grad(v)) * ufl.dx), bcs=bcs)
    A.assemble()
    return A, V


def _plain_factor_s(A) -> float:
    """Time of one MUMPS LU of A (symbolic + numeric, MUMPS's default ordering)."""
    from petsc4py import PETSc

    ksp = PETSc.KSP().create(A.comm)
    try:
        ksp.setOperators(A)
        ksp.setType("preonly")
        ksp.getPC().setType("lu")
        ksp.getPC().setFactorSolverType("mumps")
        t0 = time.perf_counter()
        ksp.setUp()
        return time.perf_counter() - t0
    finally:
        ksp.destroy()


def _condensation(cfg: BenchConfig, md, run, linear_s: float) -> dict:
    """The condensation row of a mesh (module docstring)."""
    from fem.schur import schur_complement

    A, V = _stiffness(md, run)
    try:
        rows = _contact_cell_dofs(md, V, cfg.schur_zone * run.loading.half_width)
        out = {"n_schur": int(rows.size), "zone_over_a": cfg.schur_zone, "dense_mb": 8.0 * rows.size**2 / 2**20}
        out["plain_factor_s"] = min(_plain_factor_s(A) for _ in range(2))
        if rows.size > cfg.schur_max_dofs or rows.size == 0:
            out["skipped"] = (f"n_c = {rows.size} > schur_max_dofs = {cfg.schur_max_dofs}" if rows.size
                              else "no contact facet within the zone")
            return out
        sf = schur_complement(A, rows)
        total = sf.factor_s + sf.extract_s + sf.dense_lu_s
        out.update(factor_s=sf.factor_s, extract_s=sf.extract_s, dense_lu_s=sf.dense_lu_s, total_s=total,
                   linear_solves=total / linear_s, peak_rss_mb=peak_rss_mb())
        return out
    finally:
        A.destroy()


def worker_techniques(cfg: BenchConfig, family: str, level: float) -> dict:
    """One mesh of the section, in its own process (module docstring)."""
    import dolfinx_solver  # noqa: F401

    from mpi4py import MPI
    from petsc4py import PETSc

    from fem.linear_solver import resolve

    run, md = family_mesh(family, level, cfg, comm=MPI.COMM_WORLD)
    ndofs = count_dofs(md, run)
    over = scale_overrides(cfg, ndofs)
    kind = resolve(over["linear_solver"], ndofs=ndofs)
    lin = linear_solve(md, run, repeats=1, linear_solver="auto" if over["linear_solver"] == "auto" else kind)
    row = {"family": family, "h_over_a": level, "ndofs": ndofs, "overrides": over, "linear_kind": kind,
           "linear_s": lin["linear_s"]}
    row["condensation"] = _condensation(cfg, md, run, lin["linear_s"])
    PETSc.Log.begin()
    variants, reference_P = [], None
    for label, (popts, extra) in {"row's options": ({}, {}), **cfg.technique_variants}.items():
        kw = {**over, **extra}
        try:
            solve_case(run, md, petsc_options=popts or None, **kw)  # JIT and factor pattern
            before = log_counts()
            res = solve_case(run, md, petsc_options=popts or None, **kw)
            events = log_delta(before, log_counts())
        except Exception as exc:  # a variant that does not converge is a measured outcome, named
            variants.append({"variant": label, "failed": f"{type(exc).__name__}: {str(exc)[:200]}"})
            continue
        reference_P = res.P if reference_P is None else reference_P
        variants.append({
            "variant": label, "petsc_options": popts, "overrides": extra, "solve_s": res.wall_time_s,
            "linear_solves_equivalent": res.wall_time_s / lin["linear_s"],
            "newton_iterations": list(res.newton_iterations),
            "failed_iterations": sum(int(f["iterations"]) for f in res.failed_solves),
            "triangular_solves": factor_solves(events),
            "rel_diff_P": rel_diff(res.P, reference_P),
        })
    row["variants"] = variants
    row["peak_rss_mb"] = peak_rss_mb()
    return row


def techniques(cfg: BenchConfig, *, progress) -> dict:
    """The section: one subprocess per mesh of ``technique_meshes``."""
    rows = []
    for family, level in cfg.technique_meshes:
        row = subprocess_json(["--worker", "techniques", "--family", family, "--h-contact", repr(float(level))], cfg,
                              env=malloc_env(cfg))
        rows.append(row)
        c = row["condensation"]
        cond = (f"condensation {c['n_schur']} dofs: " +
                (c["skipped"] if "skipped" in c else f"{c['linear_solves']:.2f} linear solves"))
        best = min((v for v in row["variants"] if "solve_s" in v), key=lambda v: v["solve_s"], default=None)
        progress(f"techniques {family} h=a*{level:.4g}: ndofs {row['ndofs']}, {cond}; fastest variant "
                 f"{best['variant'] if best else '-'}")
    return {"rows": rows}
