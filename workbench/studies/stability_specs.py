"""The stability sweep's runs as records (:mod:`workbench.studies.stability`): a block run is a :class:`Spec` (its
case run :meth:`Spec.run` and the study's solver options), a two-body point a :class:`TwoBodySpec`; :func:`specs`
and :func:`two_body_specs` list them from the :class:`workbench.studies.stability_config.StabilityConfig`.
Light: no dolfinx (the options record is read inside the methods). Units mm, N, MPa.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from cases.schema import Discretisation, Loading, Material, Run, Solver
from workbench.scenes.block_schema import BlockGeometry
from workbench.studies.stability_config import AL, StabilityConfig, decade

__all__ = ["PARAM_OPTIONS", "SWEEP_OPTIONS", "Spec", "TwoBodySpec", "specs", "two_body_specs"]

# The sweep's solver options beyond the record's defaults (:class:`fem.options.ContactOptions`): the case files'
# traction (vertical gap and traction, as the half-plane theory the runs are compared with assumes).
SWEEP_OPTIONS = {"traction": "halfplane"}
# The options a run's record names in ``stability.json["runs"][i]["params"]`` (read by the report and the plots).
PARAM_OPTIONS = ("method", "kappa0", "gamma0", "theta", "formulation", "kinematics", "max_it", "max_cutbacks",
                 "active_set_predictor")


@dataclass(frozen=True)
class Spec:
    """One block run of the sweep (units mm, N, MPa).

    Attributes:
        study, label: study name and run label.
        indenter: ``circle``, ``parabola`` or ``wedge`` (face slope = wedge_angle, the paper's profile).
        R: indenter radius (mm).  a_over_R: target Hertz half-width over R (circle, parabola).
        half_width: target classical half-width (mm) for the wedge.  wedge_angle: rad.
        E, nu: block material.  size_factor: block width and height over a.
        degree, h_ratio: element degree and a / h_contact.
        n_steps: load steps.
        control: ``force`` (target the Hertz load) or ``displacement`` (target ``d`` mm, faults study).
        d: displacement target (mm) for displacement control.
        options: solver options of this run: :class:`fem.options.ContactOptions` fields by name (e.g.
            ``{"method": "penalty", "kappa0": 1e2, "max_it": 4}``), over :data:`SWEEP_OPTIONS` over the record's
            defaults (:meth:`option`); a name that is not a field is a TypeError.
        condition: estimate the Jacobian's condition number.
        band: accuracy band of the errors (None: not compared, e.g. the convective run's classical errors).
        model_limit: named reason why the theory itself departs from the scene (used only if out of band).
        expect_failure: the run is meant to fail (faults study).
    """

    study: str
    label: str
    indenter: str = "circle"
    R: float = 10.0
    a_over_R: float = 0.05
    half_width: float = 0.5
    wedge_angle: float | None = None
    E: float = 2.0e5
    nu: float = 0.3
    size_factor: float = 40.0
    degree: int = 2
    h_ratio: float = 10.0
    n_steps: int = 3
    control: str = "force"
    d: float = 0.0
    options: dict = dataclasses.field(default_factory=dict, hash=False)
    condition: bool = False
    band: float | None = StabilityConfig.band
    model_limit: str | None = None
    expect_failure: bool = False

    def __post_init__(self):
        from fem.options import ContactOptions

        names = ContactOptions.field_names()
        for key in self.options:
            if key not in names:
                raise TypeError(f"Spec options: {key!r} is not a ContactOptions field")

    def option(self, name: str):
        """The value of the ContactOptions field ``name`` for this run (this spec's, the sweep's, the record's)."""
        from fem.options import ContactOptions

        return (ContactOptions.defaults() | SWEEP_OPTIONS | self.options)[name]

    def params(self) -> dict:
        """The run's parameters for its JSON record: the spec's fields and the options :data:`PARAM_OPTIONS`."""
        out = {f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.name != "options"}
        return out | {name: self.option(name) for name in PARAM_OPTIONS}

    @property
    def target_half_width(self) -> float:
        """The classical half-width the mesh is sized from (mm): a = a_over_R R, or the wedge's b."""
        return self.half_width if self.indenter == "wedge" else self.a_over_R * self.R

    def run(self) -> Run:
        """This spec as a case run (half model, labelled by its indenter): what the wiring reads; its
        ``[solver]`` fields are the spec's options of the same names. Built directly, not loaded, so a study may
        go beyond a case file's ranges (h_c = 2 a)."""
        size = self.size_factor
        if self.indenter == "wedge":
            geo = BlockGeometry(scene="block", indenter="wedge", wedge_angle=self.wedge_angle, wedge_slope="paper",
                                width_factor=size, height_factor=size, half_model=True)
        else:
            geo = BlockGeometry(scene="block", indenter=self.indenter, radius=self.R, width_factor=size,
                                height_factor=size, half_model=True)
        if self.control == "force":
            loading = Loading(control="force", half_width=self.target_half_width, steps=self.n_steps)
        else:  # the target half-width sizes the mesh (TargetSized) and nothing else
            loading = Loading(control="displacement", half_width=self.target_half_width, d=(self.d,),
                              steps=self.n_steps)
        solver = Solver(**{f.name: self.option(f.name) for f in dataclasses.fields(Solver)})
        return Run(label=self.indenter, material=Material(E=self.E, nu=self.nu), geometry=geo, loading=loading,
                   discretisation=Discretisation(degree=self.degree, h_contact=1.0 / self.h_ratio), solver=solver)

    def solver_overrides(self) -> dict:
        """The study's options beyond the case run (:func:`workbench.scenes.wiring.solve_run` overrides): the
        spec's options, and no extra first step without the active-set predictor."""
        first = 1.0 if not self.option("active_set_predictor") else self.option("first_step_fraction")
        return dict(self.options) | {"first_step_fraction": first}


def specs(cfg: StabilityConfig | None = None) -> list[Spec]:
    """Every block run of the sweep, study by study (``cfg``: :class:`StabilityConfig`, default values)."""
    cfg = StabilityConfig() if cfg is None else cfg
    out = []
    for k in cfg.penalty_kappa0:  # 1. method parameters
        out.append(Spec("method", f"penalty kappa0={decade(k)}", options=dict(method="penalty", kappa0=k),
                        condition=True, band=cfg.band))
    for theta in cfg.nitsche_theta:
        for g in cfg.nitsche_gamma0:
            out.append(Spec("method", f"nitsche gamma0={g:g} theta={theta}", options=dict(gamma0=g, theta=theta),
                            condition=True, band=cfg.band))
    for k in cfg.al_kappa0:  # 1b. augmented Lagrangian: every stiffness must converge
        out.append(Spec(AL, f"{AL} kappa0={decade(k)}", options=dict(method=AL, kappa0=k), band=cfg.band))
    for nu in cfg.incompressible_nu:  # 2. near-incompressibility
        for deg, form, h in cfg.incompressible_elements:
            out.append(Spec("incompressible", f"nu={nu:g} P{deg} {form}", nu=nu, degree=deg,
                            options=dict(formulation=form), h_ratio=h, band=cfg.band_p1 if deg == 1 else cfg.band))
    for nu, size in cfg.convective_runs:
        for kin in ("small", "convective"):
            form = "mixed" if nu >= cfg.convective_mixed_from_nu else "displacement"
            out.append(Spec("convective", f"wedge nu={nu:g} block {size:g}b {kin}", indenter="wedge",
                            wedge_angle=cfg.convective_wedge_angle, nu=nu, h_ratio=cfg.convective_h_ratio,
                            size_factor=size, options=dict(formulation=form, kinematics=kin),
                            band=cfg.band_wedge if kin == "small" else None))
    for aR in cfg.loads_a_over_R:  # 3. loads
        limit = (f"model limit: a/R = {aR:g} > {cfg.model_limit_a_over_R:g}, the exact circle departs from "
                 "Hertz's parabola (see the parabola run at the same a/R)") if aR > cfg.model_limit_a_over_R else None
        out.append(Spec("loads", f"circle a/R={aR:g}", a_over_R=aR, model_limit=limit, band=cfg.band))
    for aR in cfg.parabola_a_over_R:
        out.append(Spec("loads", f"parabola a/R={aR:g}", indenter="parabola", a_over_R=aR, band=cfg.band))
    for hr in cfg.resolution_h_ratio:  # 3b. resolution warning
        out.append(Spec("resolution", f"h_c = a/{hr:g}", h_ratio=hr, band=cfg.band))
    for E in cfg.scale_E:  # 4. scale invariance
        out.append(Spec("scale", f"E={decade(E)}", E=E, band=cfg.band))
    out.append(Spec("faults", "cut-back: single step, max_it=4", control="displacement", d=cfg.fault_d, n_steps=1,
                    options=dict(max_it=4, active_set_predictor=False), band=cfg.band))
    out.append(Spec("faults", "unrecoverable: max_it=1, 1 cut-back", control="displacement", d=cfg.fault_d,
                    n_steps=1, options=dict(max_it=1, max_cutbacks=1, active_set_predictor=False),
                    expect_failure=True, band=cfg.band))
    return out


@dataclass(frozen=True)
class TwoBodySpec:
    """One point of the ``two_body`` study: the case ``cfg.two_body_case`` (two elastic bodies) with the upper body's
    E = ``ratio`` x the lower body's and the given Poisson ratios, at h_c = a / ``h_ratio``.

    Attributes:
        label: Run label.  ratio: E_upper / E_lower.  nu_lower, nu_upper: Poisson's ratios.
        h_ratio: a / h_contact.  band: accuracy band of p_max and the moment half-width against the exact circle
            at the combined modulus and the measured load (relative).  newton: Newton iterations allowed per step.
    """

    label: str
    ratio: float
    nu_lower: float
    nu_upper: float
    h_ratio: float
    band: float
    newton: int

    def params(self) -> dict:
        """The point's parameters for its JSON record."""
        return dataclasses.asdict(self) | {"method": None, "formulation": "displacement"}


def two_body_specs(cfg: StabilityConfig | None = None) -> list[TwoBodySpec]:
    """The ``two_body`` study's points (:attr:`StabilityConfig.two_body_pairs`)."""
    cfg = StabilityConfig() if cfg is None else cfg
    return [TwoBodySpec(f"E2/E1={decade(r)} nu1={nl:g} nu2={nu:g}", r, nl, nu, cfg.two_body_h_ratio, cfg.band,
                        cfg.two_body_newton) for r, nl, nu in cfg.two_body_pairs]
