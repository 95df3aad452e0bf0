"""Packages whose names load on first use: a command pays only for what it uses.

``import bakeshop.sphere`` used to import every module of the package, and with them scipy and
the area filter's kernels; a package that calls :func:`export_lazily` instead imports the
module that defines a name when the name is first read (``from bakeshop.sphere import
guess_layout`` loads the layouts, not the area filter). What a name is and where it is defined
do not change: the table is checked against every module by the architecture tests.
"""

from __future__ import annotations

import importlib
import sys
import types


class _LazyPackage(types.ModuleType):
    """A package module whose missing attributes are imported from their submodule."""

    _exports: dict[str, str]

    def __getattr__(self, name: str) -> object:
        sub = self._exports.get(name)
        if sub is None:
            raise AttributeError(f"module {self.__name__!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(f"{self.__name__}.{sub}"), name)
        self.__dict__[name] = value
        return value

    def __setattr__(self, name: str, value: object) -> None:
        # the import system binds a submodule to its package when it first loads it; where an
        # exported name is also a submodule's (``sphere.texels``), the exported one keeps it
        if name in self._exports and isinstance(value, types.ModuleType):
            return
        super().__setattr__(name, value)

    def __dir__(self) -> list[str]:
        return sorted(set(super().__dir__()) | set(self._exports))


def export_lazily(package: str, exports: dict[str, str]) -> None:
    """Make ``package`` (its ``__name__``) import ``exports[name]`` (a submodule's name) when
    ``name`` is first read from it."""
    module = sys.modules[package]
    module.__class__ = _LazyPackage
    module.__dict__["_exports"] = dict(exports)
