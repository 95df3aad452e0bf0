"""Before/after cases of bakeshop.io.compress's kernels (issue 32): the block decoders (through
``decode_image``), the signed BC6H encoder and the half-float surface of ISPC's BC6H encoder.

Real blocks (ISPC's encodings of a 256x256 image, bakeshop's signed BC6H encoding) are tiled to
the sizes below, so that every mode a real encoder picks is decoded; the inputs are built here,
outside the timed thunks."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from bakeshop.io.compress.bc6h_signed import encode_bc6h_signed
from bakeshop.io.compress.decode import decode_image
from bakeshop.io.compress.encode import encode_image, to_half_surface


def _image(rng: np.random.Generator, size: int, channels: int) -> np.ndarray:
    """A smooth image with noise and edges, in [0, 1]."""
    y, x = np.mgrid[0:size, 0:size] / size
    base = [np.sin(7 * x + 3 * c) * np.cos(5 * y - c) for c in range(channels)]
    image = 0.5 + 0.4 * np.stack(base, -1) + 0.05 * rng.standard_normal((size, size, channels))
    image[size // 3 : size // 2, :, :] *= 0.3
    return np.clip(image, 0, 1).astype(np.float32)


def _tiled(blocks: bytes, block_bytes: int, tile: int, width: int, height: int) -> bytes:
    """The (tile/4)^2 blocks of a tile x tile image repeated to a width x height image."""
    b = np.frombuffer(blocks, np.uint8).reshape(tile // 4, tile // 4, block_bytes)
    reps = (height // tile, width // tile, 1)
    return np.tile(b, reps).tobytes()


def _decode(data: bytes, fmt: str, width: int, height: int) -> Callable[[], object]:
    return lambda: decode_image(data, fmt, width, height)


def cases() -> list[tuple[str, Callable[[], object]]]:
    rng = np.random.default_rng(32)
    ldr = _image(rng, 256, 4)
    hdr = (_image(rng, 256, 3) ** 4 * 200).astype(np.float32)
    signed = (hdr - 50).astype(np.float32)
    out: list[tuple[str, Callable[[], object]]] = []
    for fmt, w, h, source in (
        ("bc7", 2048, 2048, ldr),
        ("bc6h", 2048, 2048, hdr),
        ("bc1", 4096, 2048, ldr),
        ("bc3", 4096, 2048, ldr),
        ("bc5", 4096, 2048, ldr[..., :2]),
    ):
        block_bytes = 8 if fmt == "bc1" else 16
        data = _tiled(encode_image(source, fmt), block_bytes, 256, w, h)
        out.append((f"io.compress decode {fmt} {w}x{h}", _decode(data, fmt, w, h)))
    data = _tiled(encode_bc6h_signed(signed), 16, 256, 2048, 2048)
    out.append(
        ("io.compress decode bc6h-signed 2048x2048", _decode(data, "bc6h-signed", 2048, 2048))
    )
    big_signed = np.tile(signed, (2, 2, 1))
    out.append(("io.compress encode bc6h-signed 512x512", lambda: encode_bc6h_signed(big_signed)))
    surface = (np.tile(hdr, (8, 16, 1)) * 400).astype(np.float32)
    out.append(("io.compress to_half_surface 4096x2048x3", lambda: to_half_surface(surface)))
    return out
