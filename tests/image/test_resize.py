"""Area resampling against independent references: OpenCV's INTER_AREA and exact rational
supersampling (replicate every texel, then average integer blocks)."""

import math

import cv2
import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.image import area_weights, resize_area
from tests.tolerances import FLOAT32_MEAN, FLOAT32_VALUE


def supersampled(image, width, height):
    """Brute-force area filter: replicate each texel lcm/n times, then box-average blocks."""
    h, w = image.shape[:2]
    ly, lx = math.lcm(h, height), math.lcm(w, width)
    fine = np.repeat(np.repeat(image.astype(np.float64), ly // h, 0), lx // w, 1)
    return fine.reshape(height, ly // height, width, lx // width, -1).mean(axis=(1, 3))


@pytest.mark.parametrize(
    ("shape", "size"),
    [((12, 18, 3), (6, 4)), ((12, 18, 3), (7, 5)), ((10, 9, 1), (4, 6)), ((5, 7, 4), (11, 13))],
)
def test_matches_rational_supersampling(shape, size):
    rng = np.random.default_rng(1)
    image = rng.random(shape, dtype=np.float32) * 100
    out = resize_area(image, size)
    ref = supersampled(image, *size)
    assert out.shape == (size[1], size[0], shape[2])
    np.testing.assert_allclose(out, ref, rtol=FLOAT32_VALUE, atol=FLOAT32_VALUE * 100)


@pytest.mark.parametrize("size", [(512, 256), (300, 170), (97, 31)])
def test_downsampling_matches_opencv_inter_area(size):
    rng = np.random.default_rng(2)
    image = rng.random((512, 1024, 3), dtype=np.float32)
    ours = resize_area(image, size)
    theirs = cv2.resize(image, size, interpolation=cv2.INTER_AREA)
    np.testing.assert_allclose(ours, theirs, atol=1e-5)


@pytest.mark.parametrize("size", [(1000, 500), (333, 127), (1, 1), (4096, 2048), (17, 3000)])
def test_mean_is_preserved(size):
    rng = np.random.default_rng(3)
    image = (rng.lognormal(0, 3, (400, 800, 3))).astype(np.float32)  # HDR-like, 1e-4..1e4
    out = resize_area(image, size)
    assert out.mean(dtype=np.float64) == pytest.approx(
        image.mean(dtype=np.float64), rel=FLOAT32_MEAN
    )


def test_weights_are_a_partition():
    for n_in, n_out in [(7, 3), (3, 7), (1000, 999), (5, 5), (1, 4)]:
        w = area_weights(n_in, n_out).toarray()
        np.testing.assert_allclose(w.sum(axis=1), 1.0)
        np.testing.assert_allclose(w.sum(axis=0), n_out / n_in)
        assert (w >= 0).all()


def test_two_dimensional_input_stays_two_dimensional():
    image = np.arange(16, dtype=np.float32).reshape(4, 4)
    out = resize_area(image, (2, 2))
    np.testing.assert_array_equal(out, [[2.5, 4.5], [10.5, 12.5]])


def test_uint8_input_is_resampled_as_values():
    image = np.full((4, 4, 3), 200, np.uint8)
    out = resize_area(image, (3, 3))
    assert out.dtype == np.float32
    np.testing.assert_allclose(out, 200)


def test_nan_spreads_only_to_covering_texels():
    image = np.ones((4, 4), np.float32)
    image[0, 0] = np.nan
    out = resize_area(image, (2, 2))
    assert np.isnan(out[0, 0]) and np.isfinite(out.ravel()[1:]).all()


@pytest.mark.parametrize("bad", [(0, 4), (4, -1)])
def test_invalid_sizes(bad):
    with pytest.raises(ArgumentError):
        resize_area(np.ones((4, 4)), bad)


def test_invalid_shape():
    with pytest.raises(ArgumentError):
        resize_area(np.ones(5), (2, 2))
