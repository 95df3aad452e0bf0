"""What a command's process leaves out at start-up: numba's compiler when its kernels come from
the cache, and numba's probe for a BLAS.

**The compiler.** Before loading a cached kernel, numba refreshes its CPU target: it imports and
registers every typing and lowering table it has (the typed containers, the random generators,
``npyimpl``, ``linalg``, ...), 0.2-0.3 s of a 1 s command, although a cached kernel is machine
code that needs none of them. What it does need comes without the refresh: numba's C helpers
and math symbols when the target context is made, the reload hooks pickled with the kernel (the
thread pool of a parallel kernel), the modules its environment names, and the runtime (NRT:
allocation, reference counts), which the refresh would have initialised and which the hook
initialises itself. A kernel that is not in the cache (the first run after an install, a new
signature) is compiled as always: numba's compiler refreshes the target before it compiles.
The hook replaces ``numba.core.caching.Cache.load_overload``; it is left out, and numba's own
kept, if a numba version lacks the private methods it calls.

**The BLAS probe.** ``numba.np.arraymath`` (the environment of most kernels that reduce an
array names it) probes for a BLAS as it executes by calling ``numba.np.linalg.ensure_blas``,
which imports ``scipy.linalg.cython_blas`` and so all of ``scipy.linalg`` (0.18-0.2 s: its
array-API layer imports most of numpy's submodules). The probe's answer is used only by
``np.convolve`` and ``np.correlate`` inside compiled code, which no kernel of bakeshop calls
(``np.dot`` and ``np.linalg`` in compiled code call ``ensure_blas`` themselves when compiled).
So while that one module executes, it is given an ``ensure_blas`` that answers "none"; numba's
own is back as soon as it has run, and nothing else in the process (``sys.modules``, scipy,
another thread's imports) is touched.

Both hooks act in a command's process only (the command line installs them); a library user's
process is left alone.
"""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING, Any

from bakeshop._import_hooks import after, hook_imports
from bakeshop._kernel_stamps import CACHING

if TYPE_CHECKING:
    import importlib.abc
    import types

    from bakeshop._import_hooks import Hook

#: the module whose import probes for a BLAS.
PROBING = "numba.np.arraymath"


def _load_overload(self: Any, sig: Any, target_context: Any) -> Any:
    """The cache's ``load_overload`` as numba writes it, with the runtime initialised instead of
    the whole target refreshed (see the module notes)."""
    from numba.core.runtime import rtsys

    rtsys.initialize(target_context)
    with self._guard_against_spurious_io_errors():
        return self._load_overload(sig, target_context)
    return None  # the guard swallowed an I/O error: compile instead, as numba's own does


def _patch_cache(module: types.ModuleType) -> None:
    cache = getattr(module, "Cache", None)
    private = ("_guard_against_spurious_io_errors", "_load_overload")
    if all(hasattr(cache, name) for name in private):
        cache.load_overload = _load_overload  # type: ignore[union-attr]


def _no_blas() -> None:
    raise ImportError("the BLAS probe is skipped at a command's start-up")


def _without_blas_probe(loader: importlib.abc.Loader, module: types.ModuleType) -> None:
    import numba.np.linalg as linalg  # the CPU target imports it just before arraymath

    real = linalg.ensure_blas
    linalg.ensure_blas = _no_blas  # arraymath binds it by name as it executes
    try:
        loader.exec_module(module)
    finally:
        linalg.ensure_blas = real
        if getattr(module, "ensure_blas", None) is _no_blas:
            module.ensure_blas = real  # type: ignore[attr-defined]


#: module -> how its loader executes it in a command's process.
HOOKS: dict[str, Hook] = {
    CACHING: after(_patch_cache),
    PROBING: _without_blas_probe,
}


def trim_numba_startup() -> None:
    """Load numba's cached kernels without its compiler's registries and skip its BLAS probe
    (see the module notes): for modules already imported, what can still be done now."""
    if CACHING in sys.modules:
        _patch_cache(sys.modules[CACHING])
    hook_imports(HOOKS)
