"""PNG (8 and 16 bit) and JPEG: stored values scaled to [0, 1], no transfer function applied.

An 8-bit sample v reads as v / 255 and a 16-bit one as v / 65535, whatever the file says about
its colour space: sRGB-encoded data stays encoded (the ``srgb``, ``gamma`` and ``icc_profile``
metadata say what the file declares). Decode to linear yourself when the data is colour, with
:func:`bakeshop.image.srgb_decode` (``bakeshop convert --srgb-decode``); normal maps,
masks and height maps are data and must not be decoded. Commands that make display images say in
their ``--help`` when they sRGB-encode.

Channels (DESIGN: C in {1, 3, 4}):

==================================  ==============================================
file                                image
==================================  ==============================================
grey (1, 2, 4, 8, 16 bit)           (H, W, 1)
grey + alpha                        (H, W, 4): grey copied to R, G, B, then A
RGB                                 (H, W, 3)
RGBA                                (H, W, 4)
palette                             (H, W, 3), or (H, W, 4) when it has tRNS alpha
grey or RGB with a tRNS colour key  plus alpha: 0 where the key matches, else 1
JPEG grey / YCbCr                   (H, W, 1) / (H, W, 3)
==================================  ==============================================

Reading goes through Pillow except for 16-bit colour PNGs (RGB, RGBA, grey+alpha), which Pillow
reduces to 8 bits: bakeshop inflates and unfilters those itself (``src/io/ldr.hpp``). Before either,
the PNG's chunks are walked: a bad checksum in a critical chunk (IHDR, PLTE, IDAT, IEND) is a
:class:`FormatError`, while an ancillary chunk (text, colour profile ...) with a bad checksum is
dropped and named in the metadata (``dropped_chunks``) instead of failing the whole file, as libpng
does by default. The header is checked against the limits of ``bakeshop.io._files`` and against the
compressed data: deflate expands at most 1032:1, so a header promising more pixels than its data can
hold is refused before anything is allocated.

Writing PNG is bakeshop's own encoder (Pillow cannot write 16-bit colour): colour types grey,
RGB, RGBA at 8 bits (default) or 16 (``bits=16``), per-row adaptive filters (the minimum sum of
absolute differences heuristic of libpng), zlib level ``compression`` (0-9, default 6). JPEG is
written by Pillow, ``quality`` 1-100 (default 95), 4:4:4 chroma (no subsampling), baseline; JPEG
has no alpha. Float input is quantised as :func:`bakeshop.io._quantize.float_to_unsigned` says
(NaN -> 0, clip to [0, 1], round to nearest); unsigned integer input is written as it is.

References: ISO/IEC 15948:2004 (PNG), W3C PNG Specification (Second Edition); ITU-T T.81 (JPEG).
"""

from __future__ import annotations

import io
import os
import struct
import warnings
import zlib
from collections.abc import Iterator
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike
from PIL import Image

from bakeshop.errors import ArgumentError, BakeshopError, FormatError, UnsupportedError
from bakeshop.io import _native
from bakeshop.io._files import MAX_PIXELS, check_dimensions
from bakeshop.io._quantize import float_to_unsigned, unsigned_to_float
from bakeshop.io.budget import check_decode

NAME = "PNG/JPEG"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
JPEG_MAGIC = b"\xff\xd8\xff"

#: The largest expansion of deflate (zlib's 258-byte matches in ~2 bits each, with a margin).
DEFLATE_MAX_RATIO = 1032
#: PNG colour type -> (name, samples per pixel)
COLOUR_TYPES = {
    0: ("grey", 1),
    2: ("rgb", 3),
    3: ("palette", 1),
    4: ("grey+alpha", 2),
    6: ("rgba", 4),
}
VALID_DEPTHS = {0: (1, 2, 4, 8, 16), 2: (8, 16), 3: (1, 2, 4, 8), 4: (8, 16), 6: (8, 16)}
#: Adam7 passes: (x0, y0, dx, dy)
ADAM7 = (
    (0, 0, 8, 8),
    (4, 0, 8, 8),
    (0, 4, 4, 8),
    (2, 0, 4, 4),
    (0, 2, 2, 4),
    (1, 0, 2, 2),
    (0, 1, 1, 2),
)


def sniff(head: bytes) -> bool:
    """True for the PNG signature or a JPEG start-of-image marker."""
    return head.startswith(PNG_MAGIC) or head.startswith(JPEG_MAGIC)


# --- PNG structure ------------------------------------------------------------------------------


#: a PNG chunk: its type and where it starts and ends in the file.
Chunk = tuple[bytes, int, int]


def _png_chunks(data: bytes) -> tuple[dict, list[Chunk], list[str]]:
    """Walk the chunks: (IHDR fields, [(type, start, end) of kept chunks], dropped chunk names)."""
    pos = len(PNG_MAGIC)
    view = memoryview(data)  # checksums without copying each chunk
    kept: list[tuple[bytes, int, int]] = []
    dropped: list[str] = []
    while True:
        if pos + 12 > len(data):
            raise FormatError("truncated PNG: the file ends before its IEND chunk")
        length, kind = struct.unpack_from(">I4s", data, pos)
        if length > 0x7FFFFFFF or not kind.isalpha():
            raise FormatError(f"corrupt PNG: bad chunk header at byte {pos}")
        end = pos + 12 + length
        if end > len(data):
            raise FormatError(f"truncated PNG: chunk {kind.decode()} runs past the end of the file")
        (crc,) = struct.unpack_from(">I", data, end - 4)
        if zlib.crc32(view[pos + 4 : end - 4]) != crc:
            if kind[0] & 0x20:  # ancillary: drop it, as libpng does
                dropped.append(kind.decode())
                pos = end
                continue
            raise FormatError(f"corrupt PNG: bad checksum in the {kind.decode()} chunk")
        if not kept and kind != b"IHDR":
            raise FormatError("corrupt PNG: the first chunk is not IHDR")
        kept.append((kind, pos, end))
        pos = end
        if kind == b"IEND":
            break
    start = kept[0][1] + 8
    if kept[0][2] - start - 4 != 13:
        raise FormatError("corrupt PNG: IHDR is not 13 bytes")
    width, height, depth, colour, method, filtering, interlace = struct.unpack_from(
        ">IIBBBBB", data, start
    )
    if colour not in COLOUR_TYPES or depth not in VALID_DEPTHS[colour]:
        raise FormatError(f"corrupt PNG: bit depth {depth} with colour type {colour}")
    if method or filtering or interlace > 1:
        raise FormatError("corrupt PNG: unknown compression, filter or interlace method")
    header = {"width": width, "height": height, "depth": depth, "colour": colour}
    header["interlaced"] = bool(interlace)
    return header, kept, dropped


def _passes(
    width: int, height: int, interlaced: bool
) -> Iterator[tuple[int, int, int, int, int, int]]:
    """(x0, y0, dx, dy, pass width, pass height) of each non-empty (sub-)image."""
    for x0, y0, dx, dy in ADAM7 if interlaced else ((0, 0, 1, 1),):
        w, h = -(-(width - x0) // dx), -(-(height - y0) // dy)
        if w > 0 and h > 0:
            yield x0, y0, dx, dy, w, h


def _raw_size(header: dict) -> int:
    """Bytes of filtered scanlines the IDAT stream must inflate to."""
    bits = header["depth"] * COLOUR_TYPES[header["colour"]][1]
    passes = _passes(header["width"], header["height"], header["interlaced"])
    return sum(h * (1 + (w * bits + 7) // 8) for *_, w, h in passes)


def _unfilter(
    buf: np.ndarray, start: int, height: int, stride: int, bpp: int, out: np.ndarray
) -> int:
    """Undo PNG filters of ``height`` rows of ``stride`` bytes (each after its filter byte).

    Returns 0, or the 1-based row number whose filter type is invalid.
    """
    return int(_native.png_unfilter(buf, start, height, stride, bpp, out))


def _inflate(data: bytes, chunks: list[Chunk], size: int) -> np.ndarray:
    idat = b"".join(data[s + 8 : e - 4] for kind, s, e in chunks if kind == b"IDAT")
    try:
        raw = zlib.decompressobj().decompress(idat, size)
    except zlib.error as e:
        raise FormatError(f"corrupt PNG: the compressed pixel data is damaged ({e})") from None
    if len(raw) < size:
        raise FormatError(
            f"truncated PNG: the pixel data inflates to {len(raw)} bytes, the header needs {size}"
        )
    return np.frombuffer(raw, np.uint8)


def _decode_png16(data: bytes, header: dict, chunks: list[Chunk]) -> np.ndarray:
    """16-bit RGB, RGBA or grey+alpha PNG -> (H, W, samples) uint16."""
    width, height = header["width"], header["height"]
    samples = COLOUR_TYPES[header["colour"]][1]
    bpp = 2 * samples
    raw = _inflate(data, chunks, _raw_size(header))
    out = np.empty((height, width, samples), np.uint16)
    offset = 0
    for x0, y0, dx, dy, w, h in _passes(width, height, header["interlaced"]):
        rows = np.empty((h, w * bpp), np.uint8)
        bad = _unfilter(raw, offset, h, w * bpp, bpp, rows)
        if bad:
            raise FormatError(f"corrupt PNG: invalid filter type in scanline {bad}")
        out[y0::dy, x0::dx] = rows.view(">u2").reshape(h, w, samples)
        offset += h * (1 + w * bpp)
    return out


def _colour_key(values: np.ndarray, key: np.ndarray) -> np.ndarray:
    """Append an alpha channel that is 0 where the pixel equals the tRNS colour key."""
    opaque = np.iinfo(values.dtype).max
    alpha = np.where((values == key).all(axis=-1), 0, opaque).astype(values.dtype)
    return np.concatenate([values, alpha[..., None]], axis=-1)


def _expand_grey_alpha(values: np.ndarray) -> np.ndarray:
    return values[..., [0, 0, 0, 1]]


# --- reading -------------------------------------------------------------------------------------


def _open_with_pillow(data: bytes, max_pixels: int) -> Image.Image:
    """Decode with Pillow: its decompression-bomb limit and bakeshop's size limits and decode
    budget all apply (the budget counts the float32 image: 4 channels for a palette)."""
    try:
        with warnings.catch_warnings():
            # bakeshop checks the size against its own limits; Pillow's warning adds nothing
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            image = Image.open(io.BytesIO(data))
            check_dimensions(*image.size, max_pixels=max_pixels)
            bands = 4 if image.mode in ("P", "PA") else len(image.getbands())
            check_decode(image.size[0] * image.size[1] * bands * 4, len(data))
            image.load()
        return image
    except BakeshopError:
        raise
    except Image.DecompressionBombError:
        limit = Image.MAX_IMAGE_PIXELS
        assert limit is not None  # Pillow raises this error only when it has a limit
        raise FormatError(
            f"the image is larger than Pillow's decompression-bomb limit of {2 * limit} pixels"
        ) from None
    except (OSError, SyntaxError, ValueError, struct.error, EOFError, IndexError) as e:
        raise FormatError(f"corrupt or truncated image: {e}") from None


def _pillow_values(image: Image.Image) -> tuple[np.ndarray, int]:
    """Pillow image -> ((H, W, C) unsigned samples, their bit depth: 8 or 16).

    Grey + alpha becomes RGBA and a palette RGB(A) (with its tRNS alpha); colour keys of grey and
    RGB images are left to the caller. 1-bit grey is scaled to 0/255 as Pillow scales 2 and
    4-bit grey (v * 85, v * 17), so every low-depth v reads as v / (2^n - 1).
    """
    mode = image.mode
    if mode == "P" or mode == "PA":
        alpha = "transparency" in image.info or mode == "PA"
        return np.asarray(image.convert("RGBA" if alpha else "RGB")), 8
    if mode == "1":
        return np.asarray(image, np.uint8)[..., None] * np.uint8(255), 8
    if mode in ("I;16", "I;16B", "I;16L", "I"):
        values = np.asarray(image).astype(np.uint16)[..., None]
        bits = 16
    elif mode in ("L", "RGB", "LA", "RGBA"):
        values = np.asarray(image)
        values = values[..., None] if values.ndim == 2 else values
        bits = 8
    elif mode == "CMYK":
        raise UnsupportedError("CMYK JPEG is not supported; convert it to RGB first")
    else:
        raise UnsupportedError(f"unsupported pixel mode {mode!r}")
    if mode == "LA":
        values = _expand_grey_alpha(values)
    return values, bits


def read(path: str | os.PathLike, *, max_pixels: int = MAX_PIXELS) -> tuple[np.ndarray, dict]:
    """Read a PNG or JPEG file (the content decides, not the extension).

    Returns
    -------
    image : (H, W, C) float32
        Stored samples scaled to [0, 1]; see the module notes for C.
    metadata : dict
        ``format`` (``"PNG"`` or ``"JPEG"``), ``stored`` (``"uint8"``, ``"uint16"``, or
        ``"uint1"``/``"uint2"``/``"uint4"`` for low-depth grey PNG), ``bits``, ``colour``
        (the file's colour type), ``icc_profile`` (bool); for PNG ``srgb`` (an sRGB chunk),
        ``gamma`` (the gAMA value, if any), ``interlaced`` and ``dropped_chunks``; for JPEG
        ``progressive`` and ``exif_orientation`` (the EXIF orientation is reported, not applied);
        ``description`` when the file has one (a PNG ``Description`` text chunk, a JPEG
        comment), as bakeshop records how a picture was made.
    """
    data = Path(path).read_bytes()
    if data.startswith(PNG_MAGIC):
        return _read_png(data, max_pixels)
    if data.startswith(JPEG_MAGIC):
        return _read_jpeg(data, max_pixels)
    raise FormatError("not a PNG or JPEG file (bad magic bytes)")


def _read_png(data: bytes, max_pixels: int) -> tuple[np.ndarray, dict]:
    header, chunks, dropped = _png_chunks(data)
    check_dimensions(header["width"], header["height"], max_pixels=max_pixels)
    compressed = sum(e - s - 12 for kind, s, e in chunks if kind == b"IDAT")
    needed = _raw_size(header)
    if compressed * DEFLATE_MAX_RATIO < needed:
        raise FormatError(
            f"truncated or lying PNG: {needed} bytes of pixel data cannot come from "
            f"{compressed} compressed bytes (deflate expands at most {DEFLATE_MAX_RATIO}:1)"
        )
    kinds = {kind for kind, *_ in chunks}
    colour_name = COLOUR_TYPES[header["colour"]][0]
    colour, depth = header["colour"], header["depth"]
    # the float32 image (RGBA for grey + alpha, palettes with alpha and colour keys) and the
    # inflated scanlines, before anything is inflated
    channels = {0: 1, 2: 3, 3: 3, 4: 4, 6: 4}[colour]
    if b"tRNS" in kinds:
        channels = 4
    check_decode(header["width"] * header["height"] * channels * 4 + needed, len(data))
    if depth == 16 and colour in (2, 4, 6):
        values = _decode_png16(data, header, chunks)
        if colour == 4:
            values = _expand_grey_alpha(values)
        bits = 16
    else:
        if dropped:
            data = PNG_MAGIC + b"".join(data[s:e] for _, s, e in chunks)
        values, bits = _pillow_values(_open_with_pillow(data, max_pixels))
    trns = [data[s + 8 : e - 4] for kind, s, e in chunks if kind == b"tRNS"]
    if colour in (0, 2) and trns and len(trns[0]) == 2 * values.shape[-1]:
        # a colour key, in the file's sample units; low-depth grey was scaled to 8 bits
        key = np.frombuffer(trns[0], ">u2").astype(np.int64)
        key = key * (255 // ((1 << depth) - 1)) if depth < 8 else key
        values = _colour_key(values, key)
        if colour == 0:
            values = _expand_grey_alpha(values)
    meta = {
        "format": "PNG",
        "stored": f"uint{depth if colour == 0 else bits}",
        "bits": header["depth"],
        "colour": colour_name,
        "interlaced": header["interlaced"],
        "srgb": b"sRGB" in kinds,
        "icc_profile": b"iCCP" in kinds,
        "dropped_chunks": dropped,
    }
    for kind, s, e in chunks:
        if kind == b"gAMA" and e - s - 12 == 4:
            meta["gamma"] = struct.unpack_from(">I", data, s + 8)[0] / 100000
        elif kind == b"tEXt":
            keyword, _, text = data[s + 8 : e - 4].partition(b"\0")
            if keyword == b"Description":
                meta["description"] = text.decode("latin-1")
    return unsigned_to_float(values, bits), meta


def _read_jpeg(data: bytes, max_pixels: int) -> tuple[np.ndarray, dict]:
    image = _open_with_pillow(data, max_pixels)
    values, bits = _pillow_values(image)
    orientation = image.getexif().get(0x0112)
    meta = {
        "format": "JPEG",
        "stored": "uint8",
        "bits": 8,
        "colour": {"L": "grey", "RGB": "rgb"}.get(image.mode, image.mode),
        "icc_profile": "icc_profile" in image.info,
        "progressive": bool(image.info.get("progressive") or image.info.get("progression")),
    }
    if orientation is not None:
        meta["exif_orientation"] = int(orientation)
    comment = image.info.get("comment")
    if comment:
        meta["description"] = comment.decode("utf-8", "replace")
    return unsigned_to_float(values, bits), meta


# --- writing -------------------------------------------------------------------------------------


def _filter_rows(rows: np.ndarray, bpp: int, out: np.ndarray) -> None:
    """Filter each row of ``rows`` ((H, S) uint8) into ``out`` ((H, S + 1)), choosing per row the
    filter with the least sum of absolute signed bytes (libpng's heuristic), rows in parallel
    (``src/io/ldr.hpp``).
    """
    _native.png_filter_rows(rows, bpp, out)


def _chunk(kind: bytes, payload: bytes) -> bytes:
    return (
        struct.pack(">I", len(payload))
        + kind
        + payload
        + struct.pack(">I", zlib.crc32(kind + payload))
    )


def _write_png(
    path: str | os.PathLike,
    values: np.ndarray,
    bits: int,
    compression: int,
    description: str | None = None,
) -> None:
    height, width, channels = values.shape
    colour = {1: 0, 3: 2, 4: 6}[channels]
    rows = values.astype(">u2") if bits == 16 else values
    rows = np.ascontiguousarray(rows).view(np.uint8).reshape(height, -1)
    filtered = np.empty((height, rows.shape[1] + 1), np.uint8)
    _filter_rows(rows, channels * bits // 8, filtered)
    compressor = zlib.compressobj(compression)
    block = max(1, (1 << 22) // filtered.shape[1])  # about 4 MB per call
    parts = [compressor.compress(filtered[y : y + block].data) for y in range(0, height, block)]
    parts.append(compressor.flush())
    idat = b"".join(parts)
    with open(path, "wb") as f:
        f.write(PNG_MAGIC)
        f.write(_chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, bits, colour, 0, 0, 0)))
        if description is not None:  # a tEXt chunk, keyword "Description" (PNG spec 11.3.4.2)
            text = description.encode("latin-1", "replace").replace(b"\0", b" ")
            f.write(_chunk(b"tEXt", b"Description\0" + text))
        for i in range(0, len(idat), 1 << 20):
            f.write(_chunk(b"IDAT", idat[i : i + (1 << 20)]))
        f.write(_chunk(b"IEND", b""))


def write(
    path: str | os.PathLike,
    image: ArrayLike,
    *,
    bits: int | None = None,
    compression: int | None = None,
    quality: int | None = None,
    description: str | None = None,
) -> None:
    """Write a PNG or JPEG file (chosen by the extension of ``path``).

    Parameters
    ----------
    path : path-like
        ``.png``, ``.jpg`` or ``.jpeg``.
    image : (H, W, C) float, uint8 or uint16 array, C in {1, 3, 4}
        Floats are values in [0, 1] (NaN -> 0, clipped, rounded to the nearest level);
        unsigned integers are written as they are (uint8 at 16 bits is scaled by 257).
    bits : {8, 16}, PNG only
        Sample depth; default 16 for uint16 arrays, else 8.
    compression : int 0-9, PNG only
        zlib level (default 6). Lossless at every level.
    quality : int 1-100, JPEG only
        Default 95. JPEG stores 8 bits, no alpha (C = 4 is refused).
    description : str, optional
        A line of text kept in the file (PNG: a ``tEXt`` chunk with the keyword
        ``Description``; JPEG: a comment segment), read back as ``description``.
    """
    is_png = Path(path).suffix.lower() == ".png"
    image = np.asarray(image)
    if is_png:
        if quality is not None:
            raise ArgumentError("quality= applies to JPEG; PNG is lossless (see compression=)")
        if bits is None:
            bits = 16 if image.dtype == np.uint16 else 8
        if bits not in (8, 16):
            raise ArgumentError(f"PNG bits must be 8 or 16, not {bits!r}")
        compression = 6 if compression is None else compression
        if not isinstance(compression, (int, np.integer)) or not 0 <= compression <= 9:
            raise ArgumentError(f"PNG compression must be an integer 0-9, not {compression!r}")
        _write_png(path, float_to_unsigned(image, bits), bits, int(compression), description)
        return
    if bits not in (None, 8) or compression is not None:
        raise ArgumentError("JPEG stores 8 bits and takes quality=, not bits= or compression=")
    quality = 95 if quality is None else quality
    if not isinstance(quality, (int, np.integer)) or not 1 <= quality <= 100:
        raise ArgumentError(f"JPEG quality must be an integer 1-100, not {quality!r}")
    if image.shape[2] == 4:
        raise ArgumentError("JPEG has no alpha channel; drop it or write PNG")
    values = float_to_unsigned(image, 8)
    picture = Image.fromarray(values[..., 0] if values.shape[2] == 1 else values)
    extra = {} if description is None else {"comment": description.encode("utf-8")}
    picture.save(path, format="JPEG", quality=int(quality), subsampling=0, **extra)
