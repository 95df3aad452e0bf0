"""The area filter's kernels on its matrix (CSR: int64 row starts, int32 source texels, float32
weights): its rows assembled from the deposits of :mod:`bakeshop.sphere._area_kernels` and the
bilinear fill-in, Sinkhorn balancing, its rows reordered into a cube
picture's, and its application (see :mod:`bakeshop.sphere.area`, which drives them)."""

from __future__ import annotations

import math

import numba
from numpy import ndarray

from bakeshop.sphere._gather import EXCEPTION

#: how far the balancing may scale a column (either way): a column that cannot carry its solid
#: angle, such as a mirror ball's rim texels, all deposited into the few texels of the one
#: direction behind it (ten times their solid angle), stops there instead of growing until
#: float32 overflows and the rows turn to NaN.
AREA_COLUMN_LIMIT = 1e6


@numba.njit(parallel=True, cache=True, error_model="numpy")
def splat_rows(anchor: ndarray, wq: ndarray, scale: ndarray, row: int, offsets: ndarray,
               taps: ndarray, weights: ndarray, alpha: ndarray, inverse: ndarray, cursor: ndarray,
               fill: bool, indices: ndarray, values: ndarray) -> None:  # fmt: skip
    """The splat plan (:func:`splat_plan`, :func:`splat_exceptions`) transposed into rows, one
    per destination texel q with alpha > 0: source texel p's weight w into q becomes the entry
    (p, w alpha[q] inverse[q]) of row q. Chunk t of the source texels counts its entries per
    row into ``cursor[t, q]`` (``fill`` False), or writes them at ``cursor[t, q]`` onwards
    (``fill`` True; the chunks' starts in each row), so that each row lists p in order."""
    n = anchor.shape[0]
    chunks = cursor.shape[0]
    for t in numba.prange(chunks):
        for p in range(t * n // chunks, (t + 1) * n // chunks):
            b = anchor[p]
            if b >= 0:
                wx0, wx1 = float(wq[p, 0]), float(wq[p, 1])
                wy0, wy1 = float(wq[p, 2]), float(wq[p, 3])
                wx2, wy2 = max(0.0, 1.0 - wx0 - wx1), max(0.0, 1.0 - wy0 - wy1)
                for yb in range(3):
                    wy = wy0 if yb == 0 else (wy1 if yb == 1 else wy2)
                    for xa in range(3):
                        w = scale[p] * wy * (wx0 if xa == 0 else (wx1 if xa == 1 else wx2))
                        q = b + yb * row + xa
                        if w > 0 and alpha[q] > 0:
                            if fill:
                                e = cursor[t, q]
                                indices[e] = p
                                values[e] = w * alpha[q] * inverse[q]
                            cursor[t, q] += 1
            elif b != -1:
                k = EXCEPTION - b
                for m in range(offsets[k], offsets[k + 1]):
                    q = taps[m]
                    if weights[m] > 0 and alpha[q] > 0:
                        if fill:
                            e = cursor[t, q]
                            indices[e] = p
                            values[e] = weights[m] * alpha[q] * inverse[q]
                        cursor[t, q] += 1


@numba.njit(cache=True, error_model="numpy")
def row_starts(cursor: ndarray, extra: ndarray, indptr: ndarray) -> None:
    """Row q holds sum_t cursor[t, q] + extra[q] entries: ``indptr`` their running sum, and
    ``cursor[t, q]`` becomes where chunk t's entries of row q start (after the earlier
    chunks')."""
    total = 0
    for q in range(extra.shape[0]):
        indptr[q] = total
        for t in range(cursor.shape[0]):
            count = cursor[t, q]
            cursor[t, q] = total
            total += count
        total += extra[q]
    indptr[extra.shape[0]] = total


@numba.njit(parallel=True, cache=True, error_model="numpy")
def bilinear_rows(alpha: ndarray, row: int, base: ndarray, frac: ndarray, taps: ndarray,
                  indptr: ndarray, counts: ndarray, fill: bool, indices: ndarray,
                  values: ndarray) -> None:  # fmt: skip
    """Append to row q (at ``indptr[q + 1] - counts[q]``) the bilinear taps of the plan
    (:func:`plan`) weighted by 1 - alpha[q], where alpha[q] < 1 (``fill``); else count them
    into ``counts[q]``. A cube corner's missing tap (the mean of the other three) gives a third
    of its weight to each of them."""
    for q in numba.prange(alpha.shape[0]):
        b = base[q]
        if alpha[q] >= 1 or b == -1:
            continue
        if b >= 0:
            i0, i1, i2, i3 = b, b + 1, b + row, b + row + 1
        else:
            x = EXCEPTION - b
            i0, i1, i2, i3 = taps[x, 0], taps[x, 1], taps[x, 2], taps[x, 3]
        if not fill:
            counts[q] = (i0 >= 0) + (i1 >= 0) + (i2 >= 0) + (i3 >= 0)
            continue
        fx, fy = float(frac[q, 0]), float(frac[q, 1])
        w0, w1, w2, w3 = (1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy
        lost = (w0 if i0 < 0 else 0.0) + (w1 if i1 < 0 else 0.0)
        lost += (w2 if i2 < 0 else 0.0) + (w3 if i3 < 0 else 0.0)
        scale = 1.0 - alpha[q]
        e = indptr[q + 1] - counts[q]
        for k in range(4):
            i = i0 if k == 0 else (i1 if k == 1 else (i2 if k == 2 else i3))
            w = w0 if k == 0 else (w1 if k == 1 else (w2 if k == 2 else w3))
            if i >= 0:
                indices[e] = i
                values[e] = scale * (w + lost / 3)
                e += 1


@numba.njit(parallel=True, cache=True, error_model="numpy")
def scale_rows(indptr: ndarray, indices: ndarray, values: ndarray,
               factor: ndarray) -> None:  # fmt: skip
    """Multiply each entry by ``factor`` of its column (none: all 1), then scale each nonempty
    row to sum 1."""
    scaled = factor.shape[0] > 0
    for q in numba.prange(indptr.shape[0] - 1):
        total = 0.0
        for e in range(indptr[q], indptr[q + 1]):
            if scaled:
                values[e] = values[e] * factor[indices[e]]
            total += values[e]
        if total > 0:
            for e in range(indptr[q], indptr[q + 1]):
                values[e] = values[e] / total


@numba.njit(parallel=True, cache=True, error_model="numpy")
def balance_rows(indptr: ndarray, indices: ndarray, values: ndarray, omega_out: ndarray,
                 col: ndarray, blocks: ndarray, energy: ndarray) -> None:  # fmt: skip
    """The row step of the area filter's balancing of M = diag(r) K diag(col) (K: ``values``),
    with the next column step's sums gathered on the way: r[q] makes every nonempty row of M sum
    1, and ``energy[t, p]`` += omega_out[q] r[q] K[q, p] over the rows q of block t (rows
    ``blocks[t]:blocks[t + 1]``, one block per thread; ``energy`` zero on entry). One read of
    the matrix per step: each row's entries are read again from the cache."""
    for t in numba.prange(blocks.shape[0] - 1):
        sums = energy[t]
        for q in range(blocks[t], blocks[t + 1]):
            total = 0.0
            for e in range(indptr[q], indptr[q + 1]):
                total += values[e] * col[indices[e]]
            if total > 0:
                sent = omega_out[q] / total
                for e in range(indptr[q], indptr[q + 1]):
                    sums[indices[e]] += values[e] * sent


@numba.njit(parallel=True, cache=True, error_model="numpy")
def balance_columns(energy: ndarray, omega_in: ndarray, col: ndarray, step: ndarray) -> float:
    """The column step, over-relaxed with momentum: where source texel p sends ``energy`` =
    col[p] sum_t energy[t, p] > 0 (the row step's sums, zeroed here for the next one), log
    col[p] moves by ``step[p]`` = 1.5 log(omega_in / energy) + 0.5 x its previous step (kept as
    the factor exp(step), so no logarithms), col[p] kept within AREA_COLUMN_LIMIT of 1. Returns
    the largest |omega_in / energy - 1|."""
    err = 0.0
    for p in numba.prange(omega_in.shape[0]):
        sent = 0.0
        for t in range(energy.shape[0]):
            sent += energy[t, p]
            energy[t, p] = 0.0
        sent *= col[p]
        if sent > 0:
            r = omega_in[p] / sent
            err = max(err, abs(r - 1))
            scaled = col[p] * r * math.sqrt(r * step[p])
            scaled = min(max(scaled, 1 / AREA_COLUMN_LIMIT), AREA_COLUMN_LIMIT)
            step[p] = scaled / col[p]
            col[p] = scaled
    return err


@numba.njit(parallel=True, cache=True, error_model="numpy")
def reorder_rows(indptr: ndarray, indices: ndarray, values: ndarray, order: ndarray,
                 out_indptr: ndarray, out_indices: ndarray,
                 out_values: ndarray) -> None:  # fmt: skip
    """Row p of the output matrix = row order[p] of the input (empty where -1)."""
    for p in numba.prange(order.shape[0]):
        q = order[p]
        if q >= 0:
            o = out_indptr[p]
            for e in range(indptr[q], indptr[q + 1]):
                out_indices[o] = indices[e]
                out_values[o] = values[e]
                o += 1


@numba.njit(parallel=True, cache=True, error_model="numpy")
def area_gather(src: ndarray, indptr: ndarray, indices: ndarray, values: ndarray,
                out: ndarray) -> None:  # fmt: skip
    """The area filter applied: out[q] = sum over row q of weight x src[p], in float64, four
    channels at a time in registers."""
    nc = out.shape[1]
    for q in numba.prange(out.shape[0]):
        for c in range(0, nc, 4):
            k = min(4, nc - c)
            s0 = s1 = s2 = s3 = 0.0
            for e in range(indptr[q], indptr[q + 1]):
                p, w = indices[e], float(values[e])
                s0 += w * src[p, c]
                if k > 1:
                    s1 += w * src[p, c + 1]
                if k > 2:
                    s2 += w * src[p, c + 2]
                if k > 3:
                    s3 += w * src[p, c + 3]
            out[q, c] = s0
            if k > 1:
                out[q, c + 1] = s1
            if k > 2:
                out[q, c + 2] = s2
            if k > 3:
                out[q, c + 3] = s3
