"""TIFF and BigTIFF through tifffile: 8- and 16-bit integer and 16/32-bit float samples.

Reading returns the first image of the file (the first series of tifffile: the full-resolution
page, not a thumbnail or a reduced pyramid level) as ``(H, W, C)`` float32, C in {1, 3, 4}:

==========================  ===================================================
stored                      image
==========================  ===================================================
uint8, uint16               ``v / 255``, ``v / 65535`` (no transfer function)
float16, float32, float64   the values, as float32 (linear data stays linear)
grey + alpha (2 samples)    ``(H, W, 4)``: grey copied to R, G, B, then A
planar (one plane per       transposed to interleaved ``(H, W, C)``
sample)
==========================  ===================================================

Uncompressed and deflate (``zlib``) TIFFs are decoded by tifffile alone; LZW, PackBits, JPEG
and the other compressions need the ``imagecodecs`` package (``pip install bakeshop[tiff]``),
and a file that needs it without it is refused with that hint. The header's size is checked
against bakeshop's limits and the decode budget (:mod:`bakeshop.io.budget`: the larger of the
samples tifffile decompresses and the float32 image returned) before any pixel is decoded.

Writing: ``bits`` 8, 16 (unsigned integers, scaled from [0, 1] floats as PNG does) or 32
(float32 samples, the default for float input: an HDR TIFF); ``compression`` ``"zlib"``
(default, lossless) or ``"none"``. One image per file, contiguous samples, RGB(A) or
minisblack photometric.

Reference: Adobe, TIFF Revision 6.0 (1992); tifffile by Christoph Gohlke.
"""

from __future__ import annotations

import os
from types import ModuleType

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, BakeshopError, FormatError, UnsupportedError
from bakeshop.io._files import MAX_PIXELS, check_dimensions
from bakeshop.io._quantize import float_to_unsigned, unsigned_to_float
from bakeshop.io.budget import check_decode

NAME = "TIFF"

#: little- and big-endian TIFF, then BigTIFF.
MAGICS = (b"II*\x00", b"MM\x00*", b"II+\x00", b"MM\x00+")

#: compressions tifffile decodes without imagecodecs (codes of TIFF tag 259).
_BUILTIN_COMPRESSIONS = {1: "none", 8: "zlib", 32946: "zlib"}

_COMPRESSIONS = {"none": None, "zlib": "zlib"}


def sniff(head: bytes) -> bool:
    """True for the TIFF or BigTIFF byte-order mark and version number."""
    return head[:4] in MAGICS


def _tifffile() -> ModuleType:
    try:
        import tifffile
    except ImportError:  # pragma: no cover - a base dependency
        raise UnsupportedError("reading TIFF needs tifffile: pip install tifffile") from None
    return tifffile


def _imagecodecs_available() -> bool:
    try:
        import imagecodecs  # noqa: F401
    except ImportError:
        return False
    return True


def read(path: str | os.PathLike, *, max_pixels: int = MAX_PIXELS) -> tuple[np.ndarray, dict]:
    """Read the first image of a TIFF or BigTIFF file.

    Returns
    -------
    image : (H, W, C) float32
        See the module notes for how samples become values.
    metadata : dict
        ``format`` (``"TIFF"`` or ``"BigTIFF"``), ``stored`` (the sample dtype, ``"uint16"``...),
        ``bits``, ``compression`` (its name), ``photometric``, ``planar`` (bool).
    """
    tifffile = _tifffile()
    try:
        with tifffile.TiffFile(path) as tif:
            if not tif.series:
                raise FormatError("the TIFF holds no image")
            series = tif.series[0]
            page = series.pages[0] if series.pages else tif.pages[0]
            width, height = int(page.imagewidth), int(page.imagelength)
            check_dimensions(width, height, max_pixels=max_pixels)
            code = int(page.compression)
            if code not in _BUILTIN_COMPRESSIONS and not _imagecodecs_available():
                raise UnsupportedError(
                    f"this TIFF is {page.compression.name}-compressed, which needs the "
                    "imagecodecs package: pip install bakeshop[tiff]"
                )
            samples = int(np.prod(series.shape)) // (width * height)
            returned = width * height * (4 if samples == 2 else samples) * 4
            stored = int(np.prod(series.shape)) * series.dtype.itemsize
            check_decode(max(stored, returned), os.path.getsize(path), "the image")
            values = series.asarray()
            meta = {
                "format": "BigTIFF" if tif.is_bigtiff else "TIFF",
                "stored": str(values.dtype),
                "bits": int(page.bitspersample),
                "compression": page.compression.name.lower(),
                "photometric": page.photometric.name.lower(),
                "planar": int(page.planarconfig) == 2,
            }
            axes = series.axes
    except BakeshopError:
        raise
    except MemoryError:
        raise
    except Exception as e:  # tifffile raises many kinds on damaged files
        raise FormatError(f"corrupt or truncated TIFF: {e}") from None
    return _to_image(values, axes), meta


def _to_image(values: np.ndarray, axes: str) -> np.ndarray:
    """Tifffile's array with its axes string -> (H, W, C) float32."""
    if values.ndim == 2:
        values = values[:, :, None]
    elif values.ndim == 3 and axes[0] == "S" and axes[1:] == "YX":
        values = np.moveaxis(values, 0, -1)
    elif values.ndim != 3 or axes[-1] != "S":
        raise UnsupportedError(f"unsupported TIFF image of shape {values.shape} (axes {axes})")
    if values.shape[2] == 2:
        values = values[..., [0, 0, 0, 1]]
    elif values.shape[2] > 4:
        raise UnsupportedError(f"a TIFF with {values.shape[2]} samples per pixel")
    if values.dtype == np.uint8:
        return unsigned_to_float(values, 8)
    if values.dtype == np.uint16:
        return unsigned_to_float(values, 16)
    if values.dtype.kind == "f":
        return np.ascontiguousarray(values, dtype=np.float32)
    raise UnsupportedError(f"unsupported TIFF sample type {values.dtype}")


def write(
    path: str | os.PathLike, image: ArrayLike, *, bits: int | None = None, compression: str = "zlib"
) -> None:
    """Write one image as a TIFF.

    Parameters
    ----------
    path : path-like
    image : (H, W, C) float, uint8 or uint16 array, C in {1, 3, 4}
    bits : {8, 16, 32}
        8 and 16 store unsigned integers (floats are read as [0, 1], clipped and rounded);
        32 stores float32 (for floats only). Default: 32 for floats, else the array's depth.
    compression : {"zlib", "none"}
    """
    tifffile = _tifffile()
    image = np.asarray(image)
    if bits is None:
        bits = {np.dtype(np.uint8): 8, np.dtype(np.uint16): 16}.get(image.dtype, 32)
    if bits not in (8, 16, 32):
        raise ArgumentError(f"TIFF bits must be 8, 16 or 32, not {bits!r}")
    if compression not in _COMPRESSIONS:
        raise ArgumentError(f"TIFF compression must be 'zlib' or 'none', not {compression!r}")
    if bits == 32:
        if image.dtype.kind != "f":
            raise ArgumentError("bits=32 stores floats; pass a float image or bits=8/16")
        values = image.astype(np.float32, copy=False)
    else:
        values = float_to_unsigned(image, bits)
    photometric = "minisblack" if values.shape[2] == 1 else "rgb"
    extra = ("unassalpha",) if values.shape[2] == 4 else None
    tifffile.imwrite(
        path,
        values[..., 0] if values.shape[2] == 1 else values,
        photometric=photometric,
        planarconfig="contig",
        extrasamples=extra,
        compression=_COMPRESSIONS[compression],
    )
