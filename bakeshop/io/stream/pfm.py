"""PFM by windows: ``os.pread`` of the rows a window needs, nothing mapped, nothing cached.

PFM stores rows bottom to top, so picture rows ``top..bottom`` are the file's rows
``H - bottom .. H - top``, one contiguous run of bytes: a window is one ``pread`` of those rows
(whole rows; a narrow window of very wide rows is read row by row, only its columns), flipped on
the way in. After a read the kernel is told that those pages will not be needed again
(``posix_fadvise(DONTNEED)``), so a pass over a file larger than memory does not fill the page
cache with it. Writing puts each strip at its own offset in a file of the final size, so strips
may come in any order (the reader's order, top to bottom, writes the file back to front).
"""

from __future__ import annotations

import os
import sys
from collections.abc import Iterable

import numpy as np

from bakeshop.errors import ArgumentError, FormatError
from bakeshop.io import pfm
from bakeshop.io._files import atomic_path
from bakeshop.io.stream._base import Reader

_NATIVE = "<" if sys.byteorder == "little" else ">"
#: a window narrower than this fraction of a row is read row by row (only its columns).
_NARROW = 0.25
#: streamed images may be this large (the in-memory limit of bakeshop.io does not apply).
MAX_PIXELS = 1 << 40


def _release(fd: int, offset: int, length: int) -> None:
    if hasattr(os, "posix_fadvise"):
        os.posix_fadvise(fd, offset, length, os.POSIX_FADV_DONTNEED)


class PfmReader(Reader):
    """Window reads of a PFM file (see the module docstring)."""

    format = "PFM"
    path: str

    def __init__(self, path: str | os.PathLike) -> None:
        header = pfm._header(path, MAX_PIXELS)
        self.path = os.fspath(path)
        self.shape = (header["height"], header["width"], header["channels"])
        self.offset = header["offset"]
        self.file_dtype = np.dtype(header["byteorder"] + "f4")
        self.byteorder = header["byteorder"]
        self.scale = header["scale"]
        self.block = (max(1, (1 << 22) // (self.shape[1] * self.shape[2] * 4)), self.shape[1])

    def _read(self, top: int, bottom: int, left: int, right: int) -> np.ndarray:
        h, w, c = self.shape
        row_bytes = w * c * 4
        out = np.empty((bottom - top, right - left, c), np.float32)
        fd = os.open(self.path, os.O_RDONLY)
        try:
            first = h - bottom  # the file's first row of the window
            if (right - left) >= _NARROW * w:
                buf = np.empty((bottom - top) * w * c, self.file_dtype)
                _pread_into(fd, buf, self.offset + first * row_bytes)
                rows = buf.reshape(bottom - top, w, c)[::-1, left:right]
                out[...] = rows  # byte order converted here if the file's is not native
            else:
                buf = np.empty((right - left) * c, self.file_dtype)
                for k in range(bottom - top):
                    at = self.offset + (first + k) * row_bytes + left * c * 4
                    _pread_into(fd, buf, at)
                    out[bottom - top - 1 - k] = buf.reshape(right - left, c)
            _release(fd, self.offset + first * row_bytes, (bottom - top) * row_bytes)
        finally:
            os.close(fd)
        return out


def _pread_into(fd: int, buf: np.ndarray, offset: int) -> None:
    view = buf.data.cast("B")
    done = 0
    while done < len(view):
        n = os.preadv(fd, [view[done:]], offset + done)
        if n <= 0:
            raise FormatError("truncated PFM pixel data")
        done += n


def open(path: str | os.PathLike) -> PfmReader:  # noqa: A001 - the codec interface's name
    """A :class:`PfmReader` of ``path`` (its header checked against the file's size)."""
    return PfmReader(path)


def write_strips(
    path: str | os.PathLike,
    shape: tuple[int, int, int],
    strips: Iterable[np.ndarray],
    *,
    byteorder: str = "<",
    scale: float = 1.0,
) -> None:
    """Write a 1- or 3-channel PFM from strips top to bottom, each at its place in the file."""
    from bakeshop.errors import validate_choice

    validate_choice(byteorder, ("<", ">"), "PFM byte order")
    h, w, c = shape
    if c not in (1, 3):
        raise ArgumentError(f"PFM stores 1 (grey) or 3 (RGB) channels, not {c}")
    signed = -abs(float(scale)) if byteorder == "<" else abs(float(scale))
    header = f"{'PF' if c == 3 else 'Pf'}\n{w} {h}\n{signed!r}\n".encode("ascii")
    dtype = np.dtype(byteorder + "f4")
    row_bytes = w * c * 4
    with atomic_path(path) as tmp:
        fd = os.open(tmp, os.O_WRONLY)
        try:
            os.write(fd, header)
            os.ftruncate(fd, len(header) + h * row_bytes)
            top = 0
            for strip in strips:
                n = strip.shape[0]
                data = np.ascontiguousarray(strip[::-1], dtype=dtype)
                at = len(header) + (h - top - n) * row_bytes
                view = data.data.cast("B")
                done = 0
                while done < len(view):
                    done += os.pwrite(fd, view[done:], at + done)
                _release(fd, at, len(view))
                top += n
            os.fsync(fd)
        finally:
            os.close(fd)
