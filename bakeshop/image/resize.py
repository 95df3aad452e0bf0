"""Energy-preserving resampling of planar images.

Each output texel is the mean of the input over the output texel's footprint (a box filter with
exact fractional overlaps), so the mean of the image, its "energy", is preserved whatever the
sizes. For integer factors this is the exact box filter; otherwise it is the area-weighted
filter (the same definition as OpenCV's ``INTER_AREA`` and Photoshop's "average" downsampling).
The filter is separable, ``out = A_y @ image @ A_x.T`` with sparse overlap matrices, so the cost is
O(H_in * W_in * C) multiply-adds: one read of the input, numba-parallel over output rows.
"""

from __future__ import annotations

import numba
import numpy as np
import scipy.sparse as sp

from bakeshop.errors import ArgumentError


def area_weights(n_in: int, n_out: int) -> sp.csr_matrix:
    """Sparse ``(n_out, n_in)`` matrix of box-filter weights along one axis.

    ``W[i, k]`` is the length of the overlap of input texel ``[k, k+1)`` with output texel ``i``'s
    footprint ``[i * n_in / n_out, (i + 1) * n_in / n_out)``, divided by the footprint's length,
    so every row sums to 1 and every column to ``n_out / n_in``. Exact in rational arithmetic:
    positions are scaled by ``n_out`` so that both grids are integers.
    """
    # In units of 1/n_out input texels: input texel k spans [k*n_out, (k+1)*n_out),
    # output texel i spans [i*n_in, (i+1)*n_in).
    i = np.arange(n_out)
    lo, hi = i * n_in, (i + 1) * n_in
    k_first = lo // n_out
    k_last = (hi - 1) // n_out
    counts = k_last - k_first + 1
    rows = np.repeat(i, counts)
    cols = np.repeat(k_first, counts) + (
        np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    )
    overlap = np.minimum(hi[rows], (cols + 1) * n_out) - np.maximum(lo[rows], cols * n_out)
    return sp.csr_matrix((overlap / n_in, (rows, cols)), shape=(n_out, n_in))


def resize_area(image, size: tuple[int, int]) -> np.ndarray:
    """Resize ``image`` to ``size = (width, height)`` preserving its mean (energy).

    Parameters
    ----------
    image : (H, W) or (H, W, C) array
        Linear values (resampling display-encoded values averages the wrong quantity).
    size : (int, int)
        Output (width, height), each at least 1.

    Returns
    -------
    (height, width[, C]) float32 array
        Each texel is the exact mean of the input over its footprint. The mean of the output
        equals the mean of the input to float32 rounding (about 1e-7 relative). NaN or Inf in
        an input texel spreads to the output texels whose footprint covers it.

    Notes
    -----
    Integer factors reduce to averaging ``f_y x f_x`` blocks (the exact box filter). Upsampling
    replicates texels with area weights at fractional boundaries.
    """
    a = np.asarray(image)
    if a.ndim not in (2, 3) or a.shape[0] < 1 or a.shape[1] < 1:
        raise ArgumentError(f"an image must be (H, W) or (H, W, C); got shape {a.shape}")
    width, height = (int(s) for s in size)
    if width < 1 or height < 1:
        raise ArgumentError(f"invalid output size {width}x{height}")
    h, w = a.shape[:2]
    src = a.reshape(h, w, -1)
    if src.dtype not in (np.float32, np.float64):
        src = src.astype(np.float32)
    if (h, w) == (height, width):
        out = src.copy()
    elif h % height == 0 and w % width == 0:
        fy, fx = h // height, w // width
        out = np.empty((height, width, src.shape[2]), src.dtype)
        _box(src, fy, fx, out)
    else:
        ay, ax = area_weights(h, height), area_weights(w, width)
        tmp = np.zeros((height, w, src.shape[2]), src.dtype)
        _rows(src, ay.indptr, ay.indices, ay.data, tmp)
        out = np.zeros((height, width, src.shape[2]), src.dtype)
        _columns(tmp, ax.indptr, ax.indices, ax.data, out)
    return out.reshape((height, width) + a.shape[2:])


@numba.njit(parallel=True, cache=True)
def _box(src, fy, fx, out):
    scale = 1.0 / (fy * fx)
    for i in numba.prange(out.shape[0]):
        for j in range(out.shape[1]):
            for c in range(out.shape[2]):
                acc = 0.0
                for y in range(i * fy, (i + 1) * fy):
                    for x in range(j * fx, (j + 1) * fx):
                        acc += src[y, x, c]
                out[i, j, c] = acc * scale


@numba.njit(parallel=True, cache=True)
def _rows(src, indptr, indices, weights, out):
    for i in numba.prange(out.shape[0]):
        for t in range(indptr[i], indptr[i + 1]):
            k, wgt = indices[t], weights[t]
            for j in range(out.shape[1]):
                for c in range(out.shape[2]):
                    out[i, j, c] += wgt * src[k, j, c]


@numba.njit(parallel=True, cache=True)
def _columns(src, indptr, indices, weights, out):
    for r in numba.prange(out.shape[0]):
        for i in range(out.shape[1]):
            for t in range(indptr[i], indptr[i + 1]):
                k, wgt = indices[t], weights[t]
                for c in range(out.shape[2]):
                    out[r, i, c] += wgt * src[r, k, c]
