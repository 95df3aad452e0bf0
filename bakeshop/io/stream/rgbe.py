"""Radiance .hdr by windows: an index of scanline offsets, then only the window's scanlines.

Run-length encoded scanlines have no fixed size, so the first read walks the file once in blocks
of :data:`SCAN_BYTES` (nothing decoded, nothing held but the block) and records where each
scanline starts (opening reads the header only): 8 bytes per scanline, 128 KB for a 16384-row
image. A window then reads the bytes of its scanlines and decodes them with the in-memory
codec's decoder (:mod:`bakeshop.io.rgbe`), so a window is bit-identical to the same texels of a
whole read. Old-style run-length files, whose first pixel of a scanline may repeat the last one
of the previous scanline, decode one scanline more before the window. Files stored with
scanlines along columns (``+X``/``-X`` first in the resolution string, rare) are refused: a
window of rows would need every scanline.

Writing encodes strip after strip (new-style run-length, as the in-memory writer does).
"""

from __future__ import annotations

import builtins
import functools
import os
import threading
from collections.abc import Iterable

import numpy as np

from bakeshop.errors import FormatError, UnsupportedError
from bakeshop.io import _native, rgbe
from bakeshop.io._files import atomic_path, check_dimensions, check_payload
from bakeshop.io.stream._base import Reader

#: held while a reader walks its file's scanlines (once per reader, whichever thread reads
#: first).
_INDEXING = threading.Lock()
#: bytes read per step while indexing the scanlines.
SCAN_BYTES = 1 << 24
#: streamed images may be this large.
MAX_PIXELS = 1 << 40


_PROBLEMS = {
    1: "its run-length header gives another scanline length than the resolution string",
    2: "a run of length 0",
    3: "a run overruns the end of the scanline",
}


class RgbeReader(Reader):
    """Window reads of a Radiance file (see the module docstring)."""

    format = "Radiance HDR"
    stored = "rgbe"
    path: str

    def __init__(self, path: str | os.PathLike, *, raw: bool = False) -> None:
        self.path = os.fspath(path)
        size = os.path.getsize(path)
        with builtins.open(path, "rb") as f:
            head = np.frombuffer(f.read(rgbe._MAX_HEADER), np.uint8)
        facts, offset = rgbe._header(head)
        width, height = facts["width"], facts["height"]
        check_dimensions(width, height, 3, max_pixels=MAX_PIXELS)
        if not facts["ymajor"]:
            raise UnsupportedError(
                f"scanlines along columns ({facts['orientation']}) cannot be read by rows; "
                "convert the file in memory first"
            )
        check_payload(4 * height, size - offset, "scanlines (at least 4 bytes each)")
        self.shape = (height, width, 3)
        self.stored = facts["stored"]
        self.flip_rows = facts["ysign"] == "+"
        self.flip_cols = facts["xsign"] == "-"
        self.factors = np.ones(3, np.float64)
        if not raw:
            self.factors /= facts["exposure"] * np.asarray(facts["colorcorr"])
        self.metadata = facts
        self.block = (max(1, (1 << 22) // (4 * width)), width)
        self._extent = (offset, size)

    @functools.cached_property
    def starts(self) -> np.ndarray:
        """File offsets of the scanlines in file order, plus the end of the last one (the
        file walked on the first read; threads reading at once wait for one walk)."""
        with _INDEXING:
            if "starts" in self.__dict__:  # made by the thread this one waited for
                return self.__dict__["starts"]
            return self._walk()

    def _walk(self) -> np.ndarray:
        offset, size = self._extent
        height, width, _ = self.shape
        starts = np.empty(height + 1, np.int64)
        done, pos = 0, offset
        with builtins.open(self.path, "rb") as f:
            while done < height:
                f.seek(pos)
                data = np.frombuffer(f.read(SCAN_BYTES), np.uint8)
                walked, end, status = _native.rgbe_scan(
                    data, 0, width, height - done, starts[done:], pos
                )
                if status:
                    raise FormatError(
                        f"corrupt pixel data in scanline {done + walked + 1} of {height}: "
                        f"{_PROBLEMS[status]}"
                    )
                if walked == 0:
                    if len(data) < SCAN_BYTES:
                        raise FormatError(
                            f"truncated file: the data ends inside scanline {done + 1} of {height}"
                        )
                    raise FormatError(f"scanline {done + 1} is longer than {SCAN_BYTES} bytes")
                done += walked
                pos += end
            if hasattr(os, "posix_fadvise"):
                os.posix_fadvise(f.fileno(), 0, 0, os.POSIX_FADV_DONTNEED)
        starts[height] = pos
        return starts

    def __getstate__(self) -> dict:
        """Pickled with its index (made here if no read made it yet), so that the tasks that
        unpickle the reader do not each walk the file."""
        self.starts  # noqa: B018 - the cached index
        return self.__dict__

    def _read(self, top: int, bottom: int, left: int, right: int) -> np.ndarray:
        height, width, _ = self.shape
        # the window's scanlines in file order
        first, last = (height - bottom, height - top) if self.flip_rows else (top, bottom)
        lead = 1 if first > 0 else 0  # the previous scanline, for old-style repeats
        begin, end = self.starts[first - lead], self.starts[last]
        with builtins.open(self.path, "rb") as f:
            f.seek(begin)
            data = np.frombuffer(f.read(end - begin), np.uint8)
            if hasattr(os, "posix_fadvise"):
                os.posix_fadvise(f.fileno(), begin, end - begin, os.POSIX_FADV_DONTNEED)
        if len(data) != end - begin:
            raise FormatError("the file was truncated while it was being read")
        lines = np.empty((last - first + lead, width, 3), np.float32)
        status = rgbe._decode(data, 0, last - first + lead, width, lines, self.factors, False)
        rgbe._check(status, last - first + lead)
        lines = lines[lead:]
        if self.flip_rows:
            lines = lines[::-1]
        if self.flip_cols:
            lines = lines[:, ::-1]
        out = np.ascontiguousarray(lines[:, left:right])
        if self.stored == "xyze":
            rgbe._to_rgb(out)
        return out


def open(path: str | os.PathLike, *, raw: bool = False) -> RgbeReader:  # noqa: A001 - the codec interface's name
    """A :class:`RgbeReader` of ``path`` (header checked; the scanlines are indexed on the
    first read)."""
    return RgbeReader(path, raw=raw)


def write_strips(
    path: str | os.PathLike,
    shape: tuple[int, int, int],
    strips: Iterable[np.ndarray],
    *,
    rle: bool = True,
) -> None:
    """Write a Radiance RGBE file strip by strip, scanlines top to bottom (``-Y H +X W``)."""
    h, w, c = shape
    if c not in (1, 3):
        raise UnsupportedError(f"Radiance .hdr stores RGB, not {c} channels")
    rle = bool(rle) and rgbe._RLE_MIN <= w <= rgbe._RLE_MAX
    header = f"#?RADIANCE\nSOFTWARE=bakeshop\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n"
    with atomic_path(path) as tmp, builtins.open(tmp, "wb") as f:
        f.write(header.encode("ascii"))
        for strip in strips:
            for chunk in rgbe._scanlines(np.ascontiguousarray(strip, dtype=np.float32), rle):
                f.write(chunk)
