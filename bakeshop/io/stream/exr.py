"""OpenEXR by strips of scanlines, through what the OpenEXR Python bindings allow.

What the bindings (``OpenEXR`` 3.x on PyPI) offer for images larger than memory:

- ``OpenEXR.File`` (the current API) reads a whole part or only its header: there is no window,
  tile or scanline-range read in it, so bakeshop uses it here for headers only;
- ``OpenEXR.InputFile``, kept by the bindings for compatibility with the 1.x API (deprecated:
  they say it will be removed), reads a range of scanlines of every channel at full width
  (``channels(names, FLOAT, y1, y2)``), converting half to float; it reads the first part of a
  file, scanline or tiled (a tiled file is read through the tiles the scanlines cross, so a strip
  costs whole rows of tiles); it cannot read a column window or another part;
- ``OpenEXR.OutputFile`` writes a scanline image strip by strip (``writePixels``, top to bottom).

So an .exr window is read as the full-width strip of its rows (columns are cut after), from the
first part, and .exr files are written by strips as scanline images. The channel set is chosen as
:mod:`bakeshop.io.exr` chooses it (R, G, B (+A), Y, or a single channel; ``layer=``).
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from types import ModuleType

import numpy as np
import OpenEXR

from bakeshop.errors import ArgumentError, UnsupportedError, validate_choice
from bakeshop.io import exr
from bakeshop.io._files import atomic_path, check_dimensions
from bakeshop.io.stream._base import Reader

#: streamed images may be this large.
MAX_PIXELS = 1 << 40


def _imath() -> ModuleType:
    import Imath  # shipped with the OpenEXR bindings, for their 1.x-compatible classes

    return Imath


class ExrReader(Reader):
    """Strip reads of the first part of an OpenEXR file (see the module docstring)."""

    format = "OpenEXR"

    def __init__(self, path: str | os.PathLike, *, layer: str | None = None) -> None:
        headers = exr._library(exr._headers, path)
        header = headers[0]
        if header["storage"].startswith("deep"):
            raise UnsupportedError("deep OpenEXR images are not supported")
        (x0, y0), (x1, y1) = header["data_window"]
        check_dimensions(x1 - x0 + 1, y1 - y0 + 1, max_pixels=MAX_PIXELS)
        names = [name for name, _, _ in header["channels"]]
        _, channels, grey_alpha = exr._pick_channels(names, layer)
        for name, xs, ys in header["channels"]:
            if name in channels and (xs != 1 or ys != 1):
                raise UnsupportedError(f"channel {name!r} is sub-sampled ({xs}x{ys})")
        self.path = os.fspath(path)
        self.channels = channels
        self.grey_alpha = grey_alpha
        self.y0 = y0
        self.shape = (y1 - y0 + 1, x1 - x0 + 1, 4 if grey_alpha else len(channels))
        self.storage = header["storage"]
        self.stored = "exr"
        self.parts = len(headers)
        self.block = (64, self.shape[1])  # zip compresses 16 scanlines, piz 32: whole blocks

    def _read(self, top: int, bottom: int, left: int, right: int) -> np.ndarray:
        imath = _imath()
        pixel = imath.PixelType(imath.PixelType.FLOAT)

        def read_planes() -> list[bytes]:
            f = OpenEXR.InputFile(self.path)
            try:
                return f.channels(self.channels, pixel, self.y0 + top, self.y0 + bottom - 1)
            finally:
                f.close()

        data = exr._library(read_planes)
        w = self.shape[1]
        planes = [np.frombuffer(p, np.float32).reshape(bottom - top, w) for p in data]
        if self.grey_alpha:
            planes = [planes[0], planes[0], planes[0], planes[1]]
        out = np.empty((bottom - top, right - left, len(planes)), np.float32)
        for i, p in enumerate(planes):
            out[:, :, i] = p[:, left:right]
        return out


def open(path: str | os.PathLike, *, layer: str | None = None) -> ExrReader:  # noqa: A001 - the codec interface
    """An :class:`ExrReader` of ``path``'s first part (header checked)."""
    return ExrReader(path, layer=layer)


def write_strips(
    path: str | os.PathLike,
    shape: tuple[int, int, int],
    strips: Iterable[np.ndarray],
    *,
    pixel_type: str = "half",
    compression: str = "zip",
) -> None:
    """Write a scanline OpenEXR file strip by strip (options as :func:`bakeshop.io.exr.write`:
    half refuses finite values beyond +-65504, naming ``pixel_type=float``)."""
    validate_choice(pixel_type, tuple(exr.PIXEL_TYPES), "EXR pixel type")
    validate_choice(compression, tuple(exr.COMPRESSIONS), "EXR compression")
    imath = _imath()
    h, w, c = shape
    if c not in (1, 3, 4):
        raise ArgumentError(f"OpenEXR images here have 1, 3 or 4 channels, not {c}")
    names = {1: "Y", 3: "RGB", 4: "RGBA"}[c]
    kind = imath.PixelType.HALF if pixel_type == "half" else imath.PixelType.FLOAT
    header = OpenEXR.Header(w, h)
    header["channels"] = {n: imath.Channel(imath.PixelType(kind)) for n in names}
    header["compression"] = imath.Compression(
        getattr(imath.Compression, exr.COMPRESSIONS[compression].name)
    )
    with atomic_path(path) as tmp:
        out = OpenEXR.OutputFile(os.fspath(tmp), header)
        try:
            for strip in strips:
                a = exr.to_half(strip, "pixel_type=float") if pixel_type == "half" else strip
                out.writePixels(
                    {n: np.ascontiguousarray(a[:, :, i]).tobytes() for i, n in enumerate(names)},
                    strip.shape[0],
                )
        finally:
            out.close()
