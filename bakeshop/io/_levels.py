"""Mip chains of 2-D textures and cube maps, as the GPU texture containers (DDS, KTX) hold them."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from typing import Concatenate, ParamSpec, TypeVar

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, with_article
from bakeshop.io._files import MAX_SIDE
from bakeshop.io.budget import check_decode

P = ParamSpec("P")
R = TypeVar("R")

#: Sample types the containers store, by name.
DTYPES: dict[str, np.dtype] = {"float16": np.dtype("<f2"), "float32": np.dtype("<f4")}

#: Unsigned normalised samples (a stored c reads as c / 255), for data textures such as
#: two-channel normal maps, the input of BC5. Float values are quantised as the PNG writer does.
UNORM_DTYPES: dict[str, np.dtype] = {"unorm8": np.dtype("u1")}

#: Most mip levels a texture may have (a 2^20 side has 21).
MAX_LEVELS = 21


def mip_size(size: int, level: int) -> int:
    """Side of mip ``level`` of a texture whose level 0 is ``size`` (floor halving, at least 1)."""
    return max(1, size >> level)


def check_chain_decode(
    width: int,
    height: int,
    levels: int,
    images: int,
    channels: int,
    stored: int,
    file_size: int,
    *,
    decode: bool,
) -> None:
    """Refuse, from the header alone and before any level is read, inflated or decoded, a
    chain that would exceed the decode budget (:func:`bakeshop.io.budget.check_decode`).

    The bytes counted are the ``stored`` bytes the levels hold once read (inflated, for a
    supercompressed file) plus, with ``decode``, the float32 levels returned: ``images`` (faces
    times layers) of ``channels`` per texel at every level of a ``width`` x ``height`` chain.
    """
    texels = sum(mip_size(width, m) * mip_size(height, m) for m in range(levels))
    needed = stored + (images * texels * channels * 4 if decode else 0)
    what = f"the {levels}-level {width}x{height} chain" + (f" of {images} images" * (images > 1))
    check_decode(needed, file_size, what)


def check_levels(
    mips: Sequence[ArrayLike], *, array: bool = False
) -> tuple[list[np.ndarray], bool]:
    """Validate a mip chain and return it as a list of float arrays plus whether it is a cube.

    Parameters
    ----------
    mips : sequence of arrays
        Level 0 first. Each level is ``(H, W, C)`` (a 2-D texture; ``(H, W)`` is one channel) or
        ``(6, S, S, C)`` (a cube map in OpenGL face order), C in 1..4, level ``m`` of size
        ``max(1, size0 >> m)`` per side, all with the same channels.
    array : bool
        The levels are texture arrays: ``(L, H, W, C)`` (or ``(L, H, W)``), L >= 1 layers of
        2-D textures, the same L in every level.

    Returns
    -------
    levels : list of arrays of shape (H, W, C), (6, S, S, C) or (L, H, W, C)
    cube : bool
    """
    if isinstance(mips, np.ndarray) or not len(mips):
        raise ArgumentError("a mip chain is a non-empty list of arrays, level 0 first")
    if len(mips) > MAX_LEVELS:
        raise ArgumentError(f"at most {MAX_LEVELS} mip levels, got {len(mips)}")
    first = np.asarray(mips[0])
    cube = first.ndim == 4 and not array
    layers = first.shape[0] if array and first.ndim in (3, 4) else None
    levels = []
    for m, level in enumerate(mips):
        a = np.asarray(level)
        if a.dtype.kind not in "fiu":
            raise ArgumentError(f"mip {m}: cannot store {a.dtype} samples as floats")
        if array:
            if a.ndim == 3:
                a = a[..., None]
            if a.ndim != 4 or a.shape[0] != layers or layers < 1:
                raise ArgumentError(
                    f"mip {m} of a texture array must be (L, H, W, C) with the same L >= 1 "
                    f"in every level; got {a.shape}"
                )
            shape = a.shape[1:3]
        elif cube:
            if a.ndim != 4 or a.shape[0] != 6 or a.shape[1] != a.shape[2]:
                raise ArgumentError(f"mip {m} of a cube map must be (6, S, S, C); got {a.shape}")
            shape = a.shape[1:3]
        else:
            if a.ndim == 2:
                a = a[..., None]
            if a.ndim != 3:
                raise ArgumentError(f"mip {m} of a 2-D texture must be (H, W, C); got {a.shape}")
            shape = a.shape[:2]
        if m == 0:
            height, width = shape
            channels = a.shape[-1]
            if not (1 <= height <= MAX_SIDE and 1 <= width <= MAX_SIDE):
                raise ArgumentError(f"texture size {width}x{height} out of range")
            if not 1 <= channels <= 4:
                raise ArgumentError(f"a texture has 1 to 4 channels, got {channels}")
        expected = (mip_size(height, m), mip_size(width, m))
        if shape != expected or a.shape[-1] != channels:
            raise ArgumentError(
                f"mip {m} must be {expected[1]}x{expected[0]} with {channels} channels "
                f"(each level halves the previous); got shape {a.shape}"
            )
        if a.dtype.kind == "f" and np.isnan(a).any():
            raise ArgumentError(f"mip {m} holds NaN values")
        levels.append(a)
    if max(height, width) >> (len(levels) - 1) == 0:
        raise ArgumentError(
            f"{len(levels)} mip levels is more than {with_article(width)}x{height} texture has"
        )
    return levels, cube


def encode(level: np.ndarray, dtype: np.dtype) -> np.ndarray:
    """``level`` as little-endian ``dtype`` samples; half refuses finite values beyond
    +-65504 (:func:`bakeshop.io.exr.to_half`, naming ``dtype="float32"``); unorm8 stores uint8
    input as it is and quantises floats in [0, 1] to round(v * 255)."""
    if dtype == UNORM_DTYPES["unorm8"]:
        from bakeshop.io._quantize import float_to_unsigned

        return float_to_unsigned(level, 8)
    if dtype == DTYPES["float16"]:
        from bakeshop.io.exr import to_half

        level = level.astype(np.float32, copy=False)
        return to_half(level, 'dtype="float32"').astype("<f2", copy=False)
    return level.astype(dtype, copy=False)


def names_its_file(
    read: Callable[Concatenate[str | os.PathLike, P], R],
) -> Callable[Concatenate[str | os.PathLike, P], R]:
    """Decorate a container reader so that every error it raises names the file it read."""
    import functools

    from bakeshop.errors import BakeshopError

    @functools.wraps(read)
    def wrapper(path: str | os.PathLike, *args: P.args, **kwargs: P.kwargs) -> R:

        try:
            return read(path, *args, **kwargs)
        except BakeshopError as e:
            if e.path is None:
                e.path = os.fspath(path)
            raise
        except OSError as e:
            raise BakeshopError(e.strerror or str(e), path) from None
        except MemoryError:
            raise BakeshopError(
                "the texture is too large for this machine's memory", path
            ) from None

    return wrapper
