"""``workbench export CASE --format inp|msh|json [--h-contact H] [--out DIR]``: a block case as a benchmark.

* ``msh``: the case's own gmsh mesh (``meshes/block.py`` through :func:`workbench.scenes.block.block_mesh`, the
  builder ``workbench run`` uses; level ``--h-contact`` as a fraction of the half-width, default the case's
  ``ci_level``, else its ``h_contact``);
* ``json``: geometry, materials, load, units, what to report (the csv columns ``workbench score`` reads) and the
  reference values (the classical theory at the target load; the theory at the external load is what the score
  uses) with the case's tolerances;
* ``inp``: a CalculiX/Abaqus deck of the same mesh (:mod:`workbench.external.inp`).

Files go to ``<out>/export_<case>/<case>_h<H>.{msh,json,inp}`` (staged; nothing written on bad input), the mesh
into ``<out>/mesh_cache/``: the output folder, the export folder and the mesh cache pass the same guard as
``workbench run`` (:func:`workbench.paths.checked_paths`, :func:`workbench.owned.check_dir`: a symlink, a file or a
folder without the workbench's marker is refused before anything is written), and the level passes the same size
estimate (:func:`workbench.pipeline.size_estimate.check_run_fits`). No dolfinx is imported (the mesh is written
without XDMF). Units: mm, N, MPa.
"""

from __future__ import annotations

import argparse
import json
import math
import shutil
import sys
from pathlib import Path

__all__ = ["export_case", "main", "ExportError", "level_of", "supported"]


class ExportError(ValueError):
    """Bad input to ``workbench export`` (one line)."""


def level_of(case, h_contact: float | None) -> float:
    """The h_c / a fraction to export: the option, else the case's ci_level, else its h_contact."""
    if h_contact is not None:
        if not (math.isfinite(h_contact) and 0 < h_contact <= 1):
            raise ExportError(f"--h-contact = {h_contact!r}; allowed: 0 < H <= 1 (a fraction of the half-width)")
        return h_contact
    d = case.runs()[0].discretisation
    return d.ci_level if d.ci_level else d.h_contact


def supported(case) -> None:
    """ExportError unless the case is a block under a circle (the scene the deck models)."""
    g = case.runs()[0].geometry
    if g.scene != "block" or getattr(g, "indenter", None) != "circle":
        raise ExportError(f"case {case.name}: scene {g.scene!r} indenter {getattr(g, 'indenter', None)!r}; "
                          "allowed: block scenes with a circle indenter")


def description(case, run, theory, *, level: float, mesh_stats: dict) -> dict:
    """The JSON benchmark description."""
    g, m = run.geometry, run.material
    return {
        "case": case.name, "description": case.description, "units": {"length": "mm", "force": "N",
                                                                       "pressure": "MPa", "load": "N/mm"},
        "model": "2D plane strain, thickness 1 mm; frictionless contact; small strain",
        "geometry": {"block_width": g.width_factor * theory.half_width,
                     "block_height": g.height_factor * theory.half_width,
                     "top": "y = 0, the block occupies y < 0", "indenter": g.indenter, "radius": g.radius,
                     "indenter_center": [0.0, g.radius] if g.indenter == "circle" else None,
                     "half_model": g.half_model, "symmetry_plane": "x = 0" if g.half_model else None},
        "material": {"E": m.E, "nu": m.nu, "model": m.model, "indenter": "rigid"},
        "supports": {"bottom": "u = 0", "symmetry": "u_x = 0" if g.half_model else None, "sides": "free"},
        "load": {"P_target": theory.P, "note": "full-body load per unit thickness (N/mm), pushing the indenter down"},
        "mesh": {"h_contact_over_a": level, "h_contact": level * theory.half_width, "degree": 2, **mesh_stats},
        "report": {"format": "csv", "columns": {"x_mm": "position along the contact surface (reference configuration)",
                                                "p_MPa": "contact pressure, compression positive",
                                                "P_N_per_mm": "optional: the full-body load carried",
                                                "h_mm": "optional: element size on the contact surface"},
                   "one_file_per_mesh_level": True,
                   "command": f"workbench score {case.name} LEVEL1.csv LEVEL2.csv ..."},
        "reference": {"theory": theory.kind, "at": "the load P the result carries (the score evaluates it there)",
                      "P": theory.P, "p0": theory.p_ref, "half_width": theory.half_width, "E_star": theory.E_star,
                      "tolerances": dict(case.tolerances)},
    }


def export_case(case_name: str, *, fmt: str, h_contact: float | None, folder: Path, mesh_cache: Path,
                approach: float | None = None) -> list[Path]:
    """Write the export files of one level into ``folder`` (created by the caller); returns their paths.
    ``approach``: the deck's prescribed approach d (mm) instead of the estimate (a calibration run)."""
    import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
    from cases import load_case
    from workbench.external.inp import approach_estimate, inp_deck, read_block_msh
    from workbench.scenes.block import block_mesh

    case = load_case(case_name)
    level = level_of(case, h_contact)
    run = case.runs(h_contact=level)[0]
    g = run.geometry
    supported(case)
    files, theory = block_mesh(run, name=f"export_{case.name}", mesh_cache=mesh_cache, comm=None, write_xdmf=False)
    stem = f"{case.name}_h{level:g}"
    out = []
    if fmt == "msh":
        shutil.copyfile(files.msh, folder / f"{stem}.msh")
        out.append(folder / f"{stem}.msh")
    elif fmt == "json":
        stats = {k: files.stats[k] for k in ("cells", "nodes") if k in files.stats}
        (folder / f"{stem}.json").write_text(json.dumps(description(case, run, theory, level=level, mesh_stats=stats),
                                                        indent=1, default=str))
        out.append(folder / f"{stem}.json")
    else:
        from analytic.materials import plane_strain_modulus

        mesh = read_block_msh(files.msh)
        a = theory.half_width
        d = approach if approach is not None else approach_estimate(
            P=theory.P, E_star=plane_strain_modulus(run.material.E, run.material.nu), nu=run.material.nu, a=a,
            depth=g.height_factor * a)
        text = inp_deck(mesh, E=run.material.E, nu=run.material.nu, R=g.radius, a=a, d=d, h_contact=level * a,
                        half_model=g.half_model, title=f"{case.name} h_c/a = {level:g} (workbench export)")
        (folder / f"{stem}.inp").write_text(text)
        out.append(folder / f"{stem}.inp")
    return out


def _parser() -> argparse.ArgumentParser:
    from workbench.cli import _Parser

    p = _Parser(prog="workbench export", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("case", metavar="CASE")
    p.add_argument("--format", choices=("inp", "msh", "json"), required=True)
    p.add_argument("--h-contact", type=float, default=None, help="h_c as a fraction of the half-width")
    p.add_argument("--out", default=None, help="output folder (default: results/ of this checkout)")
    return p


def main(argv: list[str] | None = None) -> int:
    """``workbench export`` (exit 0 written, 2 bad input, 1 the mesh or the files could not be made: one line)."""
    from cases import CaseError
    from workbench import interrupt
    from workbench.atomic import atomic_dir
    from workbench.owned import check_dir, ensure_dir
    from workbench.paths import OutputError, checked_paths

    args = _parser().parse_args(argv)
    try:
        paths = checked_paths(args.out)  # the output folder's guard, whichever way it was given
        import workbench.scenes  # noqa: F401  (the scenes register their case schemas)
        from cases import load_case
        from workbench.pipeline.size_estimate import check_run_fits

        case = load_case(args.case)
        level = level_of(case, args.h_contact)
        supported(case)
        check_run_fits(case.runs(h_contact=level)[0], where=f"{case.path.name}: [{case.runs()[0].label}]",
                       field="--h-contact" if args.h_contact is not None else "discretisation.ci_level")
        folder = paths.command("export_", case.name)
        check_dir(folder, kinds=("export",))
        check_dir(paths.mesh_cache, kinds=("mesh_cache",))
    except (ExportError, CaseError, OutputError) as exc:
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    keep = [f for f in sorted(folder.glob(f"{case.name}_h*")) if f.is_file() and not f.is_symlink()]
    interrupt.stage(f"exporting {case.name} (meshing, writing {folder.name})")
    try:
        with atomic_dir(folder, kind="export") as stage:
            for f in keep:  # other formats and levels exported before stay
                shutil.copy2(f, stage / f.name)
            ensure_dir(paths.mesh_cache, kind="mesh_cache", kinds=("mesh_cache",))
            written = export_case(args.case, fmt=args.format, h_contact=args.h_contact, folder=stage,
                                  mesh_cache=paths.mesh_cache)
    except (ExportError, CaseError) as exc:  # OutputError among them: the folder changed meanwhile
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        raise  # the command line prints the one line and exits 130 / 143
    except Exception as exc:  # noqa: BLE001 - gmsh (e.g. out of memory), a full disk: one line, nothing written
        first = " ".join(str(exc).split())[:200] or type(exc).__name__
        print(f"error: export {case.name} failed: {type(exc).__name__}: {first}; nothing written (a previous export "
              "left intact)", file=sys.stderr)
        return 1
    for w in written:
        print(folder / w.name)
    return 0
