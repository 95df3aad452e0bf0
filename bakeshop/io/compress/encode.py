"""Block encoders: Intel's ISPC Texture Compressor through the ``ispc-texcomp`` wheel.

ISPC's encoders are the reference fast CPU encoders of the field (Intel, "ISPC Texture
Compressor", used by Unity and Unreal), and the wheel binds them without a build step. They
take an RGBA surface (8-bit, or half floats for BC6H) whose sides are multiples of 4; this
module pads an image to whole blocks by repeating its last row and column (so a 2x2 or 1x1 mip
level becomes one block whose extra texels copy the real ones), converts it, and runs strips of
blocks on the machine's cores (the wheel releases the GIL).

ISPC encodes BC6H unsigned only. Signed BC6H (``bc6h-signed``) goes to bakeshop's own encoder
(:mod:`bakeshop.io.compress.bc6h_signed`).
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor
from types import ModuleType
from typing import TYPE_CHECKING

import numpy as np

from bakeshop.errors import ArgumentError, BakeshopError, validate_choice
from bakeshop.io.compress import _native
from bakeshop.io.compress.formats import BlockFormat, block_format

if TYPE_CHECKING:
    from ispc_texcomp import BC6HEncSettings, BC7EncSettings


__all__ = ["QUALITIES", "HALF_MAX", "encode_image", "image_jobs", "run_jobs", "linear_to_srgb"]

#: largest finite half float; BC6H stores nothing larger.
HALF_MAX = 65504.0

#: quality profiles of each encoder family, fastest first (ISPC's profile names).
QUALITIES = {
    "bc6h": ("veryfast", "fast", "basic", "slow", "veryslow"),
    "bc6h-signed": ("fast",),
    "bc7": ("ultrafast", "veryfast", "fast", "basic", "slow"),
    "bc1": ("fast",),
    "bc3": ("fast",),
    "bc4": ("fast",),
    "bc5": ("fast",),
}

# rows of blocks per task: large enough that the per-call overhead vanishes, small enough that
# both cores get work on a 256x256 face.
_STRIP_ROWS = 64


def ispc() -> ModuleType:
    """The ISPC texture compressor module, or a one-line install hint (the compress extra)."""
    try:
        import ispc_texcomp
    except ImportError:
        raise BakeshopError(
            "block compression needs the ISPC texture compressor: install bakeshop[compress] "
            "(pip install 'bakeshop[compress]')"
        ) from None
    return ispc_texcomp


def linear_to_srgb(values: np.ndarray) -> np.ndarray:
    """The sRGB OETF (IEC 61966-2-1): ``12.92 v`` up to 0.0031308, else ``1.055 v ** (1/2.4) -
    0.055``; float32 in and out, values clipped to [0, 1] first."""
    v = np.clip(np.asarray(values, np.float32), 0, 1)
    return np.where(
        v <= 0.0031308, v * 12.92, 1.055 * np.power(v, 1 / 2.4, dtype=np.float32) - 0.055
    ).astype(np.float32)


def _pad(image: np.ndarray) -> np.ndarray:
    """``image`` padded to whole 4x4 blocks by repeating its last row and column."""
    h, w = image.shape[:2]
    ph, pw = -h % 4, -w % 4
    if ph or pw:
        image = np.pad(image, ((0, ph), (0, pw), (0, 0)), mode="edge")
    return image


def _rgba(image: np.ndarray, fill: float) -> np.ndarray:
    """``image`` as 4 channels: grey repeated, RG with B = 0, alpha ``fill`` when missing."""
    c = image.shape[2]
    if c == 4:
        return image
    if c == 1:
        rgb = np.repeat(image, 3, axis=2)
    elif c == 2:
        rgb = np.concatenate([image, np.zeros_like(image[..., :1])], axis=2)
    else:
        rgb = image
    return np.concatenate([rgb, np.full_like(image[..., :1], fill)], axis=2)


def to_half_surface(image: np.ndarray) -> np.ndarray:
    """The RGBA half-float surface ISPC's BC6H encoder reads, as float16 ``(H', W', 4)``, H' and
    W' the next multiples of 4 (edge texels repeated), in one compiled pass
    (``src/io/compress/encode.hpp``): grey repeated to RGB, missing blue 0, missing alpha 1.

    The halves are rounded to nearest even, and values beyond +-65504 (and infinities) saturate
    to +-65504, never infinity (NaN is refused before). The rounding is Giesen's
    "float_to_half_fast3_rtne": normal halves add the rounding bias ``0xFFF + odd`` before
    dropping 13 mantissa bits; subnormal halves add 0.5f, whose float addition rounds the 10 kept
    bits to nearest even."""
    image = np.ascontiguousarray(image, np.float32)
    if image.ndim == 2:
        image = image[..., None]
    h, w = image.shape[:2]
    out = np.empty((h + (-h % 4), w + (-w % 4), 4), np.uint16)
    _native.half_rgba(image.view(np.uint32), out)
    out[h:, :w] = out[h - 1 : h, :w]
    out[:, w:] = out[:, w - 1 : w]
    return out.view(np.float16)


def _surface_data(image: np.ndarray, fmt: BlockFormat) -> np.ndarray:
    """The padded surface ISPC reads: RGBA half floats for BC6H, R8 for BC4, RG8 for BC5 (what
    ISPC's kernels read, whatever the wheel's stubs say), else RGBA 8-bit unsigned."""
    from bakeshop.io._quantize import float_to_unsigned

    if fmt.hdr:
        return to_half_surface(image)
    image = _pad(np.asarray(image, np.float32))
    if fmt.channels < 3:
        c = image.shape[2]
        if c < fmt.channels:  # one channel into BC5: the same values twice
            image = np.repeat(image, fmt.channels, axis=2)
        return float_to_unsigned(np.ascontiguousarray(image[..., : fmt.channels]), 8)
    if fmt.srgb:
        image = image.copy()
        image[..., :3] = linear_to_srgb(image[..., : min(3, image.shape[2])])
    return float_to_unsigned(_rgba(image, 1.0), 8)


def _settings(
    it: ModuleType, fmt: BlockFormat, quality: str, opaque: bool
) -> BC6HEncSettings | BC7EncSettings | None:

    family = fmt.name.split("-")[0]
    if family == "bc6h":
        return it.BC6HEncSettings.from_profile(quality)
    if family == "bc7":
        return it.BC7EncSettings.from_profile(quality if opaque else f"alpha_{quality}")
    return None


def encode_image(
    image: np.ndarray, fmt: str | BlockFormat, *, quality: str = "fast", workers: int | None = None
) -> bytes:
    """Compress one image (a face of one mip level) to blocks.

    Parameters
    ----------
    image : (H, W, C) float array, C in 1..4
        BC6H: linear values in the half-float range (check them first with
        :func:`bakeshop.io.compress.check_range`; NaN is refused). Other formats: values in
        [0, 1], clipped, quantised to 8 bits (sRGB formats: linear values, sRGB-encoded
        first). Missing channels are filled: grey is repeated to RGB, alpha is 1.
    fmt : str or BlockFormat
        A name in :data:`bakeshop.io.compress.FORMATS`.
    quality : str
        Encoder profile of the format's family (:data:`QUALITIES`), fastest first: for BC6H
        ``veryfast fast basic slow veryslow``, for BC7 ``ultrafast veryfast fast basic slow``.
        BC7 uses ISPC's alpha profiles when any alpha is below 1.
    workers : int, optional
        Threads (default: the machine's cores).

    Returns
    -------
    bytes
        ``ceil(W/4) * ceil(H/4)`` blocks, rows of blocks top to bottom.
    """
    return run_jobs([image_jobs(image, fmt, quality=quality)], workers)[0]


def image_jobs(image: np.ndarray, fmt: str | BlockFormat, *, quality: str = "fast") -> list:
    """The encoding of one image as independent jobs (zero-argument callables returning the
    bytes of consecutive strips of blocks), to run on a thread pool with :func:`run_jobs`."""
    if isinstance(fmt, str):
        fmt = block_format(fmt)
    family = fmt.name if fmt.name == "bc6h-signed" else fmt.name.split("-")[0]
    validate_choice(quality, QUALITIES[family], f"{fmt.name} quality")
    image = np.asarray(image)
    if image.ndim == 2:
        image = image[..., None]
    if image.ndim != 3 or image.shape[2] not in (1, 2, 3, 4) or 0 in image.shape:
        raise ArgumentError(f"an image to compress is (H, W, C) with C in 1..4; got {image.shape}")
    if np.isnan(image).any():
        raise ArgumentError("the image holds NaN values, which no block format stores")
    if fmt.name == "bc6h-signed":
        from bakeshop.io.compress.bc6h_signed import encode_bc6h_signed

        padded = _rgba(_pad(image.astype(np.float32)), 1.0)[..., :3]
        return [lambda: encode_bc6h_signed(padded)]
    it = ispc()
    surface = _surface_data(image, fmt)
    opaque = image.shape[2] < 4 or bool(np.all(image[..., 3] >= 1))
    settings = _settings(it, fmt, quality, opaque)
    function = getattr(it, f"compress_blocks_{family}")
    width = surface.shape[1]
    rows = _STRIP_ROWS * 4

    def strip(top: int) -> bytes:
        part = surface[top : top + rows]  # whole rows of a C-contiguous array: contiguous
        stride = width * part.itemsize * part.shape[2]
        s = it.RGBASurface(part, width, part.shape[0], stride)  # read through the buffer
        data = function(s) if settings is None else function(s, settings)
        # ispc-texcomp 1.0.1 returns 16 bytes per block for BC1 too, the second half
        # uninitialised memory: keep the blocks (tests check them against BC3's colour half)
        return data[: (width // 4) * (part.shape[0] // 4) * fmt.block_bytes]

    return [lambda top=top: strip(top) for top in range(0, surface.shape[0], rows)]


def run_jobs(groups: list[list], workers: int | None = None) -> list[bytes]:
    """Run groups of jobs from :func:`image_jobs` on one thread pool; the bytes of each group."""
    jobs = [job for group in groups for job in group]
    workers = min(workers or os.cpu_count() or 1, len(jobs))
    if workers <= 1:
        results = [job() for job in jobs]
    else:
        with ThreadPoolExecutor(workers) as pool:
            results = list(pool.map(lambda job: job(), jobs))
    out, start = [], 0
    for group in groups:
        out.append(b"".join(results[start : start + len(group)]))
        start += len(group)
    return out
