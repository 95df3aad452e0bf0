"""What is in an image: per-channel statistics, non-finite counts and dynamic range."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

#: Rec. 709 / sRGB luminance weights of linear R, G, B.
LUMINANCE_WEIGHTS = (0.2126, 0.7152, 0.0722)


def luminance(image: ArrayLike) -> np.ndarray:
    """Relative luminance Y = 0.2126 R + 0.7152 G + 0.0722 B of linear Rec. 709 values.

    ``image`` is ``(..., C)``: C = 1 (or 2, grey and alpha) returns the grey channel, C = 3 or 4
    weights R, G, B (alpha ignored). Reference: ITU-R BT.709-6, item 3.3.
    """
    a = np.asarray(image)
    if a.shape[-1] < 3:
        return a[..., 0]
    return a[..., :3] @ np.asarray(LUMINANCE_WEIGHTS, dtype=a.dtype)


def describe(image: ArrayLike) -> dict:
    """Statistics of an ``(H, W, C)`` image for ``bakeshop info``.

    Returns
    -------
    dict
        ``shape``; per channel ``min``, ``max``, ``mean`` over finite values (None for a channel
        with none); ``nan`` and ``inf`` counts over all samples; ``dynamic_range_stops``:
        log2(largest / smallest positive finite luminance), None when fewer than two positive
        luminances exist.
    """
    a = np.asarray(image)
    if a.ndim == 2:
        a = a[:, :, None]
    flat = a.reshape(-1, a.shape[-1])
    finite = np.isfinite(flat)
    channels: list[dict[str, float | None]] = []
    for c in range(flat.shape[1]):
        values = flat[finite[:, c], c]
        if values.size:
            channels.append(
                {
                    "min": float(values.min()),
                    "max": float(values.max()),
                    "mean": float(values.mean(dtype=np.float64)),
                }
            )
        else:
            channels.append({"min": None, "max": None, "mean": None})
    lum = luminance(flat)
    lum = lum[np.isfinite(lum) & (lum > 0)]
    stops = float(np.log2(lum.max() / lum.min())) if lum.size >= 2 else None
    return {
        "shape": list(a.shape),
        "channels": channels,
        "nan": int(np.isnan(flat).sum()),
        "inf": int(np.isinf(flat).sum()),
        "dynamic_range_stops": stops,
    }
