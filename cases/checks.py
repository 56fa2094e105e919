"""Cross-field checks of a case's runs (after variant overrides): the loading against the scene, the model
hierarchy (:func:`vocabulary.model_conflict`, the rule the solver options are checked with too), the bulk
formulation, the error budget, the bands, the geometry keys a scene reads and the predictions it computes. Each
refusal is one line (:class:`cases.records.CaseError`).
"""

from __future__ import annotations

import re
from typing import Any

from cases.records import (
    BUDGET_SPAN,
    CONTROL_NEEDS,
    NU_DISPLACEMENT_MAX,
    NU_MIXED,
    CaseError,
    Run,
)
from cases.records import short_repr as _r
from cases.scene_schema import scene_schema, scene_schemas
from vocabulary import FINITE, LINEAR, model_conflict

__all__ = ["effective_formulation"]


def _check_run(run: Run, where: str) -> None:
    """Cross-field checks of one run (after variant overrides)."""
    g, ld = run.geometry, run.loading
    sch = scene_schema(g.scene)
    if g.indenter not in sch.indenters:
        if len(sch.indenters) == 1:
            raise CaseError(f"{where}: geometry.indenter must be {next(iter(sch.indenters))!r} for geometry.scene = "
                            f"{g.scene!r}")
        owner = next(s.name for s in scene_schemas() if g.indenter in s.indenters)
        raise CaseError(f"{where}: geometry.indenter = {g.indenter!r} needs geometry.scene = {owner!r}")
    if sch.check_geometry is not None:
        sch.check_geometry(run, where)
    if ld.control == "force":
        if (ld.P is None) == (ld.half_width is None):
            raise CaseError(f"{where}: loading needs exactly one of P (N/mm) or half_width (mm) for force control")
        if ld.d:
            raise CaseError(f"{where}: loading.d is only allowed with control = 'displacement'")
    else:
        if not ld.d:
            raise CaseError(f"{where}: loading.d (list of displacements in mm) is required for displacement control")
        if list(ld.d) != sorted(ld.d):
            raise CaseError(f"{where}: loading.d = {_r(list(ld.d))} must be increasing")
        if ld.P is not None or ld.half_width is not None:
            raise CaseError(f"{where}: loading.P/half_width are only allowed with control = 'force'")
    if ld.control not in sch.controls:
        allowed = ", ".join(f"{c!r} ({CONTROL_NEEDS[c]})" for c in sch.controls)
        raise CaseError(f"{where}: loading.control = {_r(ld.control)} is not supported by the {g.scene} scene; "
                        f"allowed: {allowed}")
    if sch.check_load is not None:
        sch.check_load(run, where)
    _check_formulation(run, where)
    _check_model(run, where)
    _check_budget(run, where)


def _scenes_that(flag: str) -> list[str]:
    """The registered scenes whose schema has ``flag`` (``finite``, ``mixed``; ``budget_widths`` None)."""
    if flag == "budget_widths":
        return [s.name for s in scene_schemas() if s.budget_widths is None]
    return [s.name for s in scene_schemas() if getattr(s, flag)]


def _check_model(run: Run, where: str) -> None:
    """The model hierarchy's combinations (``docs/models.md``): a hyperelastic material goes with finite
    kinematics and finite kinematics with a hyperelastic material, the obstacle traction, the displacement
    formulation and a scene that supports it (the options :func:`fem.options.check_model` checks again)."""
    model, sol = run.material.model, run.solver
    bad = model_conflict(kinematics=sol.kinematics, material_model=model, traction=sol.traction,
                         formulation=effective_formulation(run))
    if bad is not None and bad.allowed == (LINEAR,):
        raise CaseError(f"{where}: material.model = {_r(model)} needs solver.kinematics = 'finite' (got "
                        f"{_r(sol.kinematics)}); allowed with small or convective kinematics: model = 'linear'")
    if bad is not None and bad.name == "material_model":
        raise CaseError(f"{where}: solver.kinematics = 'finite' needs a hyperelastic material.model (got "
                        f"{_r(model)}); allowed: {', '.join(map(repr, bad.allowed))}")
    if bad is not None and bad.name == "traction":
        raise CaseError(f"{where}: solver.kinematics = 'finite' needs solver.traction = 'obstacle' (got "
                        f"{_r(sol.traction)}); allowed: 'obstacle' (traction along the obstacle's current normal)")
    if bad is not None:
        raise CaseError(f"{where}: solver.kinematics = 'finite' supports the displacement formulation only (got "
                        f"{_r(effective_formulation(run))}); allowed: formulation = 'displacement' or 'auto' with "
                        f"nu < {NU_MIXED}")
    if sol.kinematics == FINITE and not scene_schema(run.geometry.scene).finite:
        raise CaseError(f"{where}: solver.kinematics = 'finite' is not supported by the {_r(run.geometry.scene)} "
                        f"scene; allowed: scene = {' or '.join(repr(n) for n in _scenes_that('finite'))}")


def _check_budget(run: Run, where: str) -> None:
    """The error budget needs three distinct levels, and three distinct body sizes on a scene whose budget takes
    them (:attr:`SceneSchema.budget_widths`)."""
    d = run.discretisation
    if not d.budget_levels and not d.budget_widths:
        return
    why_not = scene_schema(run.geometry.scene).budget_widths
    able = _scenes_that("budget_widths")
    if why_not is not None and d.budget_widths:
        raise CaseError(f"{where}: discretisation.budget_widths = {_r(list(d.budget_widths))} is not supported by "
                        f"the {_r(run.geometry.scene)} scene ({why_not}); allowed: scene = "
                        f"{' or '.join(repr(n) for n in able)}")
    takes = why_not is None
    for name, seq in (("budget_levels", d.budget_levels), ("budget_widths", d.budget_widths))[:2 if takes else 1]:
        if len(seq) != 3 or len(set(seq)) != 3:
            raise CaseError(f"{where}: discretisation.{name} = {_r(list(seq))} is not allowed; allowed: exactly "
                            f"three distinct values ({' or '.join(able)} scenes: with both budget_levels and "
                            "budget_widths)")
    if max(d.budget_levels) > BUDGET_SPAN * min(d.budget_levels):
        raise CaseError(f"{where}: discretisation.budget_levels = {_r(list(d.budget_levels))} spans more than a "
                        f"factor {BUDGET_SPAN:g}; allowed: max <= {BUDGET_SPAN:g} min (the grading is refined with "
                        "h_c, so a wider span meshes the finest level far too densely)")


def effective_formulation(run: Run) -> str:
    """The bulk formulation a run is solved with: ``solver.formulation``, ``"auto"`` resolved by nu
    (``"mixed"`` from NU_MIXED on, else ``"displacement"``)."""
    f = run.solver.formulation
    if f == "auto":
        return "mixed" if run.material.nu >= NU_MIXED else "displacement"
    return f


def _check_formulation(run: Run, where: str) -> None:
    """nu -> 1/2: the displacement formulation locks; the mixed one needs degree 2 and an analytic obstacle."""
    nu, sol = run.material.nu, run.solver
    form = effective_formulation(run)
    if form == "displacement" and nu > NU_DISPLACEMENT_MAX:
        raise CaseError(f"{where}: solver.formulation = 'displacement' at material.nu = {nu!r} locks (volumetric "
                        f"locking; it diverged at nu = 0.4999); allowed: nu <= {NU_DISPLACEMENT_MAX}, or "
                        "formulation = 'mixed' or 'auto' (Taylor-Hood, degree = 2)")
    if form == "mixed":
        why = (f"material.nu = {nu!r} >= {NU_MIXED} needs the mixed formulation (formulation = 'auto')"
               if sol.formulation == "auto" else "solver.formulation = 'mixed'")
        if run.discretisation.degree < 2:
            raise CaseError(f"{where}: {why}, which needs discretisation.degree = 2 (Taylor-Hood P2/P1); "
                            "allowed: degree = 2")
        if not scene_schema(run.geometry.scene).mixed:
            raise CaseError(f"{where}: {why}, which needs an analytic obstacle ({' or '.join(_scenes_that('mixed'))} "
                            f"scenes); allowed on the {run.geometry.scene} scene: nu < {NU_MIXED}")
        if sol.linear_solver == "gamg":
            raise CaseError(f"{where}: solver.linear_solver = 'gamg' with the mixed formulation ({why}): a saddle "
                            "point; allowed: linear_solver = 'auto', 'lu' or 'lu_reuse'")


def _check_bands(case: Any, runs: tuple[Run, ...], where: str) -> None:
    """Band checks need the error budget (budget_levels) and name quantities the scene's budget has."""
    if not case.bands:
        return
    if not case.discretisation.budget_levels:
        raise CaseError(f"{where}: bands need the error budget; allowed: [bands] together with "
                        "discretisation.budget_levels (three levels)")
    notes = "; ".join(f"{s.name}: {s.band_note}" for s in scene_schemas() if s.band_note)
    for run in runs:
        allowed = scene_schema(run.geometry.scene).band_quantities
        for key, names in case.bands.items():
            for name in names:
                if re.sub(r"\[\d+\]$", "", name) not in allowed:
                    raise CaseError(f"{where}: bands.{key} = {_r(list(names))}: {_r(name)} is not a budget quantity "
                                    f"of the {run.geometry.scene} scene; allowed values: "
                                    f"{', '.join(repr(a) for a in allowed)}" + (f" ({notes})" if notes else ""))


def _check_used_geometry(run: Run, given: set, where: str) -> None:
    """A geometry key given but not read by the scene with this indenter is refused."""
    g = run.geometry
    used = scene_schema(g.scene).indenters.get(g.indenter, frozenset())
    for key in sorted(given - used - {"scene", "indenter"}):
        raise CaseError(f"{where}: geometry.{key} is not used by a {g.scene} scene with a {g.indenter} indenter; "
                        f"allowed keys: scene, indenter, {', '.join(sorted(used))}")


def _check_predictions(case: Any, runs: tuple[Run, ...], where: str) -> None:
    """Every listed prediction is one the scene computes for the indenter (an empty list: the scene's own); then
    each scene's case-level checks (:attr:`SceneSchema.check_case`)."""
    for run in runs:
        g = run.geometry
        allowed = scene_schema(g.scene).predictions.get(g.indenter, ())
        for name in case.analytic.predictions:
            if name not in allowed:
                raise CaseError(f"{where}: analytic.predictions = {_r(list(case.analytic.predictions))}: "
                                f"{_r(name)} is not computed for a {g.scene} scene with a {g.indenter} indenter; "
                                f"allowed values: {', '.join(repr(a) for a in allowed)}")
    for scene in dict.fromkeys(r.geometry.scene for r in runs):
        check = scene_schema(scene).check_case
        if check is not None:
            check(case, runs, where)


