"""``make emulate``: rerun the cases under what another machine would change, and hold every number to its class.

We cannot run on another CPU, so each perturbation below changes one thing a different machine changes,
reruns the cases (``workbench run CASE --ci``, or at the default level with ``--level run``) in subprocesses
into ``<out>/<perturbation>/``, and compares them with an unperturbed reference run (``<out>/reference/``):

* ``mesh``: ``WORKBENCH_MESH_PERTURB=1e-14``, the geometry reaching gmsh perturbed at 1e-14 (relative), which
  gives gmsh a different but equally valid mesh (the hook and the mesh fingerprint come with the mesh
  branch of issue 22; without the hook this run repeats the reference mesh);
* ``mumps_ordering``: MUMPS's fill-reducing ordering forced to AMD (``ICNTL(7) = 0``; PETSc's default lets
  MUMPS choose, AMF or METIS here) through ``PETSC_OPTIONS`` on every solver prefix (``fem_contact_<n>_``, n from 0,
  its Hertz predictor ``fem_contact_<n>_hertz_`` and the two-body solver ``fem_two_body_<n>_``: issue 34 found the
  two-body cases outside the perturbation until then). The first solver of every case writes its KSP view,
  and the run fails unless MUMPS reports ``INFOG(7) = 0`` (the ordering it really used);
* ``numpy_baseline``: ``NPY_DISABLE_CPU_FEATURES`` = every SIMD dispatch target numpy has on this CPU
  (``X86_V3 X86_V4 AVX512_ICL AVX512_SPR`` on the Intel Xeon here), so numpy runs its baseline kernels;
* ``openblas_kernel``: ``OPENBLAS_CORETYPE=Haswell``, OpenBLAS's AVX2 kernels (the BLAS of MUMPS's dense
  fronts). Issue 34: this is what another CPU changes. On this AVX-512 Xeon the CI-level
  ``halfplanes_wedge_beta_neg`` small run's patch centre (zero in theory) is -8.902759242e-5 mm with the
  machine's own kernels (= ``SkylakeX``), -8.902758063e-5 with ``Cooperlake`` and ``SapphireRapids``,
  -8.902757416e-5 with ``Haswell``, -8.902755340e-5 with ``Sandybridge``: moves of 1e-11 to 4e-11 mm, the class
  a new machine's ``make test`` failed on (4.5e-11 mm) while the portable regression measured a centre against
  itself (Haswell against SkylakeX: 2.0e-7 of itself, above the 1e-7 that failed it). Measured against the
  contact size (:func:`workbench.pipeline.number_classes.scale_of`) they are what they are, 2e-11 of it;
* ``h_contact`` (not in the default set; CI level only): the contact element size times 0.999, another valid
  mesh of the same case by another route, which is how the foreign-mesh tolerances were measured.

For each perturbation every verdict (the ``verdict`` class: pass flags, band checks, patch counts, and each
run's exit code) must equal the reference's, and every number must stay within its class tolerance
(:mod:`workbench.pipeline.number_classes`). The table gives, per perturbation and case, the worst
``moved / tolerance`` per class. Exit 1 if a verdict changed or a number exceeded its tolerance.

``python -m workbench.pipeline.portability [--cases a,b] [--perturb mesh,mumps_ordering,numpy_baseline]
[--level ci|run] [--out results/emulate] [--reference DIR]``
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import subprocess
import sys
from pathlib import Path
from typing import NamedTuple

from workbench.pipeline.key_numbers import key_numbers
from workbench.pipeline.number_classes import CLASSES, Move, compare_portable, worst_by_class

__all__ = ["Perturbation", "PERTURBATIONS", "DEFAULT_PERTURBATIONS", "CaseRun", "run_cases", "Outcome",
           "compare_runs", "table", "main"]

ROOT = Path(__file__).resolve().parents[2]
MUMPS_ORDERING = 0          # AMD
_N_PREFIXES = 200           # solver prefixes fem_contact_0_ ... covered by the ordering option


class Perturbation(NamedTuple):
    """One thing another machine changes: extra environment variables, or (``h_scale``) the mesh size."""

    name: str
    what: str
    env: dict
    h_scale: float = 1.0


def _numpy_dispatch_targets() -> list[str]:
    """numpy's SIMD dispatch targets that this CPU runs (what ``NPY_DISABLE_CPU_FEATURES`` may switch off)."""
    from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__

    return [f for f in __cpu_dispatch__ if __cpu_features__.get(f)]


SOLVER_PREFIXES = ("fem_contact_{i}_", "fem_contact_{i}_hertz_", "fem_two_body_{i}_")
"""The PETSc options prefixes of every solver: the rigid contact problem, its Hertz predictor, two bodies."""


def _mumps_options() -> str:
    opts = ["-options_left 0"]
    for i in range(_N_PREFIXES):
        opts += [f"-{prefix.format(i=i)}mat_mumps_icntl_7 {MUMPS_ORDERING}" for prefix in SOLVER_PREFIXES]
    return " ".join(opts)


PERTURBATIONS = {
    "mesh": Perturbation("mesh", "geometry reaching gmsh perturbed at 1e-14", {"WORKBENCH_MESH_PERTURB": "1e-14"}),
    "mumps_ordering": Perturbation("mumps_ordering", f"MUMPS ordering ICNTL(7) = {MUMPS_ORDERING} (AMD)",
                                   {"PETSC_OPTIONS": _mumps_options()}),
    "numpy_baseline": Perturbation("numpy_baseline", "numpy SIMD dispatch off",
                                   {"NPY_DISABLE_CPU_FEATURES": " ".join(_numpy_dispatch_targets())}),
    "openblas_kernel": Perturbation("openblas_kernel", "OpenBLAS Haswell kernels (MUMPS's dense BLAS)",
                                    {"OPENBLAS_CORETYPE": "Haswell"}),
    "h_contact": Perturbation("h_contact", "contact element size x 0.999 (another valid mesh)", {}, 0.999),
}
DEFAULT_PERTURBATIONS = ("mesh", "mumps_ordering", "numpy_baseline", "openblas_kernel")


class CaseRun(NamedTuple):
    """One case's run: its exit code (0 PASS, 1 tolerance FAIL, else failed) and a note (e.g. a check)."""

    case: str
    code: int
    note: str = ""


def run_cases(out: Path, *, cases: list[str], level: str = "ci", perturbation: Perturbation | None = None,
              timeout: float = 3600.0) -> list[CaseRun]:
    """Run every case into ``out`` (``workbench run``; one subprocess each, with the perturbation's env)."""
    import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
    from cases import load_case

    out = Path(out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    runs = []
    for name in cases:
        env = {**os.environ, "PYTHONPATH": os.environ.get("PYTHONPATH", str(ROOT))}
        cmd = [sys.executable, "-m", "workbench", "run", name, "--out", str(out)]
        view = out / f"ksp_view_{name}.txt"
        if perturbation is not None:
            env.update(perturbation.env)
            if perturbation.name == "mumps_ordering":  # the first solver of either kind reports its ordering
                env["PETSC_OPTIONS"] += (f" -fem_contact_0_ksp_view ascii:{view}"
                                         f" -fem_two_body_0_ksp_view ascii:{view.with_suffix('.two_body.txt')}")
        if perturbation is not None and perturbation.h_scale != 1.0:
            d = load_case(name).discretisation
            base = (d.ci_level or d.h_contact) if level == "ci" else d.h_contact
            cmd += ["--h-contact", repr(base * perturbation.h_scale)]
        elif level == "ci":
            cmd.append("--ci")
        proc = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=timeout, cwd=out)
        (out / f"{name}.log").write_text(proc.stdout + proc.stderr)
        note = ""
        if perturbation is not None and perturbation.name == "mumps_ordering":
            text = "".join(f.read_text() for f in (view, view.with_suffix(".two_body.txt")) if f.is_file())
            used = re.findall(r"INFOG\(7\) \(ordering option effectively used after analysis\):\s*(-?\d+)", text)
            note = f"MUMPS INFOG(7) = {','.join(sorted(set(used))) or 'not reported'}"
            if set(used) != {str(MUMPS_ORDERING)}:
                note += " (ordering NOT applied)"
        runs.append(CaseRun(name, proc.returncode, note))
    return runs


class Outcome(NamedTuple):
    """A perturbation's comparison with the reference: the moves, the changed verdicts, the run notes."""

    perturbation: str
    moves: list[Move]
    verdict_changes: list[str]
    notes: dict

    @property
    def ok(self) -> bool:
        return not self.verdict_changes and all(m.ok for m in self.moves)


def compare_runs(name: str, ref_dir: Path, ref_runs: list[CaseRun], new_dir: Path,
                 new_runs: list[CaseRun]) -> Outcome:
    """Compare a perturbed run folder with the reference (numbers by class, verdicts exactly)."""
    moves = compare_portable(key_numbers(new_dir), key_numbers(ref_dir), allow_new=False)
    changes = [f"{mv.key}: {mv.old!r} -> {mv.new!r}" for mv in moves if mv.cls == "verdict" and not mv.ok]
    ref_codes = {r.case: r.code for r in ref_runs}
    for r in ref_runs:
        if r.code not in (0, 1):
            changes.append(f"{r.case}: the reference run failed (exit {r.code}, see {ref_dir / (r.case + '.log')})")
    for r in new_runs:
        if r.code not in (0, 1):
            changes.append(f"{r.case}: the run failed (exit {r.code}, see {new_dir / (r.case + '.log')})")
        elif r.code != ref_codes.get(r.case):
            changes.append(f"{r.case}: exit {ref_codes.get(r.case)} -> {r.code}")
        if "NOT applied" in r.note:
            changes.append(f"{r.case}: {r.note}")
    notes = {r.case: r.note for r in new_runs if r.note}
    for r in new_runs:  # bit-identical numbers: said, not failed (numpy's SIMD may not touch a case at all)
        mine = [mv for mv in moves if mv.key.startswith(f"{r.case}/")]
        if mine and all(mv.moved == 0 for mv in mine):
            notes[r.case] = (notes.get(r.case, "") + "; " if r.case in notes else "") + \
                "every number bit-identical to the reference (perturbation without effect here)"
    return Outcome(name, moves, changes, notes)


def _cell(mv: Move | None) -> str:
    if mv is None:
        return "-"
    r = mv.ratio
    mark = "" if mv.ok else " ✗"
    return f"{r:.2g}{mark}" if math.isfinite(r) else f"inf{mark}"


def table(outcomes: list[Outcome]) -> str:
    """Markdown: per perturbation and case, the worst ``moved / tolerance`` per class (✗ above 1), whether
    the mesh differs, the verdicts; then every number that exceeded its tolerance and every changed verdict."""
    classes = [c for c in CLASSES if c != "excluded"]
    lines = ["| perturbation | case | mesh | verdicts | " + " | ".join(classes) + " |",
             "|---|---|---|---|" + "---|" * len(classes)]
    bad = []
    for oc in outcomes:
        worst = worst_by_class(oc.moves)
        for case in sorted({mv.key.split("/", 1)[0] for mv in oc.moves}):
            nd = [mv for mv in oc.moves if mv.key.startswith(f"{case}/") and mv.key.endswith("/ndofs")]
            differs = [mv for mv in nd if mv.old != mv.new]
            mesh = ("differs (" + ", ".join(f"{mv.old:.0f}->{mv.new:.0f}" for mv in differs) + ")" if differs
                    else "same dofs")
            changed = [c for c in oc.verdict_changes if c.startswith(f"{case}/") or c.startswith(f"{case}:")]
            verdicts = "CHANGED" if changed else "same"
            lines.append(f"| {oc.perturbation} | {case} | {mesh} | {verdicts} | "
                         + " | ".join(_cell(worst.get((case, c))) for c in classes) + " |")
        bad += [f"{oc.perturbation}: {c}" for c in oc.verdict_changes]
        bad += [f"{oc.perturbation}: {mv.key} [{mv.cls}] {mv.old!r} -> {mv.new!r} (moved {mv.moved:.3g}, "
                f"tolerance {mv.tolerance:.3g}{', ' + mv.note if mv.note else ''})" for mv in oc.moves if not mv.ok]
    notes = [f"- {oc.perturbation}, {case}: {note}" for oc in outcomes for case, note in sorted(oc.notes.items())]
    out = lines + [""]
    if notes:
        out += ["Checks of the perturbation itself:", *notes, ""]
    out += (["Exceeded or changed:", *[f"- {b}" for b in bad]] if bad
            else ["Every verdict unchanged, every number within its class tolerance."])
    return "\n".join(out) + "\n"


def main(argv: list[str] | None = None) -> int:
    from cases import case_names

    p = argparse.ArgumentParser(prog="python -m workbench.pipeline.portability", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--cases", default="", help="comma-separated case names (default: every case)")
    p.add_argument("--perturb", default=",".join(DEFAULT_PERTURBATIONS),
                   help=f"comma-separated, of {', '.join(PERTURBATIONS)}")
    p.add_argument("--level", choices=("ci", "run"), default="ci")
    p.add_argument("--out", type=Path, default=ROOT / "results" / "emulate")
    p.add_argument("--reference", type=Path, default=None,
                   help="an existing unperturbed run folder of the same level (default: run one into OUT/reference)")
    args = p.parse_args(argv)
    known = case_names()
    cases = [c for c in args.cases.split(",") if c] or known
    if bad := [c for c in cases if c not in known]:
        print(f"error: --cases {','.join(bad)} unknown; allowed: {', '.join(known)}", file=sys.stderr)
        return 2
    perts = [x for x in args.perturb.split(",") if x]
    if bad := [x for x in perts if x not in PERTURBATIONS] or not perts:
        print(f"error: --perturb {','.join(bad)} unknown; allowed: {', '.join(PERTURBATIONS)}", file=sys.stderr)
        return 2
    if args.level == "run" and "h_contact" in perts:
        print("error: --perturb h_contact is for --level ci only (a changed h_contact skips the budget)",
              file=sys.stderr)
        return 2
    if args.reference is not None and not args.reference.is_dir():
        print(f"error: --reference {args.reference} is not a folder; allowed: a run folder of the same level",
              file=sys.stderr)
        return 2
    if args.reference is None:
        ref_dir = args.out / "reference"
        print(f"reference: {len(cases)} case(s) at level {args.level} -> {ref_dir}", flush=True)
        ref_runs = run_cases(ref_dir, cases=cases, level=args.level)
    else:
        ref_dir = args.reference
        codes = {}
        for c in cases:
            f = ref_dir / c / "metrics.json"
            codes[c] = (0 if json.loads(f.read_text()).get("pass") else 1) if f.is_file() else -1
        ref_runs = [CaseRun(c, codes[c]) for c in cases]
    outcomes = []
    for name in perts:
        pert = PERTURBATIONS[name]
        print(f"{name}: {pert.what} -> {args.out / name}", flush=True)
        runs = run_cases(args.out / name, cases=cases, level=args.level, perturbation=pert)
        outcomes.append(compare_runs(name, ref_dir, ref_runs, args.out / name, runs))
    text = table(outcomes)
    print(text)
    (args.out / "emulate.md").write_text(f"# Emulated other machine ({args.level} level)\n\n" + text)
    return 0 if all(oc.ok for oc in outcomes) else 1


if __name__ == "__main__":
    sys.exit(main())
