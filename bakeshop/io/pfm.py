"""Portable float map (PFM): uncompressed float32 pixels behind a three-token text header.

Layout of a file::

    PF\\n                 magic: "PF" colour (3 channels), "Pf" grey (1), "PF4" RGBA (4, read only)
    768 512\\n            width height
    -1.0\\n               scale: its sign is the byte order (negative: little-endian), its
                         magnitude a free number kept as metadata ``scale``
    <float32 pixels>     rows stored bottom to top, channels interleaved

The header tokens are separated by any whitespace; ``#`` comments up to the end of a line are
skipped between tokens (netpbm-style, which some writers emit), and a CR LF after the scale
(files written in text mode on Windows) is recognised by the file's size.

Reading copies the pixels into a native float32 array in memory, in blocks of rows flipped and
byte-swapped (when the file's order is not the machine's) on the way in: the peak is the image
plus one block. Files are never memory-mapped: a mapped file that another program truncates
while the array lives kills the process with SIGBUS at the first touch of a vanished page, with
no message and no way to catch it, and a map saves nothing here (every pixel is read anyway, by
the time an image has been used). A file that shrinks while it is being read is a
:class:`FormatError`.

``PF4`` is a four-channel extension written by a few tools (not part of the original format); it
is read but never written: bakeshop writes only the two standard kinds.
"""

from __future__ import annotations

import math
import os

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, FormatError
from bakeshop.io._files import MAX_PIXELS, check_dimensions, check_payload

NAME = "PFM"

_CHANNELS = {b"PF": 3, b"Pf": 1, b"PF4": 4}
_MAGIC_OF = {3: "PF", 1: "Pf"}
_WHITESPACE = b" \t\r\n\v\f"
#: a header longer than this (comments included) is not a PFM header.
_MAX_HEADER = 1 << 16
#: rows converted per block when writing, so writing holds no second copy of the image.
_BLOCK_ROWS = 256
#: bytes read per block (whole rows, at least one), reused: reading holds no second copy either.
_READ_BLOCK_BYTES = 8 << 20


def sniff(head: bytes) -> bool:
    """True if ``head`` starts like a PFM file (``PF``, ``Pf`` or ``PF4``, then whitespace)."""
    return any(
        head.startswith(magic) and len(head) > len(magic) and head[len(magic)] in _WHITESPACE
        for magic in _CHANNELS
    )


def _tokens(head: bytes, count: int) -> tuple[list[bytes], int]:
    """The first ``count`` whitespace-separated tokens of ``head`` and the offset after the last.

    ``#`` starts a comment that runs to the end of its line. Raises FormatError when the header
    is not complete within ``head``.
    """
    tokens: list[bytes] = []
    i, n = 0, len(head)
    while len(tokens) < count:
        while i < n and (head[i] in _WHITESPACE or head[i] == ord("#")):
            if head[i] == ord("#"):
                while i < n and head[i] not in b"\r\n":
                    i += 1
            else:
                i += 1
        start = i
        while i < n and head[i] not in _WHITESPACE and head[i] != ord("#"):
            i += 1
        if i >= n:
            raise FormatError("truncated or malformed PFM header")
        tokens.append(head[start:i])
    return tokens, i


def _header(path: str | os.PathLike, max_pixels: int) -> dict:
    """Parse the header of a PFM file and check it against the file's size and the size limits.

    Returns
    -------
    dict
        ``width``, ``height``, ``channels``, ``byteorder`` ('<' or '>'), ``scale`` (magnitude),
        ``offset`` (where the pixels start) and ``size`` (the file's size in bytes).
    """
    with open(path, "rb") as f:
        head = f.read(_MAX_HEADER)
        size = os.fstat(f.fileno()).st_size
    (magic, w, h, s), end = _tokens(head, 4)
    if magic not in _CHANNELS:
        raise FormatError(f"not a PFM file: magic {magic[:8]!r}")
    if not (w.isdigit() and h.isdigit() and len(w) <= 12 and len(h) <= 12):
        raise FormatError(f"malformed PFM header: size {w[:20]!r} x {h[:20]!r}")
    try:
        scale = float(s)
    except ValueError:
        scale = math.nan
    if not math.isfinite(scale):
        raise FormatError(f"malformed PFM header: scale {s[:20]!r}")
    width, height, channels = int(w), int(h), _CHANNELS[magic]
    check_dimensions(width, height, channels, max_pixels=max_pixels)
    needed = width * height * channels * 4
    # The scale ends with exactly one whitespace byte; a CR LF pair shows in the file's size.
    offset = end + 1
    if head[end : end + 2] == b"\r\n" and size - offset == needed + 1:
        offset += 1
    check_payload(needed, size - offset)
    return {
        "width": width,
        "height": height,
        "channels": channels,
        "byteorder": "<" if math.copysign(1.0, scale) < 0 else ">",
        "scale": abs(scale),
        "offset": offset,
        "size": size,
    }


def read(path: str | os.PathLike, *, max_pixels: int = MAX_PIXELS) -> tuple[np.ndarray, dict]:
    """Read a PFM file into memory.

    Parameters
    ----------
    path : path-like
    max_pixels : int
        Largest accepted width * height.

    Returns
    -------
    image : (H, W, C) float32
        Native byte order, C-contiguous. C is 3 for ``PF``, 1 for ``Pf``, 4 for ``PF4``; row 0
        is the top of the picture (the file's last row).
    metadata : dict
        ``format`` ('PFM'), ``stored`` ('float32'), ``byteorder`` ('<' little-endian, '>'
        big-endian) and ``scale`` (the magnitude of the header's scale).
    """
    header = _header(path, max_pixels)
    height, width, channels = shape = header["height"], header["width"], header["channels"]
    stored = np.dtype(header["byteorder"] + "f4")
    row = width * channels
    rows = max(1, min(height, _READ_BLOCK_BYTES // (4 * row)))
    image = np.empty(shape, np.float32)
    block = np.empty(rows * row, stored)
    with open(path, "rb") as f:
        f.seek(header["offset"])
        for top in range(0, height, rows):
            count = min(rows, height - top)
            part = block[: count * row]
            if f.readinto(part.view(np.uint8).data) != part.nbytes:
                raise FormatError(
                    "truncated PFM pixel data: the file is shorter than its header says (it "
                    "was truncated while being read)"
                )
            # file rows run bottom to top: this block lands reversed, above the previous one
            image[height - top - count : height - top] = part.reshape(count, width, -1)[::-1]
    metadata = {
        "format": NAME,
        "stored": "float32",
        "byteorder": header["byteorder"],
        "scale": header["scale"],
    }
    return image, metadata


def write(
    path: str | os.PathLike, image: ArrayLike, *, byteorder: str = "<", scale: float = 1.0
) -> None:
    """Write a 1- or 3-channel image as a PFM file (``Pf`` or ``PF``), rows bottom to top.

    Parameters
    ----------
    path : path-like
    image : (H, W) or (H, W, C) array, C in {1, 3}
        Converted to float32 (values outside float32's range become +-inf).
    byteorder : {'<', '>'}
        '<' little-endian (the common choice; written as a negative scale), '>' big-endian.
    scale : float
        The magnitude written in the header (positive, finite); readers mostly ignore it.
    """
    from bakeshop.errors import validate_choice
    from bakeshop.io import as_image

    validate_choice(byteorder, ("<", ">"), "PFM byte order")
    scale = float(scale)
    if not (math.isfinite(scale) and scale > 0):
        raise ArgumentError(f"the PFM scale must be positive and finite; got {scale!r}")
    image = as_image(image)
    if image.dtype.kind not in "fiub":
        raise ArgumentError(f"cannot write {image.dtype} pixels as PFM float32")
    height, width, channels = image.shape
    if channels not in _MAGIC_OF:
        raise ArgumentError(
            f"PFM stores 1 (grey) or 3 (RGB) channels, not {channels}"
            + (": drop or premultiply the alpha first (--alpha)" if channels == 4 else "")
        )
    signed = -scale if byteorder == "<" else scale
    header = f"{_MAGIC_OF[channels]}\n{width} {height}\n{signed!r}\n".encode("ascii")
    dtype = np.dtype(byteorder + "f4")
    with open(path, "wb") as f:
        f.write(header)
        for stop in range(height, 0, -_BLOCK_ROWS):
            block = image[max(stop - _BLOCK_ROWS, 0) : stop][::-1]
            f.write(np.ascontiguousarray(block, dtype=dtype).data)
