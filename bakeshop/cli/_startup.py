"""What a command's process leaves out at start-up: numba's probe for a BLAS.

The first kernel a command calls loads numba's CPU target, which imports
``numba.np.arraymath``; that module probes for a BLAS at import by importing
``scipy.linalg.cython_blas``, and so all of ``scipy.linalg`` (0.18-0.2 s of a 1 s command: its
array-API layer imports most of numpy's submodules). The probe's answer is used only by
``np.convolve`` and ``np.correlate`` inside compiled code, which no kernel of bakeshop calls
(``np.dot`` and ``np.linalg`` in compiled code look for the BLAS themselves when compiled). So
while that one module executes, a command hides scipy's BLAS module; the probe answers "none",
and ``scipy.linalg`` imports as usual for whoever asks afterwards.
"""

from __future__ import annotations

import importlib.abc
import importlib.machinery
import importlib.util
import sys
import types
from collections.abc import Sequence
from typing import Any

#: the module whose import probes for a BLAS, and the module it imports to probe.
PROBING = "numba.np.arraymath"
PROBED = "scipy.linalg.cython_blas"


class _HideProbed(importlib.abc.Loader):
    """``PROBING``'s own loader, executing it with ``PROBED`` hidden (unless already loaded)."""

    def __init__(self, loader: importlib.abc.Loader) -> None:
        self._loader = loader

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> types.ModuleType | None:
        return self._loader.create_module(spec)

    def exec_module(self, module: types.ModuleType) -> None:
        hide = PROBED not in sys.modules
        if hide:
            sys.modules[PROBED] = None  # type: ignore[assignment]  # an import of it fails
        try:
            self._loader.exec_module(module)
        finally:
            if hide and sys.modules.get(PROBED, 0) is None:
                del sys.modules[PROBED]

    def __getattr__(self, name: str) -> Any:  # get_source, get_filename, ... for tracebacks
        return getattr(self._loader, name)


class _SkipBlasProbe(importlib.abc.MetaPathFinder):
    """Finds ``PROBING`` (once) through the other finders and wraps its loader."""

    def find_spec(
        self,
        fullname: str,
        path: Sequence[str] | None,
        target: types.ModuleType | None = None,
    ) -> importlib.machinery.ModuleSpec | None:
        if fullname != PROBING:
            return None
        sys.meta_path.remove(self)
        spec = importlib.util.find_spec(fullname)
        if spec is not None and spec.loader is not None:
            spec.loader = _HideProbed(spec.loader)
        return spec


def skip_blas_probe() -> None:
    """Make numba's BLAS probe answer "none" without importing scipy (see the module notes);
    nothing when numba's target is already loaded."""
    if PROBING not in sys.modules and not any(isinstance(f, _SkipBlasProbe) for f in sys.meta_path):
        sys.meta_path.insert(0, _SkipBlasProbe())
