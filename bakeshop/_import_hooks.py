"""Code run as a module of another package executes: a meta path finder that wraps the loader
of each module it is given, once (what :mod:`bakeshop._kernel_stamps` and the command line's
:mod:`bakeshop.cli._startup` do to numba as it loads)."""

from __future__ import annotations

import importlib.util
import sys
from typing import TYPE_CHECKING, Any, cast

if TYPE_CHECKING:  # importlib.abc imports importlib.resources and tempfile: 7 ms of `info`
    import importlib.abc
    import importlib.machinery
    import types
    from collections.abc import Callable, Sequence

    #: how a hooked module is executed: (its own loader, the module).
    Hook = Callable[[importlib.abc.Loader, types.ModuleType], None]


class _Hooked:
    """A hooked module's own importlib loader, executing it through its hook."""

    def __init__(self, loader: importlib.abc.Loader, hook: Hook) -> None:
        self._loader, self._hook = loader, hook

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> types.ModuleType | None:
        return self._loader.create_module(spec)

    def exec_module(self, module: types.ModuleType) -> None:
        self._hook(self._loader, module)

    def __getattr__(self, name: str) -> Any:  # get_source, get_filename, ... for tracebacks
        return getattr(self._loader, name)


class _Hooks:
    """A meta path finder: finds each module of ``hooks`` (once) through the other finders and
    wraps its loader; leaves ``sys.meta_path`` when none is pending. Finders of this kind for
    the same module nest: the first inserted runs its hook around the later one's."""

    def __init__(self, hooks: dict[str, Hook]) -> None:
        self.pending = dict(hooks)

    def find_spec(
        self,
        fullname: str,
        path: Sequence[str] | None,
        target: types.ModuleType | None = None,
    ) -> importlib.machinery.ModuleSpec | None:
        hook = self.pending.pop(fullname, None)
        if hook is None:
            return None
        if not self.pending:
            sys.meta_path.remove(self)
        spec = importlib.util.find_spec(fullname)
        if spec is not None and spec.loader is not None:
            spec.loader = cast("importlib.abc.Loader", _Hooked(spec.loader, hook))
        return spec


def after(patch: Callable[[types.ModuleType], None]) -> Hook:
    """A hook that executes the module, then gives it to ``patch``."""

    def hook(loader: importlib.abc.Loader, module: types.ModuleType) -> None:
        loader.exec_module(module)
        patch(module)

    return hook


def hook_imports(hooks: dict[str, Hook]) -> None:
    """Execute each module named in ``hooks`` through its hook when it is first imported (the
    modules already imported are left to the caller; a hook still pending is not added again)."""
    waiting = [f.pending for f in sys.meta_path if isinstance(f, _Hooks)]
    pending = {
        name: hook
        for name, hook in hooks.items()
        if name not in sys.modules and not any(p.get(name) is hook for p in waiting)
    }
    if pending:
        sys.meta_path.insert(0, _Hooks(pending))
