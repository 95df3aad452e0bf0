"""The remap plan and gather kernels: nearest and seam-aware bilinear taps, built once per
(source, destination, rotation) and applied as one parallel gather (see
:mod:`bakeshop.sphere.sampling`)."""

from __future__ import annotations

import math

import numba
import numpy as np

from bakeshop.sphere._maps import (
    LATLONG,
    coordinates,
    direction,
    face_row,
    is_cubic,
    is_disk,
    latlong_trig,
    latlong_xy,
    nearest_texel,
    resolve,
    rotate,
    valid,
)

_jit = numba.njit(cache=True, error_model="numpy")


@_jit
def _taps(
    kind: int,
    h: int,
    w: int,
    f: float,
    x: float,
    y: float,
    nearest: bool,
    index: np.ndarray,
    frac: np.ndarray,
    p: int,
) -> None:
    if not (abs(x) < 1e18 and abs(y) < 1e18):
        # a NaN or infinite direction: no texel
        for k in range(index.shape[1]):
            index[p, k] = -1
        return
    if nearest:
        index[p, 0] = nearest_texel(kind, h, w, f, x, y)
        return
    xs, ys = x - 0.5, y - 0.5
    x0, y0 = math.floor(xs), math.floor(ys)
    frac[p, 0], frac[p, 1] = xs - x0, ys - y0
    i0, j0 = int(x0), int(y0)
    index[p, 0] = resolve(kind, h, w, f, i0, j0, x)
    index[p, 1] = resolve(kind, h, w, f, i0 + 1, j0, x)
    index[p, 2] = resolve(kind, h, w, f, i0, j0 + 1, x)
    index[p, 3] = resolve(kind, h, w, f, i0 + 1, j0 + 1, x)


@numba.njit(parallel=True, cache=True, error_model="numpy")
def taps_of(
    kind: int, h: int, w: int, dirs: np.ndarray, nearest: bool, index: np.ndarray, frac: np.ndarray
) -> None:
    """Source taps for sampling layout (kind, h, w) at directions ``dirs`` (m, 3)."""
    for p in numba.prange(dirs.shape[0]):
        f, x, y = coordinates(kind, h, w, dirs[p, 0], dirs[p, 1], dirs[p, 2])
        _taps(kind, h, w, f, x, y, nearest, index, frac, p)


#: a remap plan's base index for a texel whose taps are not a 2x2 block (seams, rims, corners):
#: ``EXCEPTION - k`` points at row ``k`` of the plan's explicit taps.
EXCEPTION = -2


@_jit
def block(kind: int, h: int, w: int, f: float, i0: int, j0: int, size: int) -> int:
    """Flat index of texel (f, i0, j0) when the size x size block from it holds ordinary
    texels of one image (one face, one disk, all valid), else -1: then ``resolve`` of block
    texel (a, b) is simply that index + b w + a."""
    if i0 < 0 or j0 < 0 or i0 + size > w or j0 + size > h:
        return -1
    if is_cubic(kind):
        return (int(f) * h + j0) * w + i0
    if is_disk(kind):
        n = h
        li = i0 % n
        if li + size > n:
            return -1
        for dj in range(size):
            for di in range(size):
                if not valid(kind, h, w, 0, li + di, j0 + dj):
                    return -1
    return j0 * w + i0


@_jit
def _plan_direction(
    dkind: int, dh: int, dw: int, f: int, i: int, j: int, rot: np.ndarray, trig: np.ndarray
) -> tuple[float, float, float]:
    """Direction of destination texel (f, i, j)'s centre, rotated into the source's frame."""
    if dkind == LATLONG:
        x, y, z = trig[2, j] * trig[0, i], trig[3, j], -trig[2, j] * trig[1, i]
    else:
        x, y, z = direction(dkind, dh, dw, f, i + 0.5, j + 0.5)
    return rotate(rot, x, y, z)


@_jit
def _latlong_row(
    h: int, w: int, xs: np.ndarray, ys: np.ndarray, zs: np.ndarray, us: np.ndarray, vs: np.ndarray
) -> None:
    # a loop of selects and arithmetic only: it vectorises
    for i in range(xs.shape[0]):
        us[i], vs[i] = latlong_xy(h, w, xs[i], ys[i], zs[i])


@numba.njit(parallel=True, cache=True, error_model="numpy")
def plan(
    skind: int,
    sh: int,
    sw: int,
    dkind: int,
    dh: int,
    dw: int,
    faces: int,
    rot: np.ndarray,
    nearest: bool,
    base: np.ndarray,
    frac: np.ndarray,
    src: np.ndarray,
    out: np.ndarray,
    first_row: int,
) -> None:
    """The remap plan of destination texel centres, one destination row at a time: the rows
    ``first_row`` onwards (of the faces stacked, ``faces * dh`` rows in all), as many as
    ``base`` holds (``p`` below counts from the first of them).

    Nearest: ``base[p]`` is the source texel (-1: invalid destination texel). Bilinear:
    ``base[p]`` is the flat index of the upper-left tap of an ordinary 2x2 block (the taps are
    base, +1, +sw, +sw+1), ``EXCEPTION`` where the taps cross a seam (resolved afterwards by
    :func:`plan_exceptions`) or -1 for an invalid texel; ``frac[p]`` holds the fractions,
    float32 (as :func:`taps_of` computes them, so that ``sample`` and ``remap`` agree exactly).
    Unless ``out`` is empty, the plan is also applied to the flat image ``src`` on the way
    (the EXCEPTION texels are left to :func:`gather_at`): a first remap reads no plan back.
    """
    apply = out.shape[0] > 0
    no_taps = np.empty((0, 4), np.int32)
    trig = latlong_trig(dh, dw)
    for local in numba.prange(base.shape[0] // dw):
        row = first_row + local
        f = row // dh
        j = row - f * dh
        xs, ys, zs = np.empty(dw), np.empty(dw), np.empty(dw)
        us, vs = np.empty(dw), np.empty(dw)
        sf = np.zeros(dw, np.int64)
        if is_cubic(dkind):
            face_row(dkind, dw, f, j, xs, ys, zs)
            for i in range(dw):
                xs[i], ys[i], zs[i] = rotate(rot, xs[i], ys[i], zs[i])
        else:
            for i in range(dw):
                xs[i], ys[i], zs[i] = _plan_direction(dkind, dh, dw, f, i, j, rot, trig)
        if skind == LATLONG:
            _latlong_row(sh, sw, xs, ys, zs, us, vs)
        else:
            for i in range(dw):
                sf[i], us[i], vs[i] = coordinates(skind, sh, sw, xs[i], ys[i], zs[i])
        for i in range(dw):
            p = local * dw + i
            sx, sy = us[i], vs[i]
            if not valid(dkind, dh, dw, f, i, j) or not (abs(sx) < 1e18 and abs(sy) < 1e18):
                base[p] = -1
            elif nearest:
                base[p] = nearest_texel(skind, sh, sw, sf[i], sx, sy)
            else:
                xf, yf = sx - 0.5, sy - 0.5
                x0, y0 = math.floor(xf), math.floor(yf)
                frac[p, 0], frac[p, 1] = xf - x0, yf - y0
                b = block(skind, sh, sw, sf[i], int(x0), int(y0), 2)
                base[p] = b if b >= 0 else EXCEPTION
            if apply:
                if nearest:
                    for c in range(src.shape[1]):
                        out[p, c] = src[base[p], c] if base[p] >= 0 else 0
                elif base[p] != EXCEPTION:
                    _gather_texel(src, sw, base, frac, no_taps, p, out)


@numba.njit(parallel=True, cache=True, error_model="numpy")
def plan_exceptions(
    skind: int,
    sh: int,
    sw: int,
    dkind: int,
    dh: int,
    dw: int,
    rot: np.ndarray,
    where: np.ndarray,
    taps: np.ndarray,
) -> None:
    """The four seam-aware taps of the plan's EXCEPTION texels ``where`` (-1: a cube corner)."""
    per = dh * dw
    trig = latlong_trig(dh, dw)
    for k in numba.prange(where.shape[0]):
        f, r = divmod(where[k], per)
        j, i = divmod(r, dw)
        x, y, z = _plan_direction(dkind, dh, dw, f, i, j, rot, trig)
        sf, sx, sy = coordinates(skind, sh, sw, x, y, z)
        i0, j0 = int(math.floor(sx - 0.5)), int(math.floor(sy - 0.5))
        taps[k, 0] = resolve(skind, sh, sw, sf, i0, j0, sx)
        taps[k, 1] = resolve(skind, sh, sw, sf, i0 + 1, j0, sx)
        taps[k, 2] = resolve(skind, sh, sw, sf, i0, j0 + 1, sx)
        taps[k, 3] = resolve(skind, sh, sw, sf, i0 + 1, j0 + 1, sx)


@numba.njit(parallel=True, cache=True, error_model="numpy")
def reorder_plan(
    base: np.ndarray,
    frac: np.ndarray,
    order: np.ndarray,
    out_base: np.ndarray,
    out_frac: np.ndarray,
) -> None:
    """The plan (:func:`plan`) of texels ``order`` (-1: none, an invalid texel)."""
    for p in numba.prange(order.shape[0]):
        k = order[p]
        out_base[p] = base[k] if k >= 0 else -1
        if out_frac.shape[0] > 0:
            out_frac[p, 0] = frac[k, 0] if k >= 0 else 0
            out_frac[p, 1] = frac[k, 1] if k >= 0 else 0


@numba.njit(parallel=True, cache=True, error_model="numpy")
def gather_at(
    src: np.ndarray,
    row: int,
    base: np.ndarray,
    frac: np.ndarray,
    taps: np.ndarray,
    where: np.ndarray,
    out: np.ndarray,
) -> None:
    """:func:`gather_plan` for the output texels ``where`` only."""
    for k in numba.prange(where.shape[0]):
        _gather_texel(src, row, base, frac, taps, where[k], out)


@numba.njit(parallel=True, cache=True, error_model="numpy")
def gather_plan(
    src: np.ndarray, row: int, base: np.ndarray, frac: np.ndarray, taps: np.ndarray, out: np.ndarray
) -> None:
    """Apply a bilinear remap plan (see :func:`plan`): ``row`` is the source's row stride
    (its width). Weights are computed in the image's type (float32 stays float32)."""
    for p in numba.prange(base.shape[0]):
        _gather_texel(src, row, base, frac, taps, p, out)


@numba.njit(cache=True, error_model="numpy", inline="always")
def _gather_texel(
    src: np.ndarray,
    row: int,
    base: np.ndarray,
    frac: np.ndarray,
    taps: np.ndarray,
    p: int,
    out: np.ndarray,
) -> None:
    """out[p] from the bilinear plan (see :func:`plan`); inlined: a call costs 2x here."""
    nc = src.shape[1]
    one = src.dtype.type(1)
    b = base[p]
    if b == -1:
        for c in range(nc):
            out[p, c] = 0
        return
    fx, fy = src.dtype.type(frac[p, 0]), src.dtype.type(frac[p, 1])
    if b >= 0:
        i0, i1, i2, i3 = b, b + 1, b + row, b + row + 1
    else:
        k = EXCEPTION - b
        i0, i1, i2, i3 = taps[k, 0], taps[k, 1], taps[k, 2], taps[k, 3]
    gx, gy = one - fx, one - fy
    w0, w1, w2, w3 = gx * gy, fx * gy, gx * fy, fx * fy
    if i0 >= 0 and i1 >= 0 and i2 >= 0 and i3 >= 0:
        for c in range(nc):
            out[p, c] = w0 * src[i0, c] + w1 * src[i1, c] + w2 * src[i2, c] + w3 * src[i3, c]
    else:
        for c in range(nc):
            out[p, c] = _bilinear(src, i0, i1, i2, i3, fx, fy, c)


@_jit
def _bilinear(
    src: np.ndarray, i0: int, i1: int, i2: int, i3: int, fx: float, fy: float, c: int
) -> float:
    w0, w1 = (1 - fx) * (1 - fy), fx * (1 - fy)
    w2, w3 = (1 - fx) * fy, fx * fy
    if i0 >= 0 and i1 >= 0 and i2 >= 0 and i3 >= 0:
        return w0 * src[i0, c] + w1 * src[i1, c] + w2 * src[i2, c] + w3 * src[i3, c]
    # a cube corner: the missing texel is the mean of the other three (OpenGL)
    v0 = src[i0, c] if i0 >= 0 else 0.0
    v1 = src[i1, c] if i1 >= 0 else 0.0
    v2 = src[i2, c] if i2 >= 0 else 0.0
    v3 = src[i3, c] if i3 >= 0 else 0.0
    m = (v0 + v1 + v2 + v3) / 3
    v0 = v0 if i0 >= 0 else m
    v1 = v1 if i1 >= 0 else m
    v2 = v2 if i2 >= 0 else m
    v3 = v3 if i3 >= 0 else m
    return w0 * v0 + w1 * v1 + w2 * v2 + w3 * v3


@numba.njit(parallel=True, cache=True, error_model="numpy")
def gather_nearest(src: np.ndarray, index: np.ndarray, out: np.ndarray) -> None:
    for p in numba.prange(index.shape[0]):
        i = index[p, 0]
        for c in range(src.shape[1]):
            out[p, c] = src[i, c] if i >= 0 else 0


@numba.njit(parallel=True, cache=True, error_model="numpy")
def gather_bilinear(src: np.ndarray, index: np.ndarray, frac: np.ndarray, out: np.ndarray) -> None:
    """out[p] = bilinear blend of the four taps of ``index[p]`` with fractions ``frac[p]``;
    all taps -1: 0 (an invalid texel); one tap -1: a cube corner (the mean of the other three).
    Weights are computed in the image's type (float32 stays float32)."""
    nc = src.shape[1]
    one = src.dtype.type(1)
    for p in numba.prange(index.shape[0]):
        i0, i1, i2, i3 = index[p, 0], index[p, 1], index[p, 2], index[p, 3]
        fx, fy = src.dtype.type(frac[p, 0]), src.dtype.type(frac[p, 1])
        gx, gy = one - fx, one - fy
        w0, w1, w2, w3 = gx * gy, fx * gy, gx * fy, fx * fy
        if i0 >= 0 and i1 >= 0 and i2 >= 0 and i3 >= 0:
            for c in range(nc):
                out[p, c] = w0 * src[i0, c] + w1 * src[i1, c] + w2 * src[i2, c] + w3 * src[i3, c]
        elif i0 < 0 and i1 < 0:
            for c in range(nc):
                out[p, c] = 0
        else:
            for c in range(nc):
                out[p, c] = _bilinear(src, i0, i1, i2, i3, fx, fy, c)


@numba.njit(parallel=True, cache=True, error_model="numpy")
def gather_plan_clamped(
    src: np.ndarray,
    row: int,
    base: np.ndarray,
    frac: np.ndarray,
    taps: np.ndarray,
    clamp: float,
    out: np.ndarray,
) -> None:
    """:func:`gather_plan` of the source with every value clamped to at most ``clamp`` (the
    supersampled area filter samples the part of an image below its bright texels)."""
    nc = src.shape[1]
    for p in numba.prange(base.shape[0]):
        b = base[p]
        if b == -1:
            for c in range(nc):
                out[p, c] = 0
            continue
        fx, fy = frac[p, 0], frac[p, 1]
        if b >= 0:
            i0, i1, i2, i3 = b, b + 1, b + row, b + row + 1
        else:
            k = EXCEPTION - b
            i0, i1, i2, i3 = taps[k, 0], taps[k, 1], taps[k, 2], taps[k, 3]
        w0, w1 = (1 - fx) * (1 - fy), fx * (1 - fy)
        w2, w3 = (1 - fx) * fy, fx * fy
        for c in range(nc):
            v0 = min(src[i0, c], clamp) if i0 >= 0 else 0.0
            v1 = min(src[i1, c], clamp) if i1 >= 0 else 0.0
            v2 = min(src[i2, c], clamp) if i2 >= 0 else 0.0
            v3 = min(src[i3, c], clamp) if i3 >= 0 else 0.0
            if i0 < 0 or i1 < 0 or i2 < 0 or i3 < 0:
                # a cube corner: the missing texel is the mean of the other three (OpenGL)
                m = (v0 + v1 + v2 + v3) / 3
                v0 = v0 if i0 >= 0 else m
                v1 = v1 if i1 >= 0 else m
                v2 = v2 if i2 >= 0 else m
                v3 = v3 if i3 >= 0 else m
            out[p, c] = w0 * v0 + w1 * v1 + w2 * v2 + w3 * v3
