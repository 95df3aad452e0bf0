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
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError
from bakeshop.image import resize_area
from bakeshop.normals import _native
from bakeshop.normals.blend import DEFAULT_METHOD, blend
from bakeshop.normals.encoding import normalize

__all__ = [
    "MipChain",
    "mip_chain",
    "sample_wrapped",
    "place_detail",
    "filtered_relief",
    "mask_weights",
    "DetailLayer",
    "apply_layers",
]


@dataclass(frozen=True)
class MipChain:
    """The mip levels of an image packed in one array, level 0 first (what the samplers read).

    Attributes
    ----------
    texels : (T, C) float32
        The texels of every level, each level's rows one after the other.
    offsets : (L,) int64
        Index in ``texels`` of each level's first texel.
    shapes : (L, 2) int64
        (height, width) of each level.
    """

    texels: np.ndarray
    offsets: np.ndarray
    shapes: np.ndarray

    def __len__(self) -> int:
        return len(self.offsets)

    def level(self, i: int) -> np.ndarray:
        """Level ``i`` as an (h, w, C) view."""
        h, w = self.shapes[i]
        return self.texels[self.offsets[i] : self.offsets[i] + h * w].reshape(h, w, -1)


def mip_chain(image: ArrayLike) -> MipChain:
    """Mip levels of a tileable image, each half the size of the one before, down to 1 x 1.

    Parameters
    ----------
    image : (H, W, C) float array

    Returns
    -------
    MipChain
        Each level is the box (area) average of the previous one; vectors are *not*
        renormalised (a short average records that the normals under it disagree, and the
        samplers renormalise after filtering).
    """
    a = np.asarray(image, dtype=np.float32)
    if a.ndim != 3 or a.shape[0] < 1 or a.shape[1] < 1:
        raise ArgumentError(f"an image must be (H, W, C); got shape {a.shape}")
    levels = [a]
    while levels[-1].shape[0] > 1 or levels[-1].shape[1] > 1:
        h, w = levels[-1].shape[:2]
        levels.append(resize_area(levels[-1], (max(1, w // 2), max(1, h // 2))))
    sizes = [lv.shape[0] * lv.shape[1] for lv in levels]
    return MipChain(
        np.concatenate([lv.reshape(-1, a.shape[2]) for lv in levels]),
        np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64),
        np.array([lv.shape[:2] for lv in levels], np.int64),
    )


def sample_wrapped(
    chain: MipChain | ArrayLike,
    x: ArrayLike,
    y: ArrayLike,
    *,
    lod: ArrayLike = 0.0,
    wrap: bool = True,
) -> np.ndarray:
    """Trilinear samples of a mip chain at continuous level-0 texel coordinates.

    Parameters
    ----------
    chain : MipChain or (H, W, C) array
        From :func:`mip_chain`; a plain image is one level (bilinear).
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
    if not isinstance(chain, MipChain):
        a = np.asarray(chain, np.float32)
        chain = MipChain(
            a.reshape(-1, a.shape[2]), np.zeros(1, np.int64), np.array([a.shape[:2]], np.int64)
        )
    xs = np.ascontiguousarray(x, dtype=np.float64).reshape(-1)
    ys = np.ascontiguousarray(y, dtype=np.float64).reshape(-1)
    lods = np.ascontiguousarray(np.broadcast_to(np.asarray(lod, np.float64), xs.shape))
    out = np.empty((xs.size, chain.texels.shape[1]), np.float32)
    _native.sample_points(chain.texels, chain.offsets, chain.shapes, xs, ys, lods, wrap, out)
    return out


def as_pair(value: ArrayLike, what: str) -> tuple[float, float]:
    """A finite number or pair as ``(a, b)``; :class:`ArgumentError` naming ``what`` otherwise."""
    v = np.asarray(value, dtype=np.float64).reshape(-1)
    if v.size == 1:
        v = np.repeat(v, 2)
    if v.size != 2 or not np.isfinite(v).all():
        raise ArgumentError(f"{what} must be a finite number or a pair; got {value!r}")
    return float(v[0]), float(v[1])


def place_detail(
    detail: ArrayLike,
    shape: tuple[int, int],
    *,
    tile: float | tuple[float, float] = 1.0,
    offset: tuple[float, float] = (0.0, 0.0),
    rotation: float = 0.0,
    chain: MipChain | None = None,
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
    chain : MipChain, optional
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
    h0, w0 = (int(v) for v in chain.shapes[0])
    theta = math.radians(rotation)
    c, s = math.cos(theta), math.sin(theta)
    # output texel (x, y) -> (u, v) = (x / W, 1 - y / H) -> p = (tu u, tv v)
    # -> q = R(-theta) p + o -> detail texel (w0 q_u, h0 (1 - q_v)); all affine.
    to_uv = np.array([[1 / width, 0, 0], [0, -1 / height, 1], [0, 0, 1]])
    scale = np.diag([tu, tv, 1.0])
    rot = np.array([[c, s, ou], [-s, c, ov], [0, 0, 1]])
    to_texel = np.array([[w0, 0, 0], [0, -h0, h0], [0, 0, 1]])
    affine = to_texel @ rot @ scale @ to_uv
    lod = _lod((h0, w0), (height, width), tu, tv)
    out = np.empty((height, width, 3), np.float32)
    # the gradient of h(R(-theta) diag(tu, tv) p) is diag(tu, tv) R(theta) grad h: rotated,
    # then mirrored where a tile count is negative (the slopes' scale is left as authored).
    signs = math.copysign(1, tu), math.copysign(1, tv)
    _native.place(chain.texels, chain.offsets, chain.shapes, lod, affine, c, s, *signs, out)
    return out


def mask_weights(
    mask: ArrayLike,
    shape: tuple[int, int],
    *,
    ids: Sequence[int | tuple[int, ...]] | None = None,
) -> np.ndarray:
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
            m = sample_wrapped(np.ascontiguousarray(m), xs, ys, wrap=False)
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


def _lod(detail: tuple[int, int], shape: tuple[int, int], tu: float, tv: float) -> float:
    """The mip level a detail of (h, w) texels is sampled at, tiled (tu, tv) times over an
    output of ``shape`` (H, W): log2 of the detail texels under one output texel."""
    footprint = max(abs(tu) * detail[1] / shape[1], abs(tv) * detail[0] / shape[0])
    return math.log2(footprint) if footprint > 1 else 0.0


def _relief(normals: np.ndarray) -> float:
    """RMS angle in degrees of (unnormalised) normals from their mean direction, over an even
    sample of at most 2^20 texels."""
    step = max(1, math.ceil(math.sqrt(normals.shape[0] * normals.shape[1] / (1 << 20))))
    n = normalize(np.asarray(normals[::step, ::step], np.float64).reshape(-1, 3))
    mean = normalize(n.mean(axis=0))
    return float(np.degrees(np.sqrt(np.mean(np.arccos(np.clip(n @ mean, -1.0, 1.0)) ** 2))))


def filtered_relief(
    detail: ArrayLike, shape: tuple[int, int], *, tile: float | tuple[float, float] = 1.0
) -> tuple[float, float]:
    """How much of a detail's relief survives tiling: ``(authored, left)``, the RMS angle in
    degrees of its normals from their mean direction, as authored and at the mip level that
    :func:`place_detail` samples when it tiles the detail ``tile`` times over ``shape`` (the
    box filter averages away slopes finer than an output texel).
    """
    d = np.asarray(detail)
    tu, tv = as_pair(tile, "tile")
    chain = mip_chain(d)
    level = min(len(chain) - 1, round(_lod(d.shape[:2], (shape[0], shape[1]), tu, tv)))
    return _relief(d), _relief(chain.level(level))


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


def apply_layers(
    macro: ArrayLike, layers: Sequence[DetailLayer], *, method: str = DEFAULT_METHOD
) -> np.ndarray:
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
        strength: np.floating | np.ndarray = np.float32(layer.strength)
        if layer.mask is not None:
            m = np.asarray(layer.mask, np.float32)
            if m.shape != shape:
                raise ArgumentError(f"a layer mask must be {shape}; got shape {m.shape}")
            strength = strength * m
        result = blend(result, placed, method=method, strength=strength)
    return result
