"""Truevision TGA (.tga): read every uncompressed and RLE image type, write 8, 24 and 32 bits.

Read: image types 1 (colour-mapped), 2 (true-colour), 3 (grey) and their run-length encoded
forms 9, 10, 11; pixel depths 8, 15, 16, 24 and 32; colour maps of 15, 16, 24 or 32 bit entries
starting at any first-entry index; all four origins (descriptor bits 4 and 5); the image ID
skipped; a TGA 2.0 footer or anything else after the pixels ignored. RLE packets may cross
scanlines (TGA 2.0 forbids it, many writers do it anyway).

Values are the stored samples scaled to [0, 1] (v / 255, or v / 31 for 5-bit samples), in RGB
order, no transfer function applied. Channels:

======================================  =========================================
file                                    image
======================================  =========================================
grey, 8 bits                            (H, W, 1)
grey + alpha, 16 bits (alpha bits > 0)  (H, W, 4): grey copied to R, G, B, then A
15 bits, or 16 bits without alpha bits  (H, W, 3)
16 bits with alpha bits (1-5-5-5)       (H, W, 4), alpha 0 or 1
24 bits                                 (H, W, 3)
32 bits                                 (H, W, 4), whatever the alpha bits say
======================================  =========================================

A colour-mapped image has the channels of its map entries by the same rules.

Write: grey (C = 1) as 8-bit type 3, RGB as 24-bit type 2, RGBA as 32-bit type 2 with 8 alpha
bits; type 11 or 10 with ``rle=True`` (packets never cross scanlines); top-left origin unless
``origin="bottom-left"``; a TGA 2.0 footer. Float input is quantised as
:func:`bakeshop.io._quantize.float_to_unsigned` says (NaN -> 0, clip to [0, 1], round to
nearest); uint8 arrays are written as they are.

Reference: Truevision, "Truevision TGA File Format Specification", version 2.0, 1989.
"""

from __future__ import annotations

import os
import struct

import numpy as np

from bakeshop.errors import (
    ArgumentError,
    FormatError,
    UnsupportedError,
    validate_choice,
    with_article,
)
from bakeshop.io import _native
from bakeshop.io._files import MAX_PIXELS, check_dimensions, check_payload
from bakeshop.io._quantize import float_to_unsigned, unsigned_to_float
from bakeshop.io.budget import check_decode

NAME = "TGA"
HEADER = struct.Struct("<BBBHHBHHHHBB")
FOOTER_SIGNATURE = b"TRUEVISION-XFILE.\0"

#: image type -> (kind, run-length encoded)
TYPES = {
    1: ("colour-mapped", False),
    2: ("true-colour", False),
    3: ("grey", False),
    9: ("colour-mapped", True),
    10: ("true-colour", True),
    11: ("grey", True),
}
DEPTHS = {"colour-mapped": (8, 16), "true-colour": (15, 16, 24, 32), "grey": (8, 16)}
MAP_DEPTHS = (15, 16, 24, 32)
ORIGINS = {0x00: "bottom-left", 0x10: "bottom-right", 0x20: "top-left", 0x30: "top-right"}

_LUT8 = unsigned_to_float(np.arange(256), 8)
_LUT5 = unsigned_to_float(np.arange(32), 5)


def _parse(head: bytes) -> dict:
    """Decode and check the 18-byte header; FormatError or UnsupportedError when it is wrong."""
    if len(head) < HEADER.size:
        raise FormatError(f"truncated file: a TGA header is {HEADER.size} bytes")
    (id_len, map_type, image_type, map_first, map_len, map_bits,
     _x, _y, width, height, depth, descriptor) = HEADER.unpack_from(head)  # fmt: skip
    if image_type == 0:
        raise FormatError("the TGA file holds no image data (image type 0)")
    if image_type in (32, 33):
        raise UnsupportedError("Huffman/delta compressed TGA (types 32, 33) is not supported")
    if image_type not in TYPES:
        raise FormatError(f"not a TGA file (image type {image_type})")
    kind, rle = TYPES[image_type]
    if map_type not in (0, 1):
        raise FormatError(f"not a TGA file (colour map type {map_type})")
    if kind == "colour-mapped" and (map_type != 1 or map_len == 0):
        raise FormatError("colour-mapped TGA without a colour map")
    if map_type == 1 and map_bits not in MAP_DEPTHS:
        raise FormatError(f"unsupported colour map entry size {map_bits} bits")
    if depth not in DEPTHS[kind]:
        raise FormatError(f"{depth}-bit pixels are not valid in {with_article(kind)} TGA")
    if descriptor & 0xC0:
        raise UnsupportedError("interleaved TGA (descriptor bits 6-7) is not supported")
    return {
        "id_len": id_len,
        "map_type": map_type,
        "map_first": map_first,
        "map_len": map_len if map_type == 1 else 0,
        "map_bits": map_bits,
        "image_type": image_type,
        "kind": kind,
        "rle": rle,
        "width": width,
        "height": height,
        "depth": depth,
        "alpha_bits": descriptor & 0x0F,
        "origin": ORIGINS[descriptor & 0x30],
    }


def sniff(head: bytes) -> bool:
    """True when ``head`` is a plausible TGA header (TGA has no magic number)."""
    try:
        h = _parse(head)
    except (FormatError, UnsupportedError):
        return False
    return h["width"] > 0 and h["height"] > 0


def _unrle(data: np.ndarray, start: int, count: int, bpp: int, out: np.ndarray) -> int:
    """Decode ``count`` pixels of ``bpp`` bytes from ``data[start:]`` into ``out`` (the compiled
    decoder, ``src/io/tga.hpp``: every packet checked against both ends before it is copied).

    Returns the offset after the last packet, -1 if the data ends early, -2 if a packet runs
    past the last pixel.
    """
    return int(_native.tga_unrle(data, start, count, bpp, out))


def _rle(rows: np.ndarray, width: int, bpp: int) -> np.ndarray:
    """Run-length encode each row of ``rows`` ((H, W * bpp) uint8) into TGA packets."""
    out = np.empty(rows.shape[0] * width * (bpp + 1), np.uint8)
    return out[: _native.tga_rle(rows, width, bpp, out)]


def _expand8(
    raw: np.ndarray,
    height: int,
    width: int,
    bpp: int,
    order: np.ndarray,
    flip_x: bool,
    flip_y: bool,
    lut: np.ndarray,
    out: np.ndarray,
) -> None:
    """out[y, x, c] = lut[byte order[c] of the stored pixel that lands at (x, y)]."""
    _native.tga_expand8(raw, height, width, bpp, order, flip_x, flip_y, lut, out)


def _channel_order(bits: int, alpha_bits: int, grey: bool) -> np.ndarray:
    """Byte indices of R, G, B(, A) (or grey) inside a stored pixel of 8-bit samples."""
    if grey:
        return np.array([0] if bits == 8 or alpha_bits == 0 else [0, 0, 0, 1], np.intp)
    return np.array([2, 1, 0] if bits == 24 else [2, 1, 0, 3], np.intp)


def _decode_555(raw: np.ndarray, alpha: bool) -> np.ndarray:
    """(N * 2) bytes of little-endian A1R5G5B5 -> (N, 3 or 4) float32."""
    v = raw.view("<u2")
    planes = [(v >> 10) & 31, (v >> 5) & 31, v & 31]
    out = np.empty((v.size, 4 if alpha else 3), np.float32)
    for c, p in enumerate(planes):
        out[:, c] = _LUT5[p]
    if alpha:
        out[:, 3] = v >> 15
    return out


def _decode_entries(raw: np.ndarray, bits: int, alpha_bits: int) -> np.ndarray:
    """Colour-map entries -> (N, C) float32."""
    if bits in (15, 16):
        return _decode_555(raw, bits == 16 and alpha_bits > 0)
    n = raw.size // (bits // 8)
    order = _channel_order(bits, alpha_bits, grey=False)
    out = np.empty((1, n, order.size), np.float32)
    _expand8(raw, 1, n, bits // 8, order, False, False, _LUT8, out)
    return out[0]


def read(path: str | os.PathLike, *, max_pixels: int = MAX_PIXELS) -> tuple[np.ndarray, dict]:
    """Read a TGA file.

    Returns
    -------
    image : (H, W, C) float32
        Stored values scaled to [0, 1], RGB(A) order, row 0 at the top (see the module notes
        for C).
    metadata : dict
        ``stored`` (``"uint8"``, or ``"uint5"`` for 15/16-bit colour), ``bits`` (pixel depth),
        ``type`` (image type 1-11), ``kind``, ``origin`` (``"bottom-left"`` ...), ``rle``,
        ``alpha_bits``, and for colour-mapped files ``colormap`` (first, length, bits);
        ``image_id`` when the file has one.
    """
    size = os.path.getsize(path)
    with open(path, "rb") as f:
        h = _parse(f.read(HEADER.size))
        width, height, depth = h["width"], h["height"], h["depth"]
        check_dimensions(width, height, max_pixels=max_pixels)
        image_id = f.read(h["id_len"])
        map_bytes = h["map_len"] * ((h["map_bits"] + 7) // 8)
        check_payload(
            HEADER.size + h["id_len"] + map_bytes, size, "header, image ID and colour map"
        )
        colormap = np.frombuffer(f.read(map_bytes), np.uint8)
        bpp = (depth + 7) // 8
        count = width * height
        available = size - f.tell()
        # RLE packets repeat a pixel 128 times: the float32 image (at most 4 channels) and the
        # unpacked bytes must fit the budget for a file of this size
        check_decode(count * (4 * 4 + bpp), size)
        if h["rle"]:
            check_payload(-(-count // 128) * (1 + bpp), available, "RLE pixel data (at least)")
            data = np.fromfile(f, np.uint8)
            raw = np.empty(count * bpp, np.uint8)
            end = _unrle(data, 0, count, bpp, raw)
            if end == -1:
                raise FormatError("truncated file: the RLE pixel data ends before the last pixel")
            if end == -2:
                raise FormatError("corrupt RLE data: a packet runs past the last pixel")
        else:
            check_payload(count * bpp, available)
            raw = np.fromfile(f, np.uint8, count * bpp)

    flip_x = h["origin"].endswith("right")
    flip_y = h["origin"].startswith("bottom")
    kind, alpha_bits = h["kind"], h["alpha_bits"]
    meta = {
        "stored": "uint5" if kind == "true-colour" and depth in (15, 16) else "uint8",
        "bits": depth,
        "type": h["image_type"],
        "kind": kind,
        "origin": h["origin"],
        "rle": h["rle"],
        "alpha_bits": alpha_bits,
    }
    if image_id:
        meta["image_id"] = meta["description"] = image_id.decode("latin-1")
    if h["map_type"] == 1:
        meta["colormap"] = {"first": h["map_first"], "length": h["map_len"], "bits": h["map_bits"]}

    if kind == "grey" or (kind == "true-colour" and depth in (24, 32)):
        order = _channel_order(depth, alpha_bits, grey=kind == "grey")
        image = np.empty((height, width, order.size), np.float32)
        _expand8(raw, height, width, bpp, order, flip_x, flip_y, _LUT8, image)
        return image, meta

    if kind == "true-colour":  # 15 or 16 bits
        pixels = _decode_555(raw, depth == 16 and alpha_bits > 0)
    else:
        if h["map_bits"] in (15, 16):
            meta["stored"] = "uint5"
        palette = _decode_entries(colormap, h["map_bits"], alpha_bits)
        index = raw if depth == 8 else raw.view("<u2")
        index = index.astype(np.intp) - h["map_first"]
        if index.min() < 0 or index.max() >= h["map_len"]:
            bad = int(index[(index < 0) | (index >= h["map_len"])][0]) + h["map_first"]
            raise FormatError(
                f"colour-map index {bad} is outside the map's entries "
                f"{h['map_first']}..{h['map_first'] + h['map_len'] - 1}"
            )
        pixels = palette[index]
    image = pixels.reshape(height, width, -1)
    if flip_y:
        image = image[::-1]
    if flip_x:
        image = image[:, ::-1]
    return np.ascontiguousarray(image), meta


def write(
    path: str | os.PathLike,
    image: np.ndarray,
    *,
    rle: bool = False,
    origin: str = "top-left",
    description: str | None = None,
) -> None:
    """Write an 8-bit grey, 24-bit RGB or 32-bit RGBA TGA file.

    Parameters
    ----------
    path : path-like
    image : (H, W, C) float or uint8 array, C in {1, 3, 4}
        Floats are values in [0, 1]: NaN -> 0, clipped, rounded to the nearest of 0..255;
        uint8 is written as it is. H and W at most 65535.
    rle : bool
        Run-length encode (image types 11 and 10); packets never cross scanlines.
    origin : {"top-left", "bottom-left"}
        Row order in the file; readers that honour the descriptor (all of them should) show
        the same picture either way.
    description : str, optional
        Stored in the image ID field (at most 255 Latin-1 bytes; longer text is cut), read
        back as ``description``.
    """
    validate_choice(origin, ("top-left", "bottom-left"), "TGA origin")
    height, width, channels = image.shape
    if width > 0xFFFF or height > 0xFFFF:
        raise ArgumentError(f"TGA holds at most 65535x65535 pixels, the image is {width}x{height}")
    u8 = float_to_unsigned(image, 8)
    if channels == 3:
        u8 = u8[:, :, ::-1]
    elif channels == 4:
        u8 = u8[:, :, [2, 1, 0, 3]]
    if origin == "bottom-left":
        u8 = u8[::-1]
    rows = np.ascontiguousarray(u8).reshape(height, width * channels)
    image_type = (3 if channels == 1 else 2) + (8 if rle else 0)
    descriptor = (8 if channels == 4 else 0) | (0x20 if origin == "top-left" else 0)
    image_id = b"" if description is None else description.encode("latin-1", "replace")[:255]
    header = HEADER.pack(
        len(image_id), 0, image_type, 0, 0, 0, 0, 0, width, height, 8 * channels, descriptor
    )
    with open(path, "wb") as f:
        f.write(header)
        f.write(image_id)
        f.write((_rle(rows, width, channels) if rle else rows).data)

        f.write(struct.pack("<II", 0, 0) + FOOTER_SIGNATURE)
