"""The quality measures against hand computations, and the RGBM/RGBD packings against their
formulas (Karis / three.js RGBM, Babylon.js RGBD)."""

import math

import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.io.compress import packing, quality


def test_mpsnr_by_hand():
    """One texel differing by one 8-bit step at one exposure of nine: MSE = 1/9 per texel."""
    a = np.array([[0.5, 0.5, 0.5]], np.float32)
    assert quality.mpsnr(a, a) == math.inf
    # at c = 0, 255 * 0.5^(1/2.2) = 186.0; choose b so that only the red value moves a step
    b = a.copy()
    b[0, 0] = ((186.4 + 0.6) / 255) ** 2.2  # 187 at c = 0; check the other exposures by hand
    t = [[np.clip(np.rint(255 * (v * 2.0**c) ** (1 / 2.2)), 0, 255) for v in (a[0, 0], b[0, 0])]
         for c in range(-4, 5)]  # fmt: skip
    mse = sum((x - y) ** 2 for x, y in t) / 9
    assert quality.mpsnr(a, b) == pytest.approx(10 * math.log10(3 * 255**2 / mse))


def test_log2_rmse_and_psnr():
    a = np.full((4, 3), 2.0)
    assert quality.log2_rmse(a, 2 * a) == pytest.approx(1.0)
    assert quality.log2_rmse(np.zeros((1, 3)), np.full((1, 3), 1e-9)) == 0  # below the floor
    assert quality.psnr(np.zeros((10, 1)), np.full((10, 1), 0.1)) == pytest.approx(20.0)
    with pytest.raises(ArgumentError):
        quality.mpsnr(np.zeros((2, 3)), np.zeros((3, 3)))


def test_angular_error_and_rebuilt_z():
    angle = np.radians(2.0)
    a = np.array([[0.0, 0.0, 1.0]])
    b = np.array([[np.sin(angle), 0.0, np.cos(angle)]])
    assert quality.angular_error(a, b)["mean"] == pytest.approx(2.0)
    n = quality.rebuild_z(np.array([[0.6, 0.0]]))
    np.testing.assert_allclose(n, [[0.6, 0.0, 0.8]])


def test_rgbm_by_its_formula():
    value = np.array([[3.0, 1.5, 0.0]], np.float32)
    packed = packing.encode_rgbm(value, range=8.0)
    m = np.ceil(255 * 3.0 / 8.0) / 255  # 97 / 255
    np.testing.assert_allclose(packed, [[3 / (8 * m), 1.5 / (8 * m), 0.0, m]], rtol=1e-6)
    np.testing.assert_allclose(packing.decode_rgbm(packed, range=8.0), value, rtol=1e-6)
    assert packing.encode_rgbm(np.array([[100.0, 0, 0]]), range=8.0)[0, 0] == 1  # clipped at 8


def test_rgbd_by_babylons_formula():
    value = np.array([[10.0, 5.0, 1.0]], np.float32)
    d = np.floor(max(255 / 10.0, 1)) / 255  # 25 / 255
    packed = packing.encode_rgbd(value)
    np.testing.assert_allclose(packed[0, 3], d, rtol=1e-6)
    np.testing.assert_allclose(packed[0, :3], (value[0] * d) ** (1 / 2.2), rtol=1e-6)
    np.testing.assert_allclose(packing.decode_rgbd(packed), value, rtol=1e-5)
    dark = packing.encode_rgbd(np.array([[0.2, 0.1, 0.05]]))
    assert dark[0, 3] == 1.0  # below 1, D clamps to 1: plain gamma-2.2 colour
    top = packing.decode_rgbd(packing.encode_rgbd(np.array([[1000.0, 0, 0]])))[0, 0]
    assert top == pytest.approx(255, rel=1e-6)  # clipped at RGBD_MAX
