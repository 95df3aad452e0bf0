"""HDR values packed into 8-bit RGBA for platforms without BC6H: RGBM and RGBD.

Both store a colour and a per-texel scale in the alpha channel, so they survive an 8-bit PNG or
BC7 (non-sRGB: the alpha and the colour are data). The decode formulas, which bakeshop also
writes beside every such file:

- **RGBM** with range R (Karis, "RGBM color encoding", 2009; three.js ``RGBMLoader``, PlayCanvas):
  ``value = R * A * RGB``. Encoding: ``M = ceil(255 * max(r, g, b, 1e-6) / R) / 255`` (clamped
  to 1), ``RGB = value / (R M)``. Values above R are clipped to R.
- **RGBD** (Babylon.js, the ``.env`` environment format; ``toRGBD``/``fromRGBD`` in its
  ``helperFunctions.fx``): ``value = (RGB ^ 2.2) / A``. Encoding: ``D = clamp(floor(max(255 /
  max(r, g, b), 1)) / 255, 0, 1)``, ``RGB = (value * D) ^ (1 / 2.2)``. Values up to 255 are
  kept; brighter ones (a sun) are clipped to 255.

``RGB`` and ``A`` are the stored 8-bit values divided by 255. The functions take and return
float arrays; quantisation happens in the writer (PNG) or the encoder (BC7).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError

__all__ = [
    "RGBD_MAX",
    "encode_rgbm",
    "decode_rgbm",
    "encode_rgbd",
    "decode_rgbd",
    "DECODE_FORMULAS",
]

#: largest value RGBD stores (Babylon's rgbdMaxRange).
RGBD_MAX = 255.0
#: Babylon's gamma of the RGB part (its toGammaSpace / toLinearSpace).
RGBD_GAMMA = 2.2

#: the decode formula of each packing, as written beside the files.
DECODE_FORMULAS = {
    "rgbm": "value = {range} * A * RGB  (RGB, A = stored 8-bit value / 255; no sRGB decoding)",
    "rgbd": "value = RGB ^ 2.2 / A  (RGB, A = stored 8-bit value / 255; no sRGB decoding; "
    "Babylon.js fromRGBD)",
}


def _rgb(image: ArrayLike) -> np.ndarray:
    a = np.asarray(image, np.float32)
    if a.ndim < 1 or a.shape[-1] < 3:
        raise ArgumentError(f"RGBM and RGBD pack RGB values; got shape {a.shape}")
    if np.isnan(a[..., :3]).any():
        raise ArgumentError("the image holds NaN values")
    return np.maximum(a[..., :3], 0)


def encode_rgbm(image: ArrayLike, *, range: float = 8.0) -> np.ndarray:
    """Pack linear RGB values (``(..., C)``, C >= 3; negatives become 0) into RGBM.

    Parameters
    ----------
    image : (..., C) float array
    range : float
        The largest value stored (R); larger values are clipped.

    Returns
    -------
    (..., 4) float32
        RGB and M in [0, 1], M already on the 8-bit grid (the RGB quantisation is the
        writer's).
    """
    if not (np.isfinite(range) and range > 0):
        raise ArgumentError(f"the RGBM range must be a positive number, got {range}")
    rgb = np.minimum(_rgb(image), range)
    peak = np.maximum(np.max(rgb, axis=-1, keepdims=True), 1e-6)
    m = np.minimum(np.ceil(255 * peak / range) / 255, 1.0)
    out = np.concatenate([np.minimum(rgb / (range * m), 1.0), m], axis=-1)
    return out.astype(np.float32)


def decode_rgbm(rgbm: ArrayLike, *, range: float = 8.0) -> np.ndarray:
    """Unpack RGBM (``(..., 4)`` in [0, 1]) to linear RGB: ``range * A * RGB``."""
    a = np.asarray(rgbm, np.float32)
    return (range * a[..., 3:4] * a[..., :3]).astype(np.float32)


def encode_rgbd(image: ArrayLike) -> np.ndarray:
    """Pack linear RGB values (``(..., C)``, C >= 3; negatives become 0, values above 255 are
    clipped) into Babylon's RGBD.

    Returns
    -------
    (..., 4) float32
        RGB (gamma 1/2.2) and D in [0, 1], D on the 8-bit grid.
    """
    rgb = np.minimum(_rgb(image), RGBD_MAX)
    peak = np.maximum(np.max(rgb, axis=-1, keepdims=True), 1e-7)
    d = np.clip(np.floor(np.maximum(RGBD_MAX / peak, 1.0)) / 255, 0.0, 1.0)
    stored = np.power(np.minimum(rgb * d, 1.0), 1 / RGBD_GAMMA)
    return np.concatenate([stored, d], axis=-1).astype(np.float32)


def decode_rgbd(rgbd: ArrayLike) -> np.ndarray:
    """Unpack RGBD (``(..., 4)`` in [0, 1]) to linear RGB: ``RGB ^ 2.2 / A``."""
    a = np.asarray(rgbd, np.float32)
    d = np.maximum(a[..., 3:4], 1 / 255)
    return (np.power(a[..., :3], RGBD_GAMMA) / d).astype(np.float32)
