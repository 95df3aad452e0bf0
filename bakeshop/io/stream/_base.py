"""The reader interface every stream codec implements, and a reader over an array in memory."""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, BakeshopError, FormatError

#: a ``(start, stop)`` range of rows or columns.
Window = tuple[int, int]


def window_of(
    shape: Sequence[int], rows: Window | None = None, cols: Window | None = None
) -> tuple[int, int, int, int]:
    """``(top, bottom, left, right)`` of a window of an image of ``shape`` (H, W, ...).

    ``rows`` and ``cols`` are ``(start, stop)`` pairs (None: all); they must lie inside the
    image and be non-empty.
    """
    h, w = int(shape[0]), int(shape[1])
    top, bottom = (0, h) if rows is None else (int(rows[0]), int(rows[1]))
    left, right = (0, w) if cols is None else (int(cols[0]), int(cols[1]))
    if not (0 <= top < bottom <= h and 0 <= left < right <= w):
        raise ArgumentError(
            f"window rows {top}..{bottom}, columns {left}..{right} is not inside an image of "
            f"{h} rows and {w} columns"
        )
    return top, bottom, left, right


class Reader:
    """A window reader of one image (subclasses: one per stream codec, and :class:`ArrayReader`).

    Attributes
    ----------
    path : str or None
        The file (None for an array in memory).
    shape : (H, W, C)
    dtype : numpy.dtype
        What :meth:`read` returns: float32.
    stored : str
        The sample type in the file (``"float32"``, ``"rgbe"``, ``"half"`` ...).
    block : (int, int)
        The file's natural block (rows, columns): a tile, a chunk, or a run of scanlines;
        reads aligned to it waste nothing.
    read_floor : int
        Bytes any read costs beyond the window it returns, however small: the codec inflates
        a whole compressed block (a zarr chunk, a TIFF tile or strip) to cut a window from it.
    format : str
        The format's name.
    """

    path: str | None = None
    shape: tuple[int, int, int] = (0, 0, 0)
    dtype = np.dtype(np.float32)
    stored = "float32"
    block: tuple[int, int] = (256, 0)
    read_floor = 0
    format = ""

    @property
    def nbytes(self) -> int:
        """Bytes of the decoded image (float32)."""
        h, w, c = self.shape
        return h * w * c * 4

    def read(self, rows: Window | None = None, cols: Window | None = None) -> np.ndarray:
        """The window ``rows = (top, bottom)``, ``cols = (left, right)`` (None: all) as a
        float32 ``(bottom - top, right - left, C)`` array, row 0 at the top."""
        top, bottom, left, right = window_of(self.shape, rows, cols)
        try:
            return self._read(top, bottom, left, right)
        except (BakeshopError, MemoryError):
            raise
        except Exception as e:  # codecs raise many kinds on damaged blocks
            raise FormatError(
                f"corrupt or truncated data in rows {top}..{bottom}, columns {left}..{right}"
                + (f" ({e})" if str(e) else ""),
                self.path,
            ) from None

    def _read(self, top: int, bottom: int, left: int, right: int) -> np.ndarray:
        raise NotImplementedError

    def __repr__(self) -> str:
        h, w, c = self.shape
        return f"<{self.format} {w}x{h}x{c} {self.stored} {self.path!r}>"


class ArrayReader(Reader):
    """A reader over an ``(H, W, C)`` array already in memory (the in-memory path of the chunked
    engine: the same code reads a window of an array or of a file)."""

    format = "array"

    def __init__(self, image: ArrayLike, name: str | os.PathLike | None = None) -> None:
        a = np.asarray(image)
        if a.ndim == 2:
            a = a[:, :, None]
        if a.ndim != 3 or not 1 <= a.shape[2] <= 4:
            raise ArgumentError(f"an image must be (H, W) or (H, W, C); got shape {a.shape}")
        self.image = a
        h, w, c = (int(n) for n in a.shape)
        self.shape = (h, w, c)
        self.stored = str(a.dtype)
        self.block = (self.shape[0], self.shape[1])
        self.path = None if name is None else os.fspath(name)

    @property
    def nbytes(self) -> int:
        return int(self.image.nbytes)

    def _read(self, top: int, bottom: int, left: int, right: int) -> np.ndarray:
        return np.asarray(self.image[top:bottom, left:right], dtype=np.float32)
