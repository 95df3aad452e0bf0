"""Exposure, display encoding and tone mapping of linear HDR images.

The order of a display pipeline is: scale the scene by the exposure (:func:`exposure`), compress
the range with a tone operator, clamp to [0, 1], encode for the display (:func:`srgb_encode`),
quantise to 8 bits.

Values are linear and relative (the file's units); ``exposure`` is in photographic stops (EV):
+1 EV doubles every value.
"""

from __future__ import annotations

import math

import numpy as np

from bakeshop.errors import ArgumentError

#: IEC 61966-2-1 sRGB transfer function constants: the linear segment's end in linear light,
#: its slope, and the power segment's offset and exponent.
SRGB_LINEAR_LIMIT = 0.0031308
SRGB_SLOPE = 12.92
SRGB_OFFSET = 0.055
SRGB_GAMMA = 2.4
#: End of the linear segment in encoded values (12.92 * 0.0031308 rounded as the standard does).
SRGB_ENCODED_LIMIT = 0.04045


def _float_array(values) -> np.ndarray:
    """``values`` as a float array: float32/float64 kept, everything else becomes float32."""
    a = np.asarray(values)
    if a.dtype not in (np.float32, np.float64):
        a = a.astype(np.float32)
    return a


def exposure(image, ev: float) -> np.ndarray:
    """Scale linear values by ``2**ev`` (photographic exposure in stops).

    Parameters
    ----------
    image : (..., C) or any shape, float
        Linear values. Integer and float16 input becomes float32; float32 stays float32.
    ev : float
        Exposure in stops (EV). 0 leaves the image unchanged, +1 doubles it, -1 halves it.

    Returns
    -------
    ndarray, same shape
        ``image * 2**ev``. NaN and infinities propagate (inf stays inf, NaN stays NaN).
    """
    ev = float(ev)
    if not math.isfinite(ev):
        raise ArgumentError(f"exposure must be a finite number of stops, got {ev}")
    a = _float_array(image)
    return a * a.dtype.type(2.0**ev)


def srgb_encode(linear) -> np.ndarray:
    """Encode linear light with the sRGB transfer function (IEC 61966-2-1).

    ``V = 12.92 L`` for ``L <= 0.0031308``, else ``V = 1.055 L**(1/2.4) - 0.055``.

    Parameters
    ----------
    linear : array_like, float
        Linear values; 1 is display white. Float32 stays float32 (float64 stays float64);
        anything else becomes float32.

    Returns
    -------
    ndarray, same shape
        Encoded values. Nothing is clamped: values above 1 continue the power segment, so clamp
        (``np.clip(..., 0, 1)``) before quantising to 8 bits. Negative values are encoded as
        the odd extension of the curve, ``V(-L) = -V(L)`` (the "extended sRGB" convention of
        scRGB and CSS Color 4), which keeps :func:`srgb_decode` an exact inverse on the whole
        real line. NaN stays NaN, +-inf stays +-inf.

    References
    ----------
    IEC 61966-2-1:1999, Multimedia systems and equipment - Colour measurement and management -
    Part 2-1: Default RGB colour space - sRGB.
    """
    a = _float_array(linear)
    t = a.dtype.type
    mag = np.abs(a)
    with np.errstate(invalid="ignore"):
        power = t(1.0 + SRGB_OFFSET) * mag ** t(1.0 / SRGB_GAMMA) - t(SRGB_OFFSET)
        v = np.where(mag <= t(SRGB_LINEAR_LIMIT), t(SRGB_SLOPE) * mag, power)
    return np.copysign(v, a).astype(a.dtype, copy=False)


def srgb_decode(encoded) -> np.ndarray:
    """Decode sRGB-encoded values to linear light (inverse of :func:`srgb_encode`).

    ``L = V / 12.92`` for ``V <= 0.04045``, else ``L = ((V + 0.055) / 1.055)**2.4``.

    Parameters
    ----------
    encoded : array_like, float
        Encoded values (8-bit code values must first be divided by 255). Float32 stays
        float32 (float64 stays float64); anything else becomes float32.

    Returns
    -------
    ndarray, same shape
        Linear values. Not clamped; negative values decode as the odd extension
        ``L(-V) = -L(V)``; NaN stays NaN, +-inf stays +-inf.

    References
    ----------
    IEC 61966-2-1:1999 (see :func:`srgb_encode`).
    """
    a = _float_array(encoded)
    t = a.dtype.type
    mag = np.abs(a)
    with np.errstate(invalid="ignore"):
        power = ((mag + t(SRGB_OFFSET)) / t(1.0 + SRGB_OFFSET)) ** t(SRGB_GAMMA)
        v = np.where(mag <= t(SRGB_ENCODED_LIMIT), mag / t(SRGB_SLOPE), power)
    return np.copysign(v, a).astype(a.dtype, copy=False)
