"""A case as a benchmark another code can run: typed records every exporter, writer, runner and scorer shares.

A :class:`Benchmark` is one case at one mesh level, described without any of the workbench's own solver choices
(method, penalty, quadrature): the bodies and their materials, the mesh file that holds them (gmsh ``.msh`` with
named physical groups), the contact pairs, the supports, how the load is applied and which loads are reported, the
runs (small strain, convective, finite strain), what to report and the reference theory at the load the result
will carry. Units: mm, N, MPa; loads per unit thickness (N/mm), plane strain, thickness 1 mm.

Conventions (the names are the contract between the writers of :mod:`workbench.external` and the codes):

* Every body's cells are one 2D physical group of the mesh (:attr:`Body.cells`); every surface one 1D group.
* A rigid indenter is meshed (a band of cells along its contact surface, :attr:`Body.rigid`): every node of it
  moves with the rigid body (prescribed displacement ``d * direction``). Its exact geometry is in
  :attr:`Benchmark.geometry` for codes with analytic rigid surfaces.
* A contact pair names the slave surface (the one whose pressure is reported, on a deformable body) and the
  master surface. Frictionless.
* Positions in results are the slave surface's material (reference) coordinates; pressures compression positive.
* :class:`Drive`: the load is applied through the rigid body (or the driven group of an elastic body) along
  ``direction``; ``control`` says whether the case's targets are loads (force control: an external code may drive
  the displacement and match the load, the score evaluates the theory at the measured load) or displacements.

The result a code hands back is a csv (:mod:`workbench.external.results`): ``x_mm, p_MPa`` per sample, and the
optional columns ``P_N_per_mm`` (the load), ``h_mm``, ``run`` (a :class:`Run` label), ``step`` (the index of a
reported load in :attr:`Drive.report`) and ``body`` (the slave surface's body name).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

__all__ = ["Material", "Body", "ContactPair", "Support", "Drive", "Run", "Benchmark", "RESULT_COLUMNS", "UNITS",
           "pair_modulus"]

UNITS = {"length": "mm", "force": "N", "pressure": "MPa", "load": "N/mm (per unit thickness)",
         "model": "2D plane strain, thickness 1 mm, frictionless contact"}

RESULT_COLUMNS = {
    "x_mm": "position along the slave contact surface, reference configuration (mm)",
    "y_mm": "the second reference coordinate of the sample (mm): needed on a curved surface (the concave scenes, "
            "measured along the curve's arc length), optional elsewhere",
    "p_MPa": "contact pressure, compression positive, per unit reference length (MPa)",
    "P_N_per_mm": "optional: the full-body load carried at this step (N/mm)",
    "h_mm": "optional: the element size on the contact surface (mm)",
    "weight_mm": "optional: the sample's quadrature weight (mm; default: trapezoid weights)",
    "q_MPa": "optional: the pressure argument, p = [q]_+ (MPa; its zero crossings are the edges; default q = p)",
    "run": "optional: the run label (e.g. small, convective, finite: workbench.external.scorers.result_layout); one "
           "file may hold several runs",
    "step": "optional: the index of the reported load (0, 1, ...) of Drive.report",
    "body": "optional: the body whose surface the row samples (two elastic bodies)",
}


@dataclass(frozen=True, kw_only=True)
class Material:
    """Isotropic linear elasticity (MPa); ``model`` names the finite-strain law a finite run uses."""

    E: float
    nu: float
    model: str = "linear"


@dataclass(frozen=True, kw_only=True)
class Body:
    """A body: its cells' physical group and its material, or rigid (every node moves with the drive)."""

    name: str
    cells: str
    material: Material | None = None
    rigid: bool = False

    def __post_init__(self) -> None:
        if self.rigid == (self.material is not None):
            raise ValueError(f"body {self.name!r}: a material for an elastic body, none for a rigid one")


@dataclass(frozen=True, kw_only=True)
class ContactPair:
    """Frictionless contact between two surfaces (1D physical groups); the slave's pressure is reported."""

    slave: str
    master: str
    slave_body: str
    master_body: str


@dataclass(frozen=True, kw_only=True)
class Support:
    """Displacement components (0: x, 1: y) held at 0 on a facet group."""

    group: str
    components: tuple[int, ...]
    note: str = ""


@dataclass(frozen=True, kw_only=True)
class Drive:
    """How the load is applied: the rigid body (``body``) or a facet group of an elastic body (``group``) moves by
    ``d * direction``. ``control``: ``"force"`` (``report`` holds loads P, N/mm, full body) or ``"displacement"``
    (``report`` holds d, mm). ``report``: the loads or displacements at which results are reported, in order.
    ``components``: the displacement components prescribed on ``group`` (0: x, 1: y; the others free, e.g. the
    patch test's top moves down and may slide: ``(1,)``); a rigid body's nodes have all components prescribed."""

    control: str
    report: tuple[float, ...]
    direction: tuple[float, float] = (0.0, -1.0)
    body: str | None = None
    group: str | None = None
    half_model: bool = False
    components: tuple[int, ...] = (0, 1)


@dataclass(frozen=True, kw_only=True)
class Run:
    """One run of the case: its label and kinematics (``"small"``, ``"convective"``, ``"finite"``), what it means in
    words, and the traction direction the workbench's run uses (``"halfplane"``: vertical; ``"obstacle"``: along the
    rigid surface's normal; two bodies: the master's)."""

    label: str
    kinematics: str
    meaning: str
    traction: str = ""
    material_model: str = "linear"


@dataclass(frozen=True, kw_only=True)
class Benchmark:
    """One case at one mesh level, as a benchmark (module docstring).

    Attributes:
        case, scene, description: the case's name, its scene and its one-line description.
        level: the mesh level (the case's ``h_contact`` fraction: h_c / a, or h / W for the patch test).
        h_contact: the element size on the contact surface (mm).
        mesh: the gmsh ``.msh`` holding every body (physical groups named as below).
        bodies, pairs, supports, drive, runs: the model.
        geometry: the exact geometry (indenter shape and sizes, block sizes; mm), for a code that models a rigid
            surface analytically or a person building the model by hand.
        reference: the reference theory: its name, what it predicts at the case's target load, and how the score
            evaluates it at the load a result carries.
        report: what a result holds (:data:`RESULT_COLUMNS`) and what the score measures.
        tolerances: the case's own tolerances (its checks of the workbench's run).
    """

    case: str
    scene: str
    description: str
    level: float
    h_contact: float
    mesh: Path
    bodies: tuple[Body, ...]
    pairs: tuple[ContactPair, ...]
    supports: tuple[Support, ...]
    drive: Drive
    runs: tuple[Run, ...]
    geometry: dict = field(default_factory=dict)
    reference: dict = field(default_factory=dict)
    report: dict = field(default_factory=dict)
    tolerances: dict = field(default_factory=dict)

    def body(self, name: str) -> Body:
        """The body named ``name``."""
        for b in self.bodies:
            if b.name == name:
                return b
        raise KeyError(f"benchmark {self.case}: no body {name!r}; bodies: {[b.name for b in self.bodies]}")


def pair_modulus(bench: Benchmark, pair: ContactPair) -> float:
    """E* of a contact pair (MPa): :func:`analytic.materials.composite_modulus` of its elastic bodies (a rigid body
    adds nothing: ``E1 = inf``)."""
    from analytic.materials import composite_modulus

    elastic = [b.material for b in (bench.body(pair.slave_body), bench.body(pair.master_body)) if not b.rigid]
    if len(elastic) == 1:
        return composite_modulus(elastic[0].E, elastic[0].nu)
    lower, upper = elastic
    return composite_modulus(lower.E, lower.nu, E1=upper.E, nu1=upper.nu)
