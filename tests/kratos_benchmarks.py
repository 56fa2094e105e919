"""Benchmarks of the two-body cases built here from the case meshes, for the Kratos tests (no exporter needed: the
two-body scenes mesh both bodies, so no rigid band is involved). Units mm, N, MPa."""

from __future__ import annotations

from pathlib import Path

from workbench.external.benchmark import Benchmark, Body, ContactPair, Drive, Material, Run, Support
from workbench.external.mesh_model import MeshModel, read_msh


def two_body_benchmark(case_name: str, *, level: float, mesh_cache: Path) -> tuple[Benchmark, MeshModel]:
    """``patch_test`` (stacked blocks, displacement control, the top sliding freely) or a two-body cylinder case
    (force control through the half disk's top) as a Benchmark, with its mesh."""
    import workbench.scenes  # noqa: F401  (the scenes register their schemas)
    from cases import load_case
    from workbench.scenes.base import scene_for

    case = load_case(case_name)
    run = case.runs(h_contact=level)[0]
    g = run.geometry
    files = scene_for(run).mesh(run, name=f"kratos_{case.name}", mesh_cache=mesh_cache, comm=None).files
    lower, upper = run.bodies
    bodies = (Body(name=lower.name, cells="lower", material=Material(E=lower.E, nu=lower.nu)),
              Body(name=upper.name, cells="upper", material=Material(E=upper.E, nu=upper.nu)))
    pairs = (ContactPair(slave="contact_lower", master="contact_upper", slave_body=lower.name,
                         master_body=upper.name),)
    if g.indenter == "stacked":
        h = level * g.block_width
        supports = (Support(group="clamped", components=(1,)), Support(group="symmetry", components=(0,)))
        drive = Drive(control="displacement", report=tuple(run.loading.d), group="driven", components=(1,))
    else:
        from workbench.scenes.two_body import _estimate

        P, a0 = _estimate(run)
        h = level * a0
        supports = (Support(group="clamped", components=(0, 1)),)
        drive = Drive(control="force", report=(P,), group="driven")
    bench = Benchmark(case=case.name, scene=g.scene, description=case.description, level=level, h_contact=h,
                      mesh=Path(files.msh), bodies=bodies, pairs=pairs, supports=supports, drive=drive,
                      runs=(Run(label="small", kinematics="small", meaning="small strain"),))
    return bench, read_msh(files.msh)
