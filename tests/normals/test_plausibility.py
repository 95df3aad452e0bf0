"""What a normal map's content says about it: not a normal map at all (an HDR image), the
green convention it was made in (from the curl of its slopes), and how much of a tiled
detail survives the filter. Maps are made here from known height fields."""

from __future__ import annotations

import numpy as np
import pytest

from bakeshop.normals.encoding import (
    convert_convention,
    decode_normals,
    encode_normals,
    guess_convention,
    implausible,
)
from bakeshop.normals.tiling import filtered_relief


def bumps(size: int = 96, seed: int = 5) -> np.ndarray:
    """A tileable height field of random round bumps, in texels (not separable in x and y)."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:size, 0:size] + 0.5
    h = np.zeros((size, size))
    for cx, cy, a in zip(*rng.random((2, 12)) * size, rng.normal(0, 3, 12), strict=True):
        dx = (x - cx + size / 2) % size - size / 2
        dy = (y - cy + size / 2) % size - size / 2
        h += a * np.exp(-(dx**2 + dy**2) / (2 * (size / 12) ** 2))
    return h


def normals_of(height: np.ndarray) -> np.ndarray:
    """Unit normals (OpenGL: +Y up the picture) of a height field in texel units."""
    dh_dx = (np.roll(height, -1, 1) - np.roll(height, 1, 1)) / 2
    dh_dv = -(np.roll(height, -1, 0) - np.roll(height, 1, 0)) / 2  # v runs up the rows
    n = np.stack([-dh_dx, -dh_dv, np.ones_like(height)], axis=-1)
    return (n / np.linalg.norm(n, axis=-1, keepdims=True)).astype(np.float32)


def test_the_convention_of_a_map_is_read_from_its_curl():
    gl = normals_of(bumps())
    guess, share = guess_convention(gl)
    assert guess == "gl" and share < 0.1
    guess, share = guess_convention(convert_convention(gl, "gl", "dx"))  # a DX map read as GL
    assert guess == "dx" and share > 0.9


def test_the_convention_survives_8_bit_quantisation():
    stored = np.round(encode_normals(normals_of(bumps())) * 255) / 255
    assert guess_convention(decode_normals(stored))[0] == "gl"
    assert guess_convention(decode_normals(stored, convention="dx"))[0] == "dx"


def test_a_map_that_cannot_tell_is_not_guessed():
    size = 64
    x = np.arange(size) * 2 * np.pi / size
    separable = 3 * np.sin(x)[None, :] + 2 * np.cos(2 * x)[:, None]  # no mixed slopes
    assert guess_convention(normals_of(separable))[0] is None
    flat = np.zeros((size, size, 3), np.float32)
    flat[..., 2] = 1
    assert guess_convention(flat)[0] is None


def test_an_hdr_image_is_not_a_normal_map():
    probe = np.random.default_rng(1).lognormal(0.0, 2.0, (32, 64, 3)).astype(np.float32)
    assert "outside [0, 1]" in implausible(probe)
    grey = np.full((16, 16, 3), 0.5, np.float32)  # decodes to zero vectors
    assert "far from unit length" in implausible(grey)
    assert "--encoding packed" in implausible(
        encode_normals(normals_of(bumps())), encoding="signed"
    )
    assert implausible(encode_normals(normals_of(bumps()))) is None


def test_a_detail_tiled_finer_than_the_output_loses_its_relief():
    rng = np.random.default_rng(2)
    detail = normals_of(rng.normal(0, 1.0, (128, 128)))  # texel-scale roughness
    authored, left = filtered_relief(detail, (128, 128), tile=1)
    assert left == authored > 10
    authored, left = filtered_relief(detail, (64, 64), tile=16)  # 32x32 texels per texel
    assert left < 1.0 < authored
    smooth = normals_of(bumps(64))
    assert filtered_relief(smooth, (512, 512), tile=8)[1] == pytest.approx(
        filtered_relief(smooth, (512, 512), tile=1)[1]
    )
