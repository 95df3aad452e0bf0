"""The stamp numba's on-disk cache keeps with each of bakeshop's kernels: a hash of the kernel's
module and of every bakeshop module that module imports, directly or not.

numba stamps a cached kernel with the hash of its own source file, and loads the machine code
whenever that file is unchanged. But the machine code also holds what the kernel took from
other modules when it was compiled: the kernels it calls (compiled into it) and the globals it
reads (frozen as constants). An upgrade or an edit that changed only such a module (the
mappings of ``sphere/_maps.py``, called by the remap kernels of three other modules) left the
callers running the old code. With this stamp, a change to any module in the kernel module's
import closure (read from the import statements of the sources, so a superset of what the
kernels use) makes numba compile the kernel again.

The stamp is given through numba's cache locators (``numba.core.caching``): bakeshop's own
versions of the three that serve source files, first in the list numba tries, answering for
files of this package only. They are registered as numba's caching module loads
(:func:`install`, called by the package's ``__init__``), before any kernel is decorated.
"""

from __future__ import annotations

import functools
import hashlib
import os
import re
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from bakeshop._import_hooks import after, hook_imports

if TYPE_CHECKING:
    import types

#: the package's folder, as its modules' ``__file__`` name it.
ROOT = Path(__file__).parent
_PREFIX = str(ROOT) + os.sep
#: numba's module of on-disk kernel caches.
CACHING = "numba.core.caching"
#: ``import bakeshop.x.y`` and ``from bakeshop.x import a, b`` (names in parentheses too).
_IMPORT = re.compile(
    r"^[ \t]*(?:from[ \t]+(bakeshop(?:\.\w+)*)[ \t]+import[ \t]+(\([^)]*\)|[^\n]*)"
    r"|import[ \t]+(bakeshop(?:\.\w+)*))",
    re.MULTILINE,
)


@functools.cache
def _modules() -> dict[str, Path]:
    """Dotted name -> source file of every module of the package."""
    found = {}
    for folder, folders, files in os.walk(ROOT):
        folders[:] = [f for f in folders if f != "__pycache__"]
        package = Path(folder).relative_to(ROOT.parent).parts
        for name in files:
            if name.endswith(".py"):
                stem = name[:-3]
                parts = package if stem == "__init__" else (*package, stem)
                found[".".join(parts)] = Path(folder, name)
    return found


@functools.cache
def _imports(path: Path) -> tuple[Path, ...]:
    """The package's source files that ``path`` imports anywhere in its text."""
    found = []
    for source, names, plain in _IMPORT.findall(path.read_text(encoding="utf-8")):
        modules = [plain] if plain else [source]
        for name in re.sub(r"#[^\n]*", "", names).replace("(", " ").replace(")", " ").split(","):
            words = name.split()
            if words:
                modules.append(f"{source}.{words[0]}")  # a submodule, when it is one
        known = _modules()
        found += [known[m] for m in modules if m in known]
    return tuple(sorted(set(found)))


@functools.cache
def closure(path: Path) -> frozenset[Path]:
    """``path`` and the package's source files it imports, directly or not."""
    found, todo = {path}, [path]
    while todo:
        for imported in _imports(todo.pop()):
            if imported not in found:
                found.add(imported)
                todo.append(imported)
    return frozenset(found)


@functools.cache
def stamp(path: Path) -> str:
    """sha256 of the files of :func:`closure` (relative paths and contents, in path order)."""
    digest = hashlib.sha256()
    for file in sorted(closure(path)):
        digest.update(file.relative_to(ROOT).as_posix().encode() + b"\0" + _digest(file))
    return digest.hexdigest()


@functools.cache
def _digest(path: Path) -> bytes:
    return hashlib.sha256(path.read_bytes()).digest()


class _Stamped:
    """A numba cache locator's source stamp taken from :func:`stamp`, for the package's files."""

    _py_file: str

    def get_source_stamp(self) -> str:
        return stamp(Path(self._py_file))

    @classmethod
    def from_function(cls, py_func: Any, py_file: str) -> Any:
        if not py_file.startswith(_PREFIX):
            return None
        return super().from_function(py_func, py_file)  # type: ignore[misc]


def _register(caching: types.ModuleType) -> None:
    """Put the stamped locators first in the list numba tries."""
    bases = ("UserProvidedCacheLocator", "InTreeCacheLocator", "UserWideCacheLocator")
    impl = getattr(caching, "CacheImpl", None)
    if impl is None or not all(hasattr(caching, b) for b in bases):
        return  # another numba: its own stamps
    if any(issubclass(c, _Stamped) for c in impl._locator_classes):
        return
    mine = [type(f"Stamped{b}", (_Stamped, getattr(caching, b)), {"__module__": __name__})
            for b in bases]  # fmt: skip
    impl._locator_classes[:0] = mine


#: numba's caching module -> the stamped locators registered as it loads.
_HOOKS = {CACHING: after(_register)}


def install() -> None:
    """Stamp the package's kernels as described above: now if numba's caching module is loaded,
    else as it loads (importing numba here would cost every command 0.15 s)."""
    if CACHING in sys.modules:
        _register(sys.modules[CACHING])
    else:
        hook_imports(_HOOKS)
