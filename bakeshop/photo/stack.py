"""Exposure stacks: bracketed frames of one scene as integer codes with their exposures.

A frame's *exposure* is the light it let in relative to a reference: ``t * (S / 100) / N^2``
for exposure time ``t`` (s), ISO speed ``S`` and f-number ``N`` when all three are known (from
EXIF or given), or the exposure time alone. When every frame has all three, the stack is
*absolute*: merged values are then scene luminance in cd/m^2 to within the camera's
calibration (see :data:`LUMINANCE_PER_UNIT`).
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, DTypeLike

from bakeshop.errors import ArgumentError, BakeshopError, UnsupportedError
from bakeshop.resources import Cost, require

__all__ = ["ExposureStack", "LUMINANCE_PER_UNIT", "make_stack", "read_stack"]

#: cd/m^2 per unit of linear code over exposure ``t S / (100 N^2)``: ISO 12232's standard output
#: sensitivity puts the sRGB code 118/255 (linear 0.18) at focal-plane exposure ``H = 10 / S``
#: lux s, and ``H = q L t / N^2`` with ``q = 0.65``, so ``L = 10 N^2 / (0.65 t S)`` gives 0.18:
#: ``L = X / (t S / (100 N^2)) * 10 / (0.65 * 0.18 * 100)``.
LUMINANCE_PER_UNIT = 10.0 / (0.65 * 0.18 * 100.0)

#: largest number of frames in a stack.
MAX_FRAMES = 64


@dataclass
class ExposureStack:
    """Frames of one scene at different exposures.

    Attributes
    ----------
    codes : (P, H, W, C) uint8 or uint16
        The frames' codes, sorted by exposure (darkest first); C in {1, 3}.
    exposures : (P,) float64
        Relative exposures, ascending, positive.
    names : list of str
        Where each frame came from (file names), for messages.
    absolute : bool
        True when every exposure is ``t S / (100 N^2)`` (time, ISO and f-number known).
    settings : list of dict
        What was known of each frame (``exposure_time``, ``f_number``, ``iso``, ``source``).
    """

    codes: np.ndarray
    exposures: np.ndarray
    names: list = field(default_factory=list)
    absolute: bool = False
    settings: list = field(default_factory=list)

    @property
    def bits(self) -> int:
        """Bits per sample of the frames (8 or 16)."""
        return 8 if self.codes.dtype == np.uint8 else 16

    @property
    def span_stops(self) -> float:
        """log2 of the largest over the smallest exposure."""
        return float(math.log2(self.exposures[-1] / self.exposures[0]))

    @property
    def shape(self) -> tuple[int, int, int]:
        """``(H, W, C)`` of one frame."""
        return tuple(self.codes.shape[1:])


#: codes at or above this fraction of full scale are clipped (250 of 255).
CLIP_HIGH = 250 / 255
#: codes at or below this fraction of full scale are clipped (2 of 255).
CLIP_LOW = 2 / 255


def clip_codes(bits: int, clip_low: float | None, clip_high: float | None) -> tuple[int, int]:
    """The integer codes at and beyond which a ``bits``-bit sample is clipped."""
    clip_low = CLIP_LOW if clip_low is None else clip_low
    clip_high = CLIP_HIGH if clip_high is None else clip_high
    if not (math.isfinite(clip_low) and math.isfinite(clip_high)):
        raise ArgumentError("clip levels must be finite")
    if not 0 <= clip_low < clip_high <= 1 or clip_high - clip_low < 0.25:
        raise ArgumentError(
            f"clip levels must satisfy 0 <= low < high <= 1 with at least 0.25 between them; "
            f"got {clip_low}, {clip_high}"
        )
    top = (1 << bits) - 1
    return int(math.floor(clip_low * top)), int(math.ceil(clip_high * top))


def _exposure(settings: dict) -> tuple[float | None, bool]:
    """(relative exposure or None, whether it is absolute)."""
    t = settings.get("exposure_time")
    if t is None:
        return None, False
    n, s = settings.get("f_number"), settings.get("iso")
    if n and s:
        return t * (s / 100.0) / (n * n), True
    return t, False


def make_stack(
    codes: Sequence[np.ndarray] | np.ndarray,
    exposures: ArrayLike,
    *,
    names: Sequence[str] | None = None,
    absolute: bool = False,
) -> ExposureStack:
    """An :class:`ExposureStack` from arrays, checked and sorted by exposure.

    Parameters
    ----------
    codes : sequence of (H, W, C) uint8/uint16 arrays, or (P, H, W, C)
        A (P, H, W, C) array already in order of exposure is used as it is (not copied).
    exposures : (P,) float
        Positive, finite, not all equal.
    names : list of str, optional
    absolute : bool
        The exposures are ``t S / (100 N^2)`` (see :data:`LUMINANCE_PER_UNIT`).
    """
    frames = [np.asarray(f) for f in codes]
    if not 2 <= len(frames) <= MAX_FRAMES:
        raise ArgumentError(f"a stack needs 2-{MAX_FRAMES} frames, not {len(frames)}")
    names = list(names) if names is not None else [f"frame {i + 1}" for i in range(len(frames))]
    if len(names) != len(frames):
        raise ArgumentError(f"{len(frames)} frames need {len(frames)} names")
    first = frames[0]
    for name, f in zip(names, frames, strict=True):
        if f.ndim == 2:
            f = f[..., None]
        if f.dtype not in (np.uint8, np.uint16):
            raise ArgumentError(f"frames hold uint8 or uint16 codes, not {f.dtype}", name)
        if f.shape[:2] != first.shape[:2] or f.dtype != first.dtype:
            raise ArgumentError(
                f"all frames must have one size and depth: {f.shape[1]}x{f.shape[0]} "
                f"{f.dtype} against {first.shape[1]}x{first.shape[0]} {first.dtype}",
                name,
            )
    exposures = np.asarray(exposures, dtype=np.float64)
    if exposures.shape != (len(frames),):
        raise ArgumentError(f"{len(frames)} frames need {len(frames)} exposures")
    for name, e in zip(names, exposures, strict=True):
        if not (math.isfinite(e) and e > 0):
            raise ArgumentError(f"exposure {e!r} is not a positive number", name)
    if np.ptp(np.log(exposures)) < 1e-6:
        raise ArgumentError(
            "every frame has the same exposure, so nothing tells the brighter parts of the "
            "scene from the darker ones; bracket the exposure (or give the right times)"
        )
    order = np.argsort(exposures, kind="stable")
    given = codes if isinstance(codes, np.ndarray) else None
    if given is not None and given.ndim == 4 and np.all(order == np.arange(len(frames))):
        stacked = given  # already one sorted (P, H, W, C) array: no copy
    else:
        stacked = np.empty((len(frames),) + _hwc(first), first.dtype)
        for k, i in enumerate(order):
            f = frames[i]
            stacked[k] = f[..., None] if f.ndim == 2 else f
    return ExposureStack(
        stacked, exposures[order], [names[i] for i in order], absolute, [{} for _ in order]
    )


def _allocate(shape: tuple[int, ...], dtype: DTypeLike) -> np.ndarray:
    """An array for a whole stack, refused with the number when it cannot fit in memory."""
    needed = int(np.prod(shape)) * np.dtype(dtype).itemsize
    require(Cost(needed, int(np.prod(shape[:-1])), f"the stack's codes ({shape[0]} frames)"))
    return np.empty(shape, dtype)


def _hwc(f: np.ndarray) -> tuple[int, int, int]:
    return (f.shape[0], f.shape[1], 1 if f.ndim == 2 else f.shape[2])


def _codes(image: np.ndarray, meta: dict, path: str | os.PathLike) -> np.ndarray:
    """A reader's float32 [0, 1] image -> its stored integer codes (exact)."""
    stored = meta.get("stored", "")
    if stored == "uint8" or stored in ("uint1", "uint2", "uint4"):
        bits, dtype = 8, np.uint8
    elif stored == "uint16":
        bits, dtype = 16, np.uint16
    else:
        raise UnsupportedError(
            f"a bracket must be a camera's 8- or 16-bit picture (JPEG, PNG, TIFF); this file "
            f"stores {stored or 'floats'}",
            path,
        )
    if image.shape[2] == 4:
        image = image[..., :3]
    elif image.shape[2] == 2:
        image = image[..., :1]
    return np.rint(image * np.float32((1 << bits) - 1)).astype(dtype)


def read_stack(
    paths: Sequence[str | os.PathLike],
    *,
    exposure_times: Sequence[float] | None = None,
    f_numbers: Sequence[float] | None = None,
    isos: Sequence[float] | None = None,
) -> ExposureStack:
    """Read bracketed frames and their exposures.

    Each frame's exposure time, f-number and ISO come from the arguments when given, else from
    its EXIF (:func:`bakeshop.io.exif.read_exposure`). A frame with no exposure time either way
    is refused, naming the file.

    Parameters
    ----------
    paths : sequence of path-like
        JPEG, PNG (8/16-bit) or TIFF (8/16-bit) files of one size.
    exposure_times : sequence of float, optional
        Seconds, one per path (overrides EXIF).
    f_numbers, isos : sequence of float, optional
        One per path (override EXIF).

    Returns
    -------
    ExposureStack
        Sorted darkest first; ``absolute`` when every frame's time, f-number and ISO are known.
    """
    from bakeshop.io import read_image
    from bakeshop.io.exif import read_exposure

    paths = [os.fspath(p) for p in paths]
    given = {"exposure_time": exposure_times, "f_number": f_numbers, "iso": isos}
    for key, values in given.items():
        if values is not None and len(values) != len(paths):
            raise ArgumentError(f"{len(paths)} frames need {len(paths)} values of {key}")
    if not 2 <= len(paths) <= MAX_FRAMES:
        raise ArgumentError(f"a stack needs 2-{MAX_FRAMES} frames, not {len(paths)}")
    settings = []
    for i, path in enumerate(paths):  # the exposures first: EXIF is read without the pixels
        try:
            found = read_exposure(path)
        except BakeshopError:
            found = {}
        found["source"] = "exif" if found.get("exposure_time") else "none"
        for key, values in given.items():
            if values is not None:
                found[key] = float(values[i])
                found["source"] = "given"
        if found.get("exposure_time") is None:
            raise ArgumentError(
                "no exposure time: the file has no EXIF ExposureTime; give every frame's time "
                "(bakeshop merge --times 1/1000,1/250,...)",
                path,
            )
        settings.append(found)
    exposures, absolute = zip(*(_exposure(s) for s in settings), strict=True)
    order = np.argsort(np.asarray(exposures), kind="stable")
    # each frame read straight into its place in one (P, H, W, C) array, darkest first
    stacked = None
    for k, i in enumerate(order):
        image, meta = read_image(paths[i], with_metadata=True)
        codes = _codes(image, meta, paths[i])
        del image
        if stacked is None:
            stacked = _allocate((len(paths),) + codes.shape, codes.dtype)
        elif codes.shape != stacked.shape[1:] or codes.dtype != stacked.dtype:
            h, w = stacked.shape[1:3]
            raise ArgumentError(
                f"all frames must have one size and depth: {codes.shape[1]}x{codes.shape[0]} "
                f"{codes.dtype} against {w}x{h} {stacked.dtype}",
                paths[i],
            )
        stacked[k] = codes
    assert stacked is not None  # a stack has two frames or more
    stack = make_stack(
        stacked, [exposures[i] for i in order], names=[paths[i] for i in order],
        absolute=all(absolute),
    )  # fmt: skip
    stack.settings = [settings[i] for i in order]
    return stack
