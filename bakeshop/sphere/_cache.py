"""Byte-bounded caches of geometry that depends only on layouts and shapes (plans, texel
directions), and the one switch that empties them all (:func:`clear_caches`)."""

from __future__ import annotations

import collections
from collections.abc import Callable, Hashable

#: every cache of the package, by name, for :func:`clear_caches` and :func:`cache_info`.
_CACHES: dict[str, ByteBoundedCache] = {}


class ByteBoundedCache:
    """Least-recently-used tuples of arrays holding at most ``budget`` bytes in all; the
    newest entry is kept whatever its size (a budget of 0 keeps just the last one)."""

    def __init__(self, name: str, budget: int):
        self.budget = budget
        self.entries: collections.OrderedDict = collections.OrderedDict()
        self.hits = self.misses = 0
        _CACHES[name] = self

    def cached(self, key: Hashable, build: Callable[[], tuple]) -> tuple:
        """The entry for ``key``, built by ``build()`` and kept when missing."""
        value = self.get(key)
        return self.put(key, build()) if value is None else value

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
    """Per cache: ``{"hits", "misses", "entries", "bytes"}`` since the process started."""
    return {
        name: {
            "hits": cache.hits,
            "misses": cache.misses,
            "entries": len(cache.entries),
            "bytes": cache.nbytes(),
        }
        for name, cache in _CACHES.items()
    }
