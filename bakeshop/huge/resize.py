"""Energy-preserving resize of images larger than memory, block by block.

Each output block is computed from the window of the source its footprint covers
(:func:`bakeshop.image.area_footprint`) by :func:`bakeshop.image.resize_area_part`: the same
arithmetic, in the same order, as the in-memory :func:`bakeshop.image.resize_area`, so the result
is bit-identical to it (float64 accumulation, one rounding). A latlong panorama can instead be
reduced with solid-angle row weights (:func:`latlong_row_weights`), which preserve the integral
of radiance over the sphere exactly rather than the planar mean: the first stage of the
out-of-core area filter (:mod:`bakeshop.huge.remap`).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Sequence
from typing import Any, TypeAlias

import numpy as np

from bakeshop.errors import ArgumentError
from bakeshop.huge.engine import Engine
from bakeshop.huge.memory import blocks, plan_blocks, refuse
from bakeshop.image import area_footprint, area_weights, resample_separable, resize_area_part
from bakeshop.io.stream import ArrayReader, Reader
from bakeshop.sphere.reductions import latlong_row_weights

#: a task's window is at most this large whatever the bound (larger windows only delay the
#: first results and the progress).
MAX_WINDOW_BYTES = 256 << 20


#: what the chunked functions read: a :class:`~bakeshop.io.stream.Reader`, a path, or an
#: (H, W, C) array.
Source: TypeAlias = "Reader | str | os.PathLike | np.ndarray"


def as_reader(source: Source) -> Reader:
    """``source`` as a :class:`~bakeshop.io.stream.Reader`: a reader as it is, a path opened
    with :func:`bakeshop.io.stream.open_image`, an array wrapped in memory."""
    if isinstance(source, Reader):
        return source
    if isinstance(source, (str, os.PathLike)):
        from bakeshop.io.stream import open_image

        return open_image(source)
    return ArrayReader(source)


def _block(
    region: tuple[int, int, int, int], reader: Reader, size: tuple[int, int], weighting: str
) -> np.ndarray:
    """One output block (``region`` = top, bottom, left, right) of a resize of ``reader``."""
    top, bottom, left, right = region
    h, w, _ = reader.shape
    width, height = size
    (ly, hy), (lx, hx) = (
        area_footprint(h, height, top, bottom),
        area_footprint(w, width, left, right),
    )
    window = reader.read((ly, hy), (lx, hx))
    if weighting == "planar":
        return resize_area_part(
            window, (h, w), size, rows=(top, bottom), cols=(left, right), origin=(ly, lx)
        )
    ay = latlong_row_weights(h, height)[top:bottom]
    ax = area_weights(w, width)[left:right]
    out = np.empty((bottom - top, right - left, window.shape[2]), np.float32)
    return resample_separable(
        window, (ay.indptr, ay.indices - ly, ay.data), (ax.indptr, ax.indices - lx, ax.data), out
    )


def _block_bytes(reader: Reader, size: tuple[int, int]) -> Callable[[int, int], int]:
    """Bytes a task of (rows, columns) output texels holds: the window (read buffer and the
    array), a float64 row of scratch, and the output block."""
    h, w, c = reader.shape
    width, height = size

    def cost(rows: int, cols: int) -> int:
        in_rows = math.ceil(rows * h / height) + 1
        in_cols = math.ceil(cols * w / width) + 1
        return 2 * in_rows * in_cols * c * 4 + in_cols * c * 8 + rows * cols * c * 4

    return cost


def plan(
    reader: Reader, size: tuple[int, int], engine: Engine, *, fixed: int, what: str
) -> list[tuple[int, int, int, int]]:
    """The output blocks of a resize of ``reader`` to ``size`` under the engine's bound."""
    width, height = size
    per_task = min(engine.per_task(fixed, reader), MAX_WINDOW_BYTES)
    cost = _block_bytes(reader, size)
    if fixed + engine.workers * cost(1, 1) > engine.memory:
        raise refuse(what, fixed + engine.workers * cost(1, 1), engine.memory)
    block = plan_blocks(
        (height, width),
        cost,
        per_task,
        at_least=4 * engine.total_workers,
        what=what,
        memory=engine.memory,
        fixed=fixed,
        workers=engine.workers,
    )
    return blocks((height, width), block)


def _check_size(size: Sequence[int]) -> tuple[int, int]:
    width, height = (int(n) for n in size)
    if width < 1 or height < 1:
        raise ArgumentError(f"invalid output size {width}x{height}")
    return width, height


def resize(
    source: Source,
    size: tuple[int, int],
    *,
    engine: Engine | None = None,
    weighting: str = "planar",
) -> np.ndarray:
    """Resize an image of any size to ``size = (width, height)``, preserving its energy, within
    the engine's memory bound.

    Parameters
    ----------
    source : Reader, path or (H, W, C) array
        The image (see :func:`as_reader`).
    size : (int, int)
        Output (width, height); the output is held in memory.
    engine : Engine, optional
        Scheduler and memory bound (default: ``Engine()``).
    weighting : {"planar", "latlong"}
        ``planar``: :func:`bakeshop.image.resize_area`, bit for bit. ``latlong``: rows weighted
        by solid angle (:func:`latlong_row_weights`).

    Returns
    -------
    (height, width, C) float32

    Raises
    ------
    MemoryBoundError
        Before anything is read, when the output and one task's window cannot fit the bound.
    """
    from bakeshop.errors import validate_choice

    validate_choice(weighting, ("planar", "latlong"), "weighting")
    engine = Engine() if engine is None else engine
    reader = as_reader(source)
    engine.check_source(reader)
    width, height = _check_size(size)
    h, w, c = reader.shape
    out_bytes = width * height * c * 4
    what = f"resizing {w}x{h} to {width}x{height}"
    regions = plan(reader, (width, height), engine, fixed=out_bytes, what=what)
    out = np.empty((height, width, c), np.float32)
    return engine.assemble(_block, regions, out, (reader, (width, height), weighting), what)


def resize_to_file(
    source: Source,
    target: str | os.PathLike,
    size: tuple[int, int],
    *,
    engine: Engine | None = None,
    **options: Any,
) -> None:
    """:func:`resize` written to ``target`` by strips (for outputs larger than the bound too):
    bands of output rows are computed in parallel and written in order, atomically."""
    from bakeshop.huge.output import write_bands

    engine = Engine() if engine is None else engine
    reader = as_reader(source)
    engine.check_source(reader)
    width, height = _check_size(size)
    c = reader.shape[2]
    write_bands(
        target,
        (height, width, c),
        _block,
        (reader, (width, height), "planar"),
        _block_bytes(reader, (width, height)),
        engine,
        f"resizing {reader.shape[1]}x{reader.shape[0]} to {width}x{height}",
        **options,
    )
