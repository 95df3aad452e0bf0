"""Small files that decode to huge images, built by the tests (no file is committed).

Each builder returns the bytes of a valid file of its format whose pixels are all one value, so
the same builder at a small size is checked against an independent reader or the format's
formula, and at a large size is a decompression bomb:

====================  =========================================  ==========  ===============
builder               coding                                     16384^2 is  float32 decoded
====================  =========================================  ==========  ===============
radiance_old_rle      old-style Radiance runs (2**8 per record)  128 KiB     3 GiB (RGB)
exr_zip               zip OpenEXR, one chunk repeated            ~1 MiB      3 GiB (RGB)
tga_rle               RLE grey TGA, 128-pixel runs               4 MiB       1 GiB (+ bytes)
png_deflate           deflate of zero scanlines, grey PNG        ~260 KiB    1 GiB (+ bytes)
====================  =========================================  ==========  ===============
"""

from __future__ import annotations

import struct
import tempfile
import zlib
from pathlib import Path

import numpy as np
import OpenEXR

#: the pixel every Radiance bomb repeats: mantissas and exponent.
RGBE_PIXEL = (128, 64, 32, 129)
#: its value under Radiance's reconstruction (m + 0.5) * 2**(e - 136).
RGBE_VALUE = tuple((m + 0.5) * 2.0 ** (RGBE_PIXEL[3] - 136) for m in RGBE_PIXEL[:3])


def _repeat(count: int) -> bytes:
    """Old-style Radiance repeat records for ``count`` pixels: consecutive records shift their
    count by 8 bits each, so the count is written as its little-endian bytes."""
    records = b""
    while count:
        records += bytes([1, 1, 1, count & 255])
        count >>= 8
    return records


def radiance_old_rle(width: int, height: int) -> bytes:
    """A Radiance file: one literal pixel, then old-style repeats of it to fill every scanline
    (8 or 12 bytes per scanline, whatever the width)."""
    header = f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {height} +X {width}\n".encode()
    first = bytes(RGBE_PIXEL) + _repeat(width - 1)
    return header + first + _repeat(width) * (height - 1)


def exr_zip(width: int, height: int, channels: tuple[str, ...] = ("B", "G", "R")) -> bytes:
    """A zip scanline OpenEXR of half zeros: OpenEXR writes a 16-row file of the width, whose
    one chunk is then repeated for every 16 rows under a header whose data window says
    ``height`` rows (the chunk holds 16 rows of every channel; zeros compress ~1000:1).
    ``height`` is a multiple of 16."""
    rows = 16
    assert height % rows == 0, height
    planes = {c: np.zeros((rows, width), np.float16) for c in channels}
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "chunk.exr"
        header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
        OpenEXR.File(header, planes).write(str(path))
        data = path.read_bytes()
    for name in (b"dataWindow", b"displayWindow"):
        key = name + b"\0box2i\0" + struct.pack("<i", 16)
        at = data.index(key) + len(key)
        data = data[:at] + struct.pack("<4i", 0, 0, width - 1, height - 1) + data[at + 16 :]
    chunk_at = _first_chunk(data)
    head = data[: chunk_at - 8]
    (size,) = struct.unpack_from("<i", data, chunk_at + 4)
    payload = data[chunk_at + 8 : chunk_at + 8 + size]
    count = -(-height // rows)
    table_end = len(head) + 8 * count
    offsets = [table_end + k * (8 + size) for k in range(count)]
    chunks = b"".join(struct.pack("<ii", k * rows, size) + payload for k in range(count))
    return head + struct.pack(f"<{count}Q", *offsets) + chunks


def _first_chunk(data: bytes) -> int:
    """Where the only chunk of a one-chunk single-part OpenEXR starts: the header ends with a
    zero byte after the last attribute, and the one-entry offset table follows it."""
    pos = 8
    while data[pos] != 0:
        name_end = data.index(b"\0", pos)
        type_end = data.index(b"\0", name_end + 1)
        (size,) = struct.unpack_from("<i", data, type_end + 1)
        pos = type_end + 5 + size
    return struct.unpack_from("<Q", data, pos + 1)[0]


def tga_rle(width: int, height: int, value: int = 200) -> bytes:
    """A run-length encoded 8-bit grey TGA (type 11, top-left origin) of one grey level: runs of
    128 pixels, 2 bytes each, that may cross scanlines."""
    count = width * height
    header = struct.pack("<BBBHHBHHHHBB", 0, 0, 11, 0, 0, 0, 0, 0, width, height, 8, 0x20)
    runs, rest = divmod(count, 128)
    body = bytes([0xFF, value]) * runs + (bytes([0x80 | (rest - 1), value]) if rest else b"")
    return header + body


def _png_chunk(kind: bytes, payload: bytes) -> bytes:
    crc = zlib.crc32(kind + payload)
    return struct.pack(">I", len(payload)) + kind + payload + struct.pack(">I", crc)


def png_deflate(width: int, height: int) -> bytes:
    """An 8-bit grey PNG of zeros: every scanline is filter 0 and zero bytes, deflated as one
    stream (about 1000:1)."""
    compressor = zlib.compressobj(9)
    line = bytes(1 + width)
    block = max(1, (1 << 22) // len(line))
    parts = [compressor.compress(line * min(block, height - y)) for y in range(0, height, block)]
    idat = b"".join(parts) + compressor.flush()
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    return (
        b"\x89PNG\r\n\x1a\n"
        + _png_chunk(b"IHDR", ihdr)
        + _png_chunk(b"IDAT", idat)
        + _png_chunk(b"IEND", b"")
    )
