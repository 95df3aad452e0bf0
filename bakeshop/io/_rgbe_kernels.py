"""The numba kernels of the Radiance codec (:mod:`bakeshop.io.rgbe`): the scanline decoder for
large files (and its parts on every thread), the scanline walk of the window reader
(:mod:`bakeshop.io.stream.rgbe`) and the encoder. Imported when they are needed, so that reading
a small file (which :mod:`bakeshop.io.rgbe` decodes with numpy) does not load numba."""

from __future__ import annotations

import math

import numba
import numpy as np

from bakeshop.io._rgbe_codes import (
    _EMPTY_RUN,
    _INF_BITS,
    _LENGTH,
    _MAX_BITS,
    _NO_PREVIOUS,
    _OK,
    _OVERRUN,
    _RLE_MAX,
    _RLE_MIN,
    _TRUNCATED,
)


@numba.njit(cache=True, nogil=True)
def _decode(
    data: np.ndarray,
    pos: int,
    nscan: int,
    scanlen: int,
    out: np.ndarray,
    factors: np.ndarray,
    dry: bool,
) -> tuple[int, int, int]:
    """Decode ``nscan`` scanlines of ``scanlen`` pixels from ``data[pos:]`` into ``out[scan,
    pixel, channel]`` (float32, any strides), multiplying channel c by ``factors[c]``.

    With ``dry`` nothing is written: the pass only checks that the data holds the whole image.
    Returns (status, scanline, position after the last byte used).
    """
    n = data.size
    line = np.zeros((scanlen, 4), np.uint8)
    previous = np.zeros(4, np.uint8)
    has_previous = False
    scale = np.empty(256, np.float64)
    for e in range(256):
        scale[e] = math.ldexp(1.0, e - 136)
    for s in range(nscan):
        if (
            _RLE_MIN <= scanlen <= _RLE_MAX
            and pos + 4 <= n
            and data[pos] == 2
            and data[pos + 1] == 2
            and data[pos + 2] < 128
        ):
            if (np.int64(data[pos + 2]) << 8) + data[pos + 3] != scanlen:
                return _LENGTH, s, pos
            pos += 4
            for c in range(4):
                j = 0
                while j < scanlen:
                    if pos >= n:
                        return _TRUNCATED, s, pos
                    code = np.int64(data[pos])
                    pos += 1
                    if code > 128:
                        count = code - 128
                        if j + count > scanlen:
                            return _OVERRUN, s, pos
                        if pos >= n:
                            return _TRUNCATED, s, pos
                        value = data[pos]
                        pos += 1
                        for k in range(j, j + count):
                            line[k, c] = value
                    else:
                        count = code
                        if count == 0:
                            return _EMPTY_RUN, s, pos
                        if j + count > scanlen:
                            return _OVERRUN, s, pos
                        if pos + count > n:
                            return _TRUNCATED, s, pos
                        for k in range(count):
                            line[j + k, c] = data[pos + k]
                        pos += count
                    j += count
        else:
            j = 0
            shift = 0
            while j < scanlen:
                if pos + 4 > n:
                    return _TRUNCATED, s, pos
                if data[pos] == 1 and data[pos + 1] == 1 and data[pos + 2] == 1:
                    e = np.int64(data[pos + 3])
                    pos += 4
                    if e != 0:
                        if shift > 24 or j + (e << shift) > scanlen:
                            return _OVERRUN, s, pos
                        if j == 0 and not has_previous:
                            return _NO_PREVIOUS, s, pos
                        count = e << shift
                        for k in range(j, j + count):
                            for c in range(4):
                                line[k, c] = previous[c] if k == 0 else line[k - 1, c]
                        j += count
                    shift += 8
                else:
                    for c in range(4):
                        line[j, c] = data[pos + c]
                    pos += 4
                    j += 1
                    shift = 0
        for c in range(4):
            previous[c] = line[scanlen - 1, c]
        has_previous = True
        if not dry:
            for j in range(scanlen):
                e = line[j, 3]
                if e == 0:
                    for c in range(3):
                        out[s, j, c] = 0.0
                else:
                    f = scale[e]
                    for c in range(3):
                        out[s, j, c] = (line[j, c] + 0.5) * f * factors[c]
    return _OK, nscan, pos


@numba.njit(cache=True, nogil=True)
def scan(
    data: np.ndarray, pos: int, scanlen: int, count: int, starts: np.ndarray, first: int
) -> tuple[int, int, int]:  # pragma: no cover - compiled
    """Walk up to ``count`` scanlines of ``data[pos:]``, writing each one's start (plus
    ``first``, the offset of ``data`` in the file) into ``starts``; return (scanlines walked,
    position after the last complete one, status). Stops, status 0, at an incomplete scanline."""
    n = data.size
    done = 0
    while done < count:
        start = pos
        if (
            8 <= scanlen <= 0x7FFF
            and pos + 4 <= n
            and data[pos] == 2
            and data[pos + 1] == 2
            and data[pos + 2] < 128
        ):
            if (np.int64(data[pos + 2]) << 8) + data[pos + 3] != scanlen:
                return done, start, 1
            pos += 4
            for _c in range(4):
                j = 0
                while j < scanlen:
                    if pos >= n:
                        return done, start, 0
                    code = np.int64(data[pos])
                    pos += 1
                    if code > 128:
                        pos += 1
                        j += code - 128
                    elif code == 0:
                        return done, start, 2
                    else:
                        pos += code
                        j += code
                    if j > scanlen:
                        return done, start, 3
            if pos > n:
                return done, start, 0
        else:
            j = 0
            shift = 0
            while j < scanlen:
                if pos + 4 > n:
                    return done, start, 0
                if data[pos] == 1 and data[pos + 1] == 1 and data[pos + 2] == 1:
                    e = np.int64(data[pos + 3])
                    if e != 0:
                        if shift > 24:
                            return done, start, 3
                        j += e << shift
                    shift += 8
                else:
                    j += 1
                    shift = 0
                pos += 4
            if j > scanlen:
                return done, start, 3
        starts[done] = start + first
        done += 1
    return done, pos, 0


@numba.njit(cache=True, nogil=True, parallel=True)
def _decode_parts(data: np.ndarray, first: np.ndarray, bounds: np.ndarray, scanlen: int,
                  out: np.ndarray, factors: np.ndarray) -> bool:  # fmt: skip
    """Scanlines ``bounds[k]:bounds[k + 1]`` decoded from ``data[first[k]:]`` by
    :func:`_decode`, the parts in parallel; True when every part decodes whole."""
    ok = 0
    for k in numba.prange(first.shape[0]):
        status, _, _ = _decode(data, first[k], bounds[k + 1] - bounds[k], scanlen,
                               out[bounds[k] : bounds[k + 1]], factors, False)  # fmt: skip
        ok += status == _OK
    return ok == first.shape[0]


@numba.njit(cache=True, nogil=True, inline="always")
def _mantissa(b: int, e: int) -> int:
    """``floor(value * 2**(136 - e))`` capped at 255 for a non-negative finite float32 of bits
    ``b``: the significand (implicit 1 included) shifted right by the exponents' difference,
    exact in integers (it is the float64 product, rounded down)."""
    biased = b >> 23
    mant = (b & 0x7FFFFF) | (0x800000 if biased > 0 else 0)
    shift = min(e + 14 - max(biased, 1), 31)
    return min(mant >> shift, 255)


@numba.njit(cache=True, nogil=True)
def _rgbe_row(values: np.ndarray, bits: np.ndarray, line: np.ndarray) -> None:
    """Encode one row of linear pixels into ``line[0:4, x]`` (R, G, B mantissas and exponent).

    ``values`` is a (W, C) float32 row (C = 1 grey, or 3) and ``bits`` the same memory as
    uint32. The bytes minimise the error of the (m + 0.5) reconstruction: the largest component
    picks the smallest exponent that holds it (its mantissa in [128, 256)) and each mantissa is
    the floor, the interval holding the value, whose centre is the nearest reconstruction.
    NaN and negatives become 0; values beyond RGBE's largest (about 1.7e38, infinities
    included) saturate to it; values below 2**-128 make a black pixel. Everything is read from
    the bit patterns (non-negative floats order like their bits; NaN and negatives are the
    patterns above +infinity's), without a data-dependent branch per component: noisy images
    made the old comparisons mispredict.
    """
    width, channels = values.shape
    smallest = 1 << 21  # the bits of 2**-128 (a float32 subnormal), the least normalised RGBE
    g = 1 if channels == 3 else 0
    r = 2 if channels == 3 else 0
    for x in range(width):
        b0, b1, b2 = np.int64(bits[x, 0]), np.int64(bits[x, g]), np.int64(bits[x, r])
        b0 = min(b0, _MAX_BITS) if b0 <= _INF_BITS else 0
        b1 = min(b1, _MAX_BITS) if b1 <= _INF_BITS else 0
        b2 = min(b2, _MAX_BITS) if b2 <= _INF_BITS else 0
        top = max(b0, b1, b2)
        if top < smallest:
            line[0, x] = line[1, x] = line[2, x] = line[3, x] = 0
            continue
        biased = top >> 23
        if biased >= 2:
            e = min(biased + 2, 255)
        else:  # a subnormal float32 or the smallest normals: let frexp find the exponent
            v = values[x, 0] if top == b0 else (values[x, g] if top == b1 else values[x, r])
            e = math.frexp(np.float64(v))[1] + 128
        line[0, x] = _mantissa(b0, e)
        line[1, x] = _mantissa(b1, e)
        line[2, x] = _mantissa(b2, e)
        line[3, x] = e


@numba.njit(cache=True, nogil=True)
def _rle_plane(plane: np.ndarray, buf: np.ndarray, pos: int, differ: np.ndarray) -> int:
    """Append one byte plane as new-style runs (>= 4 equal bytes, <= 127 per run) and literals
    (<= 128 per packet) to ``buf`` at ``pos``; return the new position (``differ``: scratch of
    ``plane.size`` rounded up to 8 bytes). This is the packing of
    Radiance's fwritecolrs and of Walter's rgbe.c: the next run is the first place where four
    equal bytes start (one before it would start a run too, so it begins a fresh one); the
    literal bytes before it are written as a short run when they are 2 or 3 equal bytes.
    Where runs of four start is computed for the whole plane first and searched eight bytes
    a step."""
    n = plane.size
    # differ[i] == 0 where plane[i] == plane[i + 1] == plane[i + 2] == plane[i + 3]: a run
    # can start there (xor and or over the plane: vectorised); padded with 1, no run.
    differ[max(n - 3, 0) :] = 1
    for i in range(n - 3):
        p = plane[i]
        differ[i] = (p ^ plane[i + 1]) | (p ^ plane[i + 2]) | (p ^ plane[i + 3])
    words = differ.view(np.uint64)
    ones, highs = np.uint64(0x0101010101010101), np.uint64(0x8080808080808080)
    cur = 0
    while cur < n:
        begin = cur
        while begin < n and differ[begin] != 0:  # to the next run, eight bytes a step
            w = words[begin // 8]
            if begin % 8 == 0 and ((w - ones) & ~w & highs) == 0:  # no zero byte in w
                begin += 8
            else:
                begin += 1
        begin = min(begin, n)
        short = 2 <= begin - cur <= 3
        if short and plane[cur] == plane[cur + 1] and plane[cur] == plane[begin - 1]:
            buf[pos] = 128 + begin - cur
            buf[pos + 1] = plane[cur]
            pos += 2
            cur = begin
        while cur < begin:
            count = min(begin - cur, 128)
            buf[pos] = count
            buf[pos + 1 : pos + 1 + count] = plane[cur : cur + count]
            pos += count + 1
            cur += count
        if begin < n:
            run = 4
            while begin + run < n and run < 127 and plane[begin + run] == plane[begin]:
                run += 1
            buf[pos] = 128 + run
            buf[pos + 1] = plane[begin]
            pos += 2
            cur += run
    return pos


#: scanlines per task of the parallel encoder.
_BLOCK_ROWS = 32


@numba.njit(cache=True, nogil=True, parallel=True)
def _encode(image: np.ndarray, rle: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Encode a C-contiguous (H, W, C) float32 image (C = 1 grey or 3 RGB) into Radiance
    scanlines, blocks of :data:`_BLOCK_ROWS` scanlines in parallel, each into its own part of one
    buffer sized for the worst case (pages never written are never touched). Returns the buffer
    and each block's (start, stop): the file's bytes are the blocks' bytes in order."""
    height, width, channels = image.shape
    per_line = 4 + 4 * (width + (width + 127) // 128) if rle else 4 * width
    buf = np.empty(height * per_line, np.uint8)
    bits = image.view(np.uint32)
    blocks = (height + _BLOCK_ROWS - 1) // _BLOCK_ROWS
    starts, stops = np.empty(blocks, np.int64), np.empty(blocks, np.int64)
    for k in numba.prange(blocks):
        line = np.empty((4, width), np.uint8)
        differ = np.empty((width + 7) // 8 * 8, np.uint8)
        pos = k * _BLOCK_ROWS * per_line
        starts[k] = pos
        for y in range(k * _BLOCK_ROWS, min(height, (k + 1) * _BLOCK_ROWS)):
            _rgbe_row(image[y], bits[y], line)
            if rle:
                buf[pos] = 2
                buf[pos + 1] = 2
                buf[pos + 2] = width >> 8
                buf[pos + 3] = width & 255
                pos += 4
                for c in range(4):
                    pos = _rle_plane(line[c], buf, pos, differ)
            else:
                for x in range(width):
                    for c in range(4):
                        buf[pos + c] = line[c, x]
                    pos += 4
        stops[k] = pos
    return buf, starts, stops
