"""What a command's process leaves out at start-up: numba's probe for a BLAS.

The first kernel a command calls loads numba's CPU target, which imports
``numba.np.arraymath``; that module probes for a BLAS at import by calling
``numba.np.linalg.ensure_blas``, which imports ``scipy.linalg.cython_blas`` and so all of
``scipy.linalg`` (0.18-0.2 s of a 1 s command: its array-API layer imports most of numpy's
submodules). The probe's answer is used only by ``np.convolve`` and ``np.correlate`` inside
compiled code, which no kernel of bakeshop calls (``np.dot`` and ``np.linalg`` in compiled code
call ``ensure_blas`` themselves when compiled). So while that one module executes, a command
gives it an ``ensure_blas`` that answers "none"; numba's own is back as soon as it has run, and
nothing else in the process (``sys.modules``, scipy, another thread's imports) is touched.
"""

from __future__ import annotations

import importlib.util
import sys
from typing import TYPE_CHECKING, Any, cast

if TYPE_CHECKING:  # importlib.abc imports importlib.resources and tempfile: 7 ms of `info`
    import importlib.abc
    import importlib.machinery
    import types
    from collections.abc import Sequence

#: the module whose import probes for a BLAS.
PROBING = "numba.np.arraymath"


def _no_blas() -> None:
    raise ImportError("the BLAS probe is skipped at a command's start-up")


class _WithoutProbe:
    """``PROBING``'s own importlib loader, executing it with numba's ``ensure_blas`` answering
    "none"."""

    def __init__(self, loader: importlib.abc.Loader) -> None:
        self._loader = loader

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> types.ModuleType | None:
        return self._loader.create_module(spec)

    def exec_module(self, module: types.ModuleType) -> None:
        import numba.np.linalg as linalg  # the CPU target imports it just before arraymath

        real = linalg.ensure_blas
        linalg.ensure_blas = _no_blas  # arraymath binds it by name as it executes
        try:
            self._loader.exec_module(module)
        finally:
            linalg.ensure_blas = real
            if getattr(module, "ensure_blas", None) is _no_blas:
                module.ensure_blas = real  # type: ignore[attr-defined]

    def __getattr__(self, name: str) -> Any:  # get_source, get_filename, ... for tracebacks
        return getattr(self._loader, name)


class _SkipBlasProbe:
    """A meta path finder: finds ``PROBING`` (once) through the other finders and wraps its
    loader."""

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
            spec.loader = cast("importlib.abc.Loader", _WithoutProbe(spec.loader))
        return spec


def skip_blas_probe() -> None:
    """Make numba's BLAS probe answer "none" without importing scipy (see the module notes);
    nothing when numba's target is already loaded."""
    if PROBING not in sys.modules and not any(isinstance(f, _SkipBlasProbe) for f in sys.meta_path):
        sys.meta_path.insert(0, _SkipBlasProbe())
