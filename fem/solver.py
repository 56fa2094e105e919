"""Frictionless contact of a plane-strain elastic body against a rigid analytic obstacle (dolfinx 0.11).

Units: mm, N, MPa; loads P per unit thickness (N/mm). Gap g > 0 open; pressure p >= 0 compressive. The weak
forms are documented in :mod:`fem.contact_forms` and in the method modules (:mod:`fem.methods`: penalty,
Nitsche, augmented Lagrangian).

:func:`solve_contact` is the whole solve in three objects:

* :class:`fem.problem.ContactProblem`: spaces, supports, forms, the load measures (P by virtual work,
  P_pressure) and the dolfinx NonlinearProblem (SNES ``newtonls``/``basic``, LU/MUMPS);
* :class:`fem.stepping.LoadStepper`: load steps, cut-backs, force control (secant and tangent corrections),
  the Hertz / extrapolation / active-set predictors and the converged states;
* :class:`ContactResult`: what the caller gets back.

Reported ``iterations`` count the predictor iteration too (1 = the prescribed active set was already right;
0 = a tangent force-correction state accepted as it was).

Divergence (SNES converged reason <= 0) restores the last converged state and halves the increment, up to
``max_cutbacks`` times per step, then raises :class:`ContactSolveError` naming the reason (e.g. ``-5
(DIVERGED_MAX_IT)``). A converged result carries named ``warnings`` instead of silently wrong numbers:
"contact unresolved" (< ``min_facets_across`` facets across a patch), "contact truncated", "no contact",
"penetration", "pressure oscillation" (:mod:`fem.postprocess`) and "near-incompressible" (displacement
formulation at nu >= 0.45; ``formulation="mixed"`` is the locking-free Taylor-Hood u-p option).

Measured load ``P`` (virtual work): ``P = -a(u, w)`` with ``w`` equal to the loading direction at every
Dirichlet-constrained component dof and 0 elsewhere, i.e. the support reaction along the direction; it
equals the discrete contact force. ``P_pressure = int p (n_o . direction) ds`` is the resultant of the
contact pressure along the direction (it equals P up to round-off, because the Nitsche stress terms vanish for
a rigid test field; it is a consistency check of the assembly). For ``symmetric_half=True`` both are doubled
(full-body values) and patches are mirrored.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

from fem.errors import ContactSolveError, snes_reason_name
from fem.nested_start import nested_start_of
from fem.options import FORMULATIONS, MIN_FACETS_ACROSS, SUPPORT_KINDS, ContactOptions
from fem.partner_problem import PartnerProblem
from fem.postprocess import Patch, SurfaceSamples, find_patches
from fem.stepping import LoadStepper, Snapshot
from fem.warm_start import warm_start_of

__all__ = ["ContactSolveError", "ContactResult", "ContactOptions", "Snapshot", "solve_contact", "solve_problem",
           "snes_reason_name",
           "SUPPORT_KINDS", "FORMULATIONS", "MIN_FACETS_ACROSS"]

@dataclass(frozen=True)
class ContactResult:
    """Result of :func:`solve_contact` (full-body values for a half model).

    Attributes:
        ndofs: global number of displacement dofs.
        wall_time_s: wall time of the load stepping (s); the forms are compiled before the clock starts.
        newton_iterations: Newton iterations per converged solve (load steps and force corrections), the
            prescribed-active-set predictor iteration included.
        load_steps: one dict per converged solve: d (mm), P (N/mm), iterations, time (s), kind.
        failed_solves: one dict per solve that did not converge (then cut back): d (mm), kind, iterations, time (s),
            reason (:attr:`fem.stepping.LoadStepper.failures`): their iterations are not in ``newton_iterations``.
        d: final rigid displacement (mm).
        P: final load by virtual work / support reaction (N/mm).
        P_pressure: final resultant of the contact pressure along the loading direction (N/mm).
        samples: surface samples (half-model samples are NOT mirrored; s = X1).
        patches: contact patches (full body).
        u: displacement Function.
        options: the solver options used.
        half: True for a half model.
        forms: the ContactForms (UFL pieces) for output.
        lame: Lame parameters.
        snapshots: one :class:`Snapshot` per ``record_at`` displacement (displacement control).
        warnings: named warnings about the result's trustworthiness, e.g. ``"contact unresolved: ..."`` when a
            patch spans fewer than ``min_facets_across`` contact facets (see
            :func:`fem.postprocess.resolution_warnings`); empty when none.
        pressure_field: the P1 pressure ``p = -lambda div u`` (MPa) of the mixed formulation, else None.
        warm_start: the converged states this solve ends with (:func:`fem.warm_start.warm_start_of`): the
            ``warm_start`` option of a re-solve of the same problem (e.g. at tighter tolerances).
        nested_start: the converged state as the ``nested_start`` of a finer mesh of the same problem
            (:func:`fem.nested_start.nested_start_of`; None where the problem has no hook).
    """

    ndofs: int
    wall_time_s: float
    newton_iterations: list
    load_steps: list
    d: float
    P: float
    P_pressure: float
    samples: SurfaceSamples
    patches: list[Patch]
    u: Any
    options: dict
    half: bool
    forms: Any = field(repr=False)
    lame: Any = field(repr=False)
    snapshots: list = field(default_factory=list)
    warnings: list = field(default_factory=list)
    pressure_field: Any = field(default=None, repr=False)
    warm_start: Any = field(default=None, repr=False)
    nested_start: Any = field(default=None, repr=False)
    failed_solves: list = field(default_factory=list)


def solve_contact(mesh_data, obstacle, options: ContactOptions | None = None, **fields) -> ContactResult:
    """Solve frictionless contact of the meshed body against its contact partner (:mod:`fem.partners`).

    Args:
        mesh_data: dolfinx ``MeshData`` (mesh, facet_tags, physical_groups) of the elastic body (or bodies).
        obstacle: the partner: a rigid obstacle from :mod:`fem.obstacles`, or a second meshed elastic body in the
            same mesh (:class:`fem.two_body.problem.MeshedPartner`).
        options: the solve's :class:`ContactOptions` (every field, its units and default are documented there).
        **fields: instead of ``options``, its fields as flat keywords, sorted into its records
            (:meth:`ContactOptions.from_fields`: ``target`` required; ``E`` and ``nu`` for a rigid obstacle, none
            of the body's keywords for a meshed partner); the accepted names are
            :meth:`ContactOptions.field_names`, nothing else.

    Raises:
        TypeError: an unknown keyword, a missing required one, or ``options`` together with keywords.
        ValueError: bad option.  ContactSolveError: SNES failure after the allowed cut-backs.
    """
    if options is None:
        opts = ContactOptions.from_fields(fields, caller="solve_contact")
    elif fields:
        raise TypeError(f"solve_contact() takes options= or keywords, not both (got {sorted(fields)})")
    elif not isinstance(options, ContactOptions):
        raise TypeError(f"solve_contact() options must be a ContactOptions, got {type(options).__name__}")
    else:
        opts = options
    from fem.partners import contact_problem  # a rigid curve (checked by check_options) or a meshed partner

    return solve_problem(contact_problem(mesh_data, obstacle, opts))


def solve_problem(problem: PartnerProblem, *, step_callbacks: Sequence[Callable[[dict], None]] = ()) -> ContactResult:
    """Drive a built contact problem (:class:`fem.partner_problem.PartnerProblem`) through its load path
    (:class:`LoadStepper`) and collect the result.

    ``step_callbacks`` are called after every converged solve with its record, after ``options.on_step``, while
    the problem holds that state (e.g. :class:`fem.output.FrameRecorder` copies it for a VTK time series);
    they must only read the state.
    """
    stepper = LoadStepper(problem, on_step=problem.options.on_step)
    for fn in step_callbacks:
        stepper.add_step_callback(fn)
    try:
        stepper.run()
        return _result(problem, stepper)
    finally:
        # the SNES's callbacks (bound methods of the problem) keep the problem, its mesh, spaces and MPI
        # communicators alive after the solve; destroyed, the problem is freed with the last reference to it.
        # Measured: without this every problem of a worker stayed alive (4 of 4 after 4 runs, gc.collect), and a
        # validity worker aborted after ~125 runs with MPICH's "Too many communicators (0/2048 free)"; with it, 0 of 4.
        problem.snes.destroy()


def _result(problem: PartnerProblem, stepper: LoadStepper) -> ContactResult:
    """The ContactResult of the final converged state."""
    opts = problem.options
    samples = problem.sample()
    patches = find_patches(samples, half=opts.symmetric_half)
    warns = problem.quality_warnings(samples, stepper.states[-1].d)
    P, Pp = problem.measure()
    body = {} if opts.body is None else dict(E=opts.E, nu=opts.nu, traction=opts.traction,
                                             formulation=opts.formulation, material_model=opts.material_model)
    options = dict(**body, degree=opts.degree, method=opts.method, kinematics=opts.kinematics,
                   kappa0=opts.kappa0, gamma0=opts.gamma0, theta=opts.theta,
                   control=opts.control, target=opts.target, n_steps=opts.n_steps, symmetric_half=opts.symmetric_half,
                   supports=problem.supports, quadrature_degree=problem.qdeg, sample_degree=problem.sdeg,
                   prefix=problem.prefix, predictor="hertz" if stepper.hertz is not None else "extrapolate",
                   **problem.method.options())
    records = stepper.records
    return ContactResult(ndofs=problem.ndofs, wall_time_s=stepper.wall_time_s,
                         newton_iterations=[r["iterations"] for r in records], load_steps=records,
                         d=float(stepper.states[-1].d), P=float(P), P_pressure=float(Pp), samples=samples,
                         patches=patches, u=problem.u, options=options, half=opts.symmetric_half,
                         forms=problem.forms, lame=problem.lame, snapshots=stepper.snapshots, warnings=warns,
                         pressure_field=problem.pressure_field, warm_start=warm_start_of(stepper),
                         nested_start=nested_start_of(problem, stepper), failed_solves=list(stepper.failures))
