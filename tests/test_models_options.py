"""The model options (material.model, solver.kinematics = "finite", their combinations) are validated before
anything runs: one line naming the field and the allowed values, exit code 2, no results written; the solver's
:class:`fem.options.ContactOptions` refuses the same combinations (ValueError naming the option)."""

from __future__ import annotations

import pytest
from probe_cases import PROBE_BLOCK

from fem.options import ContactOptions, check_model
from workbench.cli import main

GOOD = PROBE_BLOCK + """[solver]
method = "penalty"
traction = "obstacle"
"""

BAD = {
    "model_unknown": ("nu = 0.3", "nu = 0.3\nmodel = 'rubber'", ["material.model", "'neo_hookean'"]),
    "model_wrong_type": ("nu = 0.3", "nu = 0.3\nmodel = 3", ["material.model", "wrong type"]),
    "kinematics_unknown": ("method = \"penalty\"", "method = \"penalty\"\nkinematics = \"large\"",
                           ["solver.kinematics", "'finite'"]),
    "finite_linear": ("method = \"penalty\"", "method = \"penalty\"\nkinematics = \"finite\"",
                      ["solver.kinematics = 'finite'", "material.model", "'neo_hookean'"]),
    "hyperelastic_small": ("nu = 0.3", "nu = 0.3\nmodel = 'neo_hookean'",
                           ["material.model = 'neo_hookean'", "solver.kinematics = 'finite'"]),
    "hyperelastic_convective": ("nu = 0.3\n", "nu = 0.3\nmodel = 'saint_venant_kirchhoff'\n",
                                ["material.model = 'saint_venant_kirchhoff'", "'finite'"]),
}


def _write(tmp_path, text, name="probe"):
    p = tmp_path / f"{name}.toml"
    p.write_text(text)
    return p


def _finite(text: str, model: str = "neo_hookean") -> str:
    return text.replace("nu = 0.3", f"nu = 0.3\nmodel = '{model}'").replace(
        'method = "penalty"', 'method = "penalty"\nkinematics = "finite"')


def _exit_2_one_line(p, tmp_path, capsys, words):
    out = tmp_path / "results"
    code = main(["run", str(p), "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    assert len(err.splitlines()) == 1, err
    for w in words:
        assert w in err, (w, err)
    assert not out.exists(), "no partial results may be written"


@pytest.mark.parametrize("name", [k for k, v in BAD.items() if v[2] is not None])
def test_bad_model_exit_2_one_line(name, tmp_path, capsys):
    old, new, words = BAD[name]
    assert old in GOOD
    _exit_2_one_line(_write(tmp_path, GOOD.replace(old, new, 1), name), tmp_path, capsys, words)


@pytest.mark.parametrize("edit, words", [
    (lambda t: t.replace('traction = "obstacle"', 'traction = "halfplane"'),
     ["solver.kinematics = 'finite'", "solver.traction", "'obstacle'"]),
    (lambda t: t.replace("nu = 0.3", "nu = 0.3\n", 1) + 'formulation = "mixed"\n',
     ["solver.kinematics = 'finite'", "displacement formulation"]),
    (lambda t: t.replace("nu = 0.3", "nu = 0.47"), ["solver.kinematics = 'finite'", "displacement formulation"]),
])
def test_finite_unsupported_combination_exit_2(edit, words, tmp_path, capsys):
    _exit_2_one_line(_write(tmp_path, edit(_finite(GOOD))), tmp_path, capsys, words)


def test_finite_variant_of_a_small_case_is_refused_with_a_linear_material(tmp_path, capsys):
    text = GOOD + '[[variant]]\nlabel = "small"\n[[variant]]\nlabel = "finite"\nsolver = { kinematics = "finite" }\n'
    _exit_2_one_line(_write(tmp_path, text), tmp_path, capsys, ["variant[1]", "material.model"])


def test_finite_case_loads(tmp_path):
    from cases import load_case

    for model in ("neo_hookean", "saint_venant_kirchhoff"):
        case = load_case(_write(tmp_path, _finite(GOOD, model)))
        (run,) = case.runs()
        assert run.material.model == model and run.solver.kinematics == "finite"
    text = GOOD + ('[[variant]]\nlabel = "small"\n[[variant]]\nlabel = "finite"\nsolver = { kinematics = "finite" }\n'
                   'material = { model = "neo_hookean" }\n')
    runs = load_case(_write(tmp_path, text)).runs()
    assert [(r.material.model, r.solver.kinematics) for r in runs] == [("linear", "small"), ("neo_hookean", "finite")]


@pytest.mark.parametrize("kw, word", [
    (dict(material_model="rubber"), "material_model"),
    (dict(kinematics="finite"), "hyperelastic material_model"),
    (dict(material_model="neo_hookean"), "needs kinematics='finite'"),
    (dict(kinematics="finite", material_model="neo_hookean", traction="halfplane"), "traction='obstacle'"),
    (dict(kinematics="finite", material_model="neo_hookean", formulation="mixed"), "formulation='displacement'"),
])
def test_contact_options_refuse_bad_models(kw, word):
    opts = ContactOptions.of(E=1.0, nu=0.3, target=1.0, **({"traction": "obstacle"} | kw))
    with pytest.raises(ValueError, match=word):
        check_model(opts)


def test_contact_options_accept_the_hierarchy():
    """Exactly the model hierarchy is accepted: linear material with small/convective kinematics, a hyperelastic
    one with finite strain; every other pairing of the 3 kinematics and 3 material models is refused."""
    def accepted(kin, model):
        try:
            check_model(ContactOptions.of(E=1.0, nu=0.3, target=1.0, kinematics=kin, material_model=model,
                                       traction="obstacle"))
        except ValueError:
            return False
        return True

    models = ("linear", "neo_hookean", "saint_venant_kirchhoff")
    table = {(kin, m) for kin in ("small", "convective", "finite") for m in models if accepted(kin, m)}
    assert table == {("small", "linear"), ("convective", "linear"), ("finite", "neo_hookean"),
                     ("finite", "saint_venant_kirchhoff")}
