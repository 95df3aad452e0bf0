"""The area filter: an energy-preserving average for downsampling between any two layouts.

Every source texel deposits its solid angle into the output texels that its footprint (the box
bounding its locally affine image) overlaps, in proportion to the overlap; where the output is
locally finer, the source texel is first cut into parts, each depositing its own solid angle.
The resulting matrix is built in four stages, each a function here over the kernels of
:mod:`bakeshop.sphere._area_kernels`:

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

from typing import NamedTuple

import numba
import numpy as np

from bakeshop import progress
from bakeshop.sphere import _area_kernels as kernels
from bakeshop.sphere import _plans
from bakeshop.sphere._cache import ByteBoundedCache
from bakeshop.sphere._gather import EXCEPTION
from bakeshop.sphere.layouts import Layout, layout
from bakeshop.sphere.rotation import key_matrix

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
    """The per-source-texel deposits of :func:`_splat` (see ``_area_kernels.splat_plan``)."""

    anchor: np.ndarray  # int32 (n,): first output texel of a 3x3 block, EXCEPTION, or -1
    wq: np.ndarray  # float32 (n, 4): box weights along x and y
    scale: np.ndarray  # float32 (n,): the texel's solid angle
    width: np.ndarray  # float32 (n,): its footprint's narrower width
    parts: np.ndarray  # int32 (n, 2): parts along each axis
    acc: np.ndarray  # float64 (chunks, m, 2): sums of weights and weighted widths


def _splat(s: Layout, src_shape, d: Layout, dst_shape, rot, omega) -> _Splat:
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
        acc=np.zeros((max(1, min(numba.get_num_threads(), AREA_BUFFER_BYTES // (m * 16))), m, 2)),
    )
    kernels.splat_plan(s.kind, sh, sw, sfaces, omega, d.kind, dh, dw, rot, *splat)
    return splat


def _merge(s: Layout, src_shape, d: Layout, dst_shape, rot, omega, where, parts):
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
        kernels.splat_exceptions(s.kind, sh, sw, omega, d.kind, dh, dw, rot, where[start:stop],
                                 parts, at, taps, weights, counts)  # fmt: skip
        kept_ends = np.cumsum(counts) + kept.size
        # room for everything at this chunk's merged share of the unmerged deposits, + 1/16
        expected = int(kept_ends[-1] / ends[stop - 1] * ends[-1] * 17 / 16) + 1024
        kept.reserve(int(kept_ends[-1]), expected)
        kernels.compact_exceptions(at, counts, taps, weights, kept_ends, *kept.arrays)
        kept.size = int(kept_ends[-1])
        start = stop
    np.cumsum(offsets, out=offsets)
    return offsets, *kept.filled()


class _Growing:
    """A pair of arrays (int32 taps, float32 weights) filled from the start, grown on demand."""

    def __init__(self):
        self.arrays = (np.empty(0, np.int32), np.empty(0, np.float32))
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


def _rows(splat: _Splat, merged, alpha, inverse, bilinear, src_width: int, dst_width: int):
    """Stage 3: the deposits transposed into CSR rows, one per output texel, with the bilinear
    taps (weighted 1 - alpha) where the deposits cover too little:
    ``(indptr int64, indices int32, values float32)``."""
    offsets, taps, weights = merged
    m = len(alpha)
    cursor = np.zeros((numba.get_num_threads(), m), np.int64)
    none = (np.empty(0, np.int32), np.empty(0, np.float32))
    deposits = (splat.anchor, splat.wq, splat.scale, dst_width, offsets, taps, weights, alpha,
                inverse, cursor)  # fmt: skip
    kernels.splat_rows(*deposits, False, *none)
    counts = np.zeros(m, np.int64)
    kernels.bilinear_rows(alpha, src_width, *bilinear, counts, counts, False, *none)
    indptr = np.zeros(m + 1, np.int64)
    kernels.row_starts(cursor, counts, indptr)
    rows = (np.empty(indptr[-1], np.int32), np.empty(indptr[-1], np.float32))
    kernels.splat_rows(*deposits, True, *rows)
    kernels.bilinear_rows(alpha, src_width, *bilinear, indptr, counts, True, *rows)
    return indptr, *rows


def _balance(indptr, indices, values, omega_out, omega_in, sums) -> float:
    """Stage 4: scale the rows and columns of the sparse matrix M (CSR, nonnegative float32
    ``values``, in place) towards every nonempty row summing to 1 (a constant stays constant)
    and every column p carrying its source texel's solid angle,
    sum_q omega_out[q] M[q, p] = omega_in[p] (radiance x solid angle is preserved).

    Sinkhorn's alternating normalisation (Sinkhorn & Knopp 1967) of the energy transport
    omega_out[q] M[q, p], on the scale vectors (one pass over M per iteration), its column
    steps over-relaxed (Thibault et al. 2017) and with momentum (the slow, smooth imbalances
    around a latlong's poles converge ~3x sooner), ending on the rows (exact). Stops when
    every column is within AREA_BALANCE_RTOL or after AREA_BALANCE_ITERATIONS; returns the
    largest relative column error left. ``sums``: zeroed scratch, (chunks, n)."""
    col = np.ones(len(omega_in))
    step = np.ones(len(omega_in))
    err = np.inf
    for _ in range(AREA_BALANCE_ITERATIONS):
        kernels.balance_rows(indptr, indices, values, omega_out, col, sums)
        err = kernels.balance_columns(sums, omega_in, col, step)
        if err <= AREA_BALANCE_RTOL:
            break
    kernels.scale_rows(indptr, indices, values, col)
    return err


def _build(src: str, src_shape, dst: str, dst_shape, rotation: bytes | None):
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
    where = np.flatnonzero(splat.anchor == EXCEPTION)
    merged = _merge(s, src_shape, d, dst_shape, rot, omega, where, splat.parts)
    if len(where):
        kernels.deposit_exceptions(where, *merged, splat.width, splat.acc)
        splat.anchor[where] = EXCEPTION - np.arange(len(where), dtype=np.int32)
    m = splat.acc.shape[1]
    alpha, inverse = np.empty(m, np.float32), np.empty(m, np.float32)
    omega_out = d.solid_angles(dst_shape).reshape(-1)
    kernels.area_alpha(splat.acc, omega_out, alpha, inverse)
    src_width, dst_width = s.grid(src_shape)[1], d.grid(dst_shape)[1]
    # the bilinear plan's taps fill in where the deposits cover too little
    bilinear = _plans.cached(src, src_shape, dst, dst_shape, "bilinear", rotation)
    plan = _rows(splat._replace(acc=None), merged, alpha, inverse, bilinear, src_width, dst_width)
    del splat, merged
    _balance(*plan, omega_out, omega, np.zeros((numba.get_num_threads(), len(omega))))
    for a in plan:
        a.setflags(write=False)
    return plan


def _build_for(src: str, src_shape, dst: str, dst_shape, rotation: bytes | None):
    """:func:`_build` into layout ``dst``; for a cube picture, the cube's matrix with its rows
    reordered into the picture's (the unused squares' rows are empty)."""
    d = layout(dst)
    if d.base is d:
        return _build(src, src_shape, dst, dst_shape, rotation)
    cube_shape = d.base.shape(d.face_size(dst_shape))
    indptr, indices, values = _build(src, src_shape, d.base.name, cube_shape, rotation)
    if len(indptr) == 0:
        return indptr, indices, values
    order = _plans.view_order(dst, cube_shape)
    lengths = np.zeros(order.size + 1, np.int64)
    used = order >= 0
    lengths[1:][used] = np.diff(indptr)[order[used]]
    view_indptr = np.cumsum(lengths)
    view_rows = (np.empty_like(indices), np.empty_like(values))
    kernels.reorder_rows(indptr, indices, values, order, view_indptr, *view_rows)
    plan = (view_indptr, *view_rows)
    for a in plan:
        a.setflags(write=False)
    return plan


#: cached area filter matrices, by (source, source shape, destination, shape, rotation).
_matrices = ByteBoundedCache("area filter matrices", AREA_PLAN_BYTES)


def area_remap(flat, s: Layout, src_shape, d: Layout, dst_shape, rotation: bytes | None):
    """The area filter of the flat source ``flat`` (n, C) into ``d`` (a cube picture: gathered
    straight into it): ``dst_shape + (C,)``, or None where the filter is bilinear (magnifying
    everywhere)."""
    with progress.step(f"area filter {s.name} -> {d.name}"):
        key = (s.name, src_shape, d.name, dst_shape, rotation)
        indptr, indices, values = _matrices.cached(key, lambda: _build_for(*key))
        if len(indptr) == 0:
            return None
        out = np.empty(dst_shape + (flat.shape[1],), flat.dtype)
        kernels.area_gather(flat, indptr, indices, values, out.reshape(-1, flat.shape[1]))
    return out
