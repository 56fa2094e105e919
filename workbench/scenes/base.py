"""What a scene is: the protocol every scene implements, the records it returns, and the scene registry.

A *scene* turns a case run (:class:`cases.schema.Run`) into a contact problem and judges its result:

0. :meth:`Scene.preflight` rejects a run that cannot be done (one-line :class:`cases.CaseError`, exit 2)
   before anything is written; :meth:`Scene.estimate_cells` says how many triangles its mesh will have (the
   memory preflight, :mod:`workbench.pipeline.size_estimate`);
1. :meth:`Scene.mesh` builds (or reuses) the run's mesh, sized from the scene's own contact estimate;
2. :meth:`Scene.obstacle` is the contact partner: a rigid analytic curve (:mod:`fem.obstacles`), or a second
   meshed elastic body (:class:`fem.two_body.problem.MeshedPartner`, :mod:`fem.partners`);
3. :meth:`Scene.load_path` says how the obstacle is driven (force or displacement control);
4. :meth:`Scene.compare` compares one converged :class:`fem.solver.ContactResult` with theory and returns an
   :class:`Outcome` (typed records; ``metrics`` is its JSON form for ``metrics.json``);
5. :meth:`Scene.judge` compares the runs of a whole case (e.g. convective against small kinematics) and
   returns a :class:`CaseComparison`;
6. :meth:`Scene.error_budget` (``make run`` only, with ``[discretisation] budget_levels``) solves the case
   again on the budget's grids through the pipeline's ``solve(run) -> Outcome`` and returns a
   :class:`SceneBudget` (``metrics.json["error_budget"]``; the block scenes': :mod:`workbench.scenes.block_budget`),
   or ``None`` for a scene without one (no rows).

The pipeline (:mod:`workbench.pipeline.run_case`) does the rest, the same way for every scene: read the mesh,
call the solver with :func:`workbench.scenes.wiring.solver_options`, write the outputs. Every scene's run entry of
``metrics.json`` opens with the same keys, written once here: :func:`run_keys` (from the run) and
:class:`SolveMetrics` (from the :class:`fem.solver.ContactResult`); their number classes are declared here too
(:mod:`workbench.scenes.numbers`). A new scene is one module with a class implementing this protocol, its case
schema (``schema``: a :class:`cases.schema.SceneSchema` with the scene's geometry record, indenters, predictions,
controls and checks; e.g. :mod:`workbench.scenes.block_schema`), its theory, and one call
``register_scene(MyScene())`` (a line in :mod:`workbench.scenes`, or the caller's own for a scene outside the
package: ``tests/test_minimal_scene.py``), which registers both; ``[geometry] scene = "<name>"`` in a case file
selects it (``docs/architecture.md``, "How to add ... a scene").
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, NamedTuple, Protocol, runtime_checkable

from cases.schema import Case, Run, SceneSchema, register_scene_schema
from workbench.scenes.numbers import (
    DISPLACEMENT,
    ERROR,
    ITERATIONS,
    LOAD,
    MESH,
    PEAK,
    ROUNDOFF,
    THEORY,
    WIDTH,
    Number,
    declare,
)

__all__ = ["CaseComparison", "LoadPath", "Outcome", "Scene", "SceneBudget", "SceneMesh", "Series", "SolveMetrics",
           "SCENES", "register_scene", "run_keys", "scene_for"]


class SolveMetrics(NamedTuple):
    """The keys every scene takes from a :class:`fem.solver.ContactResult` into its run's ``metrics.json`` entry,
    written once here (:meth:`of`, :meth:`as_dict`) instead of by hand in each scene.

    Attributes:
        ndofs: Degrees of freedom of the solve.
        wall_time_s: Wall time of the solve (s; never a key number).
        newton_iterations: Newton iterations of each converged solve.
        load_steps: The load steps' records.
        d: Final displacement of the partner (mm).
        P: Final load by virtual work (N/mm, full body).
        P_pressure: Final load as the integral of the contact pressure (N/mm).
        patches: The contact patches (``center``, ``half_width``, ``p_max``, ``P``: mm, MPa, N/mm).
        warnings: The solve's warnings (one line each).
        failed_solves: Solves that did not converge (each cut back and retried): how many.
        failed_iterations: Their Newton iterations, not in ``newton_iterations``.
        failed_time_s: Their wall time (s; never a key number).
    """

    ndofs: int
    wall_time_s: float
    newton_iterations: list
    load_steps: Any
    d: float
    P: float
    P_pressure: float
    patches: list
    warnings: list
    failed_solves: int = 0
    failed_iterations: int = 0
    failed_time_s: float = 0.0

    @classmethod
    def of(cls, result, *, patches: list | None = None, warnings: list | None = None) -> SolveMetrics:
        """The record of ``result``; ``patches`` and ``warnings`` replace the result's where a scene reports its
        own (a concave case: the last step's patches and every step's warnings)."""
        return cls(result.ndofs, result.wall_time_s, list(result.newton_iterations), result.load_steps, result.d,
                   result.P, result.P_pressure,
                   [pt._asdict() for pt in result.patches] if patches is None else patches,
                   list(result.warnings) if warnings is None else list(warnings),
                   len(result.failed_solves), int(sum(f["iterations"] for f in result.failed_solves)),
                   float(sum(f["time"] for f in result.failed_solves)))

    def as_dict(self) -> dict:
        """The JSON form (the record's field names are the ``metrics.json`` keys)."""
        return self._asdict()

    def solve_errors(self) -> dict:
        """``load_balance`` (``|P - P_pressure| / |P|``, round-off: both loads are measured, not imposed) and the
        largest Newton iteration count of a solve, as the two-body scenes' ``errors`` open."""
        return {"load_balance": abs(self.P - self.P_pressure) / abs(self.P),
                "newton_iterations": float(max(self.newton_iterations, default=0))}


# The number classes of what SolveMetrics writes (workbench.scenes.numbers), and of the main patch's peak and
# half-width every scene reports beside it: loads, peaks, widths relative to themselves; a patch's centre on its
# half-width (0 for a symmetric case), its load and peak on the run's.
declare("run", __name__, P=LOAD, P_pressure=LOAD, d=DISPLACEMENT, ndofs=MESH, newton_iterations=ITERATIONS,
        p_max=PEAK, patch_half_width=WIDTH, failed_solves=ITERATIONS, failed_iterations=ITERATIONS)
declare("patch", __name__, center=Number("physics", "position", "contact_size"), half_width=WIDTH,
        p_max=Number("physics", "peak", "run_peak"), P=Number("physics", "load", "run_load"),
        P_pressure=Number("physics", "load", "run_load"))
# errors: fractions of their reference quantity, unless declared; the load balance holds to round-off
declare("run_errors", __name__, load_balance=ROUNDOFF, newton_iterations=ITERATIONS, **{"*": ERROR})
# a judge's case-level analytic values (CaseComparison.analytic) are theory, unless the judge declares otherwise
declare("analytic", __name__, **{"*": THEORY})


def run_keys(run: Run, scene: str) -> dict:
    """The keys every scene takes from its run, which the case report's table of runs reads (``label``,
    ``scene``, ``method``, ``kinematics``, ``traction``: the case's ``[solver] traction``, which a scene whose
    partner fixes it overrides, ``nu``, ``degree``, ``h_contact``: the contact element size as the case gives it,
    a fraction of the scene's contact size)."""
    return {"label": run.label, "scene": scene, "method": run.solver.method, "kinematics": run.solver.kinematics,
            "traction": run.solver.traction, "nu": run.material.nu, "degree": run.discretisation.degree,
            "h_contact": run.discretisation.h_contact}


class Series(NamedTuple):
    """One pressure curve with its analytic predictions (one plot panel, one block of CSV rows).

    Attributes:
        label: Run or step label.
        x: Surface coordinate (mm): material abscissa (block) or arc length of the undeformed concave
            surface (concave scenes).
        p: FEM contact pressure from the contact law (MPa, >= 0).
        sigma_nn: Projected normal stress -sigma_nn (MPa), for comparison.
        predictions: Prediction name -> pressure at ``x`` (MPa).
        xlabel: Axis label of ``x``.
        xlim: Plot range of ``x`` (mm).
        weight: Quadrature weight of each sample (mm: ``sum(weight * p)`` is the load the samples carry), or None.
        q: The contact law's pressure argument ``p = [q]_+`` at each sample (MPa: its zero crossings are the
            edges), or None.
    """

    label: str
    x: Any
    p: Any
    sigma_nn: Any
    predictions: dict
    xlabel: str
    xlim: tuple[float, float]
    weight: Any = None
    q: Any = None


class Outcome(NamedTuple):
    """One FEM run of a case, compared with theory.

    Attributes:
        label: Run label.
        run: The run record.
        metrics: The run's entry of ``metrics.json["runs"]`` (JSON-ready).
        series: Pressure curves to plot and to write to ``pressure.csv``.
        theory: The scene's analytic prediction at the measured load (block: :class:`BlockTheory`), or None.
        comparison: The scene's typed comparison record (block: :class:`BlockComparison`), or None.
        result: The :class:`fem.solver.ContactResult` (for VTK output).
    """

    label: str
    run: Run
    metrics: dict
    series: list[Series]
    theory: Any
    comparison: Any
    result: Any


class CaseComparison(NamedTuple):
    """Case-level analytic values, errors, a one-line headline, extra Markdown tables, extra top-level
    fields of ``metrics.json`` (e.g. the per-step table of a concave case), and ``checked``: tolerance key ->
    the error key its check reads, where the theory that applies is not the classical one (e.g. ``p_max`` ->
    ``p_max_vs_exact_circle`` for a circle indenter); a key not listed checks the error of its own name."""

    analytic: dict
    errors: dict
    headline: str
    tables: dict
    top: dict = {}
    checked: dict = {}


class SceneMesh(NamedTuple):
    """The mesh of one run and what the scene sized it from.

    Attributes:
        files: :class:`meshes.MeshFiles` (``.msh`` path, statistics, cache key).
        estimate: The scene's contact estimate the mesh was sized from (block: :class:`BlockTheory` at the
            target load; concave: the LCP pairs along the path).
        summary: One line for the progress log (cells, sizes).
    """

    files: Any
    estimate: Any
    summary: str


class SceneBudget(NamedTuple):
    """What a scene's error budget returns to the pipeline.

    Attributes:
        rows: ``{quantity: row}`` for ``metrics.json["error_budget"]`` (row keys: ``fine``, ``extrapolated``,
            ``observed_order``, ``gci``, ``truncation``, ``theory``, ``theory_in_band`` and extras).
        subsurface: Axis samples of a Hertz run (block scenes) or None.
        title: Heading of the budget table in the case report.
        runs: ``{run label: [metrics of the run on every budget level, fine first]}`` (for checks that
            need more than the rows, e.g. the concave acceptance; not written to ``metrics.json``).
    """

    rows: dict
    subsurface: dict | None = None
    title: str = "Error budget"
    runs: dict = {}


class LoadPath(NamedTuple):
    """How the contact partner is driven: ``control`` ``"force"`` (target P, N/mm, full body) or
    ``"displacement"`` (target d, mm, with snapshots at ``record_at``), in ``n_steps`` steps; ``symmetric_half``
    for half models. ``supports``: physical group -> support kind where the scene holds its bodies in another way
    than the far field's default; ``solver``: further solver options the scene's problem needs (ContactOptions
    field -> value, e.g. the load path's predictor), below a study's own overrides."""

    control: str
    target: float
    n_steps: int
    symmetric_half: bool = False
    record_at: tuple[float, ...] | None = None
    supports: dict | None = None
    solver: dict | None = None


@runtime_checkable
class Scene(Protocol):
    """The protocol of a scene (see the module docstring)."""

    name: str
    schema: SceneSchema

    def preflight(self, run: Run, *, where: str) -> None:
        ...

    def estimate_cells(self, run: Run) -> float:
        ...

    def mesh(self, run: Run, *, name: str, mesh_cache: Path, comm, stats_dir: Path | None = None) -> SceneMesh:
        ...

    def obstacle(self, run: Run, mesh: SceneMesh):
        ...

    def load_path(self, run: Run, mesh: SceneMesh) -> LoadPath:
        ...

    def compare(self, run: Run, result, mesh: SceneMesh, *, progress) -> Outcome:
        ...

    def judge(self, case: Case, outcomes: list[Outcome]) -> CaseComparison:
        ...

    def error_budget(self, case: Case, *, solve, progress) -> SceneBudget | None:
        ...


SCENES: dict[str, Scene] = {}


def register_scene(scene: Scene) -> Scene:
    """Add a scene to the registry under ``scene.name`` (the ``[geometry] scene`` value of a case), and its case
    schema (``scene.schema``, :class:`cases.schema.SceneSchema`) to the case schema's registry."""
    if not isinstance(scene, Scene):
        raise TypeError(f"{scene!r} does not implement the Scene protocol")
    if scene.schema.name != scene.name:
        raise ValueError(f"scene {scene.name!r} carries the case schema of {scene.schema.name!r}")
    register_scene_schema(scene.schema)
    SCENES[scene.name] = scene
    return scene


def scene_for(run: Run) -> Scene:
    """The registered scene of a run (``run.geometry.scene``)."""
    try:
        return SCENES[run.geometry.scene]
    except KeyError:
        raise ValueError(f"geometry.scene = {run.geometry.scene!r} has no registered scene; "
                         f"known: {sorted(SCENES)}") from None
