"""Exact area averages: reductions whose footprints are whole source texels, so the
solid-angle-weighted mean is computed exactly (float64 accumulation) without a matrix or
samples: a latlong onto a coarser latlong (solid-angle row weights, planar column overlaps),
a cube onto faces whose size divides the source's (k x k blocks weighed by their texels' solid
angles). :func:`bakeshop.sphere.remap`'s area filter takes them when they apply
(:func:`area_exact`); the supersampled filter shares :func:`box_reduce`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from bakeshop.image import area_weights, resample_separable
from bakeshop.sphere import _native
from bakeshop.sphere.cube import cube_to_view
from bakeshop.sphere.layouts import Layout
from bakeshop.sphere.texels import cube_face_solid_angles

if TYPE_CHECKING:
    import scipy.sparse as sp


def latlong_row_weights(n_in: int, n_out: int) -> sp.csr_matrix:
    """Row weights of a latlong reduced from ``n_in`` to ``n_out`` rows preserving solid angle.

    Output row ``i`` spans colatitudes ``[theta_i, theta_{i+1}]``; input row ``k``'s overlap
    with it, ``[a, b]``, weighs ``(cos a - cos b) / (cos theta_i - cos theta_{i+1})``: its share
    of the output row's solid angle. With the planar column weights of
    :func:`bakeshop.image.area_weights`, ``sum_out L omega = sum_in L omega`` exactly (the
    radiance integral over the sphere is kept), where the planar filter keeps the planar mean.
    Same sparsity as ``area_weights(n_in, n_out)``.
    """
    import scipy.sparse as sp  # 0.08 s to import: paid by the area filters that use it

    planar = area_weights(n_in, n_out)
    rows = np.repeat(np.arange(n_out), np.diff(planar.indptr))
    k = planar.indices.astype(np.float64)
    lo = np.maximum(k, rows * (n_in / n_out))
    hi = np.minimum(k + 1, (rows + 1) * (n_in / n_out))
    share = np.cos(np.pi * lo / n_in) - np.cos(np.pi * hi / n_in)
    total = np.add.reduceat(share, planar.indptr[:-1]) if len(share) else share
    weights = share / np.repeat(total, np.diff(planar.indptr))
    return sp.csr_matrix((weights, planar.indices, planar.indptr), shape=(n_out, n_in))


def reduce_latlong(image: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """The exact area average of a latlong ``image`` (H, W, C) on a coarser latlong grid of
    ``shape`` (h, w), h <= H and w <= W: each output texel is the solid-angle-weighted mean of
    the input over its footprint (:func:`latlong_row_weights` along rows, the planar overlaps
    of :func:`bakeshop.image.area_weights` along columns), accumulated in float64 in one pass,
    so the radiance integral over the sphere is kept (to float rounding) and a one-texel sun
    keeps its energy. Returns ``(h, w, C)`` in the image's float type."""
    h_in, w_in, c = image.shape
    h, w = shape
    ay, ax = latlong_row_weights(h_in, h), area_weights(w_in, w)
    out = np.empty((h, w, c), image.dtype)
    return resample_separable(
        image, (ay.indptr, ay.indices, ay.data), (ax.indptr, ax.indices, ax.data), out
    )


def reduce_cube(image: np.ndarray, size: int) -> np.ndarray:
    """The exact area average of a cube ``image`` (6, S, S, C) on faces of ``size`` texels (a
    divisor of S): each output texel is the solid-angle-weighted mean of the k x k texels it
    holds (k = S / size), accumulated in float64, so the radiance integral is kept. Returns
    ``(6, size, size, C)`` in the image's float type."""
    s, c = image.shape[1], image.shape[-1]
    out = np.empty((6 * size, size, c), image.dtype)
    box_reduce(image.reshape(6 * s, s, c), cube_face_solid_angles(s), s // size, out)
    return out.reshape(6, size, size, c)


def box_reduce(samples: np.ndarray, weights: np.ndarray, k: int, out: np.ndarray) -> np.ndarray:
    """``out[J, I]`` = the weighted mean of the k x k ``samples`` (rows, columns, C) of output
    texel (J, I) with ``weights`` (rows, columns); 0 where they sum to 0. Returns ``out``.

    The sums are float64 (``src/sphere/reduce.hpp``); ``weights``' rows repeat when it has fewer
    than ``samples`` (a cube face's table serves its six faces)."""
    target = out
    if out.dtype != samples.dtype or not out.flags.c_contiguous:
        target = np.empty(out.shape, samples.dtype)
    _native.box_reduce(samples, np.ascontiguousarray(weights), k, target)
    if target is not out:
        out[...] = target
    return out


def area_exact(
    image: np.ndarray, s: Layout, d: Layout, dst_shape: tuple[int, ...], rotation: bytes | None
) -> np.ndarray | None:
    """The area average of a remap of ``image`` (``s``'s base form, with a channel axis) into
    ``d`` when it is an exact reduction (None otherwise): a latlong into a latlong no finer
    along either axis (:func:`reduce_latlong`), a cube into a cube (or its cross or strip)
    whose face divides the source's (:func:`reduce_cube`), without rotation."""
    if rotation is not None:
        return None
    if s.name == d.name == "latlong":
        (h, w), (dh, dw) = image.shape[:2], dst_shape
        if dh <= h and dw <= w:
            return reduce_latlong(image, (dh, dw))
    if s.name == "cube" and d.base.name == "cube":
        n, size = image.shape[1], d.base_shape(dst_shape)[1]
        if size <= n and n % size == 0:
            cube = reduce_cube(image, size)
            return cube if d.base is d else cube_to_view(cube, d.name)
    return None
