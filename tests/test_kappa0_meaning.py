"""kappa0 has one meaning on both contact partners (issue 37): ``kappa = kappa0 E* / h`` with E* the plane-strain
modulus of the pair (``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2``; against a rigid obstacle ``E* = E/(1 - nu^2)``).

Requirements: the rigid limit of the two-body penalty law (E2 -> 1e12 E1) has the rigid penalty law's stiffness for
the same h, E1, nu1 (and so does the augmented Lagrangian's augmentation stiffness); the one shipped rigid case that
sets kappa0 kept its former stiffness 1000 E / h; the docstrings and case-file docs say which modulus.
"""

from pathlib import Path

import numpy as np
import pytest

from fem.methods import get_method
from fem.methods.base import penalty_stiffness
from fem.options import ContactOptions
from fem.two_body.problem import Body, MeshedPartner
from vocabulary import AUGMENTED_LAGRANGIAN, MESHED, PENALTY

ROOT = Path(__file__).resolve().parents[1]
E1, NU1, NU2, H, KAPPA0 = 210000.0, 0.3, 0.25, 0.0125, 1e3


def _rigid_kappa(method: str, *, E: float, nu: float, kappa0: float, h: float) -> float:
    """The stiffness the rigid path computes: the method built from the options' parameters."""
    params = ContactOptions.of(E=E, nu=nu, target=1.0, method=method, kappa0=kappa0).method_params()
    law = get_method(method)(**params)
    return penalty_stiffness(law.kappa0, law.E_star, h)


def _two_body_kappa(method: str, *, E1: float, nu1: float, E2: float, nu2: float, kappa0: float, h: float) -> float:
    """The stiffness the two-body path computes: the law built as the two-body problem builds it."""
    partner = MeshedPartner(bodies=(Body(name="lower", E=E1, nu=nu1), Body(name="upper", E=E2, nu=nu2)),
                            slave="s", master="m", driven="top", driven_body="upper")
    law = get_method(method, MESHED)(kappa0=kappa0, E_star=partner.combined_modulus(), h=h, n_nodes=3,
                                     X1=np.zeros(3))
    return law.kappa


@pytest.mark.parametrize("method", [PENALTY, AUGMENTED_LAGRANGIAN])
def test_rigid_limit_of_the_two_body_law_is_the_rigid_law(method):
    rigid = _rigid_kappa(method, E=E1, nu=NU1, kappa0=KAPPA0, h=H)
    limit = _two_body_kappa(method, E1=E1, nu1=NU1, E2=1e12 * E1, nu2=NU2, kappa0=KAPPA0, h=H)
    assert rigid == pytest.approx(KAPPA0 * E1 / (1.0 - NU1**2) / H, rel=1e-15)
    assert abs(limit / rigid - 1.0) < 1e-11, (limit, rigid)
    # the former rigid meaning kappa0 E / h is 1 - nu^2 = 9 % softer: the comparison above tells them apart
    assert abs(KAPPA0 * E1 / H / rigid - 1.0) > 0.05


def test_rigid_penalty_method_reports_the_same_stiffness():
    params = ContactOptions.of(E=E1, nu=NU1, target=1.0, method=PENALTY, kappa0=KAPPA0).method_params()
    assert get_method(PENALTY)(**params).stiffness(H) == _rigid_kappa(PENALTY, E=E1, nu=NU1, kappa0=KAPPA0, h=H)


def test_the_rigid_case_with_kappa0_keeps_its_stiffness():
    """cases/hertz_augmented_lagrangian.toml set kappa0 = 1000 with the former kappa0 E / h: it now says 910 =
    1000 (1 - 0.3^2), the same stiffness, so its key numbers do not move."""
    from cases import load_case

    run = load_case("hertz_augmented_lagrangian").runs()[0]
    E, nu = run.material.E, run.material.nu
    now = _rigid_kappa(run.solver.method, E=E, nu=nu, kappa0=run.solver.kappa0, h=H)
    assert now == pytest.approx(1000.0 * E / H, rel=1e-14)


def test_kappa0_documents_one_modulus():
    for path in ("fem/options.py", "fem/methods/base.py", "fem/two_body/laws.py", "fem/methods/penalty.py",
                 "fem/methods/augmented_lagrangian.py", "docs/cases.md"):
        text = (ROOT / path).read_text()
        assert "kappa0 E* / h" in text, path
        assert "kappa0 E / h" not in text, path
