"""Whole compressed textures: a cube map or 2-D texture with its mip chain, encoded and decoded.

:class:`BlockTexture` is what the containers (DDS, KTX, KTX2) write and read: the format, the
size of level 0, whether it is a cube, and the bytes of each level (its faces in OpenGL order,
each face's blocks row by row). :func:`encode_texture` makes one from float mips,
:meth:`BlockTexture.decode` turns one back into float mips.

Values BC6H cannot store are handled by an explicit choice, never silently:
:func:`check_range` refuses them (the default) or clamps them, and says how many texels and how
much of the energy that touched. Half floats end at 65504, so an unclamped sun would become
infinity (a photographed sun often reaches 10^5 to 10^6 in linear units).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, FormatError, validate_choice
from bakeshop.io.compress.decode import decode_image
from bakeshop.io.compress.encode import HALF_MAX, image_jobs, run_jobs
from bakeshop.io.compress.formats import BlockFormat, block_format, level_bytes

__all__ = ["BlockTexture", "OVERFLOW", "check_range", "encode_texture"]

Overflow = Literal["refuse", "clamp"]
#: what to do with values a format cannot store.
OVERFLOW = ("refuse", "clamp")


@dataclass(frozen=True)
class BlockTexture:
    """A block-compressed cube map or 2-D texture with its mip chain."""

    #: the block format.
    format: BlockFormat
    #: size of level 0 in texels.
    width: int
    height: int
    #: six faces per level (OpenGL order +X, -X, +Y, -Y, +Z, -Z) or one.
    cube: bool
    #: level 0 first; each the faces' blocks concatenated, face 0 first.
    levels: tuple[bytes, ...]
    #: what the encoder did beyond compressing (clamping), for sidecars and messages.
    notes: dict = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        for m, data in enumerate(self.levels):
            expected = self.faces * self.face_bytes(m)
            if len(data) != expected:
                raise FormatError(f"level {m} holds {len(data)} bytes, expected {expected}")

    @property
    def faces(self) -> int:
        """6 for a cube map, else 1."""
        return 6 if self.cube else 1

    def level_size(self, level: int) -> tuple[int, int]:
        """(width, height) of mip ``level`` (floor halving, at least 1)."""
        return max(1, self.width >> level), max(1, self.height >> level)

    def face_bytes(self, level: int) -> int:
        """Bytes of one face of mip ``level``."""
        return level_bytes(self.format, *self.level_size(level))

    def face(self, level: int, face: int) -> bytes:
        """The blocks of one face of one level."""
        n = self.face_bytes(level)
        return self.levels[level][face * n : (face + 1) * n]

    def decode(self) -> list[np.ndarray]:
        """Float mips, level 0 first: ``(6, S, S, C)`` per level of a cube, ``(H, W, C)`` of a 2-D
        texture (C: the format's channels; see :func:`bakeshop.io.compress.decode_image`)."""
        mips = []
        for m in range(len(self.levels)):
            w, h = self.level_size(m)
            faces = [decode_image(self.face(m, f), self.format, w, h) for f in range(self.faces)]
            mips.append(np.stack(faces) if self.cube else faces[0])
        return mips


def check_range(
    mips: Sequence[ArrayLike],
    fmt: str | BlockFormat,
    *,
    overflow: Overflow = "refuse",
    path: str | os.PathLike | None = None,
) -> tuple[list[np.ndarray], dict]:
    """Apply the explicit choice for values a half-float block format cannot store.

    Unsigned BC6H stores [0, 65504], signed BC6H [-65504, 65504]; beyond that a half float is
    infinity. ``overflow="refuse"`` raises :class:`ArgumentError` naming the count and the peak;
    ``"clamp"`` clamps them into range and reports what was clamped. Other formats are returned
    as they are (their encoders clip to [0, 1], as every 8-bit writer does).

    Parameters
    ----------
    mips : sequence of arrays
        Levels ``(6, S, S, C)`` or ``(H, W, C)``.
    fmt : str or BlockFormat
    overflow : {"refuse", "clamp"}
    path : path-like, optional
        Named in the error.

    Returns
    -------
    mips : list of float32 arrays
        Clamped copies where anything was clamped, else the inputs.
    notes : dict
        ``overflow`` (the choice), ``clamped_values`` (values clamped, all channels and levels),
        ``peak`` (largest magnitude before clamping) and ``clamped_energy`` (fraction of the sum
        of the level 0 values removed by clamping); ``{}`` for the 8-bit formats.
    """
    if isinstance(fmt, str):
        fmt = block_format(fmt)
    validate_choice(overflow, OVERFLOW, "overflow choice")
    if not fmt.hdr:
        return [np.asarray(m, np.float32) for m in mips], {}
    low = -HALF_MAX if fmt.signed else 0.0
    out, count, peak = [], 0, 0.0
    removed = total = 0.0
    for m, level in enumerate(mips):
        a = np.asarray(level, np.float32)
        if np.isnan(a).any():
            raise ArgumentError(f"mip {m} holds NaN values, which BC6H cannot store", path)
        bad = (a > HALF_MAX) | (a < low)
        n = int(np.count_nonzero(bad))
        peak = max(peak, float(np.max(np.abs(a))) if a.size else 0.0)
        if n:
            clamped = np.clip(a, low, HALF_MAX)
            if m == 0:
                removed = float(np.sum(np.abs(a[bad] - clamped[bad]), dtype=np.float64))
            a = clamped
        if m == 0:
            total = float(np.sum(np.abs(np.asarray(level, np.float32)), dtype=np.float64))
        count += n
        out.append(a)
    if count and overflow == "refuse":
        what = "above 65504 or below 0" if not fmt.signed else "beyond +-65504"
        raise ArgumentError(
            f"{count} values are {what} (peak {peak:.6g}), which {fmt.name} cannot store (half "
            "floats become infinity there): clamp them (--overflow clamp, overflow='clamp') or "
            "remove the sun first",
            path,
        )
    notes = {
        "overflow": overflow,
        "clamped_values": count,
        "peak": peak,
        "clamped_energy": removed / total if total > 0 else 0.0,
    }
    return out, notes


def encode_texture(
    mips: Sequence[ArrayLike],
    fmt: str | BlockFormat,
    *,
    quality: str = "fast",
    overflow: Overflow = "refuse",
    workers: int | None = None,
) -> BlockTexture:
    """Compress a cube map or 2-D texture with its mip chain.

    Parameters
    ----------
    mips : sequence of arrays, level 0 first
        Cube levels ``(6, S, S, C)`` in OpenGL face order or 2-D levels ``(H, W, C)``, each half
        the previous (floor, at least 1) down to any level, 2x2 and 1x1 included (they are
        stored as one block each, padded by repeating their texels).
    fmt : str or BlockFormat
        A name in :data:`bakeshop.io.compress.FORMATS`.
    quality : str
        Encoder profile (:data:`bakeshop.io.compress.QUALITIES`).
    overflow : {"refuse", "clamp"}
        Values BC6H cannot store (see :func:`check_range`).
    workers : int, optional
        Threads (default: the machine's cores); every face of every level is split into strips
        that run on one pool.

    Returns
    -------
    BlockTexture
        With ``notes`` from :func:`check_range` plus ``quality``.
    """
    from bakeshop.io._levels import check_levels

    if isinstance(fmt, str):
        fmt = block_format(fmt)
    levels, cube = check_levels(mips)
    levels, notes = check_range(levels, fmt, overflow=overflow)
    groups = []
    for level in levels:
        for face in level if cube else [level]:
            groups.append(image_jobs(face, fmt, quality=quality))
    blocks = run_jobs(groups, workers)
    faces = 6 if cube else 1
    data = tuple(b"".join(blocks[m * faces : (m + 1) * faces]) for m in range(len(levels)))
    height, width = levels[0].shape[-3:-1]
    return BlockTexture(fmt, width, height, cube, data, {**notes, "quality": quality})
