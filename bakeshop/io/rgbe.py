"""Radiance picture files (.hdr, .pic): RGBE and XYZE pixels, flat or run-length encoded.

A file is a text header, a resolution string and the pixels (Ward, "Real Pixels", Graphics Gems
II, 1991, doi:10.1016/B978-0-08-050754-5.50025-2; the Radiance reference manual, "Radiance file
formats")::

    #?RADIANCE                    magic: "#?" then the writing program's name
    FORMAT=32-bit_rle_rgbe        or 32-bit_rle_xyze; lines of VARIABLE=value or comments
    EXPOSURE=2.0                  optional, may repeat
                                  a blank line ends the header
    -Y 512 +X 1024                the resolution string: orientation and size
    <scanlines>

Each pixel is four bytes: three mantissas sharing one exponent byte. bakeshop decodes with
Radiance's own reconstruction, ``(m + 0.5) * 2**(e - 136)`` (zero when ``e == 0``): the centre
of the interval of values the bytes stand for.

Scanlines are stored flat (4 bytes per pixel), in the old run-length form (a pixel ``1, 1, 1, n``
repeats the previous pixel ``n << shift`` times, the shift growing by 8 for each consecutive
repeat pixel), or in the new form (``2, 2, hi, lo`` then each of the four byte planes as runs and
literals), chosen per scanline exactly as Radiance's reader chooses.
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, FormatError, UnsupportedError
from bakeshop.io import _native
from bakeshop.io._files import MAX_PIXELS, check_dimensions, check_payload
from bakeshop.io.budget import check_decode

NAME = "Radiance HDR"

#: Scanline lengths that the new run-length form can encode (Radiance's MINELEN, MAXELEN).
_RLE_MIN, _RLE_MAX = 8, 0x7FFF
# Status codes of the decoder (src/io/rgbe.hpp).
_OK, _TRUNCATED, _OVERRUN, _EMPTY_RUN, _LENGTH, _NO_PREVIOUS = range(6)

#: Radiance's standard primaries (``STDPRIMS`` in its ``color.h``): CIE xy of red, green, blue and
#: the white point (equal-energy white E).
RADIANCE_PRIMARIES = ((0.640, 0.330), (0.290, 0.600), (0.150, 0.060), (1 / 3, 1 / 3))


def _xyz_to_rgb(primaries: Sequence[tuple[float, float]]) -> np.ndarray:
    """The CIE XYZ -> linear RGB matrix of ``primaries`` ((x, y) of R, G, B, white), scaled so
    that the white point with Y = 1 maps to RGB (1, 1, 1): the derivation of Radiance's
    ``compxyz2rgbmat``."""
    xy = np.array(primaries, dtype=np.float64)
    xyz = np.column_stack([xy[:, 0] / xy[:, 1], np.ones(4), (1 - xy.sum(axis=1)) / xy[:, 1]])
    columns = xyz[:3].T  # XYZ of each primary at Y = 1, as columns
    weights = np.linalg.solve(columns, xyz[3])
    return np.linalg.inv(columns * weights)


#: CIE XYZ -> linear RGB with :data:`RADIANCE_PRIMARIES`, applied to XYZE files on read.
XYZ_TO_RGB = _xyz_to_rgb(RADIANCE_PRIMARIES)

#: Where the header must have ended (Radiance headers carry the history of commands applied).
_MAX_HEADER = 1 << 20
_RESOLUTION = re.compile(rb"\s*([-+])([XY])\s+(\d{1,12})\s+([-+])([XY])\s+(\d{1,12})\s*")
_FORMATS = {b"32-bit_rle_rgbe": "rgbe", b"32-bit_rle_xyze": "xyze"}
_PROBLEMS = {
    _TRUNCATED: "the file ends inside the scanline",
    _OVERRUN: "a run overruns the end of the scanline",
    _EMPTY_RUN: "a run of length 0",
    _LENGTH: "its run-length header gives another scanline length than the resolution string",
    _NO_PREVIOUS: "an old-style repeat with no previous pixel",
}


def sniff(head: bytes) -> bool:
    """True if ``head`` starts like a Radiance file: ``#?`` and a program name (``#?RADIANCE``,
    ``#?RGBE``, or whatever program wrote it)."""
    return head.startswith(b"#?")


def _header(data: np.ndarray) -> tuple[dict, int]:
    """Parse the header and resolution string; return the facts and the offset of the pixels."""
    head = data[:_MAX_HEADER].tobytes()
    if not head.startswith(b"#?"):
        raise FormatError("not a Radiance file (it does not start with '#?')")
    position = 0
    lines: list[bytes] = []
    while True:
        end = head.find(b"\n", position)
        if end < 0:
            what = "has no end" if len(head) >= _MAX_HEADER else "is truncated"
            raise FormatError(f"the Radiance header {what}")
        line = head[position:end].rstrip(b"\r")
        position = end + 1
        if not line and lines:
            break
        lines.append(line)
    end = head.find(b"\n", position)
    if end < 0:
        raise FormatError("truncated file: no resolution string after the header")
    resolution = head[position:end].rstrip(b"\r")
    match = _RESOLUTION.fullmatch(resolution)
    if match is None or match[2] == match[5]:
        raise FormatError(f"malformed resolution string {resolution[:40]!r}")
    facts = _variables(lines)
    ymajor = match[2] == b"Y"
    sizes = {match[2]: int(match[3]), match[5]: int(match[6])}
    signs = {match[2]: match[1].decode(), match[5]: match[4].decode()}
    facts.update(
        width=sizes[b"X"],
        height=sizes[b"Y"],
        ymajor=ymajor,
        xsign=signs[b"X"],
        ysign=signs[b"Y"],
        orientation=" ".join(m.decode() for m in (match[1] + match[2], match[4] + match[5])),
    )
    return facts, end + 1


def _numbers(value: bytes, count: int, name: str, *, positive: bool = True) -> list[float]:
    """``count`` finite numbers (positive ones if ``positive``) from a header value."""
    try:
        numbers = [float(v) for v in value.split()]
    except ValueError:
        numbers = []
    valid = [math.isfinite(v) and (v > 0 or not positive) for v in numbers]
    if len(numbers) != count or not all(valid):
        raise FormatError(f"invalid {name} line in the header: {value[:60]!r}")
    return numbers


def _variables(lines: list[bytes]) -> dict:
    """The meaning of the header lines (the first is the ``#?PROGRAM`` magic)."""
    facts: dict[str, Any] = {
        "program": lines[0][2:].decode("latin-1").strip(),
        "stored": "rgbe",
        "exposure": 1.0,
        "colorcorr": [1.0, 1.0, 1.0],
        "header": [line.decode("latin-1") for line in lines[1:]],
    }
    for line in lines[1:]:
        key, sep, value = line.strip().partition(b"=")
        if not sep:
            continue
        if key == b"FORMAT":
            value = value.strip()
            if value not in _FORMATS:
                raise UnsupportedError(
                    f"Radiance pixel format {value[:40].decode('latin-1')!r} is not supported "
                    "(only 32-bit_rle_rgbe and 32-bit_rle_xyze)"
                )
            facts["stored"] = _FORMATS[value]
        elif key == b"EXPOSURE":
            facts["exposure"] *= _numbers(value, 1, "EXPOSURE")[0]
        elif key == b"COLORCORR":
            corr = _numbers(value, 3, "COLORCORR")
            facts["colorcorr"] = [a * b for a, b in zip(facts["colorcorr"], corr, strict=True)]
        elif key == b"PRIMARIES":
            facts["primaries"] = tuple(_numbers(value, 8, "PRIMARIES", positive=False))
        elif key == b"PIXASPECT":
            facts["pixaspect"] = facts.get("pixaspect", 1.0) * _numbers(value, 1, "PIXASPECT")[0]
    return facts


def _decode(
    data: np.ndarray,
    pos: int,
    nscan: int,
    scanlen: int,
    out: np.ndarray,
    factors: np.ndarray,
    dry: bool,
) -> tuple[int, int, int]:
    """Decode ``nscan`` scanlines of ``scanlen`` pixels from ``data[pos:]`` (uint8) into
    ``out[scan, pixel, channel]`` (float32, any strides), multiplying channel c by ``factors[c]``
    (``(m + 0.5) * 2**(e - 136) * factor`` in float64, rounded once to float32).

    The compiled decoder (``src/io/rgbe.hpp``): a file of new-style scanlines is decoded in parts
    on every thread (the scanlines located first, their packet headers only; a part starts at a
    new-style scanline, which never refers to the one before); anything else (a dry pass,
    old-style or faulty scanlines) serially, which reports what is wrong. With ``dry`` nothing is
    written: the pass only checks that the data holds the whole image. Returns (status,
    scanline, position after the last byte used)."""
    status, scanline, end = _native.rgbe_decode(
        data, int(pos), int(nscan), int(scanlen), out, factors, bool(dry)
    )
    return status, scanline, end


def read(
    path: str | os.PathLike, *, raw: bool = False, max_pixels: int = MAX_PIXELS
) -> tuple[np.ndarray, dict]:
    """Read a Radiance .hdr / .pic file.

    Parameters
    ----------
    path : path-like
    raw : bool
        False (default): pixel values are divided by the product of the header's ``EXPOSURE``
        lines and, per channel, of its ``COLORCORR`` lines, giving back the radiance that was
        rendered or captured before a tool (pfilt, an exposure slider) scaled it, as Radiance
        defines them. True: the stored values as they are.
    max_pixels : int
        Largest accepted width * height.

    Returns
    -------
    image : (H, W, 3) float32
        Linear RGB, row 0 at the top, whatever the file's orientation. XYZE files are converted
        to RGB with Radiance's standard primaries (:data:`XYZ_TO_RGB`).
    metadata : dict
        ``format``; ``stored`` ('rgbe' or 'xyze'); ``program`` (after ``#?``); ``exposure``
        (product of the EXPOSURE lines, 1 if none); ``colorcorr`` (per-channel product of the
        COLORCORR lines); ``primaries`` (the 8 numbers of a PRIMARIES line, when there is one:
        kept, not applied); ``pixaspect`` when given; ``orientation`` (the resolution string's
        axes, e.g. '-Y +X'); ``raw``; ``converted`` ('XYZ to RGB with Radiance's standard
        primaries', XYZE files only); ``header`` (every header line after the magic).
    """
    try:
        data = np.fromfile(path, dtype=np.uint8)
    except OSError as e:
        raise FormatError(f"cannot read the file: {e.strerror or e}") from None
    facts, offset = _header(data)
    width, height = facts["width"], facts["height"]
    check_dimensions(width, height, 3, max_pixels=max_pixels)
    # Old-style runs repeat a pixel up to 2**24 times per 12 bytes: bound the decode by the
    # file's size before any pass over the runs (the dry pass below included).
    check_decode(width * height * 3 * 4, data.size)
    nscan, scanlen = (height, width) if facts["ymajor"] else (width, height)
    available = data.size - offset
    check_payload(4 * nscan, available, "scanlines (at least 4 bytes each)")
    factors = np.ones(3, np.float64)
    if not raw:
        factors /= facts["exposure"] * np.asarray(facts["colorcorr"])
    # Run lengths let a small file describe a large image. When the file is smaller than the
    # most compact new-style encoding of the image, a first pass that allocates nothing checks
    # that the data really covers the image before the image is allocated.
    if _RLE_MIN <= scanlen <= _RLE_MAX:
        least = nscan * (4 + 8 * -(-scanlen // 127))
    else:
        least = 4 * nscan * scanlen
    if available < least:
        nothing = np.empty((1, 1, 3), np.float32)
        _check(_decode(data, offset, nscan, scanlen, nothing, factors, True), nscan)
    image = np.empty((height, width, 3), np.float32)
    view = image
    if facts["ysign"] == "+":
        view = view[::-1]
    if facts["xsign"] == "-":
        view = view[:, ::-1]
    if not facts["ymajor"]:
        view = view.transpose(1, 0, 2)
    _check(_decode(data, offset, nscan, scanlen, view, factors, False), nscan)
    metadata = {
        "format": NAME,
        "stored": facts["stored"],
        "program": facts["program"],
        "exposure": facts["exposure"],
        "colorcorr": tuple(facts["colorcorr"]),
        "orientation": facts["orientation"],
        "raw": bool(raw),
        "header": facts["header"],
    }
    for key in ("primaries", "pixaspect"):
        if key in facts:
            metadata[key] = facts[key]
    if facts["stored"] == "xyze":
        _to_rgb(image)
        metadata["converted"] = "XYZ to RGB with Radiance's standard primaries"
    return image, metadata


def _check(result: tuple[int, int, int], nscan: int) -> None:
    status, scanline, _ = result
    if status != _OK:
        raise FormatError(
            f"corrupt pixel data in scanline {scanline + 1} of {nscan}: {_PROBLEMS[status]}"
        )


def _to_rgb(image: np.ndarray, rows: int = 256) -> None:
    """XYZ -> RGB in place, in float64 blocks of rows (one rounding, no copy of the image)."""
    for top in range(0, image.shape[0], rows):
        image[top : top + rows] = image[top : top + rows].astype(np.float64) @ XYZ_TO_RGB.T


def write(path: str | os.PathLike, image: ArrayLike, *, rle: bool = True) -> None:
    """Write a Radiance RGBE file, scanlines top to bottom (``-Y H +X W``).

    Parameters
    ----------
    path : path-like
    image : (H, W) or (H, W, C) array, C in {1, 3}
        Linear values; grey is written as R = G = B. Negative values and NaN are written as 0;
        values beyond RGBE's largest (about 1.7e38, infinities included) saturate to it;
        values below 2**-128 become 0. Everything else is stored with the mantissas and exponent
        closest to it under the (m + 0.5) reconstruction: the error is at most half a step of
        the pixel's largest component's exponent, ``2**(e - 137)``.
    rle : bool
        True (default): new-style run-length encoding, or flat scanlines where the width is
        outside 8..32767, which that encoding cannot represent. False: flat scanlines.
    """
    from bakeshop.io import as_image

    image = as_image(image)
    if image.dtype.kind not in "fiub":
        raise ArgumentError(f"cannot write {image.dtype} pixels as Radiance RGBE")
    height, width, channels = image.shape
    if channels not in (1, 3):
        raise ArgumentError(
            f"Radiance .hdr stores RGB, not {channels} channels"
            + (": drop or premultiply the alpha first (--alpha)" if channels == 4 else "")
        )
    rle = bool(rle) and _RLE_MIN <= width <= _RLE_MAX
    chunks = _scanlines(np.ascontiguousarray(image, dtype=np.float32), rle)
    header = f"#?RADIANCE\nSOFTWARE=bakeshop\nFORMAT=32-bit_rle_rgbe\n\n-Y {height} +X {width}\n"
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.writelines(chunks)


#: scanlines per task of the parallel encoder.
_BLOCK_ROWS = 32


def _scanlines(image: np.ndarray, rle: bool) -> list[memoryview]:
    """The encoded scanlines of a C-contiguous (H, W, C) float32 image, C in {1, 3}, as the
    consecutive pieces of the file that the parallel encoder made (no copy): blocks of
    :data:`_BLOCK_ROWS` scanlines, each encoded into its own part of one buffer sized for the
    worst case (pages never written are never touched)."""
    height, width, _ = image.shape
    per_line = 4 + 4 * (width + (width + 127) // 128) if rle else 4 * width
    encoded = np.empty(height * per_line, np.uint8)
    blocks = -(-height // _BLOCK_ROWS)
    starts, stops = np.empty(blocks, np.int64), np.empty(blocks, np.int64)
    _native.rgbe_encode(image, rle, _BLOCK_ROWS, encoded, starts, stops)
    return [encoded[a:b].data for a, b in zip(starts.tolist(), stops.tolist(), strict=True)]
