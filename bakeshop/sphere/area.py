"""The area filter: an energy-preserving average for downsampling between any two layouts.

Every source texel deposits its solid angle into the output texels that its footprint (the box
bounding its locally affine image) overlaps, in proportion to the overlap; where the output is
locally finer, the source texel is first cut into parts, each depositing its own solid angle.
The resulting matrix is built in four stages, each a function here over the compiled kernels
of ``src/sphere/area.hpp`` (the deposits) and ``src/sphere/matrix.hpp`` (the matrix), through
:mod:`bakeshop.sphere._native`:

1. :func:`_splat`: the deposits of ordinary texels (a 3x3 block of output texels each) and the
   blend towards bilinear where the deposits cover too little;
2. :func:`_merge`: the deposits of texels cut into parts or crossing a seam, merged per texel,
   in chunks of bounded memory;
3. :func:`_rows`: the deposits transposed into one row per output texel, bilinear taps joined
   where the blend asks, so that applying the filter is one parallel gather;
4. :func:`_balance`: Sinkhorn balancing, so that a constant stays constant and every source
   texel sends out exactly its solid angle.

The matrix depends only on (layouts, shapes, rotation) and is cached (:data:`AREA_PLAN_BYTES`).
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from bakeshop import progress, threads
from bakeshop.sphere import _native, _plans
from bakeshop.sphere._cache import ByteBoundedCache
from bakeshop.sphere.layouts import MAX_EDGE, MAX_TEXELS, Layout, layout
from bakeshop.sphere.reductions import box_reduce
from bakeshop.sphere.rotation import key_matrix
from bakeshop.sphere.texels import (
    texel_strips,
    texels_at,
    valid_texels,
)

#: largest memory for the per-thread accumulation buffers and for one chunk of unmerged
#: deposits (fewer threads, smaller chunks above).
AREA_BUFFER_BYTES = 1 << 29
#: memory for cached area filter matrices (~48 bytes per output texel where the output is as
#: fine as the source: the matrix of 4096 x 2048 latlong -> 6 x 1024^2 cube, 320 MB, fits).
AREA_PLAN_BYTES = 1 << 29
#: the balancing (see :func:`_balance`): iterations at most, and the relative error of every
#: column's energy at which it stops.
AREA_BALANCE_ITERATIONS = 30
AREA_BALANCE_RTOL = 1e-4


class _Splat(NamedTuple):
    """The per-source-texel deposits of :func:`_splat` (see ``splat_plan`` in
    ``src/sphere/area.hpp``)."""

    anchor: np.ndarray  # int32 (n,): first output texel of a 3x3 block, _native.EXCEPTION, or -1
    wq: np.ndarray  # float32 (n, 4): box weights along x and y
    scale: np.ndarray  # float32 (n,): the texel's solid angle
    width: np.ndarray  # float32 (n,): its footprint's narrower width
    parts: np.ndarray  # int32 (n, 2): parts along each axis
    acc: np.ndarray  # float64 (chunks, m, 2): sums of weights and weighted widths


def _splat(
    s: Layout,
    src_shape: tuple[int, ...],
    d: Layout,
    dst_shape: tuple[int, ...],
    rot: np.ndarray,
    omega: np.ndarray,
) -> _Splat:
    """Stage 1: the deposits of the source texels that land on a 3x3 block of one image."""
    sh, sw, sfaces = s.grid(src_shape)
    dh, dw, faces = d.grid(dst_shape)
    n, m = sfaces * sh * sw, faces * dh * dw
    splat = _Splat(
        anchor=np.empty(n, np.int32),
        wq=np.empty((n, 4), np.float32),
        scale=np.zeros(n, np.float32),
        width=np.zeros(n, np.float32),
        parts=np.ones((n, 2), np.int32),
        # one float64 (m, 2) buffer per thread, as many as fit in AREA_BUFFER_BYTES
        acc=np.zeros((max(1, min(threads.count(), AREA_BUFFER_BYTES // (m * 16))), m, 2)),
    )
    _native.splat_plan(s.kind, sh, sw, sfaces, omega, d.kind, dh, dw, rot, *splat)
    return splat


def _merge(s: Layout, src_shape: tuple[int, ...], d: Layout, dst_shape: tuple[int, ...],
           rot: np.ndarray, omega: np.ndarray, where: np.ndarray,
           parts: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # fmt: skip
    """Stage 2: the merged deposits of the source texels ``where`` (cut into parts, or
    crossing a seam): ``(offsets, taps, weights)``, texel k's entries at offsets[k] onwards.

    Texels are taken in chunks whose unmerged deposits (at most 4 per part: a part's box is at
    most one output texel wide; 8 bytes each) fit in AREA_BUFFER_BYTES / 16, and each chunk's
    merged entries are appended to arrays grown ahead of need (fresh pages are what costs
    here, so nothing is allocated twice)."""
    sh, sw, _ = s.grid(src_shape)
    dh, dw, _ = d.grid(dst_shape)
    offsets = np.zeros(len(where) + 1, np.int64)
    if not len(where):
        return offsets, np.empty(0, np.int32), np.empty(0, np.float32)
    cut = np.take(parts, where, axis=0)
    room = 4 * cut[:, 0].astype(np.int64) * cut[:, 1]
    ends = np.cumsum(room)
    chunk_entries = AREA_BUFFER_BYTES // 16 // 8
    scratch = (
        np.empty(chunk_entries + int(room.max()), np.int32),
        np.empty(chunk_entries + int(room.max()), np.float32),
    )
    kept = _Growing()
    start = 0
    while start < len(where):
        limit = ends[start] - room[start] + chunk_entries
        stop = max(start + 1, int(np.searchsorted(ends, limit, side="right")))
        at = np.zeros(stop - start + 1, np.int64)
        np.cumsum(room[start:stop], out=at[1:])
        taps, weights = scratch[0][: at[-1]], scratch[1][: at[-1]]
        counts = offsets[start + 1 : stop + 1]
        _native.splat_exceptions(s.kind, sh, sw, omega, d.kind, dh, dw, rot, where[start:stop],
                                 parts, at, taps, weights, counts)  # fmt: skip
        kept_ends = np.cumsum(counts) + kept.size
        # room for everything at this chunk's merged share of the unmerged deposits, + 1/16
        expected = int(kept_ends[-1] / ends[stop - 1] * ends[-1] * 17 / 16) + 1024
        kept.reserve(int(kept_ends[-1]), expected)
        _native.compact_exceptions(at, counts, taps, weights, kept_ends, *kept.arrays)
        kept.size = int(kept_ends[-1])
        start = stop
    np.cumsum(offsets, out=offsets)
    taps, weights = kept.filled()
    return offsets, taps, weights


class _Growing:
    """A pair of arrays (int32 taps, float32 weights) filled from the start, grown on demand."""

    def __init__(self) -> None:
        self.arrays: tuple[np.ndarray, ...] = (np.empty(0, np.int32), np.empty(0, np.float32))
        self.size = 0

    def reserve(self, needed: int, expected: int) -> None:
        """Make room for ``needed`` entries, growing to ``expected`` when short."""
        if needed <= len(self.arrays[0]):
            return
        grown = tuple(np.empty(max(needed, expected), a.dtype) for a in self.arrays)
        for new, old in zip(grown, self.arrays, strict=True):
            new[: self.size] = old[: self.size]
        self.arrays = grown

    def filled(self) -> tuple[np.ndarray, np.ndarray]:
        return self.arrays[0][: self.size], self.arrays[1][: self.size]


def _rows(splat: _Splat, merged: tuple[np.ndarray, np.ndarray, np.ndarray], alpha: np.ndarray,
          inverse: np.ndarray, bilinear: tuple[np.ndarray, np.ndarray, np.ndarray], src_width: int,
          dst_width: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # fmt: skip
    """Stage 3: the deposits transposed into CSR rows, one per output texel, with the bilinear
    taps (weighted 1 - alpha) where the deposits cover too little:
    ``(indptr int64, indices int32, values float32)``."""
    offsets, taps, weights = merged
    m = len(alpha)
    cursor = np.zeros((threads.count(), m), np.int64)
    none = (np.empty(0, np.int32), np.empty(0, np.float32))
    deposits = (splat.anchor, splat.wq, splat.scale, dst_width, offsets, taps, weights, alpha,
                inverse, cursor)  # fmt: skip
    _native.splat_rows(*deposits, False, *none)
    counts = np.zeros(m, np.int64)
    _native.bilinear_rows(alpha, src_width, *bilinear, counts, counts, False, *none)
    indptr = np.zeros(m + 1, np.int64)
    _native.row_starts(cursor, counts, indptr)
    rows = (np.empty(indptr[-1], np.int32), np.empty(indptr[-1], np.float32))
    _native.splat_rows(*deposits, True, *rows)
    _native.bilinear_rows(alpha, src_width, *bilinear, indptr, counts, True, *rows)
    return indptr, rows[0], rows[1]


def _balance(indptr: np.ndarray, indices: np.ndarray, values: np.ndarray, omega_out: np.ndarray,
             omega_in: np.ndarray) -> float:  # fmt: skip
    """Stage 4: scale the rows and columns of the sparse matrix M (CSR, nonnegative float32
    ``values``, in place) towards every nonempty row summing to 1 (a constant stays constant)
    and every column p carrying its source texel's solid angle,
    sum_q omega_out[q] M[q, p] = omega_in[p] (radiance x solid angle is preserved).

    Sinkhorn's alternating normalisation (Sinkhorn & Knopp 1967) of the energy transport
    omega_out[q] M[q, p], on the scale vectors, one read of M per step (each row's scale, then
    its entries' share of the column sums, into one float64 buffer of the source's size per
    thread, as many as fit in AREA_BUFFER_BYTES), its column steps over-relaxed (Thibault et al.
    2017) and with momentum (the slow, smooth imbalances around a latlong's poles converge ~3x
    sooner), ending on the rows (exact). Stops when every column is within AREA_BALANCE_RTOL or
    after AREA_BALANCE_ITERATIONS; returns the largest relative column error left."""
    n = len(omega_in)
    chunks = max(1, min(threads.count(), AREA_BUFFER_BYTES // (n * 8)))
    blocks = np.searchsorted(indptr, np.linspace(0, indptr[-1], chunks + 1)).astype(np.int64)
    blocks[-1] = len(indptr) - 1  # rows of equal total length, the empty last rows included
    energy = np.zeros((chunks, n))
    col = np.ones(n)
    step = np.ones(n)
    err = np.inf
    for _ in range(AREA_BALANCE_ITERATIONS):
        _native.balance_rows(indptr, indices, values, omega_out, col, blocks, energy)
        err = _native.balance_columns(energy, omega_in, col, step)
        if err <= AREA_BALANCE_RTOL:
            break
    _native.scale_rows(indptr, indices, values, col)
    return err


def _build(
    src: str,
    src_shape: tuple[int, ...],
    dst: str,
    dst_shape: tuple[int, ...],
    rotation: bytes | None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The area filter's matrix from layout ``src`` to ``dst`` (not a cube picture): read-only
    CSR arrays (int64 row starts, int32 source texels, float32 weights; about 5 entries per
    output texel where the output is as fine as the source, ~48 bytes). Empty arrays when the
    filter is bilinear everywhere."""
    s, d = layout(src), layout(dst)
    rot = key_matrix(rotation)
    omega = s.solid_angles(src_shape).reshape(-1)
    splat = _splat(s, src_shape, d, dst_shape, rot, omega)
    if not np.any((splat.parts.min(axis=1) <= 2) & (omega > 0)):
        # magnifying everywhere (every source texel over 4/3 destination texels long along both
        # of its axes): the area filter is bilinear (an empty plan)
        return np.empty(0, np.int64), np.empty(0, np.int32), np.empty(0, np.float32)
    where = np.flatnonzero(splat.anchor == _native.EXCEPTION)
    merged = _merge(s, src_shape, d, dst_shape, rot, omega, where, splat.parts)
    if len(where):
        _native.deposit_exceptions(where, *merged, splat.width, splat.acc)
        splat.anchor[where] = _native.EXCEPTION - np.arange(len(where), dtype=np.int32)
    m = splat.acc.shape[1]
    alpha, inverse = np.empty(m, np.float32), np.empty(m, np.float32)
    omega_out = d.solid_angles(dst_shape).reshape(-1)
    _native.area_alpha(splat.acc, omega_out, alpha, inverse)
    src_width, dst_width = s.grid(src_shape)[1], d.grid(dst_shape)[1]
    # the bilinear plan's taps fill in where the deposits cover too little
    bilinear = _plans.cached(src, src_shape, dst, dst_shape, "bilinear", rotation)
    plan = _rows(splat, merged, alpha, inverse, bilinear, src_width, dst_width)
    del splat, merged
    _balance(*plan, omega_out, omega)
    for a in plan:
        a.setflags(write=False)
    return plan


def _build_for(
    src: str,
    src_shape: tuple[int, ...],
    dst: str,
    dst_shape: tuple[int, ...],
    rotation: bytes | None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_build` into layout ``dst``; for a cube picture, the cube's matrix with its rows
    reordered into the picture's (the unused squares' rows are empty)."""
    d = layout(dst)
    if d.base is d:
        return _build(src, src_shape, dst, dst_shape, rotation)
    cube_shape = d.base_shape(dst_shape)
    indptr, indices, values = _build(src, src_shape, d.base.name, cube_shape, rotation)
    if len(indptr) == 0:
        return indptr, indices, values
    order = _plans.view_order(dst, cube_shape)
    lengths = np.zeros(order.size + 1, np.int64)
    used = order >= 0
    lengths[1:][used] = np.diff(indptr)[order[used]]
    view_indptr = np.cumsum(lengths)
    view_rows = (np.empty_like(indices), np.empty_like(values))
    _native.reorder_rows(indptr, indices, values, order, view_indptr, *view_rows)
    plan = (view_indptr, *view_rows)
    for a in plan:
        a.setflags(write=False)
    return plan


#: cached area filter matrices, by (source, source shape, destination, shape, rotation).
_matrices = ByteBoundedCache("area filter matrices", AREA_PLAN_BYTES)


def area_remap(
    flat: np.ndarray,
    s: Layout,
    src_shape: tuple[int, ...],
    d: Layout,
    dst_shape: tuple[int, ...],
    rotation: bytes | None,
) -> np.ndarray | None:
    """The area filter of the flat source ``flat`` (n, C) into ``d`` (a cube picture: gathered
    straight into it): ``dst_shape + (C,)``, or None where the filter is bilinear (magnifying
    everywhere)."""
    with progress.step(f"area filter {s.name} -> {d.name}"):
        key = (s.name, src_shape, d.name, dst_shape, rotation)
        indptr, indices, values = _matrices.cached(key, lambda: _build_for(*key))
        if len(indptr) == 0:
            return None
        out = np.empty(dst_shape + (flat.shape[1],), flat.dtype)
        _native.area_gather(flat, indptr, indices, values, out.reshape(-1, flat.shape[1]))
    return out


# --- supersampling -------------------------------------------------------------------------


#: the area filter builds its matrix (~100-150 bytes and ~1 us per source texel, balanced over
#: the whole sphere) for sources of at most this many texels; beyond, it supersamples
#: (:func:`supersampling`): each output texel the solid-angle-weighted mean of k x k bilinear
#: samples at least as dense as the source's texels (:data:`SUPERSAMPLE_MIN`), computed part
#: by part with no matrix.
AREA_MATRIX_TEXELS = 1 << 22
#: the parts of a supersampled remap hold at most this many samples.
SUPERSAMPLE_PART = 1 << 20
#: fewest samples per output texel along each axis of a supersampled remap: with one, a bright
#: texel's energy goes to the few output texels that sample it (2.9-7.3 % RMS off the area
#: average at 1:1 sizes, 1.2-1.4 % with 3; tests/sphere/test_sampling.py).
SUPERSAMPLE_MIN = 3
#: a supersampled remap deposits the energy of its source's bright texels exactly: those whose
#: brightest channel exceeds BRIGHT_RATIO times the mean (solid-angle weighted), at most
#: MAX_BRIGHT of them (the threshold rises to keep that many); the rest, clamped there, is
#: sampled. (Bilinear samples as dense as the texels move a one-texel sun's energy by ~4%.)
BRIGHT_RATIO = 4.0
MAX_BRIGHT = 4096


def supersampling(
    s: Layout | str, src_shape: tuple[int, ...], d: Layout | str, dst_shape: tuple[int, ...]
) -> int:
    """Samples per output texel along each axis when the area filter supersamples a remap
    (:data:`AREA_MATRIX_TEXELS`; :func:`samples_per_side`), else 0."""
    s, d = layout(s), layout(d)
    src, dst = valid_texels(s, src_shape), valid_texels(d, dst_shape)
    if src <= AREA_MATRIX_TEXELS or src < dst:
        return 0
    return samples_per_side(src / dst, d, dst_shape)


def samples_per_side(ratio: float, d: Layout, shape: tuple[int, ...]) -> int:
    """Samples a side per output texel of ``d``, ``shape``, from a source of ``ratio`` times its
    texels: their pitches' ratio, rounded, at least :data:`SUPERSAMPLE_MIN`, at most what keeps
    the (never allocated) grid of samples a layout's shape (2 for 6 x 4096^2 faces, 1 beyond)."""
    dh, dw, faces = d.grid(shape)
    largest = max(1, min(math.isqrt(MAX_TEXELS // (faces * dh * dw)), MAX_EDGE // max(dh, dw)))
    return min(max(SUPERSAMPLE_MIN, round(math.sqrt(ratio))), largest)


def fine_shape(d: Layout, dst_shape: tuple[int, ...], k: int) -> tuple[int, ...]:
    """The spatial shape of ``d``'s grid k times finer than ``dst_shape`` (a base layout)."""
    return (
        (6, k * dst_shape[1], k * dst_shape[2]) if d.cubic else (k * dst_shape[0], k * dst_shape[1])
    )


def supersample(
    flat: np.ndarray,
    s: Layout,
    src_shape: tuple[int, ...],
    d: Layout,
    dst_shape: tuple[int, ...],
    rotation: bytes | None,
    k: int,
) -> np.ndarray:
    """The supersampled area filter of a flat source (n, C) of layout ``s`` into the base layout
    ``d``: ``dst_shape + (C,)``.

    The source is split into its bright texels' excess above a threshold (:data:`MAX_BRIGHT`
    at most: a sun, lamps) and the rest, clamped there. Output texel q holds
    ``sum_j omega_j R(d_j) / sum_j omega_j`` over the centres d_j of the k x k texels of
    ``d``'s k-times finer grid inside q (``omega_j`` their exact solid angles, ``R`` the
    seam-aware bilinear lookup of :func:`remap` in the clamped rest), plus the excess of the
    bright texels whose centres fall in q, times their solid angle over q's: their energy is
    kept exactly. Computed in parts of :data:`SUPERSAMPLE_PART` samples (each: the bilinear
    plan of its fine rows, applied, then reduced), so nothing beyond a part is held."""
    dh, dw, faces = d.grid(dst_shape)
    c = flat.shape[1]
    sh, sw, _ = s.grid(src_shape)
    fine = fine_shape(d, dst_shape, k)
    clamp, bright = _bright_texels(flat, s, src_shape)
    out = np.empty((faces * dh, dw, c), flat.dtype)
    step = max(1, SUPERSAMPLE_PART // (k * k * dw))
    if d.name == "cube":  # one fused pass, the samples' weights from the face's density
        # out[f, j, i]: the mean of the k x k samples of cube texel (f, i, j), each weighed by the
        # face's solid angle density (1 + sc^2 + tc^2)^-1.5 and looked up bilinearly in the
        # source clamped at clamp (src/sphere/reduce.hpp); with k >= 3 the samples' source
        # coordinates are the centre's plus the map's derivatives where that is within 0.05
        # source texels of exact
        _native._supersample_cube(s.kind, sh, sw, flat, clamp, dh, k, key_matrix(rotation), out)
        step = faces * dh
    for top in range(faces * dh if d.name == "cube" else 0, faces * dh, step):
        bottom = min(top + step, faces * dh)
        rows = (top * k, bottom * k)
        plan = _plans.build(s.name, src_shape, d.name, fine, "bilinear", rotation, rows=rows)
        samples = np.empty((len(plan[0]), c), flat.dtype)
        _native.gather_plan_clamped(flat, sw, *plan, clamp, samples)
        _, _, _, omega = next(texel_strips(d, fine, rows=rows, texels=1 << 62, directions=False))
        box_reduce(samples.reshape(-1, k * dw, c), omega.reshape(-1, k * dw), k, out[top:bottom])
    if len(bright):
        q, values = bright_deposits(flat[bright], bright, s, src_shape, d, dst_shape, k, rotation,
                                    clamp)  # fmt: skip
        flat_out = out.reshape(-1, c)
        np.add.at(flat_out, q, values.astype(flat_out.dtype))
    return out.reshape(tuple(dst_shape) + (c,))


def bright_deposits(
    bright_values: np.ndarray,
    bright: np.ndarray,
    s: Layout,
    src_shape: tuple[int, ...],
    d: Layout,
    dst_shape: tuple[int, ...],
    k: int,
    rotation: bytes | None,
    clamp: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Where :func:`supersample` puts the excess over ``clamp`` of the bright texels ``bright``
    (flat indices, ascending; their values ``bright_values`` (n, C)): ``(q, values)``, flat
    output texels and what each adds. The samples of the output texels around each bright
    texel weigh it as the supersampling would (their bilinear weights times their solid
    angles), and those weights are scaled to give the texel's excess energy exactly."""
    dh, dw, faces = d.grid(dst_shape)
    fine = fine_shape(d, dst_shape, k)
    rot = key_matrix(rotation)
    src_dirs, src_omega = texels_at(s, src_shape, bright)
    # the output texels the bright texels' bilinear footprints (one texel around) can reach:
    # those holding a grid of points over the footprint, a quarter of the output's mean texel
    # pitch apart (at most 0.99 source texels), so that none is skipped where the output's
    # texels are locally as small as the source's (near 1:1 sizes, a face's corners)
    pitch = math.sqrt(valid_texels(s, src_shape) / valid_texels(d, dst_shape))
    steps = max(2, math.ceil(2 * 0.99 / (pitch / 4)))
    cols, rows = np.meshgrid(
        np.linspace(-0.99, 0.99, steps + 1), np.linspace(-0.99, 0.99, steps + 1)
    )
    row, col = np.divmod(bright, s.grid(src_shape)[1])
    x = (col[:, None] + 0.5 + cols.reshape(1, -1)).reshape(-1)
    y = (row[:, None] + 0.5 + rows.reshape(1, -1)).reshape(-1)
    if s.cubic:
        size = src_shape[1]
        face = np.repeat(row // size, cols.size)
        coords = np.stack([face, x, y - face * size], axis=-1)
    else:
        coords = np.stack([x, y], axis=-1)
    reach = s.directions_at(coords, src_shape) @ rot.T
    q_all = np.unique(_texel_of(d, dst_shape, reach))
    # each reached output texel's k x k samples, looked up in the source
    a, b = np.divmod(np.arange(k * k), k)
    f, r = np.divmod(q_all // dw, dh)
    fine_rows = (f * fine[-2])[:, None] + (r * k)[:, None] + a[None, :]
    fine_index = (fine_rows * fine[-1] + (q_all % dw * k)[:, None] + b[None, :]).reshape(-1)
    dirs, omega = texels_at(d, fine, fine_index)
    taps, frac = sample_taps_of(s, src_shape, dirs @ rot)
    fx, fy = frac[:, 0].astype(np.float64), frac[:, 1].astype(np.float64)
    weights = np.stack([(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy], axis=-1)
    missing = taps < 0  # a cube corner's fourth texel: the mean of the other three
    weights += np.where(missing, 0.0, (weights * missing).sum(1, keepdims=True) / 3)
    weights[missing] = 0.0
    sample_omega = omega.reshape(-1, k * k)
    total = sample_omega.sum(1)  # each output texel's solid angle
    pos = np.searchsorted(bright, taps)
    hit = (taps >= 0) & (bright[np.minimum(pos, len(bright) - 1)] == taps)
    j, t = np.nonzero(hit)
    energy_weight = omega[j] * weights[j, t]
    p = pos[j, t]
    reached = np.bincount(p, energy_weight, minlength=len(bright))
    scale = np.divide(src_omega, reached, out=np.zeros_like(src_omega), where=reached > 0)
    excess = np.maximum(np.asarray(bright_values, np.float64) - clamp, 0)
    q = q_all[j // (k * k)]
    values = excess[p] * (scale[p] * energy_weight / total[j // (k * k)])[:, None]
    # a bright texel no sample reached (a sliver) goes whole to the texel its centre is in
    lost = np.flatnonzero(reached <= 0)
    if len(lost):
        q_lost = _texel_of(d, dst_shape, src_dirs[lost] @ rot.T)
        _, omega_q = texels_at(d, dst_shape, q_lost)
        share = src_omega[lost] / np.where(omega_q > 0, omega_q, np.inf)
        q = np.concatenate([q, q_lost])
        values = np.concatenate([values, excess[lost] * share[:, None]])
    return q, values


def _texel_of(d: Layout, shape: tuple[int, ...], dirs: np.ndarray) -> np.ndarray:
    """Flat index of the texel of base layout ``d`` holding each direction."""
    dh, dw, _ = d.grid(shape)
    coords = d.coordinates(dirs, shape)
    face = coords[:, 0].astype(np.int64) if d.cubic else 0
    y = np.clip(coords[:, -1].astype(np.int64), 0, dh - 1)
    x = np.clip(coords[:, -2].astype(np.int64), 0, dw - 1)
    return (face * dh + y) * dw + x


def sample_taps_of(
    s: Layout, shape: tuple[int, ...], dirs: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Bilinear taps (n, 4) and fractions (n, 2) of directions in base layout ``s``."""
    h, w, _ = s.grid(shape)
    taps = np.empty((len(dirs), 4), np.int32)
    frac = np.empty((len(dirs), 2), np.float32)
    _native.taps_of(s.kind, h, w, np.ascontiguousarray(dirs), False, taps, frac)
    return taps, frac


def _bright_texels(
    flat: np.ndarray, s: Layout, src_shape: tuple[int, ...]
) -> tuple[float, np.ndarray]:
    """The clamp of :func:`supersample` and the flat indices of the texels whose brightest
    channel exceeds it (ascending; at most :data:`MAX_BRIGHT`): one pass over strips."""
    parts = [
        peak_candidates(flat[start:stop], omega, start)
        for start, stop, _, omega in texel_strips(s, src_shape, directions=False)
    ]
    clamp, index, _ = bright_texels(parts)
    return clamp, index


def peak_candidates(values: np.ndarray, omega: np.ndarray, start: int = 0) -> tuple[Any, ...]:
    """The part of :func:`bright_texels`'s pass over the texels ``values`` (n, C) (flat
    indices from ``start``; texels of no solid angle left out): ``(stats, index, peaks,
    values)``, the sums ``[sum peak omega, sum omega, largest peak]`` (peak: a texel's
    brightest channel) and the :data:`MAX_BRIGHT` + 1 texels of largest peak."""
    values = np.asarray(values)
    peak = np.empty(len(values), values.dtype)
    stats = np.zeros(3)
    # peak[t]: texel t's brightest channel, -inf without solid angle (numpy's max: 8x slower)
    _native.peak_stats(values, omega, stats, peak)
    keep = min(len(peak), MAX_BRIGHT + 1)
    top = np.argpartition(peak, len(peak) - keep)[len(peak) - keep :]
    top = top[np.isfinite(peak[top])]
    return stats, start + top, peak[top], values[top]


def bright_texels(parts: list) -> tuple[float, np.ndarray, np.ndarray]:
    """The clamp of :func:`supersample` and the texels above it, from the
    :func:`peak_candidates` of every part of an image: ``(clamp, index, values)``, index
    ascending. The clamp is :data:`BRIGHT_RATIO` times the mean peak (solid-angle weighted),
    raised to the (MAX_BRIGHT + 1)-th largest peak when more texels lie above; inf when none."""
    stats = sum(p[0] for p in parts)
    none = np.inf, np.empty(0, np.int64), np.empty((0, parts[0][3].shape[1]))
    if not stats[1] > 0 or not stats[2] > 0:
        return none
    low = BRIGHT_RATIO * stats[0] / stats[1]
    index = np.concatenate([p[1] for p in parts])
    peaks = np.concatenate([p[2] for p in parts])
    values = np.concatenate([p[3] for p in parts])
    clamp = low
    if len(peaks) > MAX_BRIGHT:
        clamp = max(low, float(np.partition(peaks, len(peaks) - MAX_BRIGHT - 1)[-MAX_BRIGHT - 1]))
    above = peaks > clamp
    if not above.any():
        return none
    order = np.argsort(index[above])
    return clamp, index[above][order], values[above][order]


def sample_weights(
    d: Layout,
    dst_shape: tuple[int, ...],
    k: int,
    face: int,
    rows: tuple[int, int],
    cols: tuple[int, int],
) -> np.ndarray:
    """The weights of :func:`supersample`'s samples ``rows x cols`` (of face ``face`` of ``d``'s
    k-times finer grid): a cube's solid angle density ``(1 + sc^2 + tc^2)^-1.5`` at each sample,
    as the fused in-memory kernel weighs them; the fine texels' exact solid angles otherwise."""
    fine = fine_shape(d, dst_shape, k)
    (r0, r1), (c0, c1) = rows, cols
    if d.name == "cube":
        sc = 2.0 * (np.arange(c0, c1) + 0.5) / fine[2] - 1.0
        tc = 2.0 * (np.arange(r0, r1) + 0.5) / fine[1] - 1.0
        q = 1.0 + sc[None, :] ** 2 + tc[:, None] ** 2
        return 1.0 / (q * np.sqrt(q))
    fh = fine[-2]
    rows_of = (face * fh + r0, face * fh + r1)
    _, _, _, omega = next(texel_strips(d, fine, rows=rows_of, texels=1 << 62, directions=False))
    return omega.reshape(r1 - r0, -1)[:, c0:c1]
