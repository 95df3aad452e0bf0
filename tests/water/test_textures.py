"""Texture helpers: flipbook layout and gutters, foam that loops, mip chains, packing."""

import math

import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.water.textures import (
    encode_heights,
    flipbook,
    foam,
    normal_mips,
    pack_normals,
    persistent_foam,
    seam_error,
    unpack_normals,
)


def test_flipbook_is_row_major_with_wrapped_gutters():
    frames = np.arange(5 * 4 * 4, dtype=np.float32).reshape(5, 4, 4)
    atlas, layout = flipbook(frames, columns=3, gutter=1)
    assert (layout["rows"], layout["columns"], layout["cell"]) == (2, 3, 6)
    assert atlas.shape == (12, 18)
    r, c = divmod(4, 3)  # frame 4: second row, second column
    cell = atlas[r * 6 : (r + 1) * 6, c * 6 : (c + 1) * 6]
    np.testing.assert_array_equal(cell[1:5, 1:5], frames[4])
    np.testing.assert_array_equal(cell[0, 1:5], frames[4][-1])  # the frame's own bottom row
    np.testing.assert_array_equal(cell[1:5, 0], frames[4][:, -1])
    with pytest.raises(ArgumentError):
        flipbook(frames, gutter=9)


def test_persistent_foam_loops_exactly_and_decays_at_its_rate():
    rng = np.random.default_rng(0)
    f, n = 24, 16
    t = np.arange(f) / f
    cover = np.clip(np.sin(2 * math.pi * (t[:, None, None] + rng.random((1, n, n)))), 0, 1)
    cover = (cover > 0.95).astype(np.float32)  # brief flashes of foam
    out = persistent_foam(cover, frame_time=0.25, decay=1.0)
    # a second loop continues the first exactly: run three loops by hand and compare
    state = np.zeros((n, n), np.float32)
    fade = np.float32(math.exp(-0.25))
    history = []
    for _ in range(3):
        for k in range(f):
            state = np.maximum(cover[k], state * fade)
            history.append(state.copy())
    np.testing.assert_allclose(out, np.stack(history[f : 2 * f]), rtol=1e-6)
    np.testing.assert_allclose(np.stack(history[2 * f :]), np.stack(history[f : 2 * f]), rtol=1e-6)
    assert (out >= cover).all()


def test_foam_ramp_and_heights():
    j = np.array([1.0, 0.5, 0.25, 0.0, -1.0])
    np.testing.assert_allclose(foam(j, start=0.5, full=0.0), [0, 0, 0.5, 1, 1])
    np.testing.assert_allclose(encode_heights([-1.0, 0.0, 3.0], -1.0, 3.0), [0, 0.25, 1])


def test_normal_mips_are_renormalised_means():
    rng = np.random.default_rng(1)
    n = rng.normal(size=(8, 8, 3)) * [0.2, 0.2, 0] + [0, 0, 1]
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    mips = normal_mips(n)
    assert [m.shape[0] for m in mips] == [8, 4, 2, 1]
    block = n[2:4, 4:6].reshape(-1, 3).mean(0)  # level 1 texel (1, 2) from its four parents
    np.testing.assert_allclose(mips[1][1, 2], block / np.linalg.norm(block), rtol=1e-6)
    for m in mips:
        np.testing.assert_allclose(np.linalg.norm(m, axis=-1), 1, rtol=1e-6)


def test_pack_unpack_and_seams():
    n = np.array([[0.3, -0.2, math.sqrt(1 - 0.13)]])
    np.testing.assert_allclose(unpack_normals(pack_normals(n)), n, atol=1e-7)
    np.testing.assert_allclose(unpack_normals(pack_normals(n, channels="xy"), channels="xy"), n,
                               atol=1e-7)  # fmt: skip
    x = np.linspace(0, 2 * math.pi, 64, endpoint=False)
    tileable = np.sin(x)[None, :] * np.ones((64, 1))
    s = seam_error(tileable)
    assert s["seam_u"] <= s["inner_u"] * 1.0001
    broken = np.linspace(0, 1, 64)[None, :] * np.ones((64, 1))
    assert seam_error(broken)["seam_u"] > 10 * seam_error(broken)["inner_u"]
