"""One vocabulary module (issue 37): the words of the contact methods and kinematics are defined once, in
:mod:`vocabulary`, and the layers that check them (cases, fem, the scenes and studies) import them.

Requirements: no module outside ``vocabulary/`` (tests and docs aside) assigns a tuple, list or set literal that
spells two or more method words or two or more kinematics words; the case schema's choices, the solver's options and
registries and the studies' lists are the vocabulary's; the rule "finite kinematics needs a hyperelastic model" is
one function, which the case schema and the solver options both apply.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import vocabulary as V

ROOT = Path(__file__).resolve().parents[1]
SOURCES = ("vocabulary", "analytic", "measures", "cases", "meshes", "fem", "workbench", "examples", "tools")
WORDS = {"methods": set(V.METHODS), "kinematics": set(V.KINEMATICS)}


def _strings(node: ast.AST) -> set[str]:
    """The string constants of a (nested) tuple/list/set literal; empty for anything else."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return {node.value}
    if isinstance(node, ast.Tuple | ast.List | ast.Set):
        out: set[str] = set()
        for elt in node.elts:
            out |= _strings(elt)
        return out
    return set()


def vocabulary_definitions(path: Path) -> list[tuple[int, str, set[str]]]:
    """(line, kind, words) of every assignment in ``path`` whose value is a literal spelling >= 2 words of a kind."""
    out = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        value = node.value if isinstance(node, ast.Assign | ast.AnnAssign) else None
        if value is None or not isinstance(value, ast.Tuple | ast.List | ast.Set):
            continue
        found = _strings(value)
        out += [(node.lineno, kind, found & words) for kind, words in WORDS.items() if len(found & words) >= 2]
    return out


def test_methods_and_kinematics_are_defined_in_one_module():
    elsewhere = []
    for top in SOURCES:
        for path in sorted((ROOT / top).rglob("*.py")):
            elsewhere += [f"{path.relative_to(ROOT)}:{line} {kind} {sorted(words)}"
                          for line, kind, words in vocabulary_definitions(path)]
    assert elsewhere == [], "vocabulary lists written outside vocabulary/: " + "; ".join(elsewhere)
    # the one module names each word once (a constant), and its lists are built from those names
    tree = ast.parse((ROOT / "vocabulary" / "__init__.py").read_text())
    named = [n.value.value for n in ast.walk(tree) if isinstance(n, ast.Assign)
             and isinstance(n.value, ast.Constant) and isinstance(n.value.value, str)]
    for words in WORDS.values():
        assert sorted(w for w in named if w in words) == sorted(words)


def test_the_scan_finds_a_redefinition(tmp_path):
    """The check above can fail: a module that writes its own list is found."""
    bad = tmp_path / "bad.py"
    bad.write_text('METHODS = ("nitsche", "penalty")\nKIN: tuple = ["small", "finite"]\nok = ("small",)\n')
    assert [(line, kind) for line, kind, _ in vocabulary_definitions(bad)] == [(1, "methods"), (2, "kinematics")]


def test_the_layers_use_the_vocabulary():
    from cases.schema import _CHOICES
    from fem.contact_forms import KINEMATICS, METHODS, TRACTIONS
    from fem.linear_solver import LINEAR_SOLVERS
    from fem.methods import method_names
    from fem.options import FORMULATIONS, MATERIAL_MODELS
    from workbench.scenes.two_body_schema import PAIRINGS, TWO_BODY_METHODS
    from workbench.studies import bench_config as config

    assert _CHOICES[("solver", "method")] is V.METHODS and _CHOICES[("solver", "kinematics")] is V.KINEMATICS
    assert _CHOICES[("material", "model")] is V.MATERIAL_MODELS
    assert _CHOICES[("solver", "linear_solver")] is V.LINEAR_SOLVERS
    assert method_names() == METHODS == V.METHODS and method_names("meshed") == V.TWO_BODY_METHODS
    assert (KINEMATICS, TRACTIONS, LINEAR_SOLVERS) == (V.KINEMATICS, V.TRACTIONS, V.LINEAR_SOLVERS)
    assert (FORMULATIONS, MATERIAL_MODELS) == (V.FORMULATIONS, V.MATERIAL_MODELS)
    assert (PAIRINGS, TWO_BODY_METHODS) == (V.PAIRINGS, V.TWO_BODY_METHODS)
    assert (config.LINEAR_SOLVERS, config.ACTIVE_SETS) == (V.LINEAR_SOLVERS, V.ACTIVE_SETS)


@pytest.mark.parametrize(("kinematics", "model", "refused"), [
    ("finite", "linear", "material_model"), ("small", "neo_hookean", "material_model"),
    ("convective", "saint_venant_kirchhoff", "material_model"), ("finite", "neo_hookean", None),
    ("small", "linear", None)])
def test_the_model_rule_is_one_function(kinematics, model, refused, monkeypatch):
    bad = V.model_conflict(kinematics=kinematics, material_model=model)
    assert (bad.name if bad else None) == refused
    # both layers apply it: a rule changed here changes what cases and the solver refuse
    import cases.checks
    import fem.options

    assert cases.checks.model_conflict is V.model_conflict and fem.options.model_conflict is V.model_conflict
    monkeypatch.setattr(fem.options, "model_conflict", lambda **kw: None)
    fem.options.check_model(fem.options.ContactOptions.of(E=1.0, nu=0.3, target=1.0, kinematics="finite",
                                                       material_model="linear"))
