"""The records of a case (:mod:`cases.schema` loads them): the sections of a case file as frozen dataclasses, one
run of a case, the one-line :class:`CaseError` and the limits every check shares.

Units: mm, N, MPa; loads per unit thickness (N/mm); angles in radians. What each field means and which values it
takes is documented on its record; the checks are :mod:`cases.fields` (types, choices, ranges) and
:mod:`cases.checks` (combinations).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

__all__ = ["CASE_DIR", "CASE_NAME_RE", "RESERVED_NAMES", "COMMAND_PREFIXES", "MAX_ECHO", "CONTROL_NEEDS", "CaseError",
           "short_repr", "Material", "Body", "Geometry", "Loading", "Discretisation", "Solver", "Analytic", "Run",
           "CASE_LEVEL_DEFAULTS"]

CASE_DIR = Path(__file__).resolve().parent

# A case name names its output folder and its mesh-cache files: a slug, nothing path-like.
CASE_NAME_RE = re.compile(r"[A-Za-z0-9_-]{1,64}")
# Names the workbench gives its own folders and files under the output folder (``workbench.paths``): no case may
# take one (its results folder would replace them). Compared case-insensitively.
RESERVED_NAMES = ("mesh_cache", "analytic", "logs", "ci", "ci_report", "convergence", "stability", "bench",
                  "validity", "report", "results", "faults", "vtk")
# The folders of ``workbench score``, ``export``, ``external`` and ``forcelaw`` are ``<prefix><name>``: no case
# may start with one (a case named ``score_x`` would replace the score of case x). Compared case-insensitively.
COMMAND_PREFIXES = ("score_", "export_", "external_", "forcelaw_")
MAX_LABEL = 64  # characters of a [[variant]] label (it names files: cut in file names, refused beyond)
MAX_ECHO = 60  # characters of a value or key echoed in an error message
# Near-incompressibility (fem.postprocess.LOCKING_NU: the solver's 'near-incompressible' warning starts there).
# formulation = "auto" uses the Taylor-Hood mixed formulation from NU_MIXED on; an explicit "displacement"
# is refused above NU_DISPLACEMENT_MAX (the stability study: P2 displacement at nu = 0.4999 diverged, at 0.499
# it converged with RMS/p0 8 % and named warnings).
NU_MIXED = 0.45
NU_DISPLACEMENT_MAX = 0.499
# Extreme magnitudes. E: kappa = kappa0 E / h and the SNES tolerance 1e-13 E L must stay finite (E = 1e300
# gave inf/NaN residuals); the stability study's scale sweep covers 1e-3 ... 1e6 MPa.
E_MAX = 1e12
# A body's size over the contact half-width (scenes whose body is sized from the contact, and the budget's
# truncation study): a size of 1e6 a (height 40 a) gave a 1.9 % load-balance error with no warning; 1e5 a x 1e5 a
# measured 7.5e-13. Sizes beyond 1e4 a are refused.
MAX_SIZE_FACTOR = 1e4
BUDGET_SPAN = 8.0  # error budget: largest over smallest level (the grading is refined with h_c)
# [bands]: checks whose tolerance is the error budget's band (make run only). A listed quantity selects every
# budget row of that quantity (one per run, or one per step and patch, as the scene's budget has them);
# "name[k]" selects the rows of patch k only. The quantities are the scene's (SceneSchema.band_quantities).
BAND_KINDS = {
    "contain_theory": "the band (GCI + truncation) of the quantity contains its theory",
    "exclude_alt": "the band of the quantity excludes its alternative theory (e.g. first order, Hertz)",
    "exclude_theory": "the band of the quantity excludes its theory (a theory the scene shows to fail)",
}
# Penalty / Nitsche factors: the contact terms add kappa0 (gamma0) times the bulk stiffness entries of the contact
# rows (kappa = kappa0 E / h integrated over an edge of length h ~ kappa0 E). LU resolves the bulk part of those
# rows to about eps * kappa0 relative (eps = 2.2e-16): at the upper bound 1e12 that is 2e-4, beyond it the bulk is
# lost in round-off (1e303 even overflows to inf in the compiled form). The stability study sweeps 1e0 ... 1e10.
# Below 1e-6 the contact term is a millionth of the bulk stiffness: penetrations of 1e6 times the elastic approach,
# no contact to speak of. Between 1e-6 and ~1 a Nitsche factor may lose coercivity and the solve diverges: a named
# solver failure (exit 1, logs/<case>.log; tests/test_stability_faults.py provokes it with gamma0 = 1e-6).
FACTOR_RANGE = (1e-6, 1e12)
# Limits no real case reaches (the largest case file is 3 kB): refused in one line, so a huge file is never copied.
MAX_FILE_BYTES = 1_000_000
MAX_DESCRIPTION = 2000  # characters
MAX_LIST = 100  # entries of levels, d, budget lists
MAX_VARIANTS = 100
MAX_TOLERANCE = 10.0  # a relative error of 1000 %: anything above checks nothing
E_MIN = 1e-6  # MPa: the stability study's scale sweep starts at 1e-3
# What each load control needs (the loading checks; a scene names the controls it supports).
CONTROL_NEEDS = {"force": "with P or half_width", "displacement": "with d"}


def short_repr(value: Any) -> str:
    """``repr(value)`` cut to MAX_ECHO characters (a 200 kB string is never echoed back whole)."""
    text = repr(value)
    return text if len(text) <= MAX_ECHO else text[:MAX_ECHO - 3] + "..."


_r = short_repr


def _path_repr(text: str) -> str:
    """A path quoted for an error line: at most MAX_ECHO characters, cut in the middle (its file name stays)."""
    text = repr(str(text))
    if len(text) <= MAX_ECHO:
        return text
    head = MAX_ECHO // 3
    return text[:head] + "..." + text[len(text) - (MAX_ECHO - head - 3):]

class CaseError(ValueError):
    """A case file is malformed or holds an out-of-range value (one-line message)."""


# --- records -----------------------------------------------------------------------------------


@dataclass(frozen=True)
class Material:
    """Elastic material of the deformable body (the indenter is rigid), plane strain.

    Attributes:
        E: Young's modulus in MPa, E > 0 (the small-strain modulus of every model).
        nu: Poisson's ratio, -1 < nu < 0.5 (the small-strain ratio of every model).
        model: ``"linear"`` (small-strain Hooke, with solver.kinematics "small" or "convective"),
            ``"saint_venant_kirchhoff"`` or ``"neo_hookean"`` (hyperelastic, with solver.kinematics = "finite"
            only; :mod:`fem.hyperelastic`, ``docs/models.md``).
    """

    E: float
    nu: float
    model: str = "linear"


@dataclass(frozen=True)
class Body:
    """One elastic body of a scene with several (``[[body]]``), plane strain.

    Attributes:
        name: Its label in reports and ``metrics.json`` (1 to 64 letters, digits, ``_`` or ``-``; distinct).
        E, nu, model: Its material, with the ranges and choices of :class:`Material`.
    """

    name: str
    E: float
    nu: float
    model: str = "linear"

    @property
    def material(self) -> Material:
        """The body's material record."""
        return Material(E=self.E, nu=self.nu, model=self.model)


@dataclass(frozen=True)
class Geometry:
    """Scene geometry: what every scene's has. A scene's own geometry record subclasses this one with its fields
    (:attr:`SceneSchema.geometry`); ``run.geometry`` is an instance of the scene's record.

    Attributes:
        scene: The registered scene (:func:`scene_schemas`).
        indenter: One of the scene's indenters (:attr:`SceneSchema.indenters`).
    """

    scene: str
    indenter: str


@dataclass(frozen=True)
class Loading:
    """Loading of the rigid body.

    Exactly one of ``P`` (target load per unit thickness, N/mm) and ``half_width`` (target classical
    contact half-width b0 in mm, from which P follows by the analytic theory) sets a force-controlled
    load; ``d`` (list of rigid-body displacements in mm, recorded in order) sets displacement control.

    Attributes:
        control: ``"force"`` or ``"displacement"``.
        P: Target load per unit thickness in N/mm, > 0.
        half_width: Target classical half-width b0 in mm, > 0.
        d: Displacements of the rigid body in mm (increasing, > 0), displacement control only.
        steps: Number of load steps to the target (force control), >= 1.
    """

    control: str
    P: float | None = None
    half_width: float | None = None
    d: tuple[float, ...] = ()
    steps: int = 4


@dataclass(frozen=True)
class Discretisation:
    """Mesh and element choice.

    Attributes:
        degree: Lagrange degree of the displacement, 1 or 2.
        h_contact: Element size in the contact zone as a fraction of the contact half-width, in (0, 1].
        levels: Refinement levels for studies, as h_contact fractions, coarse to fine.
        ci_level: Fraction used by ``make ci`` (the coarsest that still meets the tolerances).
        growth: Element-to-element size ratio of the mesh grading away from the contact, in [1.05, 2].
        budget_levels: Three h_contact fractions of the error budget (``make run`` solves each run on all
            three, scenes with a truncation study on their largest body), or empty for no budget.
        budget_widths: Three body sizes W/a (width = height, in [10, MAX_SIZE_FACTOR]) of the budget's
            truncation study (at the finest budget level); required with ``budget_levels`` on a scene whose
            budget takes them, refused on the others (:attr:`SceneSchema.budget_widths` says why).
    """

    degree: int = 2
    h_contact: float = 0.05
    growth: float = 1.3
    levels: tuple[float, ...] = ()
    ci_level: float | None = None
    budget_levels: tuple[float, ...] = ()
    budget_widths: tuple[float, ...] = ()


@dataclass(frozen=True)
class Solver:
    """Contact formulation and kinematics: the ``[solver]`` fields of a case.

    Every field is the solver option of the same name, :class:`fem.options.ContactOptions` (its meaning, units and
    vocabulary are documented there, once), with the same default, except the case-level choices in
    :data:`CASE_LEVEL_DEFAULTS`: ``traction`` defaults to ``"halfplane"`` and ``formulation`` takes ``"auto"``
    (displacement below nu = NU_MIXED, Taylor-Hood mixed from there on; an explicit ``"displacement"`` is refused
    above nu = NU_DISPLACEMENT_MAX, ``"mixed"`` needs degree 2 and a scene with an analytic obstacle).
    ``kinematics = "finite"`` needs a hyperelastic material.model, traction = "obstacle", the displacement
    formulation and a scene that supports it (``docs/models.md``). The wiring passes every field through by name
    (:func:`workbench.scenes.wiring.solver_options`): a new option is one field here and one on ContactOptions.
    """

    method: str = "nitsche"
    kinematics: str = "small"
    traction: str = "halfplane"
    kappa0: float = 1.0e3
    gamma0: float = 10.0
    theta: int = 1
    formulation: str = "auto"
    linear_solver: str = "lu"


# Every [solver] field is the solver option (fem.options.ContactOptions) of the same name, with the same default,
# except these: case-level choices, each with its reason (tests/test_options_record.py checks the rest agree).
CASE_LEVEL_DEFAULTS = {
    "traction": "the case files compare with half-plane theory, which assumes a vertical gap and traction "
                "('halfplane'); a bare solve defaults to the obstacle's normal ('obstacle'), right for any geometry "
                "and the only traction finite kinematics supports",
    "formulation": "'auto' is a case-level choice resolved by nu (effective_formulation: the mixed formulation "
                   "from NU_MIXED on); the solver takes the resolved 'displacement' or 'mixed'",
}


@dataclass(frozen=True)
class Analytic:
    """Analytic predictions compared with the FEM (names of analytic/ predictions).

    Attributes:
        predictions: Names the scene computes for the run's indenter (:attr:`SceneSchema.predictions`); empty:
            the scene's own.
    """

    predictions: tuple[str, ...] = ()


@dataclass(frozen=True)
class Run:
    """One FEM run of a case: the base case with one variant's overrides applied."""

    label: str
    material: Material
    geometry: Geometry
    loading: Loading
    discretisation: Discretisation
    solver: Solver
    bodies: tuple[Body, ...] = ()


