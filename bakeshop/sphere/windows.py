"""A part of a remap from a window of its source: for images too large to hold whole.

:func:`remap_part_taps` gives, for a rectangle of one face of the destination, the source taps
and fractions of every texel: the same numbers, computed by the same scalar maps in the same
order, as the plan that :func:`bakeshop.sphere.remap` builds for the whole destination
(``src/sphere/windows.hpp`` and ``gather.hpp``). :func:`taps_window` says which rows and
columns of the source they read (the window a task must load; a latlong's longitude wraps, so
a window may be two column ranges), :func:`localise_taps` renumbers the taps into that window,
and :func:`gather_taps` blends them exactly as the plan's gather does. A remap computed part by part
from windows (:mod:`bakeshop.huge`) is therefore bit-identical to the in-memory remap for the
``nearest`` and ``bilinear`` filters.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, validate_choice
from bakeshop.sphere import _native
from bakeshop.sphere.layouts import Layout, layout
from bakeshop.sphere.rotation import key_matrix, rotation_key

__all__ = [
    "gather_taps",
    "latlong_window_geometry",
    "localise_taps",
    "remap_part_taps",
    "sample_taps",
    "taps_window",
]


def remap_part_taps(
    src: str | Layout,
    src_shape: Sequence[int],
    dst: str | Layout,
    dst_shape: Sequence[int],
    *,
    face: int = 0,
    rows: tuple[int, int],
    cols: tuple[int, int],
    filter: str = "bilinear",
    rotation: ArrayLike | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Source taps of destination texels ``rows x cols`` of ``face`` (0 for flat layouts).

    Parameters
    ----------
    src, dst : str or Layout
        Base layouts (not a cube picture: a cross's parts are the cube's faces).
    src_shape, dst_shape : tuple
        Spatial shapes.
    face : int
        The destination face (cube), 0 otherwise.
    rows, cols : (int, int)
        ``(start, stop)`` of the part on that face.
    filter : {"nearest", "bilinear"}
    rotation : optional
        As for :func:`bakeshop.sphere.remap`.

    Returns
    -------
    taps : (n, 1) or (n, 4) int32
        Flat indices into the whole source (face-major for a cube source); -1 for none (an
        invalid destination texel, or a cube corner's missing fourth tap). ``n`` is the part's
        texel count, row-major.
    frac : (n, 2) float32
        Bilinear fractions (empty for nearest).
    """
    validate_choice(filter, ("nearest", "bilinear"), "part filter")
    s, d = layout(src), layout(dst)
    if s.base is not s or d.base is not d:
        raise ArgumentError("parts are computed between base layouts (a cross is its cube)")
    sh, sw, _ = s.grid(src_shape)
    dh, dw, faces = d.grid(dst_shape)
    (j0, j1), (i0, i1) = rows, cols
    if not (0 <= face < faces and 0 <= j0 < j1 <= dh and 0 <= i0 < i1 <= dw):
        raise ArgumentError(f"part {rows} x {cols} of face {face} is outside {dst_shape}")
    nearest = filter == "nearest"
    n = (j1 - j0) * (i1 - i0)
    taps = np.empty((n, 1 if nearest else 4), np.int32)
    frac = np.empty((0 if nearest else n, 2), np.float32)
    rot = key_matrix(rotation_key(rotation))
    _native.part_taps(s.kind, sh, sw, d.kind, dh, dw, rot, face, j0, j1, i0, i1, nearest, taps,
                      frac)  # fmt: skip
    return taps, frac


def taps_window(taps: np.ndarray, width: int) -> tuple[tuple[int, int], list[tuple[int, int]]]:
    """The source rows ``(top, bottom)`` and column ranges that ``taps`` (flat indices into a
    source ``width`` texels wide; -1 ignored) read: one range, or two when the shortest arc
    covering the columns crosses the wrap from the last column to the first (a latlong's
    longitude seam). ``((0, 0), [])`` when no tap is valid."""
    t = taps[taps >= 0]
    if t.size == 0:
        return (0, 0), []
    r = t // width
    used = np.zeros(width, bool)
    used[t % width] = True
    columns = np.flatnonzero(used)
    # the largest gap between used columns, around the circle, is left out
    gaps = np.diff(np.concatenate([columns, [columns[0] + width]]))
    k = int(np.argmax(gaps))
    if gaps[k] <= 1:
        ranges = [(0, width)]
    else:
        start, stop = int(columns[(k + 1) % len(columns)]), int(columns[k]) + 1
        ranges = [(start, stop)] if start < stop else [(start, width), (0, stop)]
    return (int(r.min()), int(r.max()) + 1), ranges


def localise_taps(
    taps: np.ndarray, width: int, rows: tuple[int, int], ranges: Sequence[tuple[int, int]]
) -> np.ndarray:
    """``taps`` renumbered into the window ``rows`` x ``ranges`` (the column ranges placed side
    by side, as :func:`taps_window` gives them); -1 stays -1."""
    lookup = np.full(width, -1, np.int64)
    at = 0
    for a, b in ranges:
        lookup[a:b] = np.arange(at, at + b - a)
        at += b - a
    valid_tap = taps >= 0
    t = np.where(valid_tap, taps, 0).astype(np.int64)
    local = (t // width - rows[0]) * at + lookup[t % width]
    return np.where(valid_tap, local, -1).astype(np.int32)


def gather_taps(window_flat: np.ndarray, taps: np.ndarray, frac: np.ndarray) -> np.ndarray:
    """Values at ``taps`` of a flat ``(n, C)`` source (nearest: one tap; bilinear: four, with
    ``frac``), exactly as :func:`bakeshop.sphere.remap` blends them: ``(m, C)`` of the source's
    type."""
    src = np.ascontiguousarray(window_flat)
    out = np.empty((taps.shape[0], src.shape[1]), src.dtype)
    if taps.shape[1] == 1:
        _native.gather_nearest(src, taps, out)
    else:
        _native.gather_bilinear(src, taps, frac, out)
    return out


def latlong_window_geometry(
    shape: Sequence[int], rows: tuple[int, int], cols: tuple[int, int] | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Flat directions ``(n, 3)`` and solid angles ``(n,)`` (float64) of the texels
    ``rows x cols`` of a latlong of ``shape`` (H, W), row-major: the same numbers as the same
    texels of :func:`bakeshop.sphere.texel_geometry`, without building the whole layout's."""
    h, w = layout("latlong").check_shape(shape)
    top, bottom = rows
    left, right = (0, w) if cols is None else cols
    if not (0 <= top < bottom <= h and 0 <= left < right <= w):
        raise ArgumentError(f"window {rows} x {cols} is outside a latlong of shape {shape}")
    n = (bottom - top) * (right - left)
    dirs = np.empty((n, 3))
    _native.latlong_window(h, w, top, bottom, left, right, dirs)
    c = np.cos(np.pi * np.arange(top, bottom + 1) / h)
    band = (c[:-1] - c[1:]) * (2 * np.pi / w)
    return dirs, np.repeat(band, right - left)


def sample_taps(
    layout_name: str | Layout, shape: Sequence[int], dirs: ArrayLike, *, filter: str = "bilinear"
) -> tuple[np.ndarray, np.ndarray]:
    """Taps and fractions of :func:`bakeshop.sphere.sample` at directions ``dirs`` (n, 3) in a
    base layout of spatial ``shape`` (flat indices into the whole image; see
    :func:`remap_part_taps`), to be read from a window with :func:`taps_window`,
    :func:`localise_taps` and :func:`gather_taps`."""
    validate_choice(filter, ("nearest", "bilinear"), "sampling filter")
    lay = layout(layout_name)
    if lay.base is not lay:
        raise ArgumentError("taps are computed in base layouts (a cross is its cube)")
    h, w, _ = lay.grid(shape)
    flat = np.ascontiguousarray(np.asarray(dirs, dtype=np.float64).reshape(-1, 3))
    nearest = filter == "nearest"
    taps = np.empty((len(flat), 1 if nearest else 4), np.int32)
    frac = np.empty((0 if nearest else len(flat), 2), np.float32)
    _native.taps_of(lay.kind, h, w, flat, nearest, taps, frac)
    return taps, frac
