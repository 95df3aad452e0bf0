"""How much a compressed texture lost: the numbers printed by the commands and kept in sidecars.

- Multi-exposure PSNR (Munkberg, Clarberg, Hasselgren and Akenine-Möller, "High dynamic range
  texture compression for graphics hardware", ACM TOG 25(3), 2006, doi:10.1145/1141911.1141987):
  each image is exposed at 2^c for integer stops c = -4..4, tone-mapped to 8 bits with
  ``T(X) = clamp(round(255 (2^c X)^(1/2.2)), 0, 255)``, and

  ``mPSNR = 10 log10(3 * 255^2 / MSE)``, ``MSE = mean over exposures and texels of
  (dR^2 + dG^2 + dB^2)``

  (negative values count as 0, as a display shows them). Higher is better; the issue's floor
  for BC6H "fast" on real probes is 45 dB.
- log2 RMSE: ``sqrt(mean((log2 max(X, f) - log2 max(X', f))^2))`` over all channels, with the
  floor f = 2^-14 (the smallest normal half float; darker values are not told apart), in stops.
- PSNR of 8-bit data: ``10 log10(1 / MSE)`` of values in [0, 1].
- Normal maps: the angle between the reference unit normal and the decoded one, whose z is
  rebuilt from x and y as the shader does for BC5 (``z = sqrt(max(0, 1 - x^2 - y^2))``), in
  degrees: mean, 99th percentile and maximum.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError

__all__ = [
    "EXPOSURES",
    "mpsnr",
    "log2_rmse",
    "psnr",
    "rebuild_z",
    "angular_error",
]

#: exposure stops c of the multi-exposure PSNR (Munkberg et al. 2006): 2^-4 .. 2^4.
EXPOSURES = tuple(range(-4, 5))
#: log2 RMSE floor: the smallest normal half float.
LOG_FLOOR = 2.0**-14


def _pair(
    reference: ArrayLike, decoded: ArrayLike, channels: int = 3
) -> tuple[np.ndarray, np.ndarray]:
    a = np.asarray(reference, np.float64)
    b = np.asarray(decoded, np.float64)
    if a.shape[:-1] != b.shape[:-1] or min(a.shape[-1], b.shape[-1]) < channels:
        raise ArgumentError(
            f"cannot compare shapes {a.shape} and {b.shape} ({channels} channels needed)"
        )
    return a[..., :channels], b[..., :channels]


def _db(mse: float, peak_squared: float) -> float:
    return math.inf if mse == 0 else 10 * math.log10(peak_squared / mse)


def mpsnr(
    reference: ArrayLike,
    decoded: ArrayLike,
    *,
    exposures: Sequence[int] = EXPOSURES,
    gamma: float = 2.2,
) -> float:
    """Multi-exposure PSNR in dB of RGB values (any leading shape, last axis >= 3 channels).

    Parameters
    ----------
    reference, decoded : (..., C) arrays of linear values
    exposures : sequence of int
        Stops c; the exposures are 2^c.
    gamma : float
        Display gamma of the tone curve.

    Returns
    -------
    float
        ``inf`` when the tone-mapped images are identical.
    """
    a, b = _pair(reference, decoded)
    # (2^c X)^(1/g) = 2^(c/g) X^(1/g): one power per image instead of one per exposure
    pa = np.power(np.maximum(a, 0), 1 / gamma)
    pb = np.power(np.maximum(b, 0), 1 / gamma)
    total = 0.0
    for c in exposures:
        scale = 255 * 2.0 ** (c / gamma)
        ta = np.clip(np.rint(pa * scale), 0, 255)
        tb = np.clip(np.rint(pb * scale), 0, 255)
        total += float(np.mean(np.sum((ta - tb) ** 2, axis=-1)))
    return _db(total / len(exposures), 3 * 255.0**2)


def log2_rmse(reference: ArrayLike, decoded: ArrayLike, *, floor: float = LOG_FLOOR) -> float:
    """RMS difference of log2 values in stops, values below ``floor`` raised to it."""
    a, b = _pair(reference, decoded)
    d = np.log2(np.maximum(a, floor)) - np.log2(np.maximum(b, floor))
    return float(np.sqrt(np.mean(d * d)))


def psnr(reference: ArrayLike, decoded: ArrayLike, *, channels: int | None = None) -> float:
    """PSNR in dB of values in [0, 1] (peak 1), over the first ``channels`` (default all)."""
    a = np.asarray(reference, np.float64)
    n = a.shape[-1] if channels is None else channels
    a, b = _pair(reference, decoded, n)
    return _db(float(np.mean((a - b) ** 2)), 1.0)


def rebuild_z(xy: ArrayLike) -> np.ndarray:
    """Unit normals from their x and y (the last axis, signed components in [-1, 1]):
    ``z = sqrt(max(0, 1 - x^2 - y^2))``, then normalised, as a shader rebuilds BC5 normals."""
    xy = np.asarray(xy, np.float64)[..., :2]
    z = np.sqrt(np.maximum(0.0, 1.0 - np.sum(xy * xy, axis=-1, keepdims=True)))
    n = np.concatenate([xy, z], axis=-1)
    return n / np.linalg.norm(n, axis=-1, keepdims=True)


def angular_error(reference: ArrayLike, decoded: ArrayLike) -> dict:
    """Angles between unit normals (the last axis: x, y, z), in degrees.

    Returns
    -------
    dict
        ``mean``, ``p99`` (99th percentile) and ``max``.
    """
    a, b = _pair(reference, decoded)
    a = a / np.linalg.norm(a, axis=-1, keepdims=True)
    b = b / np.linalg.norm(b, axis=-1, keepdims=True)
    cos = np.clip(np.sum(a * b, axis=-1), -1.0, 1.0)
    angle = np.degrees(np.arccos(cos)).ravel()
    return {
        "mean": float(angle.mean()),
        "p99": float(np.percentile(angle, 99)),
        "max": float(angle.max()),
    }
