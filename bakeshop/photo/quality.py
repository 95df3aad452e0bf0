"""How close a merged HDR image is to a reference: the measures used to compare merges.

- :func:`multi_exposure_psnr`: Munkberg et al.'s multi-exposure PSNR (doi:10.1145/1141911.1141918):
  both images are shown at every whole stop ``c`` of a range, ``T(X) = 255 clip((2^c X)^(1/2.2),
  0, 1)``, and the PSNR of all those 8-bit pictures together is reported, so an error counts
  as much as it would be seen at some exposure.
- :func:`log2_rmse`: the RMS of ``log2(result / reference)`` over the pixels given (stops).
- :func:`relative_scale`: the one factor that best aligns a result whose scale is arbitrary (a
  recovered response fixes radiance only up to a constant) with the reference, as the median
  ratio of luminances.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError

__all__ = ["log2_rmse", "multi_exposure_psnr", "relative_scale"]


def _pair(
    result: ArrayLike, reference: ArrayLike, mask: ArrayLike | None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    a = np.asarray(result, dtype=np.float64)
    b = np.asarray(reference, dtype=np.float64)
    if a.shape != b.shape or a.ndim != 3:
        raise ArgumentError(f"images must be (H, W, C) of one shape, got {a.shape}, {b.shape}")
    m = np.ones(a.shape[:2], bool) if mask is None else np.asarray(mask, bool)
    if m.shape != a.shape[:2]:
        raise ArgumentError(f"the mask must be (H, W) = {a.shape[:2]}, not {m.shape}")
    return a, b, m


def relative_scale(result: ArrayLike, reference: ArrayLike, mask: ArrayLike | None = None) -> float:
    """The factor ``k`` such that ``result / k`` best matches ``reference``: the median of the
    ratio of their channel means over positive pixels in ``mask``."""
    a, b, m = _pair(result, reference, mask)
    ya, yb = a.mean(axis=-1), b.mean(axis=-1)
    ok = m & (ya > 0) & (yb > 0) & np.isfinite(ya)
    if not ok.any():
        raise ArgumentError("no pixel where both images are positive")
    return float(np.median(ya[ok] / yb[ok]))


def log2_rmse(result: ArrayLike, reference: ArrayLike, mask: ArrayLike | None = None) -> float:
    """RMS of ``log2(result / reference)`` over all channels of the pixels in ``mask`` where
    both are positive (stops)."""
    a, b, m = _pair(result, reference, mask)
    ok = m[..., None] & (a > 0) & (b > 0)
    if not ok.any():
        raise ArgumentError("no pixel where both images are positive")
    d = np.log2(a[ok] / b[ok])
    return float(np.sqrt(np.mean(d * d)))


def multi_exposure_psnr(
    result: ArrayLike,
    reference: ArrayLike,
    *,
    stops: tuple[int, int] | None = None,
    mask: ArrayLike | None = None,
) -> float:
    """Multi-exposure PSNR in dB.

    Parameters
    ----------
    result, reference : (H, W, C) array
        Linear radiance of the same scale (align first with :func:`relative_scale` when the
        result's scale is arbitrary).
    stops : (int, int), optional
        The range of exposures ``c`` (inclusive). Default: from the stop that shows the
        reference's brightest 0.1 % at mid-grey to the one that shows its darkest 0.1 % there.
    mask : (H, W) bool, optional
        Pixels compared (default all).
    """
    a, b, m = _pair(result, reference, mask)
    a, b = a[m], b[m]
    if stops is None:
        lum = b.mean(axis=-1)
        lum = lum[lum > 0]
        if lum.size == 0:
            raise ArgumentError("the reference has no positive pixel")
        hi, lo = np.quantile(lum, 0.999), np.quantile(lum, 0.001)
        stops = (int(np.floor(np.log2(0.18 / hi))), int(np.ceil(np.log2(0.18 / lo))))
    c0, c1 = stops
    if c1 < c0:
        raise ArgumentError(f"empty stop range {stops}")
    total = 0.0
    for c in range(c0, c1 + 1):
        s = 2.0**c
        ta = 255 * np.clip(np.maximum(s * a, 0) ** (1 / 2.2), 0, 1)
        tb = 255 * np.clip(np.maximum(s * b, 0) ** (1 / 2.2), 0, 1)
        total += float(np.mean((ta - tb) ** 2))
    mse = total / (c1 - c0 + 1)
    return float("inf") if mse == 0 else float(10 * np.log10(255.0**2 / mse))
