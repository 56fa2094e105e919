"""The hyperelastic laws of fem/hyperelastic.py: P = dW/dF for each model, both reduce to small-strain Hooke to
first order in Grad u, and the Cauchy stress is symmetric (frame-indifferent energies)."""

import dolfinx_solver  # noqa: F401

import dolfinx
import numpy as np
import pytest
import ufl
from mpi4py import MPI

from fem.compiled_forms import compile_forms
from fem.elasticity import lame, sigma
from fem.hyperelastic import HYPERELASTIC_MODELS, cauchy, deformation_gradient, first_piola, strain_energy

LM = lame(E=1000.0, nu=0.3)


def _field(scale: float):
    mesh = dolfinx.mesh.create_unit_square(MPI.COMM_WORLD, 2, 2)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (2,)))
    u = dolfinx.fem.Function(V)
    G = scale * np.array([[0.3, -0.7], [0.5, -0.4]])  # a homogeneous, non-symmetric displacement gradient
    u.interpolate(lambda x: G @ x[:2])
    return mesh, u


def _values(forms: dict, mesh) -> dict:
    """The scalar forms assembled, compiled together (one FFCx module: :mod:`fem.compiled_forms`)."""
    compiled = compile_forms(forms, comm=mesh.comm)
    return {k: float(dolfinx.fem.assemble_scalar(f)) for k, f in compiled.items()}


def _sq(expr, mesh):
    return ufl.inner(expr, expr) * ufl.dx(domain=mesh)


@pytest.mark.parametrize("model", HYPERELASTIC_MODELS)
def test_piola_is_the_energy_derivative(model):
    mesh, u = _field(0.2)
    Fv = ufl.variable(deformation_gradient(u))
    # W as a function of F: rebuild it from F (u only enters through F)
    C = Fv.T * Fv
    if model == "saint_venant_kirchhoff":
        E = 0.5 * (C - ufl.Identity(2))
        W = 0.5 * LM.lmbda * ufl.tr(E) ** 2 + LM.mu * ufl.inner(E, E)
    else:
        lnJ = ufl.ln(ufl.det(Fv))
        W = 0.5 * LM.mu * (ufl.tr(C) + 1.0 - 3.0) - LM.mu * lnJ + 0.5 * LM.lmbda * lnJ**2
    P = first_piola(u, model, LM)
    s = cauchy(u, model, LM)
    v = _values({"dP": _sq(P - ufl.diff(W, Fv), mesh), "P": _sq(P, mesh),
                 "dW": (W - strain_energy(u, model, LM)) * ufl.dx, "skew": _sq(s - s.T, mesh), "s": _sq(s, mesh)}, mesh)
    assert np.sqrt(abs(v["dP"])) <= 1e-12 * np.sqrt(v["P"])
    assert abs(v["dW"]) < 1e-12
    assert np.sqrt(abs(v["skew"])) <= 1e-12 * np.sqrt(v["s"])


@pytest.mark.parametrize("model", HYPERELASTIC_MODELS)
def test_small_strain_limit(model):
    errs = []
    for scale in (1e-3, 1e-4):
        mesh, u = _field(scale)
        v = _values({"d": _sq(first_piola(u, model, LM) - sigma(u, LM), mesh), "s": _sq(sigma(u, LM), mesh)}, mesh)
        errs.append(np.sqrt(abs(v["d"]) / v["s"]))
    assert errs[0] < 5e-3 and 8.0 < errs[0] / errs[1] < 12.0, errs  # the difference is first order in Grad u
