"""Height -> normal: discrete derivatives exactly, orientation, OpenCV's Sobel, real data."""

import cv2
import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.normals.encoding import decode_normals
from bakeshop.normals.height import height_to_normal
from tests import tolerances as tol
from tests.files import DATA


def test_central_differences_of_a_periodic_wave_wrap_exactly():
    w, k, amp, s = 64, 3, 0.7, 5.0
    x = np.arange(w)
    h = np.tile(amp * np.sin(2 * np.pi * k * x / w), (32, 1))
    # (h[x+1] - h[x-1]) / 2 = amp cos(2 pi k x / w) sin(2 pi k / w), wrap included
    dx = amp * np.cos(2 * np.pi * k * x / w) * np.sin(2 * np.pi * k / w)
    n = height_to_normal(h, strength=s)
    expected = np.stack([-s * dx, np.zeros(w), np.ones(w)], axis=-1)
    expected /= np.linalg.norm(expected, axis=-1, keepdims=True)
    assert n.dtype == np.float64
    np.testing.assert_allclose(n, np.broadcast_to(expected, n.shape), atol=tol.FLOAT64_UNIT)


def test_a_bump_leans_outwards_and_dx_flips_y():
    y, x = np.mgrid[0:65, 0:65]
    h = np.exp(-((x - 32.0) ** 2 + (y - 32.0) ** 2) / 100).astype(np.float32)
    n = height_to_normal(h, strength=10, wrap=False)
    assert n.dtype == np.float32
    assert n[32, 40, 0] > 0.1 and n[32, 24, 0] < -0.1  # right of the top leans right
    assert n[24, 32, 1] > 0.1 and n[40, 32, 1] < -0.1  # above the top (smaller row) leans up
    dx = height_to_normal(h, strength=10, wrap=False, convention="dx")
    np.testing.assert_array_equal(dx * (1, -1, 1), n)


def test_sobel_matches_opencv():
    h = np.random.default_rng(0).random((40, 50))
    gx = cv2.Sobel(h, cv2.CV_64F, 1, 0, ksize=3, borderType=cv2.BORDER_REPLICATE) / 8
    gy = cv2.Sobel(h, cv2.CV_64F, 0, 1, ksize=3, borderType=cv2.BORDER_REPLICATE) / 8
    expected = np.stack([-3 * gx, 3 * gy, np.ones_like(h)], axis=-1)
    expected /= np.linalg.norm(expected, axis=-1, keepdims=True)
    got = height_to_normal(h, strength=3, derivative="sobel", wrap=False)
    np.testing.assert_allclose(got, expected, atol=tol.FLOAT64_UNIT)


def test_flat_and_bad_input():
    np.testing.assert_array_equal(height_to_normal(np.full((4, 5), 3.0)), [[[0, 0, 1]] * 5] * 4)
    with pytest.raises(ArgumentError, match="height map"):
        height_to_normal(np.zeros((4, 5, 3)))
    with pytest.raises(ArgumentError, match="derivative"):
        height_to_normal(np.zeros((4, 5)), derivative="prewitt")
    assert np.isfinite(height_to_normal(np.array([[np.nan, 1.0], [0.0, np.inf]]))).all()


def test_a_real_detail_map_is_directx():
    """cgbookcase's Scratched Gold normal map agrees with its height map in the DX convention."""
    height = cv2.imread(str(DATA / "Scratched_gold_01_1K_Height_crop256.png"))[..., 0] / 255.0
    rgb = cv2.imread(str(DATA / "Scratched_gold_01_1K_Normal_crop256.png"))[..., ::-1] / 255.0
    ours = height_to_normal(height, strength=10)
    for convention, sign in (("dx", 1), ("gl", -1)):
        theirs = decode_normals(rgb, convention=convention)
        r = [np.corrcoef(ours[..., i].ravel(), theirs[..., i].ravel())[0, 1] for i in (0, 1)]
        assert r[0] > 0.5 and sign * r[1] > 0.5
