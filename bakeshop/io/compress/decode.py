"""bakeshop's own decoders of the block-compressed formats, written from their specifications.

Sources: Khronos Data Format Specification 1.4, sections 17 (S3TC: BC1, BC3), 19 (RGTC: BC4,
BC5) and 18 (BPTC: BC6H, BC7), which define the same decoding as Microsoft's "Texture Block
Compression in Direct3D 11", "BC6H format" and "BC7 format" pages. Each decoder returns what a
GPU's sampler returns for the texel (before filtering):

- BC1, BC3: ``RGB_n = color_n / (31, 63, 31)`` and the interpolated colours ``(2 RGB0 + RGB1) / 3``
  and ``(RGB0 + 2 RGB1) / 3`` (or ``(RGB0 + RGB1) / 2`` and black, transparent in BC1, when
  ``color0 <= color1``; BC3 always uses the four-colour rule), computed in real arithmetic, and
  BC3's alpha as BC4's;
- BC4, BC5: ``red0 / 255``, ``red1 / 255`` and ``((7 - i) red0 + (i - 1) red1) / 7 / 255`` or the
  five-value rule with 0 and 1, in real arithmetic;
- BC7: 8-bit endpoints interpolated as ``((64 - w) E0 + w E1 + 32) >> 6``, divided by 255
  (bit-exact by the specification);
- BC6H: 16-bit endpoints unquantised, interpolated the same way and mapped by the final
  ``(i * 31) >> 6`` (unsigned) or ``(|i| * 31) >> 5`` with the sign (signed) to a half float
  (bit-exact by the specification); a reserved mode decodes to 0.

sRGB formats come back linear (the sRGB transfer function of the Khronos Data Format spec,
section 13.3, applied to R, G and B), as a sampler of an ``*_SRGB`` texture returns them. The
decoders are compiled loops over blocks (``src/io/compress/decode.hpp``), parallel across the
machine's cores (:mod:`bakeshop.threads`); the tables below are theirs.
"""

from __future__ import annotations

import numpy as np

from bakeshop.errors import ArgumentError, FormatError, with_article
from bakeshop.io.compress import _bptc, _native
from bakeshop.io.compress.formats import BlockFormat, block_format, level_bytes

__all__ = ["decode_image", "decode_blocks", "srgb_to_linear"]

# BC7 mode parameters (the spec's table-bptcmodes): NS, PB, RB, ISB, CB, AB, EPB, SPB, IB, IB2.
_BC7_MODES = np.array(
    [
        [3, 4, 0, 0, 4, 0, 1, 0, 3, 0],
        [2, 6, 0, 0, 6, 0, 0, 1, 3, 0],
        [3, 6, 0, 0, 5, 0, 0, 0, 2, 0],
        [2, 6, 0, 0, 7, 0, 1, 0, 2, 0],
        [1, 0, 2, 1, 5, 6, 0, 0, 2, 3],
        [1, 0, 2, 0, 7, 8, 0, 0, 2, 2],
        [1, 0, 0, 0, 7, 7, 1, 0, 4, 0],
        [2, 6, 0, 0, 5, 5, 1, 0, 2, 0],
    ],
    np.int64,
)
# Interpolation weights for 2-, 3- and 4-bit indices (the spec's BPTCInterpolation), by bits.
_WEIGHTS = np.zeros((5, 16), np.int64)
_WEIGHTS[2, :4] = [0, 21, 43, 64]
_WEIGHTS[3, :8] = [0, 9, 18, 27, 37, 46, 55, 64]
_WEIGHTS[4] = [0, 4, 9, 13, 17, 21, 26, 30, 34, 38, 43, 47, 51, 55, 60, 64]

# BC6H: mode number -> (valid, transformed, partition bits, endpoint bits, delta R, G, B).
_BC6H_MODES = np.zeros((32, 7), np.int64)
for _mode, _params in _bptc.BC6H_MODES.items():
    _BC6H_MODES[_mode] = (1, *_params)
_BC6H_BITS = _bptc.bc6h_bit_table()
_P2 = _bptc.PARTITIONS2
_P3 = _bptc.PARTITIONS3
_A2 = _bptc.ANCHOR2
_A31 = _bptc.ANCHOR3_1
_A32 = _bptc.ANCHOR3_2


def srgb_to_linear(values: np.ndarray) -> np.ndarray:
    """The sRGB EOTF (IEC 61966-2-1): ``v / 12.92`` up to 0.04045, else ``((v + 0.055) / 1.055)
    ** 2.4``; float32 in and out."""
    v = np.asarray(values, np.float32)
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4).astype(np.float32)


def decode_blocks(blocks: np.ndarray, fmt: BlockFormat) -> np.ndarray:
    """Decode ``(n, block_bytes)`` uint8 blocks to ``(n, 16, channels)`` float32 texels, row-major
    within each block, as stored (no sRGB decoding)."""
    n = blocks.shape[0]
    blocks = np.ascontiguousarray(blocks, np.uint8)
    base = fmt.name.split("-")[0]
    if base == "bc7":
        texels = np.empty((n, 16, 4), np.float32)  # the 8-bit values / 255, in float32
        _native.decode_bc7(blocks, texels, _BC7_MODES, _WEIGHTS, _P2, _P3, _A2, _A31, _A32)
        return texels
    if base == "bc6h":
        bits = np.empty((n, 16, 3), np.uint16)
        _native.decode_bc6h(blocks, bits, fmt.signed, _BC6H_MODES, _BC6H_BITS, _WEIGHTS, _P2, _A2)
        return bits.view(np.float16).astype(np.float32)
    kind = int(base[2])
    texels = np.empty((n, 16, fmt.channels), np.float32)
    _native.decode_s3tc(blocks, texels, kind)
    return texels


def decode_image(data: bytes, fmt: str | BlockFormat, width: int, height: int) -> np.ndarray:
    """Decode one block-compressed image (a face of one mip level) to float32 ``(H, W, C)``.

    Parameters
    ----------
    data : bytes-like
        ``ceil(W/4) * ceil(H/4)`` blocks, rows of blocks top to bottom.
    fmt : str or BlockFormat
        The format (:data:`bakeshop.io.compress.FORMATS`).
    width, height : int
        The image's size in texels; texels of the padding blocks beyond it are dropped.

    Returns
    -------
    (H, W, C) float32
        C is the format's channel count (BC4 1, BC5 2, BC6H 3, others 4): half floats for BC6H,
        values in [0, 1] for the others, sRGB formats decoded to linear.
    """
    if isinstance(fmt, str):
        fmt = block_format(fmt)
    if width < 1 or height < 1:
        raise ArgumentError(f"invalid image size {width}x{height}")
    expected = level_bytes(fmt, width, height)
    raw = np.frombuffer(data, np.uint8)
    if raw.size != expected:
        raise FormatError(
            f"{with_article(width)}x{height} {fmt.name} image holds {expected} bytes, "
            f"not {raw.size}"
        )
    bx, by = -(-width // 4), -(-height // 4)
    texels = decode_blocks(raw.reshape(bx * by, fmt.block_bytes), fmt)
    image = texels.reshape(by, bx, 4, 4, fmt.channels).transpose(0, 2, 1, 3, 4)
    image = image.reshape(by * 4, bx * 4, fmt.channels)[:height, :width]
    image = np.ascontiguousarray(image)
    if fmt.srgb:
        image[..., :3] = srgb_to_linear(image[..., :3])
    return image
