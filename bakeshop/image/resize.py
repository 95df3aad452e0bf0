"""Energy-preserving resampling of planar images.

Each output texel is the mean of the input over the output texel's footprint (a box filter with
exact fractional overlaps), so the mean of the image, its "energy", is preserved whatever the
sizes. For integer factors this is the exact box filter; otherwise it is the area-weighted
filter (the same definition as OpenCV's ``INTER_AREA`` and Photoshop's "average" downsampling).
The filter is separable, ``out = A_y @ image @ A_x.T`` with sparse overlap matrices, so the cost is
O(H_in * W_in * C) multiply-adds: one read of the input, parallel over output rows (the compiled
kernels of ``src/image/resize.hpp``), each output row accumulated in float64 (one row of
scratch per thread, no image-sized temporary).

Any rectangle of the output can be computed from the window of the input that its footprint
covers (:func:`area_footprint`, :func:`resize_area_part`) with the same arithmetic in the same
order, so a resize computed in parts (:mod:`bakeshop.huge`) is bit-identical to the whole.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from bakeshop import threads
from bakeshop.errors import ArgumentError
from bakeshop.image import _native
from bakeshop.resources import Cost, require

if TYPE_CHECKING:
    import scipy.sparse as sp

#: bytes of the sparse weights per entry (float64 value, int32 index) and per row (int32).
_WEIGHT_BYTES = 12
#: bytes that a call holds whatever its size (a margin for the weights' int64 temporaries and
#: the threads' working set; 4 MB was 3 MB short of a measured peak, RSS counting the threads'
#: stacks and the pages the kernels touch).
_OVERHEAD = 8 << 20


@functools.lru_cache(maxsize=8)
def area_weights(n_in: int, n_out: int) -> sp.csr_matrix:
    """Sparse ``(n_out, n_in)`` matrix of box-filter weights along one axis.

    ``W[i, k]`` is the length of the overlap of input texel ``[k, k+1)`` with output texel ``i``'s
    footprint ``[i * n_in / n_out, (i + 1) * n_in / n_out)``, divided by the footprint's length,
    so every row sums to 1 and every column to ``n_out / n_in``. Exact in rational arithmetic:
    positions are scaled by ``n_out`` so that both grids are integers.
    """
    import scipy.sparse as sp  # 0.08 s to import: paid by the commands that build weights

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
    matrix = sp.csr_matrix((overlap / n_in, (rows, cols)), shape=(n_out, n_in))
    for a in (matrix.data, matrix.indices, matrix.indptr):
        a.setflags(write=False)  # cached: shared by every caller
    return matrix


def area_footprint(n_in: int, n_out: int, start: int, stop: int) -> tuple[int, int]:
    """The input texels ``[lo, hi)`` that output texels ``[start, stop)`` of a resize from
    ``n_in`` to ``n_out`` texels (along one axis) read: ``lo = floor(start n_in / n_out)``,
    ``hi = ceil(stop n_in / n_out)``."""
    return start * n_in // n_out, -(-stop * n_in // n_out)


def resize_area_cost(shape: Sequence[int], size: tuple[int, int], *, itemsize: int = 4) -> Cost:
    """What :func:`resize_area` of an image of ``shape`` ((H, W) or (H, W, C)) to ``size``
    (width, height) holds at its peak: the output (``itemsize`` bytes per sample; float32 for
    integer images, which are converted first, a copy of the input), the sparse weights of both
    axes, one float64 row of scratch per thread and a fixed overhead. ``work`` is in input
    samples."""
    h, w = (int(n) for n in shape[:2])
    channels = int(math.prod(shape[2:]))
    width, height = (int(n) for n in size)
    weights = _WEIGHT_BYTES * (h + height + w + width) * 2
    scratch = threads.count() * w * channels * 8
    copy = h * w * channels * 4 if itemsize not in (4, 8) else 0
    memory = width * height * channels * max(itemsize, 4) + weights + scratch + copy + _OVERHEAD
    what = f"resizing {w}x{h} to {width}x{height}"
    return Cost(int(memory), h * w * channels, what)


def resize_area(image: ArrayLike, size: tuple[int, int]) -> np.ndarray:
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
    replicates texels with area weights at fractional boundaries. The memory it needs is
    checked first (:func:`resize_area_cost`): a size that cannot fit is refused with the number.
    """
    a = np.asarray(image)
    if a.ndim not in (2, 3) or a.shape[0] < 1 or a.shape[1] < 1:
        raise ArgumentError(f"an image must be (H, W) or (H, W, C); got shape {a.shape}")
    width, height = (int(s) for s in size)
    if width < 1 or height < 1:
        raise ArgumentError(f"invalid output size {width}x{height}")
    h, w = a.shape[:2]
    require(resize_area_cost(a.shape, (width, height), itemsize=a.itemsize))
    src = a.reshape(h, w, -1)
    if src.dtype not in (np.float32, np.float64):
        src = src.astype(np.float32)
    if (h, w) == (height, width):
        out = src.copy()
    else:
        out = resize_area_part(src, (h, w), (width, height))
    return out.reshape((height, width) + a.shape[2:])


def resize_area_part(
    window: np.ndarray,
    full_shape: tuple[int, int],
    size: tuple[int, int],
    *,
    rows: tuple[int, int] | None = None,
    cols: tuple[int, int] | None = None,
    origin: tuple[int, int] = (0, 0),
) -> np.ndarray:
    """Output rows ``rows`` and columns ``cols`` of :func:`resize_area` of an image of which
    only ``window`` is given: the same values, bit for bit, as the same part of the whole.

    Parameters
    ----------
    window : (h, w, C) float array
        The texels ``[y0, y0 + h) x [x0, x0 + w)`` of the whole image, ``origin = (y0, x0)``;
        they must cover the part's footprint (:func:`area_footprint` along each axis).
    full_shape : (int, int)
        The whole image's (H, W).
    size : (int, int)
        The whole output's (width, height).
    rows, cols : (int, int), optional
        ``(start, stop)`` of the part along each axis (default: the whole output).
    origin : (int, int)
        Where ``window`` starts in the whole image.

    Returns
    -------
    (rows, cols, C) array of the window's float type
        Accumulated in float64, rounded once.
    """
    (h, w), (width, height) = (int(n) for n in full_shape), (int(n) for n in size)
    i0, i1 = (0, height) if rows is None else rows
    j0, j1 = (0, width) if cols is None else cols
    y0, x0 = origin
    src = np.asarray(window)
    (ly, hy), (lx, hx) = area_footprint(h, height, i0, i1), area_footprint(w, width, j0, j1)
    if ly < y0 or lx < x0 or hy > y0 + src.shape[0] or hx > x0 + src.shape[1]:
        raise ArgumentError(
            f"the window at {origin} of shape {src.shape[:2]} does not cover the footprint "
            f"rows {ly}..{hy}, columns {lx}..{hx} of output rows {i0}..{i1}, columns {j0}..{j1}"
        )
    out = np.empty((i1 - i0, j1 - j0, src.shape[2]), src.dtype)
    if h % height == 0 and w % width == 0:
        fy, fx = h // height, w // width
        _native.box(_rows(src[ly - y0 : hy - y0, lx - x0 : hx - x0]), fy, fx, out)
    else:
        ay, ax = area_weights(h, height)[i0:i1], area_weights(w, width)[j0:j1]
        resample_separable(src, (ay.indptr, ay.indices - y0, ay.data),
                           (ax.indptr, ax.indices - x0, ax.data), out)  # fmt: skip
    return out


def resample_separable(
    src: np.ndarray,
    rows: tuple[np.ndarray, np.ndarray, np.ndarray],
    cols: tuple[np.ndarray, np.ndarray, np.ndarray],
    out: np.ndarray,
) -> np.ndarray:
    """``out[i, j] = sum_k sum_l Ay[i, k] Ax[j, l] src[k, l]``, accumulated in float64.

    ``rows = (indptr, indices, weights)`` is ``Ay`` in CSR form (``len(indptr) = out rows +
    1``, indices into ``src``'s rows), ``cols`` is ``Ax`` (indices into its columns); the sums
    run over each CSR row in its stored order. Parallel over output rows; one float64 row of
    scratch per thread. ``src`` and ``out`` are float32 or float64, ``out`` C-ordered. Returns
    ``out``.
    """
    ry, ky, wy = _csr(rows)
    rx, kx, wx = _csr(cols)
    _native.separable(_rows(src), ry, ky, wy, rx, kx, wx, out)
    return out


def _csr(
    matrix: tuple[np.ndarray, np.ndarray, np.ndarray],
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(indptr, indices, weights) in the types the kernel takes: int64, int64, float64."""
    indptr, indices, weights = matrix
    return (
        np.asarray(indptr, np.int64),
        np.asarray(indices, np.int64),
        np.asarray(weights, np.float64),
    )


def _rows(src: np.ndarray) -> np.ndarray:
    """``src`` (h, w, C) as (h, w * C) rows, a view when each row's texels are contiguous (a
    window cut out of a C-ordered image is), else a contiguous copy: the kernels run along
    rows of ``w * C`` samples, which vectorises, instead of texel by texel."""
    h, w, c = src.shape
    if src.strides[2] != src.itemsize or src.strides[1] != c * src.itemsize:
        src = np.ascontiguousarray(src)
    return src.reshape(h, w * c)
