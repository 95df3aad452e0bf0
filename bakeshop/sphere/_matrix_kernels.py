"""The area filter's kernels on its built matrix (CSR: int64 row starts, int32 source texels,
float32 weights): Sinkhorn balancing through its transpose, its rows reordered into a cube
picture's, and its application (see :mod:`bakeshop.sphere.area`, which drives them)."""

from __future__ import annotations

import math

import numba
from numpy import ndarray


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


@numba.njit(cache=True, error_model="numpy")
def transpose(indptr: ndarray, indices: ndarray, values: ndarray, colptr: ndarray, rows: ndarray,
              by_column: ndarray) -> None:  # fmt: skip
    """The CSR matrix (``indptr``, ``indices``, ``values``) in CSC form: column p's entries are
    ``colptr[p]:colptr[p + 1]`` of ``rows`` and ``by_column`` (``colptr`` zero on entry; rows in
    increasing order within a column)."""
    for e in range(indices.shape[0]):
        colptr[indices[e] + 1] += 1
    for p in range(colptr.shape[0] - 1):
        colptr[p + 1] += colptr[p]
    cursor = colptr[:-1].copy()
    for q in range(indptr.shape[0] - 1):
        for e in range(indptr[q], indptr[q + 1]):
            k = cursor[indices[e]]
            rows[k] = q
            by_column[k] = values[e]
            cursor[indices[e]] = k + 1


@numba.njit(parallel=True, cache=True, error_model="numpy")
def balance_rows(indptr: ndarray, indices: ndarray, values: ndarray, omega_out: ndarray,
                 col: ndarray, sent: ndarray) -> None:  # fmt: skip
    """The row step of the area filter's balancing of M = diag(r) K diag(col) (K: ``values``):
    ``sent[q]`` = omega_out[q] r[q], r making every nonempty row of M sum 1 (0 for an empty
    row): the energy per unit weight that output texel q draws."""
    for q in numba.prange(indptr.shape[0] - 1):
        total = 0.0
        for e in range(indptr[q], indptr[q + 1]):
            total += values[e] * col[indices[e]]
        sent[q] = omega_out[q] / total if total > 0 else 0.0


@numba.njit(parallel=True, cache=True, error_model="numpy")
def balance_columns(colptr: ndarray, rows: ndarray, by_column: ndarray, sent: ndarray,
                    omega_in: ndarray, col: ndarray, step: ndarray) -> float:  # fmt: skip
    """The column step, over-relaxed with momentum: where source texel p sends ``energy`` =
    col[p] sum_q sent[q] K[q, p] > 0 (K in CSC form: ``colptr``, ``rows``, ``by_column``),
    log col[p] moves by ``step[p]`` = 1.5 log(omega_in / energy) + 0.5 x its previous step
    (kept as the factor exp(step), so no logarithms). Returns the largest
    |omega_in / energy - 1|."""
    err = 0.0
    for p in numba.prange(omega_in.shape[0]):
        energy = 0.0
        for k in range(colptr[p], colptr[p + 1]):
            energy += by_column[k] * sent[rows[k]]
        energy *= col[p]
        if energy > 0:
            r = omega_in[p] / energy
            err = max(err, abs(r - 1))
            step[p] = r * math.sqrt(r * step[p])
            col[p] *= step[p]
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
