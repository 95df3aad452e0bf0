"""Remapping panoramas larger than memory to any layout, tile by tile.

The output is cut into tiles (per cube face); a tile's task computes its texels' source taps
(:func:`bakeshop.sphere.windows.remap_part_taps`, the in-memory plan's own arithmetic), reads only
the window of the source those taps touch (a latlong's longitude wraps: a window may be two
column ranges; a tile whose window would exceed its share of the bound is split in four) and
blends them. ``nearest`` and ``bilinear`` are therefore bit-identical to
:func:`bakeshop.sphere.remap`.

The area filter of :func:`bakeshop.sphere.remap` balances one matrix over every source texel
(Sinkhorn), which cannot be cut into windows (its plan alone is ~80 bytes per source texel).
Out of core, ``area`` is instead two steps: the latlong source is reduced with solid-angle row
weights (:func:`bakeshop.huge.resize.latlong_row_weights`, preserving the radiance integral
exactly, in float64) to an intermediate latlong, which the in-memory area filter then takes to
the output when its plan fits the bound (the intermediate has twice the output's texels:
energy-preserving, within ~1e-3 RMS of the area filter of the whole source); when even that
does not fit (a 6 x 2048^2 cube under 2 GB), the intermediate has as many texels as the output
and is remapped tile by tile with ``bilinear`` (a mip level and bilinear, as a GPU samples; a
one-texel sun's energy then moves by up to ~1 %). A latlong output without rotation is the
reduction itself (exact).
Sources are flat layouts (latlong, angular, mirrorball, octahedral, dual-paraboloid), and the
area filter needs a latlong source.
"""

from __future__ import annotations

import math

import numpy as np

from bakeshop.errors import ArgumentError, UnsupportedError, validate_choice
from bakeshop.huge.engine import Engine
from bakeshop.huge.memory import blocks, plan_blocks, refuse
from bakeshop.huge.resize import as_reader, resize
from bakeshop.io.stream import ArrayReader, Reader
from bakeshop.sphere import cube_to_view, layout
from bakeshop.sphere.windows import gather_taps, localise_taps, remap_part_taps, taps_window

#: layouts a chunked remap reads (one image file each, addressed by rows and columns).
FLAT_SOURCES = ("latlong", "angular", "mirrorball", "octahedral", "dual-paraboloid")
FILTERS = ("auto", "nearest", "bilinear", "area")
#: bytes the in-memory area filter needs per output texel, from an intermediate of twice the
#: output's texels (its splat, 36 bytes per source texel; its rows, ~48 per output texel; the
#: bilinear plan it starts from, 12; the balancing's sums): measured peak, with a margin.
AREA_BYTES_PER_TEXEL = 200
#: bytes per output texel of a tile's task besides its window: taps (16), fractions (8),
#: local taps (16), the blended texel (4 per channel) and the block (4 per channel).
_TEXEL_BYTES = 40


def valid_texels(name: str, shape) -> int:
    """Texels of a layout's image that see the sphere, without building any per-texel array:
    exact for latlong, octahedral and cubes, pi/4 of the square for the disk layouts (within a
    rim's worth)."""
    lay = layout(name)
    n = int(np.prod(lay.base.shape(lay.face_size(shape)) if lay.base is not lay else shape))
    return round(n * math.pi / 4) if name in ("angular", "mirrorball", "dual-paraboloid") else n


def output_shape(src: str, src_shape, dst: str, size=None) -> tuple[int, ...]:
    """The spatial shape of a remap of a ``src`` image of ``src_shape`` to ``dst`` at ``size``
    (None: about as many valid texels), as :func:`bakeshop.sphere.remap_shape` gives it."""
    d = layout(dst)
    if size is None:
        size = d.default_size(valid_texels(src, src_shape))
    return d.shape(size)


def choose_filter(src: str, src_shape, dst: str, dst_shape) -> str:
    """``"area"`` when the output has at most half the source's valid texels, else
    ``"bilinear"`` (the rule of :func:`bakeshop.sphere.auto_filter`)."""
    small = 2 * valid_texels(dst, dst_shape) <= valid_texels(src, src_shape)
    return "area" if small else "bilinear"


def _intermediate(h: int, w: int, texels: int) -> tuple[int, int]:
    """The smallest latlong (rows, columns) of a ``h x w`` latlong's aspect with at least
    ``texels`` texels (the source's own size at most)."""
    hi = min(h, max(1, math.ceil(math.sqrt(texels * h / w))))
    wi = min(w, max(1, round(hi * w / h)))
    while hi < h and hi * wi < texels:
        hi += 1
        wi = min(w, max(1, round(hi * w / h)))
    return hi, wi


def _part(
    reader: Reader,
    src: str,
    src_shape,
    dst: str,
    dst_shape,
    face,
    rows,
    cols,
    filter,
    rotation,
    per_task,
):
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


def _block(region, reader, src, src_shape, dst, dst_shape, side, filter, rotation, per_task):
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


def remap_tiles(
    reader: Reader,
    src: str,
    dst: str,
    dst_shape,
    *,
    filter: str,
    rotation,
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
    per_task = engine.per_task(out_bytes)
    texels_per = max(1.0, valid_texels(src, (h, w)) / max(1, faces * dh * dw))

    def cost(rows: int, cols: int) -> int:
        return rows * cols * (_TEXEL_BYTES + 8 * c + int(2 * texels_per * c * 4))

    block = plan_blocks(
        (dh, dw),
        cost,
        min(per_task, 64 << 20),
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
    out = np.empty((faces * dh, dw, c), np.float32)
    args = (reader, src, (h, w), dst, tuple(dst_shape), dh, filter, rotation, per_task)
    engine.assemble(_block, regions, out, args, what)
    return out.reshape(tuple(dst_shape) + (c,))


def remap(
    source,
    src: str,
    dst: str,
    size=None,
    *,
    filter: str = "auto",
    rotation=None,
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
    base_shape = dst_shape if d.base is d else d.base.shape(d.face_size(dst_shape))
    what = f"remapping {s.name} {w}x{h} to {d.name} {'x'.join(map(str, dst_shape))} ({filter})"
    if filter == "area":
        if s.name != "latlong":
            raise UnsupportedError(
                f"the chunked area filter reads latlong sources; remap this {s.name} with "
                "filter='bilinear', or convert it to a latlong first"
            )
        if d.name == "latlong" and rotation is None:
            dh, dw = dst_shape
            if dh > h or dw > w:
                raise ArgumentError("the area filter reduces; this output is larger (bilinear)")
            return resize(reader, (dw, dh), engine=engine, weighting="latlong")
        needed = valid_texels(d.name, dst_shape)
        out_bytes = needed * c * 4
        # the in-memory area filter from an intermediate of twice the output's texels, when
        # its plan (AREA_BYTES_PER_TEXEL per output texel) fits the bound; else bilinear from
        # one of as many texels
        in_memory = out_bytes * 3 + AREA_BYTES_PER_TEXEL * needed <= engine.memory
        hi, wi = _intermediate(h, w, 2 * needed if in_memory else needed)
        if (hi, wi) != (h, w):
            reader = ArrayReader(resize(reader, (wi, hi), engine=engine, weighting="latlong"))
            src_shape = (hi, wi)
        if in_memory:
            from bakeshop import progress, sphere

            with progress.step(f"area filter {wi}x{hi} -> {d.name}"):
                out = sphere.remap(
                    reader.image, "latlong", d.name, size, filter="area", rotation=rotation
                )
                sphere.clear_caches()  # its plan would outlive the job, beyond the bound
            return out
        if engine.distributed:  # the intermediate is in this process's memory
            engine = Engine("threads", memory=engine.memory)
        filter = "bilinear"
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
