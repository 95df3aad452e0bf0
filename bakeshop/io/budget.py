"""How much one file may decode to: bakeshop's guard against decompression bombs.

Run-length and deflate coding let a small file describe a huge image: a 196 KB Radiance file
whose old-style run lengths repeat pixels 2**24 times, or a 1.6 MB zip OpenEXR of a flat
16384 x 16384 picture, each decode to 3 GiB of float32 pixels, and a few such files exhaust a
machine. Every decoder therefore states, from the header and before it allocates or decodes
anything, how many bytes it will produce and handle, and refuses when that exceeds the budget:

    budget = max(DECODE_FLOOR, DECODE_RATIO * size of the file)

that is, any file may decode to 1 GiB (an 8192 x 8192 RGB float32 image is 768 MiB), and a
larger result needs at least one byte of file per 256 bytes decoded. Real pictures stay far
below that ratio (a float32 pixel decoded from an RLE Radiance file or a zip OpenEXR costs 2 to
6 bytes of file, rarely under 1/10 of a byte even for flat regions), while bombs are built far
above it. The bytes counted are the larger of the float32 image returned and the samples the
codec must decompress to get it (an OpenEXR part's channels that are not returned still have to
be inflated; they are never converted or kept).

A larger budget, or a smaller one, is an explicit choice: ``read_image(path,
max_decoded=BYTES)`` for one read, :func:`decode_budget` for a block of code, or
``bakeshop --max-decoded SIZE COMMAND ...`` for a run of the command line. The budget bounds
the image a read returns; what a command then computes from it has its own estimates.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator

from bakeshop.errors import ArgumentError, FormatError

#: Bytes decoded per byte of file beyond which a large image is refused.
DECODE_RATIO = 256
#: Bytes any file may decode to, whatever its size (1 GiB).
DECODE_FLOOR = 1 << 30

#: The budget set by :func:`decode_budget` (None: the rule above). Process-wide on purpose:
#: threads that read images (a pool, dask's workers) see the setting of the run.
_limit: int | None = None

__all__ = ["DECODE_RATIO", "DECODE_FLOOR", "decode_budget", "decode_limit", "check_decode"]


def decode_limit(file_size: int) -> int:
    """The bytes a file of ``file_size`` bytes may decode to now (see the module notes)."""
    if _limit is not None:
        return _limit
    return max(DECODE_FLOOR, DECODE_RATIO * int(file_size))


@contextlib.contextmanager
def decode_budget(max_bytes: int | None) -> Iterator[None]:
    """Within the block, every file may decode to at most ``max_bytes`` bytes, whatever its
    size (None: the default rule, ``max(DECODE_FLOOR, DECODE_RATIO * file size)``).

    Example: ``with decode_budget(8 << 30): image = read_image("flat_16k_mask.png")``.
    """
    global _limit
    if max_bytes is not None:
        if isinstance(max_bytes, bool) or not isinstance(max_bytes, (int, float)):
            raise ArgumentError(f"the decode budget must be a number of bytes; got {max_bytes!r}")
        if not (math.isfinite(max_bytes) and max_bytes >= 1):
            raise ArgumentError(
                f"the decode budget must be a finite number of bytes >= 1; got {max_bytes!r}"
            )
        max_bytes = int(max_bytes)
    saved, _limit = _limit, max_bytes
    try:
        yield
    finally:
        _limit = saved


def check_decode(needed: int, file_size: int, what: str = "the image") -> None:
    """Refuse, before anything is allocated, a decode of ``needed`` bytes from a file of
    ``file_size`` bytes that exceeds the budget (:func:`decode_limit`).

    Raises
    ------
    bakeshop.errors.FormatError
        Saying how much the file would decode to, from how little, and how to allow it.
    """
    limit = decode_limit(file_size)
    if needed <= limit:
        return
    rule = (
        "the budget set for this run"
        if _limit is not None
        else f"max({format_bytes(DECODE_FLOOR)}, {DECODE_RATIO} x the file's size)"
    )
    raise FormatError(
        f"refused as a possible decompression bomb: {what} would decode to "
        f"{format_bytes(needed)} from {format_bytes(file_size)} of file, more than the "
        f"budget of {format_bytes(limit)} ({rule}); if the file is trusted, allow more with "
        "'bakeshop --max-decoded SIZE' or read_image(..., max_decoded=BYTES)"
    )


def format_bytes(count: int) -> str:
    """``1536`` -> ``'1.5 KiB'``: a byte count for people."""
    if count < 1024:
        return f"{count} bytes"
    value = float(count)
    for unit in ("KiB", "MiB", "GiB"):
        value /= 1024
        if value < 1024:
            return f"{value:.3g} {unit}"
    return f"{value / 1024:.3g} TiB"
