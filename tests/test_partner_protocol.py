"""Contact partners behind one declared protocol (issue 37): :class:`fem.partner_problem.PartnerProblem`.

Requirements: ``fem`` exports the protocol in ``__all__`` and its docstring names both partners; the rigid
obstacle's ContactProblem and the two bodies' TwoBodyProblem implement every member, the two-body problem without
placeholders (no ``obstacle``, ``far_field``, ``ph``, ``method_rule`` standing in for what it lacks); the load
stepper reaches its problem through the protocol's members only (a proxy that hides every other attribute
gives the same solve, bit for bit); the supports are resolved by one function and the contact laws of both
partners sit in one registry.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401

import typing

import numpy as np
import pytest
from mpi4py import MPI
from test_fem_patch import structured_block

import fem
from fem.obstacles import PlaneObstacle
from fem.options import ContactOptions
from fem.partner_problem import PartnerProblem
from fem.problem import ContactProblem
from fem.stepping import LoadStepper
from fem.two_body.problem import Body, MeshedPartner, TwoBodyProblem

MEMBERS = sorted({*typing.get_type_hints(PartnerProblem)} | {
    n for n, v in vars(PartnerProblem).items() if not n.startswith("_") and (callable(v) or isinstance(v, property))})
RIGID_KW = dict(E=1000.0, nu=0.3, degree=2, method="penalty", control="displacement", target=1e-3, n_steps=2,
                supports={"clamped": "roller_y", "sides": "roller_x"})


class ProtocolOnly:
    """A problem seen through the protocol only: any other attribute is an AttributeError naming it."""

    def __init__(self, problem):
        object.__setattr__(self, "_pb", problem)

    def __getattr__(self, name):
        if name not in MEMBERS:
            raise AttributeError(f"the load stepper read {name!r}, which PartnerProblem does not declare")
        return getattr(self._pb, name)


@pytest.fixture(scope="module")
def stacked(tmp_path_factory):
    from meshes.two_body import build_stacked_blocks
    from workbench.mesh_io import read_mesh

    mf = build_stacked_blocks(width=1.0, height_lower=1.0, height_upper=0.5, h_lower=1 / 7, h_upper=1 / 4.3,
                              out_dir=tmp_path_factory.mktemp("mesh"))
    return read_mesh(mf.msh, MPI.COMM_SELF)


def _two_body(md, method="penalty"):
    partner = MeshedPartner(bodies=(Body(name="lower", E=200.0, nu=0.3), Body(name="upper", E=70.0, nu=0.25)),
                            slave="contact_upper", master="contact_lower", driven="driven", driven_body="upper",
                            driven_components=(1,))
    opts = ContactOptions.of(target=1e-3, degree=2, method=method, control="displacement", n_steps=2,
                          supports={"clamped": "roller_y", "symmetry": "roller_x"})
    return TwoBodyProblem(md, partner, opts)


def test_fem_exports_the_protocol():
    assert "PartnerProblem" in fem.__all__ and fem.PartnerProblem is PartnerProblem
    assert "MeshedPartner" in fem.__all__
    assert "rigid analytic obstacle or a second meshed elastic body" in " ".join(fem.__doc__.split())
    assert {"options", "d", "E_star", "tangent_applies", "solve_once", "tangent", "law_samples"} <= set(MEMBERS)


@pytest.mark.parametrize("cls", [ContactProblem, TwoBodyProblem])
def test_both_problems_define_every_method_of_the_protocol(cls):
    data = set(typing.get_type_hints(PartnerProblem))
    missing = [n for n in MEMBERS if n not in data and not hasattr(cls, n)]
    assert missing == [], f"{cls.__name__} lacks {missing}"


def test_the_stepper_uses_the_protocol_only_rigid():
    ref = fem.solve_contact(structured_block(), PlaneObstacle(), **RIGID_KW)
    pb = ContactProblem(structured_block(), PlaneObstacle(), ContactOptions.of(**RIGID_KW))
    assert isinstance(pb, PartnerProblem)
    stepper = LoadStepper(ProtocolOnly(pb))
    stepper.run()
    assert np.array_equal(pb.u.x.array, ref.u.x.array)
    assert [r["iterations"] for r in stepper.records] == ref.newton_iterations


@pytest.mark.parametrize("method", ["penalty", "augmented_lagrangian"])
def test_the_stepper_uses_the_protocol_only_two_bodies(stacked, method):
    ref = _two_body(stacked, method)
    LoadStepper(ref).run()
    pb = _two_body(stacked, method)
    assert isinstance(pb, PartnerProblem)
    for placeholder in ("obstacle", "far_field", "ph", "method_rule"):
        assert not hasattr(pb, placeholder), placeholder
    stepper = LoadStepper(ProtocolOnly(pb))
    stepper.run()
    assert np.array_equal(pb.u.x.array, ref.u.x.array) and stepper.states[-1].P > 0


def test_supports_and_laws_are_written_once():
    import fem.problem
    import fem.supports
    import fem.two_body.laws
    import fem.two_body.problem
    from fem.methods import REGISTRY, get_method

    assert fem.problem.resolve_supports is fem.supports.resolve_supports
    assert fem.two_body.problem.resolve_supports is fem.supports.resolve_supports
    assert not hasattr(fem.two_body.laws, "TWO_BODY_METHODS")
    assert get_method("penalty", "meshed") is fem.two_body.laws.PenaltyLaw is REGISTRY["penalty"]["meshed"]
    with pytest.raises(ValueError, match="not available for two elastic bodies"):
        get_method("nitsche", "meshed")
