"""The package's numba kernels, found by importing every module (not from any list kept by the
code under test)."""

from __future__ import annotations

import importlib
import pkgutil
from collections.abc import Iterator

from numba.core.dispatcher import Dispatcher

import bakeshop


def package_kernels() -> Iterator[tuple[str, Dispatcher]]:
    """(qualified name, kernel) for every kernel defined in a module of the package."""
    for info in pkgutil.walk_packages(bakeshop.__path__, "bakeshop."):
        module = importlib.import_module(info.name)
        for kernel in vars(module).values():
            if isinstance(kernel, Dispatcher) and kernel.__module__ == info.name:
                yield f"{info.name}.{kernel.py_func.__qualname__}", kernel
