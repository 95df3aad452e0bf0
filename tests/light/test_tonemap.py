"""Exposure and the sRGB transfer curve against published values and an independent decoder."""

import numpy as np
import OpenImageIO as oiio
import pytest
from tolerances import FLOAT32_CURVE_RTOL, OIIO_SRGB_ATOL

from bakeshop.errors import ArgumentError
from bakeshop.light.tonemap import exposure, srgb_decode, srgb_encode

# Published reference values of the IEC 61966-2-1 curve (linear -> encoded), float64.
SRGB_PAIRS = [
    (0.0, 0.0),
    (0.0031308, 0.040449936),  # end of the linear segment, 12.92 * 0.0031308
    (0.18, 0.4613561295),  # photographic mid grey
    (0.2140411405, 0.5),
    (0.5, 0.7353569831),
    (1.0, 1.0),
]


def test_exposure_scales_by_powers_of_two():
    img = np.full((2, 3, 3), 0.25, np.float32)
    assert exposure(img, 2).dtype == np.float32
    np.testing.assert_array_equal(exposure(img, 2), 1.0)
    np.testing.assert_array_equal(exposure(img, -1), 0.125)
    np.testing.assert_allclose(exposure(img, 0.5), 0.25 * np.sqrt(2), rtol=FLOAT32_CURVE_RTOL)
    assert exposure(np.array([1, 2]), 1).dtype == np.float32


def test_exposure_propagates_nan_inf_and_rejects_bad_ev():
    out = exposure(np.array([np.nan, np.inf, -1.0], np.float32), 1)
    assert np.isnan(out[0]) and out[1] == np.inf and out[2] == -2
    with pytest.raises(ArgumentError):
        exposure(np.ones(3), float("nan"))


@pytest.mark.parametrize(("linear", "encoded"), SRGB_PAIRS)
def test_srgb_published_values(linear, encoded):
    assert srgb_encode(np.float64(linear)) == pytest.approx(encoded, abs=1e-9)
    assert srgb_decode(np.float64(encoded)) == pytest.approx(linear, abs=1e-9)


def test_srgb_8bit_code_values():
    # Widely tabulated decodings of 8-bit sRGB codes: 128 -> 0.2158605, 10 -> 10/255/12.92.
    assert srgb_decode(128 / 255) == pytest.approx(0.2158605001, abs=1e-9)
    assert srgb_decode(10 / 255) == pytest.approx(10 / 255 / 12.92, abs=1e-12)
    assert srgb_decode(11 / 255) == pytest.approx(0.0033465358, abs=1e-9)


def test_srgb_curve_is_continuous_at_the_segment_joint():
    eps = 1e-12
    for f, x in ((srgb_encode, 0.0031308), (srgb_decode, 0.04045)):
        lo, hi = f(np.float64(x - eps)), f(np.float64(x + eps))
        assert abs(hi - lo) < 1e-7  # the standard's rounded constants leave a ~1e-8 step


def test_srgb_round_trip_float32_and_dtype():
    x = np.linspace(-2, 4, 10001, dtype=np.float32)
    e = srgb_encode(x)
    assert e.dtype == np.float32 and srgb_decode(e).dtype == np.float32
    np.testing.assert_allclose(srgb_decode(e), x, rtol=1e-5, atol=1e-7)
    # float32 agrees with a float64 evaluation
    np.testing.assert_allclose(e, srgb_encode(x.astype(np.float64)), rtol=FLOAT32_CURVE_RTOL)


def test_srgb_negative_nan_inf():
    x = np.array([-0.5, -0.001, np.nan, np.inf, -np.inf], np.float64)
    e = srgb_encode(x)
    assert e[0] == pytest.approx(-0.7353569831) and e[1] == pytest.approx(-0.01292)
    assert np.isnan(e[2]) and e[3] == np.inf and e[4] == -np.inf
    d = srgb_decode(x)
    assert d[0] == pytest.approx(-0.2140411405) and np.isnan(d[2]) and d[3] == np.inf


def test_srgb_matches_openimageio():
    x = np.linspace(0, 1, 257, dtype=np.float32).reshape(1, -1, 1)
    ref = oiio.ImageBufAlgo.colorconvert(oiio.ImageBuf(x), "linear", "sRGB")
    np.testing.assert_allclose(
        srgb_encode(x), ref.get_pixels(oiio.FLOAT).reshape(x.shape), atol=OIIO_SRGB_ATOL
    )
