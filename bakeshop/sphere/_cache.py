"""Byte-bounded caches of geometry that depends only on layouts and shapes (plans, texel
directions), the one switch that empties them all (:func:`clear_caches`), and the one that keeps
the costly ones between processes (:func:`persist_caches`)."""

from __future__ import annotations

import collections
import functools
import hashlib
from collections.abc import Callable, Hashable, Sequence
from pathlib import Path
from typing import Protocol

import numpy as np

#: every cache of the package, by name, for :func:`clear_caches` and :func:`cache_info`.
_CACHES: dict[str, ByteBoundedCache] = {}

#: the caches worth keeping between processes: what costs far more to build than to read
#: (an area-filter matrix: seconds to build, a file read at disk speed). Nearest and bilinear
#: plans are not among them: building one is a single pass over the output, as fast as
#: reading it.
PERSISTED = ("area filter matrices",)


class Store(Protocol):
    """Where :func:`persist_caches` keeps entries: :class:`bakeshop.io.ArrayStore`."""

    def load(self, key: str) -> tuple[np.ndarray, ...] | None: ...

    def put(self, key: str, arrays: Sequence[np.ndarray]) -> bool: ...


#: the store of the persisted caches: :func:`bakeshop.io.user_store` until
#: :func:`persist_caches` says otherwise (None: each process builds its own).
_store: Store | None = None
_chosen = False


def persist_caches(store: Store | None) -> None:
    """Keep the entries of the costly caches (:data:`PERSISTED`) in ``store`` between
    processes: a miss reads the store before building, and what is built is saved there.
    ``None`` stops. Without a call, the library and the command line alike use
    :func:`bakeshop.io.user_store` (``BAKESHOP_CACHE_BYTES=0`` keeps nothing); any
    :class:`bakeshop.io.ArrayStore` may be passed.

    An entry's key holds the cache's name, the key in the process, and a fingerprint of the
    code of :mod:`bakeshop.sphere` and of bakeshop's version, so an entry built by other code
    is never read."""
    global _store, _chosen
    _store, _chosen = store, True


def _current_store() -> Store | None:
    """The store of the persisted caches, the user's one when none was chosen."""
    if not _chosen:
        from bakeshop.io.store import user_store

        persist_caches(user_store())
    return _store


@functools.cache
def _fingerprint() -> str:
    """A digest of bakeshop's version and of every source file and compiled kernel of this
    package."""
    from bakeshop import __version__
    from bakeshop.sphere import _native

    digest = hashlib.sha256(__version__.encode())
    folder = Path(__file__).parent
    for path in sorted(folder.rglob("*.py")):
        digest.update(str(path.relative_to(folder)).encode() + path.read_bytes())
    digest.update(Path(_native.__file__).read_bytes())  # wherever the install put it
    return digest.hexdigest()[:16]


class ByteBoundedCache:
    """Least-recently-used tuples of arrays holding at most ``budget`` bytes in all; the
    newest entry is kept whatever its size (a budget of 0 keeps just the last one)."""

    def __init__(self, name: str, budget: int):
        self.budget = budget
        self.entries: collections.OrderedDict = collections.OrderedDict()
        self.name = name
        self.hits = self.misses = 0
        #: entries built, and entries read from the store of :func:`persist_caches`.
        self.builds = self.loads = 0
        _CACHES[name] = self

    def cached(self, key: Hashable, build: Callable[[], tuple]) -> tuple:
        """The entry for ``key``: from memory, else from the persisted store (when this cache
        is persisted), else built by ``build()``; kept (and saved to the store) when missing."""
        value = self.get(key)
        if value is not None:
            return value
        store = _current_store() if self.name in PERSISTED else None
        disk_key = f"{self.name}|{_fingerprint()}|{key!r}"
        value = None if store is None else store.load(disk_key)
        if value is not None:
            self.loads += 1
            return self.put(key, value)
        value = build()
        self.builds += 1
        if store is not None:
            store.put(disk_key, value)
        return self.put(key, value)

    def get(self, key: Hashable) -> tuple | None:
        """The cached result for ``key`` (now the most recent), or None."""
        if key not in self.entries:
            self.misses += 1
            return None
        self.hits += 1
        self.entries.move_to_end(key)
        return self.entries[key]

    def put(self, key: Hashable, value: tuple) -> tuple:
        """Cache ``value`` for ``key``, dropping the least recent beyond the budget."""
        self.entries[key] = value
        while len(self.entries) > 1 and self.nbytes() > self.budget:
            self.entries.popitem(last=False)
        return value

    def nbytes(self) -> int:
        """Bytes held by the cached arrays."""
        return sum(a.nbytes for value in self.entries.values() for a in value)

    def clear(self) -> None:
        """Drop every entry (the counters stay)."""
        self.entries.clear()


def clear_caches() -> None:
    """Empty every geometry cache of :mod:`bakeshop.sphere` (remap plans, area-filter
    matrices, texel directions and solid angles), freeing their memory."""
    for cache in _CACHES.values():
        cache.clear()


def cache_info() -> dict[str, dict[str, int]]:
    """Per cache: ``{"hits", "misses", "builds", "loads", "entries", "bytes"}`` since the
    process started (``loads``: entries read from the store of :func:`persist_caches`)."""
    return {
        name: {
            "hits": cache.hits,
            "misses": cache.misses,
            "builds": cache.builds,
            "loads": cache.loads,
            "entries": len(cache.entries),
            "bytes": cache.nbytes(),
        }
        for name, cache in _CACHES.items()
    }
