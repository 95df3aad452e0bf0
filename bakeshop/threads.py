"""The threads of bakeshop's compiled kernels (OpenMP, :mod:`bakeshop._native`).

Each kernel's parallel loops use the calling thread's count: ``OMP_NUM_THREADS`` when it is set,
else the processors this process may use. :func:`use` sets it for the calling thread (the
command line's ``--threads``), :func:`limited` for a block (a dask task runs its kernels on one
thread per task, so that a cluster does not run more threads than it has cores).
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

from bakeshop import _native

__all__ = ["count", "limited", "use"]


def count() -> int:
    """The threads the calling thread's kernels use."""
    return int(_native.get_threads())


def use(threads: int) -> None:
    """Run the calling thread's kernels on ``threads`` threads (at least 1)."""
    if threads < 1:
        raise ValueError(f"the thread count must be at least 1, not {threads}")
    _native.set_threads(threads)


@contextlib.contextmanager
def limited(threads: int) -> Iterator[None]:
    """Run the calling thread's kernels on ``threads`` threads inside the block."""
    before = count()
    use(threads)
    try:
        yield
    finally:
        use(before)
