"""Placing a tileable detail normal map on the macro map: tiling, offset, rotation, masks, layers.

Coordinates
-----------
A texture coordinate (u, v) has v *up* the picture, as the tangent frame's +Y (the OpenGL,
OBJ and trimesh convention): in an ``(H, W)`` image it lies at column x = u W and row
y = (1 - v) H, and texel (i, j)'s centre is x = i + 0.5, y = j + 0.5. A tileable map repeats
with period 1 in (u, v).

A detail layer is placed by tiles t = (t_u, t_v) (repetitions across the output), an offset o
(in tiles) and a rotation theta (degrees, counter-clockwise as seen in the picture): the output
texel at (u, v) shows the detail at q = R(-theta) (t_u u, t_v v) + o. Rotating the picture of a
normal map rotates the vectors' XY with it, so the sampled normal's (x, y) is turned by
R(theta): the result is the normal map of the rotated height field (tests/normals).

Filtering
---------
Samples are bilinear with wrap-around, so tiles meet without seams, from a mip chain of the
detail (2x2 box averages of the vectors) at the level of the footprint, blending the two nearest
levels (trilinear, as a GPU does); the sampled vectors are renormalised. Minified detail is
therefore prefiltered instead of aliasing, and an integer number of tiles gives an output
that is itself exactly tileable.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from bakeshop.errors import ArgumentError
from bakeshop.normals.blend import DEFAULT_METHOD, blend
from bakeshop.normals.encoding import normalize
from bakeshop.resample import resize_area

__all__ = [
    "mip_chain",
    "sample_wrapped",
    "place_detail",
    "mask_weights",
    "DetailLayer",
    "apply_layers",
]


def mip_chain(image) -> list[np.ndarray]:
    """Mip levels of a tileable image, level 0 first, each half the size of the one before.

    Parameters
    ----------
    image : (H, W, C) float array

    Returns
    -------
    list of (H_l, W_l, C) float32 arrays, down to 1 x 1. Each level is the box (area) average of
    the previous one; vectors are *not* renormalised (a short average records that the normals
    under it disagree, and the sampler renormalises after filtering).
    """
    a = np.asarray(image, dtype=np.float32)
    if a.ndim != 3 or a.shape[0] < 1 or a.shape[1] < 1:
        raise ArgumentError(f"an image must be (H, W, C); got shape {a.shape}")
    levels = [np.ascontiguousarray(a)]
    while levels[-1].shape[0] > 1 or levels[-1].shape[1] > 1:
        h, w = levels[-1].shape[:2]
        levels.append(resize_area(levels[-1], (max(1, w // 2), max(1, h // 2))))
    return levels


@numba.njit(cache=True, inline="always")
def _bilinear_add(src, x, y, wrap, weight, out):
    """out += weight * bilinear sample of src at continuous texel coordinates (x, y)."""
    h, w, c = src.shape
    x -= 0.5
    y -= 0.5
    x0 = math.floor(x)
    y0 = math.floor(y)
    fx = x - x0
    fy = y - y0
    if wrap:
        i0 = int(x0) % w
        i1 = (i0 + 1) % w
        j0 = int(y0) % h
        j1 = (j0 + 1) % h
    else:
        i0 = min(max(int(x0), 0), w - 1)
        i1 = min(max(int(x0) + 1, 0), w - 1)
        j0 = min(max(int(y0), 0), h - 1)
        j1 = min(max(int(y0) + 1, 0), h - 1)
    w00 = (1 - fx) * (1 - fy) * weight
    w10 = fx * (1 - fy) * weight
    w01 = (1 - fx) * fy * weight
    w11 = fx * fy * weight
    for k in range(c):
        out[k] += w00 * src[j0, i0, k] + w10 * src[j0, i1, k] + w01 * src[j1, i0, k]
        out[k] += w11 * src[j1, i1, k]


@numba.njit(cache=True, parallel=True)
def _sample_points(lo, hi, scale_lo, scale_hi, t, xs, ys, wrap, out):
    n = xs.shape[0]
    for p in numba.prange(n):
        o = out[p]
        for k in range(o.shape[0]):
            o[k] = 0.0
        _bilinear_add(lo, xs[p] * scale_lo[0], ys[p] * scale_lo[1], wrap, 1.0 - t[p], o)
        if t[p] > 0:
            _bilinear_add(hi, xs[p] * scale_hi[0], ys[p] * scale_hi[1], wrap, t[p], o)


def _level_pair(chain, lod: float):
    lod = min(max(float(lod), 0.0), len(chain) - 1.0)
    lo = int(math.floor(lod))
    hi = min(lo + 1, len(chain) - 1)
    return lo, hi, lod - lo


def sample_wrapped(chain, x, y, *, lod=0.0, wrap: bool = True) -> np.ndarray:
    """Trilinear samples of a mip chain at continuous level-0 texel coordinates.

    Parameters
    ----------
    chain : list of (H_l, W_l, C) arrays
        From :func:`mip_chain` (a one-level list samples bilinearly).
    x, y : (N,) float arrays
        Column and row in level-0 texels; texel (i, j)'s centre is (i + 0.5, j + 0.5).
    lod : float or (N,) array
        Level of detail: log2 of the footprint in level-0 texels (0 = bilinear on level 0).
    wrap : bool
        Repeat the image (tileable maps) or clamp to its edge.

    Returns
    -------
    (N, C) float32 samples (not renormalised).
    """
    xs = np.ascontiguousarray(x, dtype=np.float64).reshape(-1)
    ys = np.ascontiguousarray(y, dtype=np.float64).reshape(-1)
    lods = np.clip(np.broadcast_to(np.asarray(lod, np.float64), xs.shape), 0, len(chain) - 1)
    out = np.empty((xs.size, chain[0].shape[2]), np.float32)
    base = np.floor(lods).astype(np.intp)
    h0, w0 = chain[0].shape[:2]
    for level in np.unique(base):
        sel = np.nonzero(base == level)[0]
        hi = min(level + 1, len(chain) - 1)
        t = lods[sel] - level
        scales = [
            np.array([chain[lv].shape[1] / w0, chain[lv].shape[0] / h0]) for lv in (level, hi)
        ]
        part = np.empty((sel.size, out.shape[1]), np.float32)
        _sample_points(chain[level], chain[hi], *scales, t, xs[sel], ys[sel], wrap, part)
        out[sel] = part
    return out


@numba.njit(cache=True, parallel=True)
def _place(lo, hi, t, w0, h0, affine, cos_r, sin_r, sign_x, sign_y, out):
    """Sample two mip levels along an affine map of output texels (to level-0 texels of size
    w0 x h0), rotate XY, renormalise."""
    height, width = out.shape[:2]
    s_lo = (lo.shape[1] / w0, lo.shape[0] / h0)
    s_hi = (hi.shape[1] / w0, hi.shape[0] / h0)
    acc = np.empty((height, 3))
    for j in numba.prange(height):
        a = acc[j]
        for i in range(width):
            a[0] = 0.0
            a[1] = 0.0
            a[2] = 0.0
            x = affine[0, 0] * (i + 0.5) + affine[0, 1] * (j + 0.5) + affine[0, 2]
            y = affine[1, 0] * (i + 0.5) + affine[1, 1] * (j + 0.5) + affine[1, 2]
            _bilinear_add(lo, x * s_lo[0], y * s_lo[1], True, 1.0 - t, a)
            if t > 0:
                _bilinear_add(hi, x * s_hi[0], y * s_hi[1], True, t, a)
            nx = (cos_r * a[0] - sin_r * a[1]) * sign_x
            ny = (sin_r * a[0] + cos_r * a[1]) * sign_y
            nz = a[2]
            length = math.sqrt(nx * nx + ny * ny + nz * nz)
            if length > 0 and math.isfinite(length):
                out[j, i, 0] = nx / length
                out[j, i, 1] = ny / length
                out[j, i, 2] = nz / length
            else:
                out[j, i, 0] = 0.0
                out[j, i, 1] = 0.0
                out[j, i, 2] = 1.0


def as_pair(value, what: str) -> tuple[float, float]:
    """A finite number or pair as ``(a, b)``; :class:`ArgumentError` naming ``what`` otherwise."""
    v = np.asarray(value, dtype=np.float64).reshape(-1)
    if v.size == 1:
        v = np.repeat(v, 2)
    if v.size != 2 or not np.isfinite(v).all():
        raise ArgumentError(f"{what} must be a finite number or a pair; got {value!r}")
    return float(v[0]), float(v[1])


def place_detail(
    detail, shape, *, tile=1.0, offset=(0.0, 0.0), rotation: float = 0.0, chain=None
) -> np.ndarray:
    """Tile a detail normal map over an output of ``shape`` (see the module notes).

    Parameters
    ----------
    detail : (h, w, 3) float array
        Unit normals of one tile of the detail (OpenGL tangent frame).
    shape : (H, W)
        Output size in texels (the macro map's).
    tile : float or (float, float)
        Repetitions of the detail across the output, along u and v. Must be non-zero;
        a negative value mirrors the detail (and its normals) along that axis. Unequal
        counts stretch the pattern but keep its slopes as authored.
    offset : (float, float)
        Shift of the pattern, in tiles (1 = a whole tile).
    rotation : float
        Counter-clockwise rotation of the pattern in degrees; the normals turn with it.
    chain : list of arrays, optional
        A precomputed :func:`mip_chain` of ``detail`` (when placing it several times).

    Returns
    -------
    (H, W, 3) float32 unit normals.
    """
    d = np.asarray(detail)
    if d.ndim != 3 or d.shape[2] != 3:
        raise ArgumentError(f"a detail normal map must be (h, w, 3); got shape {d.shape}")
    height, width = (int(s) for s in shape)
    if height < 1 or width < 1:
        raise ArgumentError(f"invalid output shape {shape}")
    tu, tv = as_pair(tile, "tile")
    ou, ov = as_pair(offset, "offset")
    if tu == 0 or tv == 0:
        raise ArgumentError(f"tile must be non-zero; got {tile!r}")
    if not math.isfinite(rotation):
        raise ArgumentError(f"rotation must be finite; got {rotation!r}")
    chain = mip_chain(d) if chain is None else chain
    h0, w0 = chain[0].shape[:2]
    theta = math.radians(rotation)
    c, s = math.cos(theta), math.sin(theta)
    # output texel (x, y) -> (u, v) = (x / W, 1 - y / H) -> p = (tu u, tv v)
    # -> q = R(-theta) p + o -> detail texel (w0 q_u, h0 (1 - q_v)); all affine.
    to_uv = np.array([[1 / width, 0, 0], [0, -1 / height, 1], [0, 0, 1]])
    scale = np.diag([tu, tv, 1.0])
    rot = np.array([[c, s, ou], [-s, c, ov], [0, 0, 1]])
    to_texel = np.array([[w0, 0, 0], [0, -h0, h0], [0, 0, 1]])
    affine = to_texel @ rot @ scale @ to_uv
    footprint = max(abs(tu) * w0 / width, abs(tv) * h0 / height)
    lo, hi, t = _level_pair(chain, math.log2(footprint) if footprint > 1 else 0.0)
    out = np.empty((height, width, 3), np.float32)
    # the gradient of h(R(-theta) diag(tu, tv) p) is diag(tu, tv) R(theta) grad h: rotated,
    # then mirrored where a tile count is negative (the slopes' scale is left as authored).
    signs = math.copysign(1, tu), math.copysign(1, tv)
    _place(chain[lo], chain[hi], t, float(w0), float(h0), affine, c, s, *signs, out)
    return out


def mask_weights(mask, shape, *, ids=None) -> np.ndarray:
    """Per-texel weights of a detail layer from a greyscale mask or a material-ID map.

    Parameters
    ----------
    mask : (h, w) or (h, w, C) float array
        As read by :func:`bakeshop.io.read_image` (8/16-bit values scaled to [0, 1]).
    shape : (H, W)
        The output's size; a mask of another size is resampled to it over the same UV square
        (bilinear for greyscale, nearest texel for IDs, which must not be blended).
    ids : sequence, optional
        Material IDs where the layer applies. Each is a grey level 0-255 (an int) or an
        (r, g, b) colour of 0-255 integers. Without ``ids`` the mask's first channel is the
        weight, clipped to [0, 1].

    Returns
    -------
    (H, W) float32 weights in [0, 1].
    """
    m = np.asarray(mask, dtype=np.float32)
    if m.ndim == 2:
        m = m[:, :, None]
    if m.ndim != 3 or m.shape[0] < 1 or m.shape[1] < 1:
        raise ArgumentError(f"a mask must be (h, w) or (h, w, C); got shape {np.shape(mask)}")
    height, width = (int(s) for s in shape)
    if m.shape[:2] != (height, width):
        ys, xs = np.meshgrid(
            (np.arange(height) + 0.5) * m.shape[0] / height,
            (np.arange(width) + 0.5) * m.shape[1] / width,
            indexing="ij",
        )
        if ids is not None:
            m = m[ys.astype(np.intp), xs.astype(np.intp)]
        else:
            m = sample_wrapped([np.ascontiguousarray(m)], xs, ys, wrap=False)
            m = m.reshape(height, width, -1)
    if ids is None:
        return np.clip(np.nan_to_num(m[:, :, 0]), 0, 1).astype(np.float32)
    codes = np.rint(np.nan_to_num(m) * 255)
    weights = np.zeros((height, width), bool)
    for ident in ids:
        key = np.atleast_1d(np.asarray(ident, dtype=np.float64))
        if key.size == 1:
            hit = (codes[:, :, : min(3, codes.shape[2])] == key[0]).all(axis=2)
        elif key.size == 3 and codes.shape[2] >= 3:
            hit = (codes[:, :, :3] == key).all(axis=2)
        else:
            raise ArgumentError(
                f"material ID {ident!r} must be a grey level or an (r, g, b) colour of an RGB mask"
            )
        weights |= hit
    return weights.astype(np.float32)


@dataclass
class DetailLayer:
    """One detail layer: a tileable normal map, where and how strongly it applies.

    Attributes
    ----------
    normals : (h, w, 3) float array
        Unit normals of one tile (OpenGL tangent frame).
    tile, offset, rotation
        As for :func:`place_detail`.
    strength : float
        Height scale of the detail (see :mod:`bakeshop.normals.blend`).
    mask : (H, W) float array, optional
        Per-texel weight in [0, 1] at the output's size (see :func:`mask_weights`).
    """

    normals: np.ndarray
    tile: float | tuple[float, float] = 1.0
    offset: tuple[float, float] = (0.0, 0.0)
    rotation: float = 0.0
    strength: float = 1.0
    mask: np.ndarray | None = None


def apply_layers(macro, layers, *, method: str = DEFAULT_METHOD) -> np.ndarray:
    """Blend detail layers onto a macro normal map, one after the other.

    Each layer is placed with :func:`place_detail` and blended onto the result so far with
    ``method``, its strength times its mask as the per-texel strength; a later layer therefore
    perturbs the surface that the earlier ones made.

    Parameters
    ----------
    macro : (H, W, 3) float array
        Unit normals of the macro map.
    layers : sequence of DetailLayer
    method : str
        A blend method of :mod:`bakeshop.normals.blend`.

    Returns
    -------
    (H, W, 3) float32 unit normals.
    """
    result = normalize(np.asarray(macro, dtype=np.float32))
    if result.ndim != 3:
        raise ArgumentError(f"a macro normal map must be (H, W, 3); got shape {result.shape}")
    shape = result.shape[:2]
    for layer in layers:
        d = np.asarray(layer.normals)
        identity = (
            d.shape[:2] == shape
            and as_pair(layer.tile, "tile") == (1.0, 1.0)
            and as_pair(layer.offset, "offset") == (0.0, 0.0)
            and layer.rotation % 360 == 0
        )
        placed = (
            normalize(d)
            if identity
            else place_detail(
                d, shape, tile=layer.tile, offset=layer.offset, rotation=layer.rotation
            )
        )
        strength = np.float32(layer.strength)
        if layer.mask is not None:
            m = np.asarray(layer.mask, np.float32)
            if m.shape != shape:
                raise ArgumentError(f"a layer mask must be {shape}; got shape {m.shape}")
            strength = strength * m
        result = blend(result, placed, method=method, strength=strength)
    return result
