"""The one place where a case run becomes solver options (a :class:`fem.options.ContactOptions` record).

Every caller (the case pipeline, the studies) goes through :func:`solver_options` and :func:`solve_run`. The
options are derived from the record by field name: a new field of :class:`cases.schema.Solver` that is a
ContactOptions field of the same name passes through with no line here (any other is a TypeError); the flat
names are sorted into the options' records by :meth:`fem.options.ContactOptions.from_fields`. Against a meshed
partner the run's body fields (E, nu, model, formulation, traction: :class:`fem.options.RigidBody`) are not
passed: the partner's bodies carry their materials.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import fields

from cases.schema import Run, effective_formulation
from fem.far_field import far_field_supports
from fem.options import ContactOptions
from vocabulary import RIGID
from workbench.scenes.base import LoadPath

__all__ = ["solver_options", "solve_run", "step_printer"]


def solver_options(run: Run, load: LoadPath, *, rigid: bool = True, **overrides) -> ContactOptions:
    """The solver options of ``run`` driven along ``load`` (``overrides``: any other ContactOptions field;
    ``rigid``: the partner is a rigid obstacle, so the options carry the run's body, :class:`fem.options.RigidBody`).

    Derived from the record, not written out: every field of the run's :class:`cases.schema.Solver` is the
    :class:`fem.options.ContactOptions` field of the same name (the bulk formulation's ``"auto"`` resolved by nu,
    :func:`cases.schema.effective_formulation`); the material (E in MPa, nu, model) and the element degree come
    from the run; control, target (N/mm or mm), steps, snapshots and the half model from ``load``; the supports
    from the geometry's ``far_field`` (None, the default, for ``"clamped"`` or a scene without a far field).
    Every other field keeps the record's default unless ``overrides`` names it.
    """
    names = ContactOptions.field_names()
    case_level = {f.name: getattr(run.solver, f.name) for f in fields(run.solver)}
    stray = sorted(set(case_level) - set(names))
    if stray:  # a new [solver] field must be a ContactOptions field of the same name (or be wired here)
        raise TypeError(f"cases.schema.Solver fields {stray} are not ContactOptions fields")
    opts = case_level | dict(
        E=run.material.E, nu=run.material.nu, material_model=run.material.model, degree=run.discretisation.degree,
        formulation=effective_formulation(run), control=load.control, target=load.target, n_steps=load.n_steps,
        symmetric_half=load.symmetric_half,
        supports=(load.supports if load.supports is not None else
                  far_field_supports(far_field=getattr(run.geometry, "far_field", "clamped"),
                                     symmetric_half=load.symmetric_half)))
    if load.record_at is not None:
        opts["record_at"] = load.record_at
    if not rigid:  # a meshed partner's bodies carry their materials: no field the two-body solve would ignore
        opts = {k: v for k, v in opts.items() if ContactOptions.section_of(k) != "body"}
    return ContactOptions.from_fields(opts | (load.solver or {}) | overrides, caller="solver_options")


def solve_run(run: Run, mesh_data, obstacle, load: LoadPath, *, case: str, on_step: Callable | None = None,
              frames: list | None = None, **overrides):
    """Solve one run's contact problem against its partner ``obstacle`` (a rigid curve or a meshed body,
    :func:`fem.solver.solve_contact`): :func:`solver_options` plus any study-specific ``overrides``
    (e.g. ``petsc_options``, ``predictor``, ``formulation``). ``frames``: a list that receives the converged
    state of every step (:class:`fem.output.Frame`, for the VTK time series); the result is the same."""
    from fem.partners import partner_kind
    from fem.solver import solve_contact

    options = solver_options(run, load, rigid=partner_kind(obstacle) == RIGID, on_step=on_step, case=case,
                             **overrides)
    if frames is None:
        return solve_contact(mesh_data, obstacle, options=options)
    from fem.output import solve_recording

    result, recorded = solve_recording(mesh_data, obstacle, options=options)
    frames.extend(recorded)
    return result


def step_printer(progress: Callable[[str], None], label: str) -> Callable[[dict], None]:
    """An ``on_step`` callback that prints one line per converged solve."""

    def on_step(rec: dict) -> None:
        progress(f"[{label}] {rec.get('kind', 'step')}: d = {rec['d']:.6g} mm, P = {rec['P']:.6g} N/mm, "
                 f"{rec['iterations']} Newton its, {rec['time']:.2f} s")

    return on_step
