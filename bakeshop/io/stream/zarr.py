"""zarr v3 arrays: the native chunked store of images larger than memory.

A store is a directory (``pano.zarr``) holding one array of shape (H, W, C), float32 (or
float16), in chunks of ``(rows, columns, C)``, each compressed on its own: a window reads the
chunks it touches, a dask task on any machine that sees the directory reads its own chunks, and
dask writes chunks in parallel (:func:`bakeshop.huge.convert`). The attributes record what
bakeshop wrote (``{"bakeshop": {"layout": ...}}`` when known). Written atomically: into a
temporary directory beside the target, renamed when complete (a store that was there is replaced
only then).
"""

from __future__ import annotations

import contextlib
import math
import os
import shutil
import tempfile
from collections.abc import Iterable, Iterator
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

from bakeshop.errors import BakeshopError, FormatError, UnsupportedError
from bakeshop.io._files import check_dimensions
from bakeshop.io.stream._base import Reader

#: streamed images may be this large.
MAX_PIXELS = 1 << 40
#: default chunk edge (rows and columns): 256 x 256 x 3 float32 is 768 KB.
CHUNK = 256


def _zarr() -> ModuleType:
    try:
        import zarr
    except ImportError:  # pragma: no cover - depends on the installation
        raise UnsupportedError("zarr stores need zarr 3: install bakeshop[huge]") from None
    return zarr


class ZarrReader(Reader):
    """Window reads of a zarr array of shape (H, W, C) or (H, W)."""

    format = "zarr"

    def __init__(self, path: str | os.PathLike) -> None:
        zarr = _zarr()
        try:
            a = zarr.open_array(os.fspath(path), mode="r")
        except Exception as e:  # zarr raises many kinds for a directory that is not a store
            raise FormatError("not a zarr array" + (f" ({e})" if str(e) else "")) from None
        if a.ndim not in (2, 3) or (a.ndim == 3 and not 1 <= a.shape[2] <= 4):
            raise UnsupportedError(f"a zarr image is (H, W) or (H, W, C<=4); got {a.shape}")
        if a.dtype.kind != "f":
            raise UnsupportedError(f"zarr images of {a.dtype} are not supported (float only)")
        h, w = a.shape[:2]
        c = a.shape[2] if a.ndim == 3 else 1
        check_dimensions(w, h, c, max_pixels=MAX_PIXELS)
        if min(a.chunks) < 1:
            raise FormatError(f"the chunk shape {a.chunks} has an empty side")
        self.path = os.fspath(path)
        self.shape = (h, w, c)
        self.stored = str(a.dtype)
        self.block = (int(a.chunks[0]), int(a.chunks[1]))
        # a chunk is inflated whole, in its stored type, from its compressed bytes (at most as
        # many), to cut any window from it
        chunk = math.prod(min(n, s) for n, s in zip(a.chunks, a.shape, strict=True))
        self.read_floor = 2 * chunk * a.dtype.itemsize
        self.attributes = dict(a.attrs)

    def array(self) -> Any:  # a zarr.Array (zarr is an optional dependency)
        """The zarr array itself, opened read-only (for dask.array.from_zarr)."""
        return _zarr().open_array(self.path, mode="r")

    def _read(self, top: int, bottom: int, left: int, right: int) -> np.ndarray:
        a = self.array()[top:bottom, left:right]
        return np.asarray(a, dtype=np.float32).reshape(bottom - top, right - left, self.shape[2])


def open(path: str | os.PathLike) -> ZarrReader:  # noqa: A001 - the codec interface's name
    """A :class:`ZarrReader` of the store ``path``."""
    return ZarrReader(path)


@contextlib.contextmanager
def atomic_directory(target: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary directory beside ``target``; on success it replaces ``target``, on
    failure it is removed (a failed write leaves the old store, or nothing)."""
    target = Path(target)
    parent = target.parent if str(target.parent) else Path(".")
    if not parent.is_dir():
        raise BakeshopError(f"directory {str(parent)!r} does not exist", target)
    tmp = Path(tempfile.mkdtemp(prefix=f".{target.stem}.", suffix=target.suffix, dir=parent))
    try:
        yield tmp
        old = None
        if target.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{target.stem}.old.", dir=parent))
            os.replace(target, old / "store")
        os.replace(tmp, target)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def create(
    path: str | os.PathLike,
    shape: tuple[int, int, int],
    *,
    chunks: tuple[int, int] | None = None,
    pixel_type: str = "float",
    attributes: dict | None = None,
) -> Any:
    """Create an empty zarr array for an image of ``shape`` (H, W, C) at ``path`` (a plain
    directory: the caller makes it atomic) and return it; ``chunks`` (rows, columns)."""
    zarr = _zarr()
    h, w, c = shape
    rows, cols = (CHUNK, CHUNK) if chunks is None else chunks
    a = zarr.create_array(
        store=os.fspath(path),
        shape=(h, w, c),
        chunks=(min(int(rows), h), min(int(cols), w), c),
        dtype=np.float16 if pixel_type == "half" else np.float32,
        fill_value=0.0,
        overwrite=True,
    )
    if attributes:
        a.attrs.update(attributes)
    return a


def write_strips(
    path: str | os.PathLike,
    shape: tuple[int, int, int],
    strips: Iterable[np.ndarray],
    *,
    chunks: tuple[int, int] | None = None,
    pixel_type: str = "float",
    attributes: dict | None = None,
) -> None:
    """Write a zarr store from strips top to bottom (chunks of ``chunks`` = (rows, columns),
    default 256 x 256); strips are buffered into whole rows of chunks before writing. Half
    refuses finite values beyond +-65504, naming ``pixel_type=float``."""
    if pixel_type == "half":
        from bakeshop.io.exr import check_half

        strips = (check_half(s, "pixel_type=float") for s in strips)
    with atomic_directory(path) as tmp:
        a = create(tmp, shape, chunks=chunks, pixel_type=pixel_type, attributes=attributes)
        rows = a.chunks[0]
        band, held, top = [], 0, 0
        for strip in strips:
            band.append(strip)
            held += strip.shape[0]
            if held >= rows:
                block = np.concatenate(band) if len(band) > 1 else band[0]
                take = held // rows * rows
                a[top : top + take] = block[:take]
                top += take
                band = [block[take:]] if take < held else []
                held -= take
        if held:
            a[top : top + held] = np.concatenate(band)
