"""The solver's parts: method registry, ContactOptions, and ContactProblem + LoadStepper by hand.

Requirements: the registry is the one list of methods (``fem.contact_forms.METHODS`` is derived from it, a
duplicate name is refused); ``solve_contact(options=ContactOptions(...))`` is the same solve as the keywords
(bit-identical on the flat-punch patch) and mixing both is a TypeError; building the problem and the stepper
by hand reproduces ``solve_contact`` and calls every step callback once per converged solve.
"""

import dolfinx_solver  # noqa: F401

import numpy as np
import pytest
from test_fem_patch import structured_block

import fem
from fem.contact_forms import METHODS
from fem.methods import REGISTRY, ContactMethod, create, method_names, register
from fem.obstacles import PlaneObstacle
from fem.problem import ContactProblem
from fem.solver import ContactOptions, solve_contact
from fem.stepping import LoadStepper

KW = dict(E=1000.0, nu=0.3, degree=2, method="penalty", control="displacement", target=1e-3, n_steps=2,
          supports={"clamped": "roller_y", "sides": "roller_x"})


def test_registry_is_the_method_list():
    assert method_names() == METHODS == ("nitsche", "penalty", "augmented_lagrangian")
    assert set(REGISTRY) == set(METHODS) and all(issubclass(k["rigid"], ContactMethod) for k in REGISTRY.values())
    with pytest.raises(ValueError, match="already registered"):
        register(type("Other", (ContactMethod,), {"name": "penalty"}))
    with pytest.raises(ValueError, match="method must be one of"):
        create("mortar", E=1.0)
    with pytest.raises(ValueError, match="kappa0"):
        create("augmented_lagrangian", E=1.0, E_star=1.0, kappa0=0.0)
    assert fem.method_names() == METHODS


def test_options_record_is_the_keyword_call():
    opts = ContactOptions.of(**KW)
    a = solve_contact(structured_block(), PlaneObstacle(), **KW)
    b = solve_contact(structured_block(), PlaneObstacle(), options=opts)
    assert np.array_equal(a.u.x.array, b.u.x.array) and a.P == b.P and a.newton_iterations == b.newton_iterations
    assert set(ContactOptions.field_names()) >= {"E", "nu", "target", "uzawa_rtol", "uzawa_max_it"}
    assert opts.replace(n_steps=3).n_steps == 3 and opts.replace(n_steps=3).law == opts.law
    with pytest.raises(TypeError, match="not both"):
        solve_contact(structured_block(), PlaneObstacle(), options=opts, n_steps=3)
    with pytest.raises(TypeError, match="missing"):
        solve_contact(structured_block(), PlaneObstacle(), nu=0.3, target=1e-3)


def test_problem_and_stepper_by_hand():
    md = structured_block()
    ref = solve_contact(md, PlaneObstacle(), **KW)
    problem = ContactProblem(md, PlaneObstacle(), ContactOptions.of(**KW))
    seen = []
    stepper = LoadStepper(problem)
    stepper.add_step_callback(seen.append)
    stepper.run()
    assert [r["iterations"] for r in seen] == ref.newton_iterations
    assert np.array_equal(problem.u.x.array, ref.u.x.array)
    P, Pp = problem.measure()
    assert P == ref.P and Pp == ref.P_pressure
    assert stepper.states[-1].d == ref.d and len(stepper.states) == len(seen) + 1
    state = problem.get_state()
    problem.set_state(state * 0.0)
    assert problem.measure()[0] == 0.0
    problem.set_state(state)
    assert problem.measure()[0] == P
