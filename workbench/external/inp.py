"""Any benchmark as a CalculiX/Abaqus ``.inp`` deck: 2D plane strain, frictionless penalty contact.

:func:`inp_deck` writes the deck of one :class:`workbench.external.benchmark.Benchmark` level and one of its runs
from the benchmark's :class:`workbench.external.mesh_model.MeshModel` (units mm, N, MPa; thickness 1 mm, so
forces are N per mm of thickness); :func:`ccx_runs` says which runs CalculiX models and how, and why not the
others; :func:`write` is the ``inp`` format of ``workbench export`` (registered in :mod:`workbench.external.writers`).

* nodes: the model's, quadratic (:func:`quadratic_model`: a node at the middle of every edge, moved onto the
  exact surface on the benchmark's curved surfaces, :func:`workbench.external.benchmarks.surfaces.quadratic`),
  with 13 significant digits at most (CalculiX reads 20 characters per field and cuts a longer one silently);
* every body its own ``*ELEMENT, TYPE=CPE6, ELSET=E_<BODY>`` (gmsh and Abaqus number the six nodes the same way;
  the model's triangles are counter-clockwise) and its own material: ``*ELASTIC E, nu`` for small strain, and
  under ``NLGEOM`` the run's hyperelastic law: ``*HYPERELASTIC, NEO HOOKE`` with ``C10 = mu/2``, ``D1 = 2/K``
  (``K = lambda + 2 mu/3``: CalculiX's neo-Hooke, ``W = C10 (I1bar - 3) + (J - 1)^2 / D1``, is not the
  workbench's Ciarlet-Simo form, ``docs/models.md``; the two agree to first order in the strain) or ``*ELASTIC``
  (Saint Venant-Kirchhoff under ``NLGEOM``). A rigid body gets an elastic material too (every one of its nodes is
  prescribed: it carries no strain; the stiffest elastic body's E);
* supports (:class:`Support`): ``*BOUNDARY N_<GROUP>, i, i, 0.`` for each held component (1-based in the deck);
* the drive (:class:`Drive`): a rigid body's every node moves by ``u = d * direction`` (both components
  prescribed: a rigid translation, as a ``*RIGID BODY`` would: measured on hertz_cylinder, the same pressures to the
  last digit); an elastic body's driven facet group gets the components :attr:`Drive.components`. Each value of
  ``d`` is one loading ``*STEP`` (a displacement schedule: every reported step; a force-controlled case's
  calibrated approach is one value), ramped from the previous one: in one increment for small strain (frictionless
  small-strain contact does not depend on the path), in increments of at most a quarter of the step under
  ``NLGEOM``. Each loading step is followed by a HOLD step (the same displacements, one increment) that alone
  writes output (deck step ``2 k + 2`` reports ``d[k]``, :func:`report_steps`). Why: CalculiX builds its contact
  elements from the geometry at the start of an increment, and CPRESS is the contact force per slave area of THAT
  geometry, so what the last increment started from decides what CPRESS is a force per. Measured on hertz_cylinder
  (h_c = a/10, rigid circle), p at the centre per reference length: 5670.7 MPa read as per current length after
  one increment (it was per reference length: 5741.5), 5720.7 / 5731.9 / 5739.2 / 5740.2 in 2 / 4 / 20 / 50
  increments (the error goes as 1/n), 5741.1 with the hold step (2 more iterations; the 1/n extrapolation 5740.9).
  One increment alone is no way out: where its converged state has tensile contact springs, CalculiX appends a
  zero-size increment ("pressure ratio ... zero-size increment is appended") whose contact elements come from that
  wrong intermediate state (measured: h_c = a/40, 5760 MPa); the hold step starts from the converged state. The
  hold step's CPRESS is a force per current area (:func:`workbench.external.frd.chain_pressure` turns it into a
  force per reference length): the contact is CalculiX's finite-sliding one, in the current configuration. On the
  patch test it leaves a spike at the free end of the interface (+0.46 %, +0.84 %, +1.7 % at h = W/7, W/14, W/28;
  1.7e-4 to 8e-4 elsewhere); the same deck in one increment from the reference geometry is uniform to 5.6e-7 (its
  CPRESS then per reference length: no zero-size increment was appended there);
* contact: one ``*CONTACT PAIR`` per :class:`ContactPair`, slave the pair's slave surface (element faces of the
  slave body), master the master surface; frictionless (no ``*FRICTION``); ``*SURFACE BEHAVIOR,
  PRESSURE-OVERCLOSURE=LINEAR`` with the penalty slope ``K = kappa E_min / h_contact`` (MPa/mm, ``E_min`` the
  smaller Young's modulus of the pair's elastic bodies). ``contact``: ``"surface_to_surface"`` (default;
  CalculiX's segment-to-segment penalty, integrated on the slave faces) or ``"node_to_surface"`` (a penalty
  spring at each slave node). CalculiX's ``TYPE=MORTAR`` does not run on plane elements (2.20: ``*ERROR in
  catsmpcslavno: slave node ... is connected als dependent node in a MPC``: the plane elements are expanded to
  3D ones tied by MPCs);
* kinematics: a run whose kinematics is ``small`` is a small-strain step; ``convective`` or ``finite`` gets
  ``*STEP, NLGEOM`` (finite strain, total Lagrangian, contact at the current positions): CalculiX's nearest model
  to the convective theory (small strain with the contact read at the displaced points), not that theory;
* output at the end of every hold step only (``FREQUENCY=0`` in the loading steps; in the hold steps the step's
  increment limit: CalculiX always writes a step's last increment): ``*NODE FILE U, RF`` and ``*CONTACT FILE
  CSTR`` (the ``.frd``), ``*NODE PRINT, NSET=DRIVE, TOTALS=ONLY RF`` (the ``.dat``: the load each step carries is
  the drive set's reaction along ``direction``, doubled for a half model).

Names in the deck: ELSETs and materials are the body names in capitals (``E_``/``M_`` prefixed); NSETs
``N_<GROUP>``; surfaces ``S_<GROUP>``; the drive set ``DRIVE``. Face labels of 2D elements in ``*SURFACE,
TYPE=ELEMENT``: S1 = nodes 1-2, S2 = 2-3, S3 = 3-1, as in the CalculiX 2.20 manual's element face tables.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from pathlib import Path
from typing import NamedTuple

import numpy as np

__all__ = ["inp_deck", "ccx_runs", "Modelled", "quadratic_model", "first_approach", "write", "cannot",
           "CONTACT_TYPES", "KAPPA", "deck_name", "finite_law", "report_steps"]

KAPPA = 50.0  # penalty slope K = KAPPA E / h_contact (MPa/mm): the penetration p h / (50 E) is 2e-4 h at p = E/100
CONTACT_TYPES = {"surface_to_surface": "SURFACE TO SURFACE", "node_to_surface": "NODE TO SURFACE"}
_FACES = ((0, 1), (1, 2), (2, 0))  # CPE6 faces S1, S2, S3 by their corner nodes


def deck_name(name: str) -> str:
    """A group or body name as a deck name: capitals, ``[A-Z0-9_]`` only (``contact_lower`` -> ``CONTACT_LOWER``)."""
    return re.sub(r"[^A-Z0-9_]", "_", name.upper())


def _elastic(E: float, nu: float, law: str) -> list[str]:
    """The ``*ELASTIC`` or ``*HYPERELASTIC, NEO HOOKE`` card of a material (module docstring)."""
    if law == "neo_hookean":
        mu = E / (2.0 * (1.0 + nu))
        K = E / (3.0 * (1.0 - 2.0 * nu))
        return ["*HYPERELASTIC, NEO HOOKE", f"{_num(mu / 2.0)}, {_num(2.0 / K)}"]
    return ["*ELASTIC", f"{_num(E)}, {_num(nu)}"]


def _surface(model, group: str, body_cells: np.ndarray, offset: int) -> list[str]:
    """The element faces (``<element>, S<k>``) of a facet group on the given cells (1-based element ids from
    ``offset + 1``); ValueError if a facet is no face of those cells."""
    faces = {}
    for e, row in enumerate(body_cells):
        for f, (i, j) in enumerate(_FACES):
            faces[frozenset((int(row[i]), int(row[j])))] = (offset + e + 1, f + 1)
    out = []
    for edge in model.facets[group]:
        key = frozenset((int(edge[0]), int(edge[1])))
        if key not in faces:
            raise ValueError(f"surface {group!r}: the facet {tuple(int(v) for v in edge[:2])} is no face of its body")
        e, f = faces[key]
        out.append(f"{e}, S{f}")
    return out


def inp_deck(benchmark, model, *, run, d: float | Sequence[float], contact: str = "surface_to_surface",
             kappa: float = KAPPA, increments: int = 200, title: str = "") -> str:
    """The ``.inp`` text of ``benchmark`` (one level) for ``run`` (one of ``benchmark.runs``) at the approach(es)
    ``d`` (mm along ``benchmark.drive.direction``; a sequence: one ``*STEP`` each). See the module docstring.

    Raises:
        ValueError: a group the benchmark names is not in the model, a contact surface is no face of its body,
            an unknown ``contact`` type.
    """
    if contact not in CONTACT_TYPES:
        raise ValueError(f"contact = {contact!r}; allowed: {', '.join(CONTACT_TYPES)}")
    steps = [float(d)] if np.ndim(d) == 0 else [float(v) for v in d]
    if not steps:
        raise ValueError("d: no approach given; allowed: one value or a schedule")
    model = model.quadratic()
    drive = benchmark.drive
    elastic = [b for b in benchmark.bodies if not b.rigid]
    law = finite_law(run) if run.kinematics != "small" else "linear"
    for name in [b.cells for b in benchmark.bodies]:
        if name not in model.cells:
            raise ValueError(f"body cells {name!r} are not in the mesh; its cell groups: {sorted(model.cells)}")
    needed = [s.group for s in benchmark.supports] + [g for p in benchmark.pairs for g in (p.slave, p.master)]
    needed += [drive.group] if drive.group else []
    for name in needed:
        if name not in model.facets:
            raise ValueError(f"group {name!r} is not in the mesh; its facet groups: {sorted(model.facets)}")

    out = ["*HEADING", title or f"{benchmark.case} level {benchmark.level:g} run {run.label} (workbench)",
           "** units: mm, N, MPa; plane strain, thickness 1 mm; frictionless contact", "*NODE, NSET=NALL"]
    out += [f"{i + 1}, {_num(x)}, {_num(y)}" for i, (x, y) in enumerate(model.nodes)]
    offsets, e0 = {}, 0
    for b in benchmark.bodies:
        cells = model.cells[b.cells]
        offsets[b.name] = e0
        out.append(f"*ELEMENT, TYPE=CPE6, ELSET=E_{deck_name(b.name)}")
        out += [f"{e0 + k + 1}, " + ", ".join(str(int(n) + 1) for n in row) for k, row in enumerate(cells)]
        e0 += len(cells)

    def nset(name: str, ids) -> list[str]:
        return [f"*NSET, NSET={name}", *_lines(np.asarray(ids) + 1)]

    for g in dict.fromkeys(s.group for s in benchmark.supports):
        out += nset(f"N_{deck_name(g)}", model.group_nodes(g))
    if drive.group is None:  # a rigid body: every node of it
        out += nset("DRIVE", model.group_nodes(benchmark.body(drive.body).cells))
    else:
        out += nset("DRIVE", model.group_nodes(drive.group))
    surfaces = {}
    for p in benchmark.pairs:
        for group, body in ((p.slave, p.slave_body), (p.master, p.master_body)):
            if group not in surfaces:
                b = benchmark.body(body)
                surfaces[group] = _surface(model, group, model.cells[b.cells], offsets[b.name])
    for group, faces in surfaces.items():
        out += [f"*SURFACE, NAME=S_{deck_name(group)}, TYPE=ELEMENT", *faces]
    stiff = max(b.material.E for b in elastic)
    for b in benchmark.bodies:
        name = deck_name(b.name)
        mat = b.material
        out += [f"*MATERIAL, NAME=M_{name}", *(_elastic(stiff, 0.3, "linear") if b.rigid
                                               else _elastic(mat.E, mat.nu, law)),
                f"*SOLID SECTION, ELSET=E_{name}, MATERIAL=M_{name}", "1."]
    for k, p in enumerate(benchmark.pairs):
        E_min = min(benchmark.body(n).material.E for n in (p.slave_body, p.master_body)
                    if not benchmark.body(n).rigid)
        out += [f"*SURFACE INTERACTION, NAME=I{k + 1}", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
                f"{_num(kappa * E_min / benchmark.h_contact)}, 0."]
        out += [f"*CONTACT PAIR, INTERACTION=I{k + 1}, TYPE={CONTACT_TYPES[contact]}",
                f"S_{deck_name(p.slave)}, S_{deck_name(p.master)}"]
    out.append("*BOUNDARY")
    for s in benchmark.supports:
        out += [f"N_{deck_name(s.group)}, {c + 1}, {c + 1}, 0." for c in s.components]
    comps = (0, 1) if drive.group is None else tuple(drive.components)
    none, every = "FREQUENCY=0", f"FREQUENCY={int(increments)}"  # no output; the end of the step only
    output = {False: [f"*NODE FILE, {none}", "U", f"*CONTACT FILE, {none}", "CSTR",
                      f"*NODE PRINT, NSET=DRIVE, TOTALS=ONLY, {none}", "RF"],
              True: [f"*NODE FILE, {every}", "U, RF", f"*CONTACT FILE, {every}", "CSTR",
                     f"*NODE PRINT, NSET=DRIVE, TOTALS=ONLY, {every}", "RF"]}

    def step(*, value: float | None, nlgeom: bool, control: str, write: bool) -> list[str]:
        head = [f"*STEP, INC={int(increments)}{', NLGEOM' if nlgeom else ''}", "*STATIC", control]
        drive_lines = [] if value is None else ["*BOUNDARY"] + [
            f"DRIVE, {c + 1}, {c + 1}, {_num(value * drive.direction[c])}" for c in comps]
        return head + drive_lines + output[write] + ["*END STEP"]

    finite = run.kinematics != "small"
    # small strain: one increment per loading step (frictionless small-strain contact does not depend on the path;
    # measured on elastic_cylinder_dissimilar at h = a/40: 25 iterations and 21 s against 91 and 62 s in eight
    # increments); finite strain: increments of at most a quarter of the step
    load = "0.1, 1., 1e-6, 0.25" if finite else "1., 1., 1e-6, 1."
    for v in steps:  # the loading step, then the hold step that writes
        out += step(value=v, nlgeom=finite, control=load, write=False)
        out += step(value=None, nlgeom=finite, control="1., 1., 1e-6, 1.", write=True)
    return "\n".join(out) + "\n"


def _num(v) -> str:
    """A float in at most 20 characters (CalculiX reads a field of up to 20): the shortest text that reads back
    to the same double, else 13 significant digits."""
    text = repr(float(v))
    return text if len(text) <= 20 else f"{float(v):.13g}"


def _lines(ids, per: int = 16) -> list[str]:
    ids = [int(i) for i in ids]
    return [", ".join(str(i) for i in ids[k:k + per]) for k in range(0, len(ids), per)]


class Modelled(NamedTuple):
    """A run CalculiX models: the benchmark's :class:`Run`, the contact type of its deck (:data:`CONTACT_TYPES`),
    what CalculiX solves (in words), the label its result reports (``finite`` for the finite-strain stand-in of a
    convective run: the score's added finite run, :mod:`workbench.external.scorers.runs`) and its variant (``""``:
    the result every score reads; ``"node_to_surface"``: CalculiX's other contact discretisation of the same
    problem, a result and a score of its own)."""

    run: object
    contact: str
    model: str
    label: str
    variant: str = ""


_CONVECTIVE = ("finite strain (NLGEOM, total Lagrangian; {law}), frictionless penalty contact searched and "
               "integrated in the current configuration, the traction along the master's current normal: CalculiX "
               "has no small-strain convective kinematics, and this is its nearest model. Against the convective "
               "theory it is the real kinematics held against the theory's model: it adds the bulk's finite-strain "
               "terms and the traction's turning, of the order of the strain in the contact ({strain}), the order "
               "of the convective effect itself; its b/b0 over the small run is what a finite-strain code predicts, "
               "not a check of Ciavarella and Hills's assumptions")


def finite_law(run) -> str:
    """The bulk law of an ``NLGEOM`` run: its hyperelastic model, or neo-Hookean for a convective run (whose case
    material is linear: small strain)."""
    return run.material_model if run.material_model in ("neo_hookean", "saint_venant_kirchhoff") else "neo_hookean"


def ccx_runs(benchmark) -> tuple[tuple[Modelled, ...], dict]:
    """The runs of ``benchmark`` CalculiX models (:class:`Modelled`) and the others with the reason (label -> words).

    Every run is modelled: ``small`` as small strain with segment-to-segment penalty contact (a patch test's run
    labelled ``node-to-segment`` with CalculiX's node-to-surface contact, its counterpart: a variant of its own),
    ``convective`` and ``finite`` under ``NLGEOM`` (:data:`_CONVECTIVE` says what that means against the convective
    theory; a convective run's result is labelled ``finite``, what it is, unless the case has finite runs of its own:
    then the convective runs are named as not modelled, with that reason). A run of another kinematics is named as
    not modelled."""
    modelled, skipped = [], {}
    strain = benchmark.reference.get("strain") or "see the run's meaning"
    finite_runs = [r.label for r in benchmark.runs if r.kinematics == "finite"]
    for run in benchmark.runs:
        if run.kinematics == "convective" and finite_runs:
            # CalculiX answers a convective run with its NLGEOM model, which the case's own finite runs are already;
            # labelled "finite" it would name no run of the case (found by make external on halfplanes_finite_parabola)
            skipped[run.label] = (f"convective: CalculiX's answer is its finite-strain model, which is this case's "
                                  f"finite run(s) {', '.join(finite_runs)} already")
            continue
        contact = "node_to_surface" if run.label == "node-to-segment" else "surface_to_surface"
        if run.kinematics == "small":
            words = ("small strain, linear elastic; frictionless penalty contact, "
                     + ("node-to-surface (a penalty spring at every slave node)" if contact == "node_to_surface"
                        else "segment-to-segment (integrated on the slave faces)")
                     + ", the contact elements built in the current configuration, the traction along the master's "
                       "normal")
        elif run.kinematics in ("convective", "finite"):
            law = {"neo_hookean": "CalculiX's neo-Hooke law", "saint_venant_kirchhoff":
                   "Saint Venant-Kirchhoff"}[finite_law(run)]
            words = (_CONVECTIVE.format(law=law, strain=strain) if run.kinematics == "convective"
                     else f"finite strain (NLGEOM, total Lagrangian; {law}), frictionless penalty contact in the "
                          "current configuration")
        else:
            skipped[run.label] = f"kinematics {run.kinematics!r}: CalculiX has no such model"
            continue
        label = "finite" if run.kinematics == "convective" else run.label
        modelled.append(Modelled(run, contact, words, label, "" if contact == "surface_to_surface" else contact))
    return tuple(modelled), skipped


def quadratic_model(benchmark, model):
    """The 6-node model of a benchmark: mid-edge nodes on the exact curved surfaces it names
    (``benchmark.geometry["surfaces"]``), at the middle of the straight edges elsewhere."""
    from workbench.external.benchmarks.surfaces import quadratic

    return quadratic(model, (benchmark.geometry or {}).get("surfaces", {}))


def first_approach(benchmark) -> list[float]:
    """The approaches (mm) of a deck before any calibration: a displacement schedule as it is; a force-controlled
    case's ``P / (0.3 E*)`` per reported load (the workbench stepper's stiffness guess; measured: 15 % above the
    target load on hertz_cylinder, 4 % on wedge, 6 % on elastic_cylinder_dissimilar, 14 % below on
    parabola_convective: the load a deck carries is what its ``.dat`` says)."""
    drive = benchmark.drive
    if drive.control != "force":
        return [float(v) for v in drive.report]
    from workbench.external.benchmark import pair_modulus

    E_star = min(pair_modulus(benchmark, p) for p in benchmark.pairs)
    return [float(P) / (0.3 * E_star) for P in drive.report]


def cannot(case) -> str | None:
    """Why CalculiX cannot model a case (None: it models a run of every case; :func:`ccx_runs` names the runs)."""
    return None


def write(exported, *, approach: float | None = None) -> list[Path]:
    """The decks of an exported benchmark (``workbench export --format inp``): one per run CalculiX models,
    ``<stem>.inp`` (one run) or ``<stem>_<run>.inp``, at ``approach`` (mm) or :func:`first_approach`; a
    force-controlled deck's load is what its ``.dat`` reports (``workbench external ccx`` calibrates it)."""
    from cases.schema import label_folder

    bench = exported.benchmark
    model = quadratic_model(bench, exported.model)
    modelled, skipped = ccx_runs(bench)
    d = first_approach(bench) if approach is None else [float(approach)] * len(bench.drive.report)
    files = []
    for m in modelled:
        name = bench.mesh.stem if len(modelled) == 1 else f"{bench.mesh.stem}_{label_folder(m.run.label)}"
        path = exported.folder / f"{name}.inp"
        control = ("approach d estimated (P / (0.3 E*)): read the load from the .dat" if bench.drive.control ==
                   "force" and approach is None else "")
        path.write_text(inp_deck(bench, model, run=m.run, d=d, contact=m.contact,
                                 title=f"{bench.case} level {bench.level:g} run {m.run.label} (workbench export)"
                                       + (f"; {control}" if control else "")))
        files.append(path)
    return files


def _register() -> None:
    from workbench.external.writers import DeckWriter, register_writer

    register_writer(DeckWriter("inp", "CalculiX/Abaqus .inp (CPE6, frictionless penalty contact; one deck per run)",
                               write, cannot))


_register()


def report_steps(run, n: int) -> list[int]:
    """The deck steps (1-based) whose output reports the ``n`` values of ``d`` of :func:`inp_deck`: the hold steps
    2, 4, 6, ... (deck step k ends at total time k)."""
    return [2 * k + 2 for k in range(n)]
