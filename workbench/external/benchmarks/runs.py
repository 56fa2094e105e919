"""A case's runs as :class:`workbench.external.benchmark.Run` records: the label, the kinematics and, in words, what
the run means for another code (which of its options reproduces it, and what a substitute changes).

The words follow the model hierarchy of ``docs/models.md`` (traction x kinematics x material model).
"""

from __future__ import annotations

from cases.schema import Run as CaseRun
from workbench.external.benchmark import Run

__all__ = ["run_records"]

_SMALL = {
    "halfplane": ("small strain, small sliding: the contact pairs the points opposite each other in the undeformed "
                  "configuration, the gap and the traction are vertical (the workbench's traction 'halfplane'): the "
                  "classical half-plane theory's model. A code's small-strain, small-sliding frictionless contact is "
                  "this run; its traction along the master surface's normal differs from the vertical by the "
                  "surface's slope in the contact ({slope}), which moves the result by that order (docs/models.md)."),
    "obstacle": ("small strain, small sliding: the gap to the rigid surface along its normal at the undeformed "
                 "point, linearised, the traction along that normal (the workbench's traction 'obstacle'). A code's "
                 "small-strain frictionless contact with the rigid body as master is this run."),
}
_CONVECTIVE_RIGID = (
    "Ciavarella and Hills's convective kinematics at small strain: the rigid profile is read where the block's "
    "surface point has moved to (x = X + u), the traction vertical. At the same load, b/b0 = this run's half-width "
    "over the small run's measures the convective effect. General-purpose codes do not offer these kinematics as "
    "such: the counterpart is a finite-sliding contact (the pairing searched in the current configuration), with "
    "small-strain elements where the code allows it, else finite strain (geometrically nonlinear). Finite strain "
    "adds the bulk's finite-strain terms and a traction along the current normal, effects of the order of the "
    "strain ({slope}), like the convective effect itself: scored against the convective theory, such a run is the "
    "real kinematics held against the theory's model, not a check of the theory's own assumptions; the verdict "
    "names which of the workbench's models (docs/models.md) hold it.")
_CONVECTIVE_TWO = (
    "Ciavarella and Hills's convective kinematics (their eq. (8)) at small strain: the upper body's points opposite "
    "in the undeformed state carry the displacements and forces, and the profile is read at the convected abscissa, "
    "so the relative tangential displacement of the dissimilar materials (Dundurs beta = {beta:+.4f}) enters the "
    "gap. The counterpart in another code is a finite-sliding contact on the shaped bodies of this benchmark (the "
    "points that touch now are paired), which differs from the theory's model at the order of the effect where the "
    "upper body deforms (docs/models.md: convection 'pairing'), and finite strain adds terms of the order of the "
    "strain ({slope}), as for a rigid indenter.")
_FINITE = ("finite strain: the hyperelastic law '{model}' built from the small-strain E and nu (docs/models.md gives "
           "W, S and P), total Lagrangian, the contact in the current configuration with the traction along the "
           "rigid surface's current normal; the workbench compares it in the current configuration (positions "
           "x = X + u, pressure per deformed length).")
_PAIRING = {"mortar": "mortar (segment-to-segment)", "node_to_segment": "node-to-segment"}


def run_records(runs: tuple[CaseRun, ...], *, slope: str, two_bodies: bool = False, beta: float | None = None,
                patch_test: bool = False) -> tuple[Run, ...]:
    """The :class:`Run` records of one benchmark's runs. ``slope``: the surface slope (or strain) in the contact in
    words (e.g. ``"a/R = 0.05"``); ``two_bodies``: both bodies elastic (the traction is the half-plane theory's,
    vertical, whatever the case file says); ``beta``: Dundurs' beta of a two-body convective run; ``patch_test``:
    the runs differ only in the workbench's pairing."""
    out = []
    for run in runs:
        kin, sol = run.solver.kinematics, run.solver
        traction = "halfplane" if two_bodies else sol.traction
        if kin == "finite":
            meaning = _FINITE.format(model=run.material.model)
        elif kin == "convective":
            meaning = (_CONVECTIVE_TWO.format(beta=beta, slope=slope) if two_bodies
                       else _CONVECTIVE_RIGID.format(slope=slope))
        else:
            meaning = _SMALL[traction].format(slope=slope)
        pairing = getattr(run.geometry, "pairing", None)
        if patch_test:
            meaning = (f"the contact patch test at small strain; the workbench pairs the surfaces by "
                       f"{_PAIRING[pairing]}. The interface is flat, so every formulation's gap and traction are "
                       "vertical. An exact contact discretisation carries the uniform pressure to round-off on these "
                       "non-matching meshes (mortar does, node-to-segment does not): report your code's run under the "
                       "label of the kind of discretisation it uses (segment-to-segment or mortar: 'mortar'; "
                       "node-to-surface: 'node-to-segment').")
        elif two_bodies and pairing is not None:
            meaning += (f" The workbench pairs the two meshes by {_PAIRING[pairing]}; another code reports its own "
                        "contact discretisation under this label.")
        out.append(Run(label=run.label, kinematics=kin, meaning=meaning, traction=traction,
                       material_model=run.material.model))
    return tuple(out)
