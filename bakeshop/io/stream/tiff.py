"""(Big)TIFF by windows through ``tifffile``: the tiles or strips a window touches.

Float32 and float16 samples are read as they are; 8- and 16-bit unsigned samples are scaled to
[0, 1] (as the in-memory readers of 8/16-bit formats do: display-encoded values, never
linearised here). The first page (series 0, level 0) is the image. Writing makes a tiled
BigTIFF of float32 (or float16) samples from strips: tiles of ``tile`` rows are cut from each
band of rows as it arrives, so strips are held one band at a time.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Iterator
from types import ModuleType

import numpy as np

from bakeshop.errors import FormatError, UnsupportedError
from bakeshop.io._files import atomic_path, check_dimensions
from bakeshop.io.stream._base import Reader

#: streamed images may be this large.
MAX_PIXELS = 1 << 40

_SCALE = {np.dtype(np.uint8): 1 / 255, np.dtype(np.uint16): 1 / 65535}


def _tifffile() -> ModuleType:
    try:
        import tifffile
    except ImportError:  # pragma: no cover - depends on the installation
        raise UnsupportedError(
            "reading and writing TIFF needs tifffile: install bakeshop[huge]"
        ) from None
    return tifffile


class TiffReader(Reader):
    """Window reads of the first image of a TIFF or BigTIFF file."""

    format = "TIFF"

    def __init__(self, path: str | os.PathLike) -> None:
        tifffile = _tifffile()
        try:
            with tifffile.TiffFile(path) as t:
                page = t.pages.first
                shape, dtype, axes = page.shape, page.dtype, page.axes
                tiled = page.is_tiled
                block = (page.tilelength, page.tilewidth) if tiled else (page.rowsperstrip, 0)
                self.bigtiff = t.is_bigtiff
        except (tifffile.TiffFileError, ValueError, OSError, IndexError) as e:
            raise FormatError(f"not a readable TIFF file ({e})") from None
        if axes not in ("YX", "YXS"):
            raise UnsupportedError(f"TIFF images with axes {axes!r} are not read here (YX, YXS)")
        if dtype.kind != "f" and dtype not in _SCALE:
            raise UnsupportedError(f"TIFF samples of type {dtype} are not supported")
        h, w = shape[:2]
        c = shape[2] if len(shape) == 3 else 1
        check_dimensions(w, h, c, max_pixels=MAX_PIXELS)
        if not 1 <= c <= 4:
            raise UnsupportedError(f"TIFF images of {c} samples per pixel are not supported")
        self.path = os.fspath(path)
        self.shape = (h, w, c)
        self.stored = str(dtype)
        self.block = (min(int(block[0]), h), min(int(block[1]) or w, w))
        # a tile or strip is inflated whole, from its compressed bytes (at most as many)
        self.read_floor = 2 * self.block[0] * self.block[1] * c * dtype.itemsize

    def _read(self, top: int, bottom: int, left: int, right: int) -> np.ndarray:
        tifffile = _tifffile()
        a = tifffile.imread(self.path, selection=(slice(top, bottom), slice(left, right)))
        a = a.reshape(bottom - top, right - left, self.shape[2])
        scale = _SCALE.get(a.dtype)
        out = a.astype(np.float32)
        if scale is not None:
            out *= np.float32(scale)
        return out


def open(path: str | os.PathLike) -> TiffReader:  # noqa: A001 - the codec interface's name
    """A :class:`TiffReader` of ``path``."""
    return TiffReader(path)


def write_strips(
    path: str | os.PathLike,
    shape: tuple[int, int, int],
    strips: Iterable[np.ndarray],
    *,
    tile: int = 256,
    compression: str | None = None,
    pixel_type: str = "float",
) -> None:
    """Write a tiled BigTIFF of float samples from strips (``tile`` x ``tile`` tiles;
    ``compression`` as tifffile names it: None, ``"zlib"``, ``"zstd"`` ...). Half refuses
    finite values beyond +-65504, naming ``pixel_type=float``."""
    tifffile = _tifffile()
    h, w, c = shape
    dtype = np.float16 if pixel_type == "half" else np.float32
    if pixel_type == "half":
        from bakeshop.io.exr import check_half

        strips = (check_half(s, "pixel_type=float") for s in strips)

    def row_of_tiles(rows: np.ndarray) -> Iterator[np.ndarray]:
        for x in range(0, w, tile):
            t = np.ascontiguousarray(rows[:, x : x + tile], dtype=dtype)
            yield t[:, :, 0] if c == 1 else t

    def tiles() -> Iterator[np.ndarray]:
        band = np.empty((0, w, c), np.float32)
        for strip in strips:
            band = np.concatenate([band, strip])
            while band.shape[0] >= tile:
                yield from row_of_tiles(band[:tile])
                band = band[tile:]
        if band.shape[0]:
            yield from row_of_tiles(band)

    photometric = "rgb" if c in (3, 4) else "minisblack"
    extrasamples = ("unassalpha",) if c == 4 else None
    with atomic_path(path) as tmp:
        tifffile.imwrite(
            tmp,
            tiles(),
            shape=(h, w, c) if c > 1 else (h, w),
            dtype=dtype,
            tile=(tile, tile),
            bigtiff=True,
            photometric=photometric,
            extrasamples=extrasamples,
            compression=compression,
        )
