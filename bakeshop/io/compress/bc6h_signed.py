"""bakeshop's own encoder of signed BC6H (DXGI_FORMAT_BC6H_SF16), which ISPC does not encode.

The encoder uses the four one-subset modes of the format (Khronos Data Format spec 1.4,
table-bptcblockmodes: mode 3 with two 10-bit endpoints, and modes 7, 11 and 15 with an 11-, 12-
or 16-bit endpoint and a 9-, 8- or 4-bit difference) and keeps the one with the smallest error.
It works where the hardware interpolates: in the signed integer domain q that the decoder's last
step maps to half floats (``half = sign | (|q| * 31) >> 5``), which is close to logarithmic in
the value. For each mode it takes the endpoints at the extremes of the block's principal axis,
quantises them, picks each texel's index, refits the endpoints by least squares once, and swaps
them when the first texel's index would need the anchor's missing top bit.

The encoder is compiled (``src/io/compress/bc6h_signed.hpp``) and runs the blocks in parallel.
Two-subset modes are not searched, so blocks that hold two very different colours (an edge)
lose more than ISPC's unsigned encoder would; the measured quality is in docs/BENCHMARKS.md.
"""

from __future__ import annotations

import numpy as np

from bakeshop.io.compress import _bptc, _native

__all__ = ["encode_bc6h_signed"]

# (32, 82, 2): (endpoint field, bit) of each of a block's first 82 bits, by mode number
_LAYOUT = _bptc.bc6h_bit_table()


def encode_bc6h_signed(image: np.ndarray) -> bytes:
    """Encode an ``(H, W, 3)`` float image (sides multiples of 4, values within +-65504) as
    signed BC6H blocks, rows of blocks top to bottom."""
    h, w = image.shape[:2]
    half = np.asarray(image, np.float32).astype(np.float16).view(np.uint16).astype(np.int64)
    magnitude = half & 0x7FFF
    q = np.where(half & 0x8000, -1, 1) * np.minimum(magnitude * 32 / 31, 0x7FFF)
    blocks = q.reshape(h // 4, 4, w // 4, 4, 3).transpose(0, 2, 1, 3, 4).reshape(-1, 16, 3)
    out = np.zeros((blocks.shape[0], 16), np.uint8)
    _native.encode_bc6h_signed(np.ascontiguousarray(blocks, np.float64), out, _LAYOUT)
    return out.tobytes()
