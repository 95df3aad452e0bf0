"""bakeshop's own encoder of signed BC6H (DXGI_FORMAT_BC6H_SF16), which ISPC does not encode.

The encoder uses the four one-subset modes of the format (Khronos Data Format spec 1.4,
table-bptcblockmodes: mode 3 with two 10-bit endpoints, and modes 7, 11 and 15 with an 11-, 12-
or 16-bit endpoint and a 9-, 8- or 4-bit difference) and keeps the one with the smallest error.
It works where the hardware interpolates: in the signed integer domain q that the decoder's last
step maps to half floats (``half = sign | (|q| * 31) >> 5``), which is close to logarithmic in
the value. For each mode it takes the endpoints at the extremes of the block's principal axis,
quantises them, picks each texel's index, refits the endpoints by least squares once, and swaps
them when the first texel's index would need the anchor's missing top bit.

Two-subset modes are not searched, so blocks that hold two very different colours (an edge)
lose more than ISPC's unsigned encoder would; the measured quality is in docs/BENCHMARKS.md.
"""

from __future__ import annotations

import numba
import numpy as np

from bakeshop.io.compress import _bptc

__all__ = ["encode_bc6h_signed"]

_MODES = np.array([3, 7, 11, 15], np.int64)
_EPB = np.array([10, 11, 12, 16], np.int64)
_DELTA = np.array([10, 9, 8, 4], np.int64)  # mode 3 is untransformed: E1 has 10 bits of its own
_LAYOUT = _bptc.bc6h_bit_table()
_W4 = np.array([0, 4, 9, 13, 17, 21, 26, 30, 34, 38, 43, 47, 51, 55, 60, 64], np.int64)


@numba.njit(cache=True, inline="always")
def _unquantize(x: int, bits: int) -> int:  # pragma: no cover - compiled
    """The spec's signed unquantisation of an endpoint of ``bits`` bits."""
    if bits >= 16:
        return x
    negative = x < 0
    if negative:
        x = -x
    if x == 0:
        unq = 0
    elif x >= (1 << (bits - 1)) - 1:
        unq = 0x7FFF
    else:
        unq = ((x << 15) + 0x4000) >> (bits - 1)
    return -unq if negative else unq


@numba.njit(cache=True, inline="always")
def _quantize(q: float, bits: int) -> int:  # pragma: no cover - compiled
    """The endpoint of ``bits`` bits whose unquantised value is nearest ``q``."""
    top = (1 << (bits - 1)) - 1
    guess = int(np.round(q * (1 << (bits - 1)) / 32768.0))
    best, best_error = 0, 1e30
    for x in range(guess - 1, guess + 2):
        x = min(max(x, -top), top)
        error = abs(_unquantize(x, bits) - q)
        if error < best_error:
            best, best_error = x, error
    return best


@numba.njit(cache=True, inline="always")
def _finish(v: int) -> int:  # pragma: no cover - compiled
    """The interpolated integer -> the signed q domain value the half float represents."""
    if v < 0:
        return -(((-v) * 31) >> 5)
    return (v * 31) >> 5


@numba.njit(cache=True)
def _fit(
    q: np.ndarray, mode: int, ends: np.ndarray, quantized: np.ndarray, indices: np.ndarray
) -> float:  # pragma: no cover - compiled
    """Quantise the endpoints ``ends`` (2, 3) for mode slot ``mode``, choose indices; returns the
    squared error in the q domain (the endpoints and indices are written in place)."""
    epb, delta = _EPB[mode], _DELTA[mode]
    for c in range(3):
        a = _quantize(ends[0, c], epb)
        b = _quantize(ends[1, c], epb)
        if mode > 0:  # transformed: B is stored as a difference of ``delta`` bits
            low, high = -(1 << (delta - 1)), (1 << (delta - 1)) - 1
            b = a + min(max(b - a, low), high)
        quantized[0, c], quantized[1, c] = a, b
    unq = np.zeros((2, 3), np.int64)
    for e in range(2):
        for c in range(3):
            unq[e, c] = _unquantize(quantized[e, c], epb)
    palette = np.zeros((16, 3), np.int64)
    for i in range(16):
        w = _W4[i]
        for c in range(3):
            palette[i, c] = _finish(((64 - w) * unq[0, c] + w * unq[1, c] + 32) >> 6)
    total = 0.0
    for t in range(16):
        best, best_error = 0, 1e30
        for i in range(16):
            error = 0.0
            for c in range(3):
                d = palette[i, c] - q[t, c] * 31.0 / 32.0
                error += d * d
            if error < best_error:
                best, best_error = i, error
        indices[t] = best
        total += best_error
    return total


@numba.njit(cache=True)
def _encode_block(q: np.ndarray, out: np.ndarray, layout: np.ndarray) -> None:  # pragma: no cover
    """Encode one block of 16 texels in the q domain (16, 3) into 16 bytes."""
    mean = np.zeros(3)
    for t in range(16):
        mean += q[t]
    mean /= 16
    cov = np.zeros((3, 3))
    for t in range(16):
        d = q[t] - mean
        cov += np.outer(d, d)
    axis = np.ones(3) / np.sqrt(3.0)
    for _ in range(8):
        axis = cov @ axis
        n = np.sqrt(np.sum(axis * axis))
        if n == 0:
            axis = np.ones(3) / np.sqrt(3.0)
            break
        axis /= n
    lo, hi = 1e30, -1e30
    for t in range(16):
        p = np.sum((q[t] - mean) * axis)
        lo, hi = min(lo, p), max(hi, p)
    best_error = 1e300
    best_mode = 0
    best_q = np.zeros((2, 3), np.int64)
    best_indices = np.zeros(16, np.int64)
    quantized = np.zeros((2, 3), np.int64)
    indices = np.zeros(16, np.int64)
    ends = np.zeros((2, 3))
    for mode in range(4):
        for c in range(3):
            ends[0, c] = mean[c] + lo * axis[c]
            ends[1, c] = mean[c] + hi * axis[c]
        for attempt in range(2):
            error = _fit(q, mode, ends, quantized, indices)
            if error < best_error:
                best_error, best_mode = error, mode
                best_q[:] = quantized
                best_indices[:] = indices
            if attempt == 1:
                break
            # least-squares refit of the endpoints to the chosen weights
            a = b = d = 0.0
            rhs0 = np.zeros(3)
            rhs1 = np.zeros(3)
            for t in range(16):
                w = _W4[indices[t]] / 64.0
                a += (1 - w) * (1 - w)
                b += (1 - w) * w
                d += w * w
                rhs0 += (1 - w) * q[t]
                rhs1 += w * q[t]
            det = a * d - b * b
            if abs(det) < 1e-9:
                break
            for c in range(3):
                ends[0, c] = min(max((d * rhs0[c] - b * rhs1[c]) / det, -32767.0), 32767.0)
                ends[1, c] = min(max((a * rhs1[c] - b * rhs0[c]) / det, -32767.0), 32767.0)
    # the anchor (texel 0) has three index bits: its index must be below 8
    if best_indices[0] >= 8:
        swapped = np.zeros((2, 3))
        for c in range(3):
            swapped[0, c] = _unquantize(best_q[1, c], _EPB[best_mode])
            swapped[1, c] = _unquantize(best_q[0, c], _EPB[best_mode])
        _fit(q, best_mode, swapped, quantized, indices)
        if indices[0] >= 8:  # a clamped difference: flip the indices of the same endpoints
            for t in range(16):
                indices[t] = 15 - best_indices[t]
            for c in range(3):
                quantized[0, c], quantized[1, c] = best_q[1, c], best_q[0, c]
        best_q[:] = quantized
        best_indices[:] = indices
    fields = np.zeros(13, np.int64)
    for c in range(3):
        fields[c] = best_q[0, c]
        fields[3 + c] = best_q[1, c] - best_q[0, c] if best_mode > 0 else best_q[1, c]
    mode_number = _MODES[best_mode]
    bits = np.zeros(128, np.uint8)
    for i in range(5):
        bits[i] = (mode_number >> i) & 1
    for i in range(82):
        f = layout[mode_number, i, 0]
        if f >= 0:
            bits[i] = (fields[f] >> layout[mode_number, i, 1]) & 1
    position = 65
    for t in range(16):
        n = 3 if t == 0 else 4
        for k in range(n):
            bits[position + k] = (best_indices[t] >> k) & 1
        position += n
    for byte in range(16):
        v = 0
        for k in range(8):
            v |= bits[8 * byte + k] << k
        out[byte] = v


@numba.njit(cache=True, parallel=True)
def _encode(
    q_blocks: np.ndarray, out: np.ndarray, layout: np.ndarray
) -> None:  # pragma: no cover - compiled

    for b in numba.prange(q_blocks.shape[0]):
        _encode_block(q_blocks[b], out[b], layout)


def encode_bc6h_signed(image: np.ndarray) -> bytes:
    """Encode an ``(H, W, 3)`` float image (sides multiples of 4, values within +-65504) as
    signed BC6H blocks, rows of blocks top to bottom."""
    h, w = image.shape[:2]
    half = np.asarray(image, np.float32).astype(np.float16).view(np.uint16).astype(np.int64)
    magnitude = half & 0x7FFF
    q = np.where(half & 0x8000, -1, 1) * np.minimum(magnitude * 32 / 31, 0x7FFF)
    blocks = q.reshape(h // 4, 4, w // 4, 4, 3).transpose(0, 2, 1, 3, 4).reshape(-1, 16, 3)
    out = np.zeros((blocks.shape[0], 16), np.uint8)
    _encode(np.ascontiguousarray(blocks, np.float64), out, _LAYOUT)
    return out.tobytes()
