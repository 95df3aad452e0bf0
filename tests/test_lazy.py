"""Packages whose names load on first use (bakeshop._lazy): every exported name resolves to
the object its module defines, and importing the package loads no numerical kernels."""

from __future__ import annotations

import importlib
import json
import subprocess
import sys
from pathlib import Path

import pytest

LAZY_PACKAGES = [
    "bakeshop.sphere",
    "bakeshop.image",
    "bakeshop.normals",
    "bakeshop.light",
    "bakeshop.huge",
]


@pytest.mark.parametrize("name", LAZY_PACKAGES)
def test_every_exported_name_is_in_the_table_and_resolves_to_its_definition(name):
    package = importlib.import_module(name)
    table = package.__dict__["_exports"]
    assert set(package.__all__) == set(table)
    for attr, module in table.items():
        defined = getattr(importlib.import_module(f"{name}.{module}"), attr)
        assert getattr(package, attr) is defined, attr
        assert attr in dir(package)


@pytest.mark.parametrize("name", LAZY_PACKAGES)
def test_the_imports_type_checkers_read_are_the_table(name):
    """The ``if TYPE_CHECKING:`` imports of the package name each entry of the table, from its
    module (what mypy and editors see is what loads)."""
    import ast

    package = importlib.import_module(name)
    tree = ast.parse(Path(package.__file__).read_text())
    (guard,) = [
        n for n in tree.body if isinstance(n, ast.If) and "TYPE_CHECKING" in ast.unparse(n.test)
    ]
    imported = {
        alias.name: node.module.rpartition(".")[2]
        for node in guard.body
        if isinstance(node, ast.ImportFrom)
        for alias in node.names
    }
    assert imported == package.__dict__["_exports"]


def test_a_name_shared_with_a_submodule_stays_the_function():
    """``bakeshop.sphere.texels`` is a function and a module's name: the function wins, as it
    did when the package imported everything."""
    import bakeshop.sphere
    import bakeshop.sphere.texels  # noqa: F401  (the import system binds the module)

    assert callable(bakeshop.sphere.texels)
    assert not isinstance(bakeshop.sphere.texels, type(sys))


def test_an_unknown_name_is_an_attribute_error():
    import bakeshop.sphere

    with pytest.raises(AttributeError, match="no attribute 'no_such_thing'"):
        bakeshop.sphere.no_such_thing  # noqa: B018


@pytest.mark.parametrize("name", LAZY_PACKAGES)
def test_importing_the_package_loads_no_kernels(name):
    code = (
        f"import json, sys, {name}\n"
        f"heavy = ('scipy', 'matplotlib', '{name}._native')\n"
        "print(json.dumps([m for m in heavy if m in sys.modules]))"
    )
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True)
    assert json.loads(out.stdout) == []
