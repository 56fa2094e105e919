"""What an external result may name: the runs, the reported steps and the bodies of a case, and which group of
samples is which (strict, one line per refusal).

**Runs.** An external code runs the case's physics, not the workbench's numerics. The case's runs that differ only in
the workbench's own choices (the pairing, mesh ratios, the apex treatment, the convection model, the half model:
:data:`NUMERICS`; method, penalty and solver settings) are one benchmark run; runs that differ in physics (the
wedge's two angles) are separate benchmark runs, and so are runs of different kinematics. A benchmark run's label
(:func:`benchmark_runs`) is

* its kinematics (``small``, ``convective``) where the case has one scene (one geometry, material and loading), so
  ``hertz_cylinder``'s run is ``small``, ``parabola_convective``'s ``small`` and ``convective``, ``patch_test``'s
  ``small`` (its mortar and node-to-segment runs are the workbench's two pairings of one problem);
* the case's own variant label where the case has several scenes (``wedge``: ``theta=pi/20``, ``theta=pi/5``).

The case's own labels (``base``, ``mortar``, ``node-to-segment``, ``theta=pi/5`` ...) are accepted as aliases. Where a
finite-strain comparison is fair (a scene of the workbench with finite kinematics, or a case with a convective run: a
finite-strain code's answer to the convective question) and the case has one scene, a ``finite`` run may be added
(``ScoredRun.added``): scored with the same measures, its ratio to the small run against the convective theory.

**Steps.** :func:`schedule`: a force-controlled case reports its target load (one step, index 0); a
displacement-controlled case every displacement of ``[loading] d`` (index i = the i-th, in order).

**Bodies.** The scorer of each scene says which bodies' surfaces it scores (:attr:`Body` role ``slave``, the one the
case's verdict reads, or ``master``) and the names a file may use for them.
"""

from __future__ import annotations

import dataclasses
from typing import NamedTuple

from cases.schema import Case, Run
from workbench.external.results import ExternalResult, ResultError, group_name, label_shown

__all__ = ["NUMERICS", "ScoredRun", "ReportStep", "ScoredBody", "Group", "benchmark_runs", "schedule", "assign"]

NUMERICS = frozenset({"pairing", "size_ratio", "apex", "convection", "half_model", "far_field"})
"""Geometry fields that are the workbench's numerics, not the problem's physics."""


class ScoredRun(NamedTuple):
    """One benchmark run of a case.

    Attributes:
        label: its label in results and ``score.json``.
        kinematics: ``small``, ``convective`` or ``finite``.
        run: the case run whose scene (geometry, materials, loading) it is (for ``finite``: the small run's).
        physics: the scene's label where the case has several scenes (the model bands' prefix), else None.
        aliases: the other labels a file may give it (the case's own run labels).
        added: a finite run the case itself does not carry.
    """

    label: str
    kinematics: str
    run: Run
    physics: str | None
    aliases: tuple[str, ...] = ()
    added: bool = False


class ReportStep(NamedTuple):
    """One reported step: its index, the control (``force``: ``value`` is P, N/mm; ``displacement``: d, mm)."""

    index: int
    control: str
    value: float


class ScoredBody(NamedTuple):
    """A body whose contact surface a result may sample: its name, its role (``slave``: read by the verdict;
    ``master``: information) and the other names a file may use."""

    name: str
    role: str
    aliases: tuple[str, ...] = ()


class Group(NamedTuple):
    """One (run, step, body) group of samples of one level (one file)."""

    run: ScoredRun
    step: int
    body: ScoredBody
    result: ExternalResult


def _physics(run: Run) -> tuple:
    geo = {k: v for k, v in dataclasses.asdict(run.geometry).items() if k not in NUMERICS}
    return (repr(sorted(geo.items())), repr(run.loading), repr(run.material), repr(run.bodies))


def benchmark_runs(case: Case, *, finite: bool) -> tuple[ScoredRun, ...]:
    """The benchmark runs of ``case`` (module docstring); ``finite``: the scene allows an added finite run."""
    groups: dict[tuple, list[Run]] = {}
    for run in case.runs():
        groups.setdefault(_physics(run), []).append(run)
    several = len(groups) > 1
    out: list[ScoredRun] = []
    for runs in groups.values():
        by_kin: dict[str, list[Run]] = {}
        for run in runs:
            by_kin.setdefault(run.solver.kinematics, []).append(run)
        for kin, members in by_kin.items():
            aliases = tuple(r.label for r in members)
            if several:
                label = members[0].label
                out.append(ScoredRun(label, kin, members[0], label, tuple(a for a in aliases if a != label)))
            else:
                out.append(ScoredRun(kin, kin, members[0], None, tuple(a for a in aliases if a != kin)))
    kinds = {r.kinematics for r in out}
    if finite and not several and "finite" not in kinds:
        small = next((r for r in out if r.kinematics == "small"), out[0])
        out.append(ScoredRun("finite", "finite", small.run, None, (), added=True))
    return tuple(out)


def schedule(run: Run, *, target_load: float | None) -> tuple[ReportStep, ...]:
    """The reported steps of a run (module docstring); ``target_load``: the force-controlled target P (N/mm)."""
    ld = run.loading
    if ld.control == "displacement":
        return tuple(ReportStep(i, "displacement", float(d)) for i, d in enumerate(ld.d))
    return (ReportStep(0, "force", float(target_load)),)


def _describe(steps: tuple[ReportStep, ...]) -> str:
    if steps[0].control == "force":
        return f"step 0: the target load P = {steps[0].value:.6g} N/mm"
    ds = ", ".join(f"{s.value:g}" for s in steps)
    return f"steps 0 to {len(steps) - 1}: d = {ds} mm"


def _given(value, i: int):
    """The option value for the i-th RESULT (one per RESULT, or one for all), or None."""
    if value is None:
        return None
    return value[0] if len(value) == 1 else value[i]


def _find(label: str, runs: tuple[ScoredRun, ...]) -> ScoredRun | None:
    for r in runs:
        if label == r.label or label in r.aliases:
            return r
    return None


def assign(case: Case, results: list[list[ExternalResult]], *, runs: tuple[ScoredRun, ...],
           steps: dict[str, tuple[ReportStep, ...]], bodies: tuple[ScoredBody, ...], run_option=None,
           step_option=None, body_option=None) -> list[list[Group]]:
    """Every group of every RESULT (``results[i]``: the groups of the i-th file) as a (run, step, body) of the
    case; ``*_option``: the ``--run/--step/--body`` values (one per RESULT or one for all) for files without the
    column. ResultError (one line naming the file) for a label, step or body that is not the case's, an option for
    a file that has the column, a missing one where the case needs it, or a (run, step, body) twice in one file."""
    labels = ", ".join(r.label for r in runs)
    alias_text = "; ".join(f"{r.label}: {', '.join(r.aliases)}" for r in runs if r.aliases)
    out = []
    for i, groups in enumerate(results):
        seen = set()
        level = []
        for g in groups:
            where = f"{g.path} ({group_name(g)})" if len(groups) > 1 else g.path
            opt = {"run": _given(run_option, i), "step": _given(step_option, i), "body": _given(body_option, i)}
            for key in ("run", "step", "body"):
                if opt[key] is not None and getattr(g, key) is not None:
                    raise ResultError(f"{where}: has a {key} column and --{key} was given for it; allowed: --{key} "
                                      f"only for a file without a {key} column")
            label = g.run if g.run is not None else opt["run"]
            if label is None:
                own = [r for r in runs if not r.added]
                if len(own) != 1:
                    raise ResultError(f"{where}: no run column, and case {case.name} has the runs {labels}; allowed: "
                                      "a run column or --run")
                srun = own[0]
            else:
                srun = _find(str(label), runs)
                if srun is None:
                    raise ResultError(f"{where}: run {label_shown(str(label))!r} is not a run of case {case.name}; "
                                      f"allowed: {labels}" + (f" (aliases {alias_text})" if alias_text else ""))
            sched = steps[srun.label]
            step = g.step if g.step is not None else opt["step"]
            if step is None:
                if len(sched) != 1:
                    raise ResultError(f"{where}: no step column, and run {srun.label} of case {case.name} reports "
                                      f"{len(sched)} steps ({_describe(sched)}); allowed: a step column or --step")
                step = 0
            if not 0 <= int(step) < len(sched):
                raise ResultError(f"{where}: step {step} is outside the schedule of case {case.name} "
                                  f"({_describe(sched)})")
            name = g.body if g.body is not None else opt["body"]
            if name is None:
                body = next(b for b in bodies if b.role == "slave")
            else:
                body = next((b for b in bodies if name == b.name or name in b.aliases), None)
                if body is None:
                    allowed = ", ".join(f"{b.name}" + (f" ({'/'.join(b.aliases)})" if b.aliases else "")
                                        for b in bodies)
                    raise ResultError(f"{where}: body {label_shown(str(name))!r} is not a body of case {case.name} "
                                      f"whose contact pressure is scored; allowed: {allowed}")
            key = (srun.label, int(step), body.name)
            if key in seen:
                raise ResultError(f"{where}: run {srun.label}, step {step}, body {body.name} appears twice (under "
                                  "two of its names); allowed: once per file")
            seen.add(key)
            level.append(Group(srun, int(step), body, g._replace(run=srun.label, step=int(step), body=body.name)))
        out.append(level)
    return out
