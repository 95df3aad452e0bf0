"""Constants shared by the Radiance codec (:mod:`bakeshop.io.rgbe`, no numba) and its numba
kernels (:mod:`bakeshop.io._rgbe_kernels`), kept apart so that reading a small file needs
neither numba nor its import time."""

from __future__ import annotations

#: Scanline lengths that the new run-length form can encode (Radiance's MINELEN, MAXELEN).
_RLE_MIN, _RLE_MAX = 8, 0x7FFF

# Status codes of the decoders.
_OK, _TRUNCATED, _OVERRUN, _EMPTY_RUN, _LENGTH, _NO_PREVIOUS = range(6)

#: float32 bit patterns: +infinity (larger patterns are NaN) and the sign bit.
_INF_BITS, _SIGN_BIT = 0x7F800000, 0x80000000
#: float32's largest finite value and its bits (infinities are stored as it).
_FLOAT32_MAX, _MAX_BITS = 3.4028234663852886e38, 0x7F7FFFFF
