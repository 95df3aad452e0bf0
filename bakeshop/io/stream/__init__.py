"""Images larger than memory: readers that give any window of a file, writers that take strips.

>>> from bakeshop.io.stream import open_image, write_strips
>>> src = open_image("pano_32k.pfm")            # reads the header only
>>> src.shape, src.dtype                         # ((16384, 32768, 3), dtype('float32'))
>>> block = src.read((0, 256), (0, 1024))        # rows 0..255, columns 0..1023: (256, 1024, 3)
>>> write_strips("copy.zarr", src.shape, (src.read((y, y + 256)) for y in range(0, 16384, 256)))

A reader holds its file's header and nothing else: it is cheap to pickle (a dask task on another
machine opens the file again by its path), each read opens the file, reads what the window needs
and returns a float32 ``(h, w, C)`` array, row 0 at the top of the picture (DESIGN.md), whatever
the file's own order. Headers are checked against the file's size before anything is allocated,
and a window read allocates the window, never the image.

===========  ========================================================  ========================
format       how a window is read                                      writer
===========  ========================================================  ========================
.pfm         ``os.pread`` of the window's rows (file order is          strips, written at their
             bottom-up); the page cache behind is released             offsets (any order)
.hdr         an index of scanline offsets (one pass over the file,     strips, top to bottom
             8 bytes per scanline), then the window's scanlines
.exr         the OpenEXR bindings read one whole part (they have no    refused above the
             window or tile reader): files up to ``max_bytes``;        ``--memory`` bound
             larger ones are refused with the size needed
.tif .tiff   ``tifffile``: the tiles or strips the window touches      tiles (BigTIFF), strips
             (float32, float16, uint16/uint8 scaled to [0, 1])         in order
.zarr        ``zarr`` v3: the chunks the window touches (the native    chunks, by strips or by
             chunked store; dask reads it directly)                    dask tasks in parallel
===========  ========================================================  ========================

Each format is one module of this package exposing ``open(path) -> Reader`` and, where it
writes, ``write_strips(path, shape, strips, **options)``; :data:`STREAM_CODECS` maps
extensions to them (plain data).
"""

from __future__ import annotations

import importlib
import os
from collections.abc import Iterable, Iterator, Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, BakeshopError, UnsupportedError
from bakeshop.io._options import checked_options
from bakeshop.io.stream._base import ArrayReader, Reader, window_of

#: stream codec module -> the extensions it owns.
STREAM_CODECS: dict[str, tuple[str, ...]] = {
    "pfm": (".pfm",),
    "rgbe": (".hdr", ".pic", ".rgbe"),
    "exr": (".exr",),
    "tiff": (".tif", ".tiff"),
    "zarr": (".zarr",),
}

__all__ = [
    "STREAM_CODECS",
    "ArrayReader",
    "Reader",
    "open_image",
    "stream_codec_for",
    "window_of",
    "write_strips",
]


def stream_codec_for(path: str | os.PathLike) -> str:
    """The stream codec that owns ``path``'s extension; :class:`UnsupportedError` if none."""
    ext = Path(path).suffix.lower()
    for name, extensions in STREAM_CODECS.items():
        if ext in extensions:
            return name
    known = ", ".join(e for exts in STREAM_CODECS.values() for e in exts)
    raise UnsupportedError(
        f"{ext or 'no extension'}: images larger than memory are read from {known}; "
        "convert the file first (bakeshop convert)",
        path,
    )


def _module(name: str) -> ModuleType:
    return importlib.import_module(f"bakeshop.io.stream.{name}")


def open_image(path: str | os.PathLike, **options: Any) -> Reader:
    """Open an image for window reads: the header is read and checked, no pixel is.

    Parameters
    ----------
    path : path-like
        A .pfm, .hdr, .exr, .tif/.tiff file or a .zarr store.
    **options
        Passed to the format's ``open`` (for example ``max_bytes`` for OpenEXR).

    Returns
    -------
    Reader
        ``shape`` (H, W, C), ``dtype`` (float32), ``read(rows, cols)``.
    """
    name = stream_codec_for(path)
    if not Path(path).exists():
        raise BakeshopError("no such file or directory", path)
    try:
        return _module(name).open(Path(path), **options)
    except BakeshopError as e:
        if e.path is None:
            e.path = os.fspath(path)
        raise


def write_strips(
    path: str | os.PathLike, shape: Sequence[int], strips: Iterable[np.ndarray], **options: Any
) -> None:
    """Write an image of ``shape`` (H, W, C) from strips of rows, top to bottom, atomically.

    Parameters
    ----------
    path : path-like
        .pfm, .hdr, .tif/.tiff or .zarr (OpenEXR is written whole, by
        :func:`bakeshop.io.write_image`).
    shape : (int, int, int)
        The whole image's (H, W, C).
    strips : iterable of (h, W, C) arrays
        Consecutive strips whose heights add up to H; only one is held at a time.
    **options
        The format's writer options (TIFF ``tile``, ``compression``; zarr ``chunks``).
    """
    name = stream_codec_for(path)
    module = _module(name)
    if not hasattr(module, "write_strips"):
        raise UnsupportedError(
            f"{Path(path).suffix} is not written by strips; write .zarr, .tif, .pfm or .hdr "
            "(bakeshop convert turns it into any other format when it fits in memory)",
            path,
        )
    h, w, c = (int(n) for n in shape)
    if min(h, w, c) < 1:
        raise ArgumentError(f"invalid image shape {shape}", path)
    try:
        options = checked_options(module.write_strips, options, name, path)
        module.write_strips(Path(path), (h, w, c), _checked(strips, (h, w, c), path), **options)
    except BakeshopError as e:
        if e.path is None:
            e.path = os.fspath(path)
        raise


def _checked(
    strips: Iterable[ArrayLike], shape: tuple[int, int, int], path: str | os.PathLike
) -> Iterator[np.ndarray]:
    """The strips as float32 (h, W, C) arrays, refusing any that does not fit ``shape``."""
    h, w, c = shape
    done = 0
    for strip in strips:
        a = np.asarray(strip)
        if a.ndim == 2:
            a = a[:, :, None]
        if a.ndim != 3 or a.shape[1:] != (w, c) or done + a.shape[0] > h:
            raise ArgumentError(
                f"a strip of shape {a.shape} does not continue an image of shape {shape} "
                f"at row {done}",
                path,
            )
        done += a.shape[0]
        yield np.ascontiguousarray(a, dtype=np.float32)
    if done != h:
        raise ArgumentError(f"the strips cover {done} of {h} rows", path)
