"""Remapping panoramas larger than memory to any layout, tile by tile.

The output is cut into tiles (per cube face); a tile's task computes its texels' source taps
(:func:`bakeshop.sphere.windows.remap_part_taps`, the in-memory plan's own arithmetic), reads only
the window of the source those taps touch (a latlong's longitude wraps: a window may be two
column ranges; a tile whose window would exceed its share of the bound is split in four) and
blends them. ``nearest`` and ``bilinear`` are therefore bit-identical to
:func:`bakeshop.sphere.remap`.

The area filter of :func:`bakeshop.sphere.remap` builds and balances one matrix over every
source texel, which cannot be cut into windows; for large sources it supersamples instead
(:func:`bakeshop.sphere.area.supersample`), and so does this module, tile by tile: each output
texel is the solid-angle-weighted mean of k x k bilinear samples (k the ratio of the texel
pitches: samples about as dense as the source's texels) of the source clamped below its bright
texels, whose excess (a sun, lamps: a few thousand texels at most, found in one pass of
strips) is deposited exactly. The energy is kept (to ~1e-5 on the default probe); a tile's
window is read clamped, and a tile whose window would exceed its share of the bound is split.
A latlong output without rotation is the exact solid-angle-weighted reduction
(:func:`bakeshop.huge.resize.resize`).
Sources are flat layouts (latlong, angular, mirrorball, octahedral, dual-paraboloid).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, UnsupportedError, validate_choice
from bakeshop.huge.engine import Engine
from bakeshop.huge.memory import blocks, plan_blocks, refuse
from bakeshop.huge.resize import Source, as_reader, resize
from bakeshop.io.stream import Reader
from bakeshop.sphere import area, cube_to_view, layout, texel_strips, valid_texels
from bakeshop.sphere.reductions import box_reduce
from bakeshop.sphere.windows import gather_taps, localise_taps, remap_part_taps, taps_window

#: layouts a chunked remap reads (one image file each, addressed by rows and columns).
FLAT_SOURCES = ("latlong", "angular", "mirrorball", "octahedral", "dual-paraboloid")
FILTERS = ("auto", "nearest", "bilinear", "area")
#: the largest tile task's samples, and its window: larger ones save nothing (the work is per
#: texel) and, times the tasks running at once, would go past the bound (a polar tile's window
#: spans every column: a 16k source's cube remap peaked at 1280 MB under 1 GB with windows up
#: to a task's whole share).
TILE_BYTES = 64 << 20
#: bytes per output texel of a tile's task besides its window: taps (16), fractions (8),
#: local taps (16), the blended texel (4 per channel) and the block (4 per channel).
_TEXEL_BYTES = 40


def output_shape(
    src: str, src_shape: Sequence[int], dst: str, size: int | tuple[int, int] | None = None
) -> tuple[int, ...]:
    """The spatial shape of a remap of a ``src`` image of ``src_shape`` to ``dst`` at ``size``
    (None: about as many valid texels), as :func:`bakeshop.sphere.remap_shape` gives it."""
    d = layout(dst)
    if size is None:
        size = d.default_size(valid_texels(src, src_shape))
    return d.shape(size)


def choose_filter(src: str, src_shape: Sequence[int], dst: str, dst_shape: Sequence[int]) -> str:
    """``"area"`` when the output has at most half the source's valid texels, else
    ``"bilinear"`` (the rule of :func:`bakeshop.sphere.auto_filter`)."""
    small = 2 * valid_texels(dst, dst_shape) <= valid_texels(src, src_shape)
    return "area" if small else "bilinear"


def _part(
    reader: Reader,
    src: str,
    src_shape: Sequence[int],
    dst: str,
    dst_shape: Sequence[int],
    face: int,
    rows: tuple[int, int],
    cols: tuple[int, int],
    filter: str,
    rotation: ArrayLike | None,
    per_task: int,
) -> np.ndarray:
    """The texels ``rows x cols`` of ``face`` of the output, from their window of the source."""
    c = reader.shape[2]
    taps, frac = remap_part_taps(
        src,
        src_shape,
        dst,
        dst_shape,
        face=face,
        rows=rows,
        cols=cols,
        filter=filter,
        rotation=rotation,
    )
    width = src_shape[1]
    window_rows, ranges = taps_window(taps, width)
    shape = (rows[1] - rows[0], cols[1] - cols[0], c)
    if not ranges:
        return np.zeros(shape, np.float32)
    columns = sum(b - a for a, b in ranges)
    window_bytes = 2 * (window_rows[1] - window_rows[0]) * columns * c * 4
    if window_bytes > per_task and shape[0] * shape[1] > 1:
        # a window too large for this task's share: split the tile along its longer side
        if shape[0] >= shape[1]:
            mid = (rows[0] + rows[1]) // 2
            halves = [((rows[0], mid), cols), ((mid, rows[1]), cols)]
            axis = 0
        else:
            mid = (cols[0] + cols[1]) // 2
            halves = [(rows, (cols[0], mid)), (rows, (mid, cols[1]))]
            axis = 1
        return np.concatenate(
            [
                _part(
                    reader, src, src_shape, dst, dst_shape, face, r, k, filter, rotation, per_task
                )
                for r, k in halves
            ],
            axis=axis,
        )
    pieces = [reader.read(window_rows, r) for r in ranges]
    window = pieces[0] if len(pieces) == 1 else np.concatenate(pieces, axis=1)
    local = localise_taps(taps, width, window_rows, ranges)
    return gather_taps(window.reshape(-1, c), local, frac).reshape(shape)


def _block(
    region: tuple[int, int, int, int],
    reader: Reader,
    src: str,
    src_shape: Sequence[int],
    dst: str,
    dst_shape: Sequence[int],
    side: int,
    filter: str,
    rotation: ArrayLike | None,
    per_task: int,
) -> np.ndarray:
    """A block of the output stacked face over face: ``region`` rows of face ``top // side``."""
    top, bottom, left, right = region
    face = top // side
    rows = (top - face * side, bottom - face * side)
    return _part(
        reader,
        src,
        src_shape,
        dst,
        dst_shape,
        face,
        rows,
        (left, right),
        filter,
        rotation,
        per_task,
    )


class _Peaks:
    """A strip's part of the bright texels' pass (:func:`bakeshop.sphere.area.peak_candidates`);
    the sum of two keeps the sums of both and their MAX_BRIGHT + 1 texels of largest peak, all
    that :func:`bakeshop.sphere.area.bright_texels` reads of the whole image's, so that the
    engine reduces the strips' parts as they come (never one per strip at once)."""

    def __init__(self, part: tuple[Any, ...]):
        self.part = part

    def __add__(self, other: _Peaks) -> _Peaks:
        (s1, i1, p1, v1), (s2, i2, p2, v2) = self.part, other.part
        index, peaks = np.concatenate([i1, i2]), np.concatenate([p1, p2])
        keep = min(len(peaks), area.MAX_BRIGHT + 1)
        top = np.argpartition(peaks, len(peaks) - keep)[len(peaks) - keep :]
        return _Peaks((s1 + s2, index[top], peaks[top], np.concatenate([v1, v2])[top]))


def _peaks(rows: tuple[int, int], reader: Reader, src: str) -> _Peaks:
    values, omega = _strip_texels(rows, reader, src)
    return _Peaks(area.peak_candidates(values, omega, rows[0] * reader.shape[1]))


def _strip_texels(rows: tuple[int, int], reader: Reader, src: str) -> tuple[np.ndarray, np.ndarray]:
    h, w, c = reader.shape
    _, _, _, omega = next(texel_strips(src, (h, w), rows=rows, texels=1 << 62, directions=False))
    return reader.read(rows).reshape(-1, c), omega


def _supersampled_part(
    reader: Reader,
    src: str,
    src_shape: Sequence[int],
    dst: str,
    dst_shape: tuple[int, ...],
    face: int,
    rows: tuple[int, int],
    cols: tuple[int, int],
    k: int,
    rotation: ArrayLike | None,
    clamp: float,
    per_task: int,
) -> np.ndarray:
    """The texels ``rows x cols`` of ``face`` of the supersampled area filter
    (:func:`bakeshop.sphere.area.supersample`) from their window of the source, clamped:
    the same samples and weights as in memory, each sample's coordinates computed exactly."""
    c = reader.shape[2]
    d = layout(dst)
    fine = area.fine_shape(d, dst_shape, k)
    fine_rows, fine_cols = (rows[0] * k, rows[1] * k), (cols[0] * k, cols[1] * k)
    taps, frac = remap_part_taps(src, src_shape, dst, fine, face=face, rows=fine_rows,
                                 cols=fine_cols, filter="bilinear", rotation=rotation)  # fmt: skip
    width = src_shape[1]
    window_rows, ranges = taps_window(taps, width)
    shape = (rows[1] - rows[0], cols[1] - cols[0], c)
    columns = sum(b - a for a, b in ranges)
    window_bytes = 2 * (window_rows[1] - window_rows[0]) * columns * c * 4
    if window_bytes > per_task and shape[0] * shape[1] > 1:
        axis = 0 if shape[0] >= shape[1] else 1
        span = rows if axis == 0 else cols
        mid = (span[0] + span[1]) // 2
        halves = [(span[0], mid), (mid, span[1])]
        return np.concatenate(
            [
                _supersampled_part(
                    reader,
                    src,
                    src_shape,
                    dst,
                    dst_shape,
                    face,
                    half if axis == 0 else rows,
                    cols if axis == 0 else half,
                    k,
                    rotation,
                    clamp,
                    per_task,
                )  # fmt: skip
                for half in halves
            ],
            axis=axis,
        )
    window = np.concatenate([reader.read(window_rows, r) for r in ranges], axis=1)
    np.minimum(window, np.float32(clamp), out=window)
    local = localise_taps(taps, width, window_rows, ranges)
    samples = gather_taps(window.reshape(-1, c), local, frac)
    weights = area.sample_weights(d, dst_shape, k, face, fine_rows, fine_cols)
    out = np.empty(shape, np.float32)
    box_reduce(samples.reshape(len(weights), -1, c), weights, k, out)
    return out


def _supersampled_block(
    region: tuple[int, int, int, int],
    reader: Reader,
    src: str,
    src_shape: Sequence[int],
    dst: str,
    dst_shape: tuple[int, ...],
    side: int,
    k: int,
    rotation: ArrayLike | None,
    clamp: float,
    per_task: int,
) -> np.ndarray:
    top, bottom, left, right = region
    face = top // side
    rows = (top - face * side, bottom - face * side)
    return _supersampled_part(reader, src, src_shape, dst, dst_shape, face, rows, (left, right),
                              k, rotation, clamp, per_task)  # fmt: skip


def _tiles(
    grid: tuple[int, int, int],
    cost: Callable[[int, int], int],
    per_task: int,
    out_bytes: int,
    engine: Engine,
    what: str,
) -> tuple[list[tuple[int, int, int, int]], int]:
    """The output tiles of a ``(rows, cols, faces)`` grid (rows of the faces stacked), each within
    a task's share of memory by ``cost(rows, cols)``, and that share: the most a tile's source
    window may take (at most :data:`TILE_BYTES`)."""
    dh, dw, faces = grid
    share = min(per_task, TILE_BYTES)
    block = plan_blocks(
        (dh, dw),
        cost,
        share,
        at_least=max(1, 4 * engine.total_workers // faces),
        what=what,
        memory=engine.memory,
        fixed=out_bytes,
        workers=engine.workers,
    )
    regions = [
        (top + f * dh, bottom + f * dh, left, right)
        for f in range(faces)
        for top, bottom, left, right in blocks((dh, dw), block)
    ]
    return regions, share


def supersample_tiles(
    reader: Reader,
    src: str,
    dst: str,
    dst_shape: Sequence[int],
    *,
    k: int,
    rotation: ArrayLike | None,
    engine: Engine,
    what: str,
) -> np.ndarray:
    """The supersampled area filter (:func:`bakeshop.sphere.area.supersample`) of ``reader``
    (a flat layout ``src``) into the base layout ``dst``, tile by tile: one pass of strips
    finds the bright texels (their clamp, indices and values), then each tile
    reads its window, clamped, and the bright texels' excess is deposited exactly;
    ``dst_shape + (C,)`` float32."""
    from bakeshop.huge.light import _strips
    from bakeshop.sphere.rotation import rotation_key

    d = layout(dst)
    h, w, c = reader.shape
    dh, dw, faces = d.grid(dst_shape)
    out_bytes = faces * dh * dw * c * 4
    strips = _strips(reader, engine, out_bytes, what)
    peaks = engine.reduce(_peaks, [(r, reader, src) for r in strips], f"{what}: bright texels")
    clamp, bright, values = area.bright_texels([peaks.part])
    per_task = engine.per_task(out_bytes, reader)
    sample_bytes = 64 + 24 * c  # taps, fractions, local taps, weights, the clamped window

    def cost(rows: int, cols: int) -> int:
        return rows * cols * k * k * sample_bytes

    regions, share = _tiles((dh, dw, faces), cost, per_task, out_bytes, engine, what)
    out = np.empty((faces * dh, dw, c), np.float32)
    args = (reader, src, (h, w), dst, tuple(dst_shape), dh, k, rotation, clamp, share)
    engine.assemble(_supersampled_block, regions, out, args, what)
    if len(bright):
        key = rotation_key(rotation)
        q, add = area.bright_deposits(values, bright, layout(src), (h, w), d, tuple(dst_shape), k,
                                      key, clamp)  # fmt: skip
        np.add.at(out.reshape(-1, c), q, add.astype(np.float32))
    return out.reshape(tuple(dst_shape) + (c,))


def remap_tiles(
    reader: Reader,
    src: str,
    dst: str,
    dst_shape: Sequence[int],
    *,
    filter: str,
    rotation: ArrayLike | None,
    engine: Engine,
    what: str,
) -> np.ndarray:
    """``nearest`` or ``bilinear`` remap of ``reader`` (a flat layout ``src``) into the base
    layout ``dst`` of spatial ``dst_shape``, tile by tile; ``dst_shape + (C,)`` float32."""
    d = layout(dst)
    h, w, c = reader.shape
    dh, dw, faces = d.grid(dst_shape)
    out_bytes = faces * dh * dw * c * 4
    if out_bytes + engine.workers * (_TEXEL_BYTES + 2 * 4 * 4 * c) > engine.memory:
        raise refuse(what, out_bytes + engine.workers * 4096, engine.memory)
    per_task = engine.per_task(out_bytes, reader)
    texels_per = max(1.0, valid_texels(src, (h, w)) / max(1, faces * dh * dw))

    def cost(rows: int, cols: int) -> int:
        return rows * cols * (_TEXEL_BYTES + 8 * c + int(2 * texels_per * c * 4))

    regions, share = _tiles((dh, dw, faces), cost, per_task, out_bytes, engine, what)
    out = np.empty((faces * dh, dw, c), np.float32)
    args = (reader, src, (h, w), dst, tuple(dst_shape), dh, filter, rotation, share)
    engine.assemble(_block, regions, out, args, what)
    return out.reshape(tuple(dst_shape) + (c,))


def remap(
    source: Source,
    src: str,
    dst: str,
    size: int | tuple[int, int] | None = None,
    *,
    filter: str = "auto",
    rotation: ArrayLike | None = None,
    engine: Engine | None = None,
) -> np.ndarray:
    """Convert a panorama of any size between layouts within the engine's memory bound.

    Parameters
    ----------
    source : Reader, path or (H, W, C) array
        The panorama in a flat layout (:data:`FLAT_SOURCES`).
    src, dst : str
        Layout names; ``dst`` may be any layout (cube, crosses and strips included).
    size : int or (int, int), optional
        Output size as for :func:`bakeshop.sphere.remap` (default: about as many texels).
    filter : {"auto", "nearest", "bilinear", "area"}
        ``nearest`` and ``bilinear`` equal :func:`bakeshop.sphere.remap` bit for bit; ``area``
        is the two exact steps of the module docstring (latlong sources); ``auto`` is ``area``
        when the output has at most half the source's texels, else ``bilinear``.
    rotation : optional
        As for :func:`bakeshop.sphere.remap`.
    engine : Engine, optional

    Returns
    -------
    array
        ``dst``'s shape + (C,), float32; held in memory (it must fit the bound).
    """
    validate_choice(filter, FILTERS, "filter")
    engine = Engine() if engine is None else engine
    reader = as_reader(source)
    engine.check_source(reader)
    s, d = layout(src), layout(dst)
    if s.name not in FLAT_SOURCES:
        raise UnsupportedError(
            f"a chunked remap reads {', '.join(FLAT_SOURCES)} sources, not {s.name}; a cube or "
            "cross is small enough to remap in memory (bakeshop.sphere.remap)"
        )
    h, w, c = reader.shape
    src_shape = s.check_shape((h, w))
    dst_shape = output_shape(s.name, src_shape, d.name, size)
    if filter == "auto":
        filter = choose_filter(s.name, src_shape, d.name, dst_shape)
    base_shape = d.base_shape(dst_shape)
    what = f"remapping {s.name} {w}x{h} to {d.name} {'x'.join(map(str, dst_shape))} ({filter})"
    if filter == "area":
        if s.name == d.name == "latlong" and rotation is None:
            dh, dw = dst_shape
            if dh > h or dw > w:
                raise ArgumentError("the area filter reduces; this output is larger (bilinear)")
            return resize(reader, (dw, dh), engine=engine, weighting="latlong")
        ratio = valid_texels(s.name, src_shape) / valid_texels(d.name, dst_shape)
        if ratio >= 1:  # k as the in-memory filter takes it (bakeshop.sphere.area.supersampling)
            k = area.samples_per_side(ratio, d.base, base_shape)
            out = supersample_tiles(reader, s.name, d.base.name, base_shape, k=k, rotation=rotation,
                                    engine=engine, what=what)  # fmt: skip
            return out if d.base is d else cube_to_view(out, d.name)
        filter = "bilinear"  # magnifying: the area filter is bilinear there
    out = remap_tiles(
        reader,
        s.name,
        d.base.name,
        base_shape,
        filter=filter,
        rotation=rotation,
        engine=engine,
        what=what,
    )
    return out if d.base is d else cube_to_view(out, d.name)
