"""Unsigned integer samples <-> float32 values in [0, 1], shared by the LDR codecs (TGA, PNG, JPEG).

Reading scales a stored sample v of n bits to v / (2^n - 1), correctly rounded in float32, so
255 -> 1.0 and 128 -> 0.50196...; no transfer function is applied. Writing inverts it exactly:
every value a reader returned goes back to the same integer.
"""

from __future__ import annotations

import os

import numpy as np

from bakeshop.errors import ArgumentError
from bakeshop.io import _native

_UNSIGNED = {8: np.uint8, 16: np.uint16}


def unsigned_to_float(values: np.ndarray, bits: int) -> np.ndarray:
    """Stored unsigned samples of ``bits`` bits -> float32 ``values / (2**bits - 1)``.

    The float32 division is correctly rounded, so the result is the float32 nearest the exact
    quotient (the same as OpenCV's or Pillow's ``v / 255`` computed in float64 and rounded).
    """
    return np.divide(values, np.float32((1 << bits) - 1), dtype=np.float32)


def float_to_unsigned(
    image: np.ndarray, bits: int, path: str | os.PathLike | None = None
) -> np.ndarray:
    """Quantise an image to ``bits``-bit unsigned samples (8 -> uint8, 16 -> uint16).

    Float input is read as values in [0, 1]: NaN becomes 0, values are clipped to [0, 1]
    (so -Inf -> 0 and +Inf -> the maximum), then ``round(v * (2**bits - 1))`` to the nearest
    integer (ties to even). Unsigned input of the target depth is written as it is; a uint8
    array written at 16 bits is scaled by 257 (exact: 255 -> 65535). Any other dtype raises
    :class:`ArgumentError`.
    """
    target = _UNSIGNED[bits]
    a = np.asarray(image)
    if a.dtype == target:
        return a
    if a.dtype == np.uint8 and bits == 16:
        return a.astype(np.uint16) * np.uint16(257)
    if a.dtype.kind != "f":
        raise ArgumentError(
            f"cannot write {a.dtype} samples at {bits} bits: pass floats in [0, 1] "
            f"or {np.dtype(target).name} values",
            path,
        )
    out = np.empty(a.shape, target)
    _quantize(a.astype(np.float32, copy=False).reshape(-1), (1 << bits) - 1, out.reshape(-1))
    return out


def _quantize(values: np.ndarray, top: int, out: np.ndarray) -> None:
    """Out = rint(clip(v, 0, 1) * top), NaN -> 0, in one parallel pass (``src/io/quantize.hpp``;
    ``out`` uint8 or uint16)."""
    _native.quantize(values, top, out)
