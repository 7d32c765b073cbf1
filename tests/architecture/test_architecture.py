"""The shape of the package: the import layers (import-linter's contract in pyproject.toml) and
one identity per law (no law name spelled outside the registry)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import viscontact
from viscontact.physics.laws import MODELS

PACKAGE = Path(viscontact.__file__).resolve().parent
ROOT = PACKAGE.parent.parent

#: modules allowed to spell a law's name: the registry itself
REGISTRY = {"physics/laws.py"}


def test_import_layers_point_down():
    """physics at the bottom, cli on top; a lower layer never imports a higher one."""
    importlinter = pytest.importorskip("importlinter.cli")
    config = ROOT / "pyproject.toml"
    if not config.is_file():
        pytest.skip("pyproject.toml is not next to the package (installed, not a checkout)")
    assert importlinter.lint_imports(config_filename=str(config)) == 0


def _docstrings(tree: ast.AST) -> set[int]:
    """ids of the docstring nodes of a module, its classes and functions."""
    ids = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
                ids.add(id(body[0].value))
    return ids


def law_literals(path: Path) -> list[str]:
    """``file:line name`` for every string constant in ``path`` that is exactly a law's name
    (docstrings aside)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    skip = _docstrings(tree)
    return [f"{path.relative_to(PACKAGE).as_posix()}:{node.lineno} {node.value!r}"
            for node in ast.walk(tree)
            if isinstance(node, ast.Constant) and isinstance(node.value, str)
            and node.value in MODELS and id(node) not in skip]


def test_law_names_are_spelled_only_in_the_registry():
    """A law's name, exponent and needs come from :mod:`viscontact.physics.laws`: code that
    means "the law with the relaxation time" asks the registry (``needs_beta``), it does not
    compare with a name."""
    found = [hit for path in sorted(PACKAGE.rglob("*.py"))
             if path.relative_to(PACKAGE).as_posix() not in REGISTRY
             for hit in law_literals(path)]
    assert not found, "law names outside the registry:\n" + "\n".join(found)


def test_the_literal_check_can_fail(tmp_path):
    bad = PACKAGE / "physics" / "laws.py"  # the registry does spell them
    assert law_literals(bad)


def test_old_module_paths_are_the_new_modules():
    """Code written against the flat layout keeps working: ``viscontact.laws`` is the module
    ``viscontact.physics.laws`` itself (not a copy), as an import and as an attribute."""
    import importlib

    from viscontact._moved import MOVED

    for old, new in MOVED.items():
        assert (importlib.import_module(f"viscontact.{old}")
                is importlib.import_module(f"viscontact.{new}")), old
    assert viscontact.experiment is importlib.import_module("viscontact.paper.experiment")
    with pytest.raises(AttributeError, match="no attribute 'not_there'"):
        viscontact.not_there
