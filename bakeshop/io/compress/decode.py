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
decoders are numba loops over blocks, parallel across the machine's cores.
"""

from __future__ import annotations

import numba
import numpy as np

from bakeshop.errors import ArgumentError, FormatError, with_article
from bakeshop.io.compress import _bptc
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
_P2 = _bptc.PARTITIONS2.astype(np.int64)
_P3 = _bptc.PARTITIONS3.astype(np.int64)
_A2 = _bptc.ANCHOR2.astype(np.int64)
_A31 = _bptc.ANCHOR3_1.astype(np.int64)
_A32 = _bptc.ANCHOR3_2.astype(np.int64)


@numba.njit(cache=True, inline="always")
def _bits(
    lo: np.uint64, hi: np.uint64, position: int, count: int
) -> np.int64:  # pragma: no cover - compiled
    """``count`` bits of a 128-bit little-endian block (two uint64 halves) from ``position``."""
    mask = (np.uint64(1) << np.uint64(count)) - np.uint64(1)
    if position >= 64:
        return np.int64((hi >> np.uint64(position - 64)) & mask)
    value = lo >> np.uint64(position)
    if position + count > 64:
        value |= hi << np.uint64(64 - position)
    return np.int64(value & mask)


@numba.njit(cache=True, inline="always")
def _halves(blocks: np.ndarray, b: int) -> tuple[np.uint64, np.uint64]:  # pragma: no cover
    lo = np.uint64(0)
    hi = np.uint64(0)
    for k in range(8):
        lo |= np.uint64(blocks[b, k]) << np.uint64(8 * k)
        hi |= np.uint64(blocks[b, 8 + k]) << np.uint64(8 * k)
    return lo, hi


@numba.njit(cache=True, parallel=True)
def _decode_bc7(
    blocks: np.ndarray,
    out: np.ndarray,
    modes: np.ndarray,
    weights: np.ndarray,
    p2: np.ndarray,
    p3: np.ndarray,
    a2: np.ndarray,
    a31: np.ndarray,
    a32: np.ndarray,
) -> None:  # pragma: no cover - compiled
    """BC7 blocks (n, 16) uint8 -> RGBA texels (n, 16, 4) uint8."""
    for b in numba.prange(blocks.shape[0]):
        lo, hi = _halves(blocks, b)
        first = blocks[b, 0]
        if first == 0:  # reserved: every channel 0
            out[b] = 0
            continue
        mode = 0
        while not (first >> mode) & 1:
            mode += 1
        ns, pb, rb, isb, cb, ab, epb, spb, ib, ib2 = modes[mode]
        position = mode + 1
        part = _bits(lo, hi, position, pb)
        position += pb
        rotation = _bits(lo, hi, position, rb)
        position += rb
        selector = _bits(lo, hi, position, isb)
        position += isb
        endpoints = np.zeros((6, 4), np.int64)
        for c in range(3):
            for e in range(2 * ns):
                endpoints[e, c] = _bits(lo, hi, position, cb)
                position += cb
        if ab:
            for e in range(2 * ns):
                endpoints[e, 3] = _bits(lo, hi, position, ab)
                position += ab
        color_bits, alpha_bits = cb, ab
        if epb or spb:
            for e in range(2 * ns):
                if epb:
                    p = _bits(lo, hi, position + e, 1)
                else:
                    p = _bits(lo, hi, position + e // 2, 1)
                for c in range(4):
                    endpoints[e, c] = endpoints[e, c] << 1 | p
            position += 2 * ns if epb else ns
            color_bits += 1
            if ab:
                alpha_bits += 1
        for e in range(2 * ns):
            for c in range(4):
                n = color_bits if c < 3 else alpha_bits
                if n == 0:
                    endpoints[e, c] = 255
                else:
                    v = endpoints[e, c] << (8 - n)
                    endpoints[e, c] = v | (v >> n)
        primary = np.zeros(16, np.int64)
        secondary = np.zeros(16, np.int64)
        subset = np.zeros(16, np.int64)
        for i in range(16):
            if ns == 2:
                subset[i] = p2[part, i]
            elif ns == 3:
                subset[i] = p3[part, i]
        for i in range(16):
            anchor = i == 0
            if ns == 2:
                anchor = anchor or i == a2[part]
            elif ns == 3:
                anchor = anchor or i == a31[part] or i == a32[part]
            n = ib - 1 if anchor else ib
            primary[i] = _bits(lo, hi, position, n)
            position += n
        if ib2:
            for i in range(16):
                n = ib2 - 1 if i == 0 else ib2
                secondary[i] = _bits(lo, hi, position, n)
                position += n
        for i in range(16):
            e0 = 2 * subset[i]
            if ib2 and selector:
                wc = weights[ib2, secondary[i]]
                wa = weights[ib, primary[i]]
            elif ib2:
                wc = weights[ib, primary[i]]
                wa = weights[ib2, secondary[i]]
            else:
                wc = weights[ib, primary[i]]
                wa = wc
            for c in range(4):
                w = wc if c < 3 else wa
                v = ((64 - w) * endpoints[e0, c] + w * endpoints[e0 + 1, c] + 32) >> 6
                out[b, i, c] = v
            if rotation:
                c = rotation - 1
                swap = out[b, i, c]
                out[b, i, c] = out[b, i, 3]
                out[b, i, 3] = swap


@numba.njit(cache=True, inline="always")
def _extend(value: int, bits: int) -> int:  # pragma: no cover - compiled
    """Sign-extend the low ``bits`` bits of ``value``."""
    value &= (1 << bits) - 1
    return value - (1 << bits) if value >> (bits - 1) & 1 else value


@numba.njit(cache=True, inline="always")
def _unquantize(x: int, bits: int, signed: bool) -> int:  # pragma: no cover - compiled
    if not signed:
        if bits >= 15 or x == 0:
            return x
        if x == (1 << bits) - 1:
            return 0xFFFF
        return ((x << 15) + 0x4000) >> (bits - 1)
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


@numba.njit(cache=True, parallel=True)
def _decode_bc6h(
    blocks: np.ndarray,
    out: np.ndarray,
    signed: bool,
    modes: np.ndarray,
    layout: np.ndarray,
    weights: np.ndarray,
    p2: np.ndarray,
    a2: np.ndarray,
) -> None:  # pragma: no cover - compiled
    """BC6H blocks (n, 16) uint8 -> half-float bit patterns (n, 16, 3) uint16."""
    for b in numba.prange(blocks.shape[0]):
        lo, hi = _halves(blocks, b)
        mode = np.int64(lo & np.uint64(3))
        if mode >= 2:
            mode = np.int64(lo & np.uint64(31))
        valid, transformed, pb, epb, d0, d1, d2 = modes[mode]
        if not valid:
            out[b] = 0
            continue
        fields = np.zeros(13, np.int64)
        for i in range(82):
            f = layout[mode, i, 0]
            if f >= 0:
                fields[f] |= _bits(lo, hi, i, 1) << layout[mode, i, 1]
        ns = 2 if pb else 1
        part = fields[12]
        delta = (d0, d1, d2)
        endpoints = np.zeros((4, 3), np.int64)
        for c in range(3):
            base = fields[c]
            if signed:
                base = _extend(base, epb)
            endpoints[0, c] = base
            for e in range(1, 2 * ns):
                v = fields[3 * e + c]
                if signed or transformed:
                    v = _extend(v, delta[c])
                if transformed:
                    v = (base + v) & ((1 << epb) - 1)
                    if signed:
                        v = _extend(v, epb)
                endpoints[e, c] = v
        for e in range(2 * ns):
            for c in range(3):
                endpoints[e, c] = _unquantize(endpoints[e, c], epb, signed)
        index_bits = 4 if ns == 1 else 3
        position = 65 if ns == 1 else 82
        for i in range(16):
            anchor = i == 0 or (ns == 2 and i == a2[part])
            n = index_bits - 1 if anchor else index_bits
            index = _bits(lo, hi, position, n)
            position += n
            s = p2[part, i] if ns == 2 else 0
            w = weights[index_bits, index]
            for c in range(3):
                v = ((64 - w) * endpoints[2 * s, c] + w * endpoints[2 * s + 1, c] + 32) >> 6
                if not signed:
                    out[b, i, c] = (v * 31) >> 6
                elif v < 0:
                    out[b, i, c] = (((-v) * 31) >> 5) | 0x8000
                else:
                    out[b, i, c] = (v * 31) >> 5


@numba.njit(cache=True, inline="always")
def _bc1_colors(
    c0: np.int64, c1: np.int64, four: bool, colors: np.ndarray
) -> None:  # pragma: no cover - compiled
    """The four RGBA colours of a BC1 colour block (real arithmetic, values in [0, 1])."""
    r0, g0, b0 = (c0 >> 11) / 31.0, ((c0 >> 5) & 63) / 63.0, (c0 & 31) / 31.0
    r1, g1, b1 = (c1 >> 11) / 31.0, ((c1 >> 5) & 63) / 63.0, (c1 & 31) / 31.0
    colors[0, 0], colors[0, 1], colors[0, 2], colors[0, 3] = r0, g0, b0, 1.0
    colors[1, 0], colors[1, 1], colors[1, 2], colors[1, 3] = r1, g1, b1, 1.0
    if four:
        colors[2, 0] = (2 * r0 + r1) / 3
        colors[2, 1] = (2 * g0 + g1) / 3
        colors[2, 2] = (2 * b0 + b1) / 3
        colors[3, 0] = (r0 + 2 * r1) / 3
        colors[3, 1] = (g0 + 2 * g1) / 3
        colors[3, 2] = (b0 + 2 * b1) / 3
        colors[2, 3] = colors[3, 3] = 1.0
    else:
        colors[2, 0] = (r0 + r1) / 2
        colors[2, 1] = (g0 + g1) / 2
        colors[2, 2] = (b0 + b1) / 2
        colors[2, 3] = 1.0
        colors[3, 0] = colors[3, 1] = colors[3, 2] = colors[3, 3] = 0.0


@numba.njit(cache=True, inline="always")
def _bc4_values(
    blocks: np.ndarray, b: int, offset: int, values: np.ndarray
) -> None:  # pragma: no cover - compiled
    """The eight values of a BC4 block (or BC3's alpha, BC5's channel) at ``offset``."""
    r0 = np.float64(blocks[b, offset])
    r1 = np.float64(blocks[b, offset + 1])
    values[0] = r0 / 255
    values[1] = r1 / 255
    if r0 > r1:
        for i in range(2, 8):
            values[i] = ((8 - i) * r0 + (i - 1) * r1) / 7 / 255
    else:
        for i in range(2, 6):
            values[i] = ((6 - i) * r0 + (i - 1) * r1) / 5 / 255
        values[6] = 0.0
        values[7] = 1.0


@numba.njit(cache=True, inline="always")
def _bc4_codes(blocks: np.ndarray, b: int, offset: int) -> np.uint64:  # pragma: no cover
    bits = np.uint64(0)
    for k in range(6):
        bits |= np.uint64(blocks[b, offset + 2 + k]) << np.uint64(8 * k)
    return bits


@numba.njit(cache=True, parallel=True)
def _decode_s3tc(blocks: np.ndarray, out: np.ndarray, kind: int) -> None:  # pragma: no cover
    """BC1 (kind 1), BC3 (3), BC4 (4) and BC5 (5) blocks -> texels (n, 16, C) float32."""
    for b in numba.prange(blocks.shape[0]):
        colors = np.zeros((4, 4))
        values = np.zeros(8)
        if kind == 1 or kind == 3:
            o = 8 if kind == 3 else 0
            c0 = np.int64(blocks[b, o]) | np.int64(blocks[b, o + 1]) << 8
            c1 = np.int64(blocks[b, o + 2]) | np.int64(blocks[b, o + 3]) << 8
            _bc1_colors(c0, c1, kind == 3 or c0 > c1, colors)
            codes = np.int64(0)
            for k in range(4):
                codes |= np.int64(blocks[b, o + 4 + k]) << (8 * k)
            for i in range(16):
                code = (codes >> (2 * i)) & 3
                for c in range(4):
                    out[b, i, c] = colors[code, c]
            if kind == 3:
                _bc4_values(blocks, b, 0, values)
                bits = _bc4_codes(blocks, b, 0)
                for i in range(16):
                    out[b, i, 3] = values[np.int64((bits >> np.uint64(3 * i)) & np.uint64(7))]
        else:
            for channel in range(kind - 3):
                _bc4_values(blocks, b, 8 * channel, values)
                bits = _bc4_codes(blocks, b, 8 * channel)
                for i in range(16):
                    code = np.int64((bits >> np.uint64(3 * i)) & np.uint64(7))
                    out[b, i, channel] = values[code]


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
        texels = np.empty((n, 16, 4), np.uint8)
        _decode_bc7(blocks, texels, _BC7_MODES, _WEIGHTS, _P2, _P3, _A2, _A31, _A32)
        return texels.astype(np.float32) / np.float32(255)
    if base == "bc6h":
        bits = np.empty((n, 16, 3), np.uint16)
        _decode_bc6h(blocks, bits, fmt.signed, _BC6H_MODES, _BC6H_BITS, _WEIGHTS, _P2, _A2)
        return bits.view(np.float16).astype(np.float32)
    kind = int(base[2])
    texels = np.empty((n, 16, fmt.channels), np.float32)
    _decode_s3tc(blocks, texels, kind)
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
