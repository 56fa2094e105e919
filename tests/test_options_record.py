"""The solver options are one record (issue 24): :class:`fem.options.ContactOptions`.

Requirements: ``solve_contact``'s keywords are the record's fields and nothing else (an unknown keyword is a
TypeError naming it); the case schema's ``[solver]`` fields are ContactOptions fields with the same defaults,
except the case-level choices listed, with a reason, in :data:`cases.schema.CASE_LEVEL_DEFAULTS`; the wiring and
the stability sweep derive their options from the record.
"""

import dataclasses
import inspect

import pytest

from cases.schema import CASE_LEVEL_DEFAULTS, Solver
from fem.options import ContactOptions
from fem.solver import solve_contact


def test_solve_contact_takes_the_record():
    params = inspect.signature(solve_contact).parameters
    assert list(params) == ["mesh_data", "obstacle", "options", "fields"]
    assert params["fields"].kind is inspect.Parameter.VAR_KEYWORD
    with pytest.raises(TypeError, match="unexpected keyword argument 'bogus_option'"):
        solve_contact(None, None, E=1.0, nu=0.3, target=1.0, bogus_option=3)
    with pytest.raises(TypeError, match=r"missing required keyword-only argument\(s\): \['E'\]"):
        solve_contact(None, None, nu=0.3, target=1.0)
    with pytest.raises(TypeError, match="not both"):
        solve_contact(None, None, ContactOptions.of(E=1.0, nu=0.3, target=1.0), n_steps=2)


def test_every_field_is_documented_once_on_the_record():
    """Each flat keyword is documented on the record of its concern (issue 37: options by concern)."""
    import fem.options as o

    records = {"law": o.ContactLaw, "load": o.LoadControl, "newton": o.NewtonSolve, "body": o.RigidBody,
               "": ContactOptions}
    missing = [n for n in ContactOptions.field_names()
               if f"\n    {n}:" not in inspect.cleandoc(records[ContactOptions.section_of(n)].__doc__)]
    assert not missing, f"ContactOptions fields without an Attributes entry on their record: {missing}"
    assert "Args:" in solve_contact.__doc__ and "kappa0" not in solve_contact.__doc__  # not written out again


def test_schema_solver_defaults_agree_with_the_record():
    defaults = ContactOptions.defaults()
    solver = {f.name: f.default for f in dataclasses.fields(Solver)}
    assert set(solver) <= set(ContactOptions.field_names()), set(solver) - set(ContactOptions.field_names())
    differ = {k for k, v in solver.items() if v != defaults[k]}
    assert differ == set(CASE_LEVEL_DEFAULTS), (differ, set(CASE_LEVEL_DEFAULTS))
    assert all(len(why) > 40 for why in CASE_LEVEL_DEFAULTS.values())  # each with its reason
    assert (solver["traction"], defaults["traction"]) == ("halfplane", "obstacle")


def test_wiring_derives_from_the_record():
    from cases import load_case
    from workbench.scenes.base import LoadPath
    from workbench.scenes.wiring import solver_options

    run = load_case("hertz_cylinder").runs()[0]
    opts = solver_options(run, LoadPath("force", 10.0, 3, symmetric_half=True), max_it=7)
    assert isinstance(opts, ContactOptions)
    for f in dataclasses.fields(Solver):
        if f.name != "formulation":
            assert getattr(opts, f.name) == getattr(run.solver, f.name), f.name
    assert (opts.E, opts.nu, opts.target, opts.n_steps, opts.max_it) == (run.material.E, run.material.nu, 10.0, 3, 7)
    assert opts.snes_rtol == ContactOptions.defaults()["snes_rtol"]
    with pytest.raises(TypeError, match="unexpected keyword argument 'bogus'"):
        solver_options(run, LoadPath("force", 10.0, 3), bogus=1)


def test_stability_spec_derives_from_the_record():
    from workbench.studies.stability import Spec

    spec = Spec("t", "t", options={"method": "penalty"})
    assert spec.option("snes_rtol") == ContactOptions.defaults()["snes_rtol"]
    assert spec.option("traction") == "halfplane" and spec.option("method") == "penalty"
    assert spec.run().solver.method == "penalty"
    with pytest.raises(TypeError, match="'kapa0' is not a ContactOptions field"):
        Spec("t", "t", options={"kapa0": 1.0})


def test_schema_solver_vocabularies_are_the_solvers():
    """The case schema cannot import fem (layers), so it lists the [solver] choices itself: they must be the
    solver's vocabularies (a new contact method or linear solver is added to both, or this fails)."""
    from cases.schema import _CHOICES
    from fem.contact_forms import KINEMATICS, TRACTIONS
    from fem.methods import method_names
    from fem.options import FORMULATIONS, LINEAR_SOLVERS, MATERIAL_MODELS

    assert set(_CHOICES[("solver", "method")]) == set(method_names())
    assert set(_CHOICES[("solver", "kinematics")]) == set(KINEMATICS)
    assert set(_CHOICES[("solver", "traction")]) == set(TRACTIONS)
    assert set(_CHOICES[("solver", "linear_solver")]) == set(LINEAR_SOLVERS)
    assert set(_CHOICES[("solver", "formulation")]) == {"auto", *FORMULATIONS}
    assert set(_CHOICES[("material", "model")]) == set(MATERIAL_MODELS)
