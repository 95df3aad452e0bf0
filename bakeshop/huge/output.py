"""Outputs larger than the memory bound: bands of rows computed in parallel, written in order."""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator, Sequence
from typing import Any

import numpy as np

from bakeshop import progress
from bakeshop.huge.engine import Engine
from bakeshop.huge.memory import blocks, plan_blocks, refuse
from bakeshop.io.stream import write_strips


def band_rows(
    shape: Sequence[int], engine: Engine, cost: Callable[[int, int], int], what: str
) -> int:
    """Rows of output per band: a band (held twice: computed, and being written) takes at most
    a third of the bound, leaving the rest to the tasks filling it."""
    h, w, c = shape
    row = w * c * 4
    rows = max(1, min(h, engine.memory // 3 // (2 * row)))
    needed = 2 * row + engine.workers * cost(1, 1)
    if needed > engine.memory:
        raise refuse(what, needed, engine.memory)
    return rows


def write_bands(
    target: str | os.PathLike,
    shape: Sequence[int],
    fn: Callable,
    args: tuple,
    cost: Callable[[int, int], int],
    engine: Engine,
    what: str,
    **options: Any,
) -> None:
    """Write ``target`` (any :func:`bakeshop.io.stream.write_strips` format) of ``shape``
    (h, w, C), each block ``(top, bottom, left, right)`` being ``fn(region, *args)``."""
    h, w, c = shape
    rows = band_rows(shape, engine, cost, what)
    per_task = max(1, (engine.memory - 2 * rows * w * c * 4) // engine.workers)
    bands = list(range(0, h, rows))

    def strips() -> Iterator[np.ndarray]:
        with progress.task(what, len(bands)) as t:
            for top in bands:
                bottom = min(top + rows, h)
                block = plan_blocks(
                    (bottom - top, w),
                    cost,
                    per_task,
                    at_least=4 * engine.total_workers,
                    what=what,
                    memory=engine.memory,
                    workers=engine.workers,
                )
                regions = [
                    (a + top, b + top, left, right)
                    for a, b, left, right in blocks((bottom - top, w), block)
                ]
                out = np.empty((bottom - top, w, c), np.float32)
                yield engine.assemble(
                    fn, regions, out, args, f"rows {top}..{bottom}", origin=(top, 0)
                )
                t.advance()

    write_strips(target, shape, strips(), **options)
