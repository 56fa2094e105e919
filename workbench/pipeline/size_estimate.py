"""How large a run's mesh and solve will be, estimated before meshing, and the refusal of one that cannot fit.

Element count (linear triangles from gmsh's size field, :mod:`meshes.sizing`): the size grows from h0 on the
refined contact segments as h(d) = h0 + k d (k = growth - 1) up to h_far. An equilateral triangle of side h
covers sqrt(3)/4 h^2, so the count is C * integral of dA / h^2 with C = 4/sqrt(3). Around a refined segment of
length L on the free surface the band at distance d has length L + c d (c = pi for a full block, pi/2 for the
half model at its symmetry edge), so

    N = F * C * [ L/k (1/h0 - 1/h_far) + c/k^2 (ln(h_far/h0) + h0/h_far - 1) + A_far / h_far^2 ],

with A_far the area left at h_far. F is fitted to the meshes gmsh really makes (``CELL_FACTOR``, measured with
``workbench mesh`` on hertz_cylinder, wedge and the concave designs; the fit is in ``tests/test_size_preflight.py``).
Degrees of freedom: P2 vectors have about 2 nodes per triangle (4 dofs), P1 about 1/2 (1 dof); the mixed
formulation adds P1 pressures (1/2 per triangle).

Memory (peak resident size of a whole ``workbench run`` process: Python + dolfinx, gmsh, assembly, the MUMPS
LU factor) is modelled by :func:`memory_bytes`, fitted to measured runs (``MEM_MEASURED``).
A run is refused when the estimate exceeds ``MEM_FRACTION`` of MemAvailable (``/proc/meminfo``), or when the
count passes ``MAX_CELLS`` whatever the memory (a mesh gmsh would take hours to make).
"""

from __future__ import annotations

import math
from typing import NamedTuple

__all__ = ["SizeEstimate", "estimate_run", "check_run_fits", "mem_available", "smallest_fitting_h", "graded_triangles"]

from meshes.sizing import graded_triangles  # noqa: E402  (re-exported: the model lives with the mesh sizes)

# Measured cells / model cells: 1.20 ... 1.28 over 10 meshes of 1.5k ... 80k cells (hertz_cylinder h_c = 0.01
# ... 2e-4, wedge 0.002, concave_symmetric and close_to_conformal 0.2 and 0.05): the mean, within +-4 %.
CELL_FACTOR = 1.24
# Peak RSS of `workbench run hertz_cylinder --h-contact h` (P2, Nitsche, MUMPS LU; /usr/bin/time -v), dofs = 4 x cells:
MEM_MEASURED = {33_276: 501e6, 92_776: 556e6, 183_824: 922e6, 318_208: 1460e6}  # dofs -> bytes
# Fit through the two largest points: 4.0 kB per dof above a 0.18 GB base; MUMPS's fill grows like n log n in 2D,
# so the per-dof term is scaled by ln(dofs)/ln(3.2e5) beyond the measured range. The two smaller runs sit below
# the floor of 0.5 GB (Python + dolfinx + the JIT forms), which the model keeps as its minimum.
MEM_BASE = 1.8e8
MEM_PER_DOF = 4.0e3
MEM_FLOOR = 5.0e8
MEM_FRACTION = 0.8  # of MemAvailable: the margin left to the system and the other processes
MAX_CELLS = 2.0e7  # whatever the memory: gmsh alone would take hours


def memory_bytes(dofs: float) -> float:
    """The memory model (bytes) of a run with ``dofs`` unknowns (see MEM_MEASURED)."""
    if not math.isfinite(dofs):
        return math.inf
    return max(MEM_FLOOR, MEM_BASE + MEM_PER_DOF * dofs * max(1.0, math.log(max(dofs, 2.0)) / math.log(3.2e5)))


class SizeEstimate(NamedTuple):
    """Estimated mesh size and memory of one run: ``cells`` triangles, ``dofs`` unknowns, ``bytes`` peak RSS."""

    cells: float
    dofs: float
    bytes: float


def _dofs(cells: float, run) -> float:
    from cases.schema import effective_formulation

    per = 4.0 if run.discretisation.degree == 2 else 1.0
    if effective_formulation(run) == "mixed":
        per += 0.5
    return per * cells


def estimate_run(run) -> SizeEstimate:
    """The estimate for one run (its ``discretisation.h_contact`` and growth), before anything is meshed."""
    from workbench.scenes import scene_for

    cells = scene_for(run).estimate_cells(run)  # the scene's model count (meshes.sizing.graded_triangles)
    cells *= CELL_FACTOR
    dofs = _dofs(cells, run)
    return SizeEstimate(cells, dofs, memory_bytes(dofs))


def mem_available() -> float:
    """MemAvailable of /proc/meminfo in bytes (inf where there is none)."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024.0
    except OSError:
        pass
    return math.inf


def _fits(est: SizeEstimate, available: float) -> bool:
    return est.cells <= MAX_CELLS and est.bytes <= MEM_FRACTION * available


def smallest_fitting_h(run, available: float) -> float | None:
    """The smallest h_contact (fraction of the half-width) at which ``run`` fits, by bisection in log h."""
    from dataclasses import replace

    def fits(h):
        return _fits(estimate_run(replace(run, discretisation=replace(run.discretisation, h_contact=h))), available)

    lo, hi = 1e-12, run.discretisation.h_contact
    if not fits(1.0):
        return None
    hi = 1.0
    for _ in range(60):
        mid = math.sqrt(lo * hi)
        if fits(mid):
            hi = mid
        else:
            lo = mid
        if hi / lo < 1.01:
            break
    return hi


def check_run_fits(run, *, where: str, field: str, available: float | None = None) -> SizeEstimate:
    """Raise CaseError (one line: the field, the estimate, the memory available, the allowed h) if ``run``
    would not fit; return the estimate otherwise."""
    from cases import CaseError

    available = mem_available() if available is None else available
    try:
        est = estimate_run(run)
    except (OverflowError, ZeroDivisionError, ValueError):
        est = SizeEstimate(math.inf, math.inf, math.inf)
    if _fits(est, available):
        return est
    h_ok = smallest_fitting_h(run, available)
    allowed = f"{field} >= {h_ok:.2g}" if h_ok is not None else "a coarser mesh"
    raise CaseError(f"{where}: {field} = {run.discretisation.h_contact:g} needs about {est.cells:.3g} triangles, "
                    f"{est.dofs:.3g} dofs and {est.bytes / 2**30:.3g} GiB of memory; available "
                    f"{available / 2**30:.3g} GiB (MemAvailable; runs are kept within {MEM_FRACTION:.0%} of it, "
                    f"and below {MAX_CELLS:.0e} triangles); allowed: {allowed}")


def check_case_fits(case, *, h_contact: float | None = None, ci: bool = False,
                    available: float | None = None) -> None:
    """Every run of ``case`` as ``workbench run`` would solve it fits: at ``--h-contact`` (field ``--h-contact``),
    at its ci_level (``--ci``), or at ``discretisation.h_contact`` plus the error budget's finest level on its
    largest block (``discretisation.budget_levels``)."""
    from dataclasses import replace

    where = case.path.name
    if ci and h_contact is None:
        h_contact = case.discretisation.ci_level or case.discretisation.h_contact
        field = "discretisation.ci_level"
    else:
        field = "--h-contact" if h_contact is not None else "discretisation.h_contact"
    available = mem_available() if available is None else available
    for run in case.runs(h_contact=h_contact):
        check_run_fits(run, where=f"{where}: [{run.label}]", field=field, available=available)
        d = run.discretisation
        if h_contact is None and d.budget_levels:
            g = run.geometry
            if g.scene == "block" and d.budget_widths:
                w = max(d.budget_widths)
                g = replace(g, width_factor=w, height_factor=w)
            fine = replace(run, geometry=g, discretisation=replace(d, h_contact=min(d.budget_levels)))
            check_run_fits(fine, where=f"{where}: [{run.label}] error budget", field="discretisation.budget_levels",
                           available=available)


def check_levels_fit(case_names, levels, *, study: str, field: str, available: float | None = None) -> None:
    """A study's configuration: every run of every case at every level (h_c fractions) fits; else one line."""
    import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
    from cases import load_case

    available = mem_available() if available is None else available
    for name in case_names:
        case = load_case(name)
        for level in levels:
            if level is None:
                continue
            for run in case.runs(h_contact=level):
                check_run_fits(run, where=f"{study}: {case.path.name} [{run.label}]", field=field,
                               available=available)
