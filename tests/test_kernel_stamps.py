"""numba's cache of bakeshop's kernels is stamped with each kernel's import closure
(:mod:`bakeshop._kernel_stamps`): a kernel whose own file is unchanged compiles again when a
module it imports changes, where numba's own stamp (its file alone) loaded the old machine code.

Checked end to end on a copy of the package with two small kernel modules added, in fresh
processes sharing one NUMBA_CACHE_DIR; and the closure, read from import statements, against
what every kernel of the package names when it runs."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from bakeshop._kernel_stamps import ROOT, closure

CALLER = """import numba

from bakeshop import _stamp_b  # noqa: a module, called through its name
from bakeshop._stamp_a import (  # a kernel, in parentheses
    g,  # and a comment
)


@numba.njit(cache=True)
def f():
    return 10 * g() + _stamp_b.h()
"""
CALLEE = """import numba


@numba.njit(cache=True)
def {name}():
    return {value}
"""
RUN = """
import json, bakeshop
from bakeshop._stamp_caller import f
f()
print(json.dumps([bakeshop.__file__, f(), f.stats.cache_hits.most_common(), \
f.stats.cache_misses.most_common()]))
"""


@pytest.fixture
def package(tmp_path):
    """A copy of the package (without caches) with the caller and its two callees added."""
    copy = tmp_path / "bakeshop"
    shutil.copytree(ROOT, copy, ignore=shutil.ignore_patterns("__pycache__"))
    (copy / "_stamp_caller.py").write_text(CALLER)
    (copy / "_stamp_a.py").write_text(CALLEE.format(name="g", value=1))
    (copy / "_stamp_b.py").write_text(CALLEE.format(name="h", value=2))
    return copy


def run(package) -> tuple[int, bool]:
    """f() in a fresh process, and whether it came from numba's cache."""
    env = {
        **os.environ,
        "PYTHONPATH": str(package.parent),
        "NUMBA_CACHE_DIR": str(package.parent / "kernels"),
    }
    # from the copy's parent folder: `python -c` puts the working folder first on sys.path
    done = subprocess.run([sys.executable, "-c", RUN], env=env, cwd=package.parent,
                          capture_output=True, text=True)  # fmt: skip
    assert done.returncode == 0, done.stderr
    file, value, hits, misses = json.loads(done.stdout)
    assert file == str(package / "__init__.py")  # the copy, not the installed package
    return value, bool(hits) and not misses


def test_a_kernel_compiles_again_when_a_module_it_imports_changes(package):
    assert run(package) == (12, False)  # compiled
    assert run(package) == (12, True)  # loaded
    (package / "_stamp_a.py").write_text(CALLEE.format(name="g", value=3))
    assert run(package) == (32, False)  # numba's own stamp loaded 12 here
    assert run(package) == (32, True)
    (package / "_stamp_b.py").write_text(CALLEE.format(name="h", value=4))
    assert run(package) == (34, False)
    (package / "_stamp_caller.py").write_text(CALLER.replace("10 * g()", "100 * g()"))
    assert run(package) == (304, False)


def test_the_closure_follows_every_form_of_import():
    rel = {p.relative_to(ROOT).as_posix() for p in closure(ROOT / "sphere" / "_gather.py")}
    # its kernels call _maps's; _maps reads the cube's face bases
    assert {"sphere/_gather.py", "sphere/_maps.py", "sphere/cube.py"} <= rel
    # a command module imports the commands' shared options, the library lazily (in functions)
    rel = {p.relative_to(ROOT).as_posix() for p in closure(ROOT / "cli" / "irradiance.py")}
    assert {"cli/_common.py", "light/diffuse.py", "sphere/_maps.py"} <= rel


def _names(code) -> set[str]:
    """The global names a code object and the functions nested in it read."""
    names = set(code.co_names)
    for const in code.co_consts:
        if hasattr(const, "co_names"):
            names |= _names(const)
    return names


def test_every_kernel_and_module_a_kernel_names_is_in_its_closure():
    """The closure is read from import statements; what numba compiles into a kernel is what
    its code names at run time: every kernel it calls and every package module it reads from
    must be in the closure of the kernel's file (the constants come through those modules)."""
    import inspect
    import types

    from numba.core.dispatcher import Dispatcher

    from tests.kernels import package_kernels

    checked, outside = 0, []
    for qualified, kernel in package_kernels():
        own = closure(Path(inspect.getfile(kernel.py_func)))
        for name in _names(kernel.py_func.__code__):
            value = kernel.py_func.__globals__.get(name)
            if isinstance(value, Dispatcher):
                file = inspect.getfile(value.py_func)
            elif isinstance(value, types.ModuleType):
                file = getattr(value, "__file__", None) or ""
            else:
                continue
            checked += 1
            if file.startswith(str(ROOT)) and Path(file) not in own:
                outside.append(f"{qualified} -> {name} ({file})")
    assert checked > 100
    assert outside == []


def test_the_import_statements_read_are_those_pythons_parser_finds():
    """The closure reads import statements with a regular expression (a parse of every module
    would cost a command's start-up 50 ms); Python's own parser is the reference, on every
    module of the package, so that a form of import it misses cannot come in unseen."""
    import ast

    from bakeshop._kernel_stamps import _imports, _modules

    modules = _modules()
    for name, path in modules.items():
        found = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                found |= {alias.name for alias in node.names}
            elif isinstance(node, ast.ImportFrom):
                assert node.level == 0, f"{name}: a relative import"
                found.add(node.module or "")
                found |= {f"{node.module}.{alias.name}" for alias in node.names}
        expected = {modules[m] for m in found if m in modules}
        assert set(_imports(path)) >= expected - {path}, name
