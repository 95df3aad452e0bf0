"""Exposure and the sRGB transfer curve against published values and an independent decoder."""

import numpy as np
import OpenImageIO as oiio
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bakeshop.errors import ArgumentError
from bakeshop.image import (
    ACES_FITS,
    aces_filmic,
    adapt_exposure,
    auto_exposure,
    exposure,
    log_average_luminance,
    metering_weights,
    reinhard,
    srgb_decode,
    srgb_encode,
    to_srgb8,
    tonemap,
)
from bakeshop.image.display import HILL_INPUT, HILL_OUTPUT
from tests.tolerances import FLOAT32_CURVE_RTOL, OIIO_SRGB_ATOL

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


# --- tone operators ---------------------------------------------------------------------------


def _reinhard_by_hand(lum, white):
    return lum * (1 + lum / white**2) / (1 + lum)


def test_reinhard_eq4_on_luminance_preserves_colour():
    rgb = np.array([[[0.5, 2.0, 4.0], [1.0, 1.0, 1.0], [0.0, 0.0, 0.0]]], np.float32)
    out = reinhard(rgb, white=3.0)
    assert out.dtype == np.float32
    lum = 0.2126 * rgb[..., 0] + 0.7152 * rgb[..., 1] + 0.0722 * rgb[..., 2]
    lum_out = 0.2126 * out[..., 0] + 0.7152 * out[..., 1] + 0.0722 * out[..., 2]
    np.testing.assert_allclose(lum_out, _reinhard_by_hand(lum, 3.0), rtol=FLOAT32_CURVE_RTOL)
    # channel ratios (hue and saturation) kept
    np.testing.assert_allclose(out[0, 0] / out[0, 0, 0], rgb[0, 0] / rgb[0, 0, 0], rtol=1e-6)
    np.testing.assert_array_equal(out[0, 2], 0)


def test_reinhard_white_point_maps_to_one_and_none_is_eq3():
    grey = np.array([0.0, 1.0, 3.0, 10.0])
    assert reinhard(grey[:, None], white=3.0)[2, 0] == pytest.approx(1.0)
    np.testing.assert_allclose(reinhard(grey[:, None])[:, 0], grey / (1 + grey))
    # (H, W) input is a grey image
    np.testing.assert_allclose(
        reinhard(grey.reshape(2, 2), white=2.0).ravel(), _reinhard_by_hand(grey, 2.0)
    )
    rgba = np.array([[[1.0, 1.0, 1.0, 0.25]]])
    assert reinhard(rgba)[0, 0, 3] == 0.25
    with pytest.raises(ArgumentError):
        reinhard(grey[:, None], white=0)


def test_aces_narkowicz_formula():
    x = np.array([0.0, 0.18, 1.0, 100.0])[:, None]
    out = aces_filmic(x, fit="narkowicz")[:, 0]
    assert out[0] == 0
    assert out[1] == pytest.approx(
        0.18 * (2.51 * 0.18 + 0.03) / (0.18 * (2.43 * 0.18 + 0.59) + 0.14)
    )
    assert out[2] == pytest.approx(2.54 / 3.16)
    assert out[3] == 1.0  # the curve tends to 2.51 / 2.43 > 1 and is saturated


def _hill_scalar(rgb):
    # BakingLab ACES.hlsl, transcribed loop by loop.
    m_in = [[0.59719, 0.35458, 0.04823], [0.07600, 0.90834, 0.01566], [0.02840, 0.13383, 0.83777]]
    m_out = [
        [1.60475, -0.53108, -0.07367],
        [-0.10208, 1.10813, -0.00605],
        [-0.00327, -0.07276, 1.07602],
    ]
    v = [sum(m_in[i][j] * rgb[j] for j in range(3)) for i in range(3)]
    v = [
        (x * (x + 0.0245786) - 0.000090537) / (x * (0.983729 * x + 0.4329510) + 0.238081) for x in v
    ]
    v = [sum(m_out[i][j] * v[j] for j in range(3)) for i in range(3)]
    return [min(max(x, 0.0), 1.0) for x in v]


def _rgb_to_xyz(primaries, white):
    xy = np.array(primaries)
    p = np.stack([xy[:, 0] / xy[:, 1], np.ones(3), (1 - xy[:, 0] - xy[:, 1]) / xy[:, 1]])
    w = np.array([white[0] / white[1], 1, (1 - white[0] - white[1]) / white[1]])
    return p * np.linalg.solve(p, w)


def test_hill_matrices_from_first_principles():
    # Hill's matrices are sRGB -> XYZ -> Bradford D65 to D60 -> ACES AP1, then the RRT's
    # saturation (0.96 towards AP1 luminance), and back with the ODT's (0.93): derived here from
    # the primaries and white points (IEC 61966-2-1, SMPTE ST 2065-1 / Academy S-2014-004).
    d65, d60 = (0.3127, 0.3290), (0.32168, 0.33767)
    srgb = _rgb_to_xyz([(0.64, 0.33), (0.30, 0.60), (0.15, 0.06)], d65)
    ap1 = _rgb_to_xyz([(0.713, 0.293), (0.165, 0.830), (0.128, 0.044)], d60)
    bradford = np.array(
        [[0.8951, 0.2664, -0.1614], [-0.7502, 1.7135, 0.0367], [0.0389, -0.0685, 1.0296]]
    )

    def adapt(src, dst):
        s = bradford @ np.array([src[0] / src[1], 1, (1 - src[0] - src[1]) / src[1]])
        d = bradford @ np.array([dst[0] / dst[1], 1, (1 - dst[0] - dst[1]) / dst[1]])
        return np.linalg.inv(bradford) @ np.diag(d / s) @ bradford

    def saturation(s):
        return (1 - s) * np.outer(np.ones(3), ap1[1]) + s * np.eye(3)

    to_ap1 = np.linalg.inv(ap1) @ adapt(d65, d60) @ srgb
    from_ap1 = np.linalg.inv(srgb) @ adapt(d60, d65) @ ap1
    # Hill printed five decimals
    np.testing.assert_allclose(saturation(0.96) @ to_ap1, HILL_INPUT, atol=1e-5)
    np.testing.assert_allclose(from_ap1 @ saturation(0.93), HILL_OUTPUT, atol=1e-5)


def test_aces_hill_matches_transcription_and_is_monotonic():
    rgb = np.array([[0.18, 0.18, 0.18], [1.0, 0.2, 0.05], [0.0, 0.0, 0.0], [20.0, 15.0, 9.0]])
    out = aces_filmic(rgb[None])[0]
    for row, expect in zip(out, map(_hill_scalar, rgb), strict=True):
        np.testing.assert_allclose(row, expect, atol=1e-12)
    ramp = np.geomspace(1e-4, 1e3, 500)[:, None]
    for fit in ACES_FITS:
        y = aces_filmic(ramp, fit=fit)[:, 0]
        assert np.all(np.diff(y) >= 0) and y.max() <= 1 and y.min() >= 0
    # grey through the matrices equals the curve alone (rows of both matrices sum to 1)
    np.testing.assert_allclose(
        aces_filmic(np.full((1, 1, 3), 0.4))[0, 0],
        aces_filmic(np.full((1, 1), 0.4))[0, 0],
        atol=2e-5,
    )


def test_tonemap_pipeline_and_srgb8():
    img = np.array([[[0.25, 0.5, 8.0], [np.nan, -1.0, 0.0]]], np.float32)
    lin = tonemap(img, ev=1, operator="none")
    np.testing.assert_array_equal(lin, [[[0.5, 1.0, 1.0], [0.0, 0.0, 0.0]]])
    code = to_srgb8(lin)
    assert code.dtype == np.uint8
    # 0.5 linear -> 0.73536 encoded -> round(187.52) = 188
    np.testing.assert_array_equal(code, [[[188, 255, 255], [0, 0, 0]]])
    with pytest.raises(ArgumentError):
        tonemap(img, operator="filmic")


def test_triangular_dither_is_unbiased_bounded_and_spares_clipped_values():
    flat = np.full((200, 200, 3), srgb_decode(np.float64(100.3 / 255)), np.float32)
    plain = to_srgb8(flat)
    dithered = to_srgb8(flat, dither="triangular", seed=1)
    assert np.all(plain == 100)
    assert set(np.unique(dithered)) <= {99, 100, 101}
    assert dithered.mean() == pytest.approx(100.3, abs=0.01)
    np.testing.assert_array_equal(dithered, to_srgb8(flat, dither="triangular", seed=1))
    ends = np.zeros((50, 50, 4), np.float32)
    ends[:, :25] = 1.0
    d = to_srgb8(ends, dither="triangular")
    assert set(np.unique(d[:, :25])) == {255} and set(np.unique(d[:, 25:])) == {0}
    half_alpha = np.full((20, 20, 4), 0.3, np.float32)
    half_alpha[..., 3] = 0.5
    d = to_srgb8(half_alpha, dither="triangular")
    assert np.all(d[..., 3] == 128) and len(np.unique(d[..., :3])) > 1  # alpha: linear, no dither


# --- metering and adaptation ------------------------------------------------------------------


def test_metering_weights_follow_their_definition():
    for shape in ((48, 64), (31, 17)):
        for w_c in (0.0, 0.3, 0.75, 1.0):
            w = metering_weights(shape, center_weight=w_c)
            assert w.shape == shape and w.sum() == pytest.approx(1.0)
            # the uniform part is (1 - W) / N everywhere; what is left is the centre spot
            spot = w - (1 - w_c) / w.size
            assert spot.sum() == pytest.approx(w_c) and spot.min() >= -1e-15
            # symmetric about the frame centre, peak at the centre
            np.testing.assert_allclose(w, w[::-1, ::-1], rtol=1e-12)
            assert w[shape[0] // 2, shape[1] // 2] == pytest.approx(w.max(), rel=1e-12)
    # the spot's sigma is a sixth of the short side: 39.3% of it within one sigma
    h, wd = 600, 600
    spot = metering_weights((h, wd), center_weight=1.0)
    y, x = np.mgrid[:h, :wd] + 0.5
    r = np.hypot(y - h / 2, x - wd / 2)
    assert spot[r <= h / 6].sum() == pytest.approx(1 - np.exp(-0.5), abs=5e-3)  # pixelated disc
    with pytest.raises(ArgumentError):
        metering_weights((4, 4), center_weight=1.5)


def test_log_average_and_auto_exposure():
    rng = np.random.default_rng(0)
    img = rng.lognormal(0.0, 1.5, size=(40, 60)).astype(np.float32)
    plain = np.exp(np.mean(np.log(1e-4 + img.astype(np.float64))))
    assert log_average_luminance(img, center_weight=0) == pytest.approx(plain, rel=1e-9)
    # any centre weight: the definition written out with the full weight array, NaN left out
    img[3, 7] = np.nan
    w = metering_weights(img.shape, center_weight=0.6)
    ok = np.isfinite(img)
    want = np.exp(np.sum(w[ok] * np.log(1e-4 + img[ok].astype(np.float64))) / np.sum(w[ok]))
    assert log_average_luminance(img, center_weight=0.6) == pytest.approx(want, rel=1e-9)
    img[3, 7] = 1.0
    ev = auto_exposure(img, center_weight=0, delta=1e-12)
    assert log_average_luminance(exposure(img, ev), center_weight=0, delta=1e-12) == pytest.approx(
        0.18, rel=1e-6
    )
    # a bright centre on a dark frame: metering rises with the centre weight
    frame = np.full((90, 120, 3), 0.01, np.float32)
    frame[30:60, 40:80] = 10.0
    levels = [log_average_luminance(frame, center_weight=w) for w in (0, 0.25, 0.5, 0.75, 1)]
    assert np.all(np.diff(levels) > 0)
    # non-finite pixels are left out
    frame[0, 0] = np.nan
    frame[0, 1] = np.inf
    assert np.isfinite(log_average_luminance(frame))
    with pytest.raises(ArgumentError):
        log_average_luminance(np.full((4, 4), np.nan))


def test_adaptation_step_reaches_63_percent_after_one_time_constant():
    for fps in (24, 30, 60, 1000):
        dt = 1 / fps
        n = round(0.5 / dt)  # tau_brighter = 0.5 s
        # scene gets brighter by 3 stops: target exposure drops from 0 to -3
        ev = adapt_exposure(np.full(4 * n, -3.0), frame_time=dt, start=0.0)
        assert ev[n - 1] / -3.0 == pytest.approx(1 - np.exp(-1), abs=1e-12)
        # darker: uses tau_darker = 2 s
        m = round(2.0 / dt)
        ev = adapt_exposure(np.full(m, 2.0), frame_time=dt, start=0.0)
        assert ev[m - 1] / 2.0 == pytest.approx(1 - np.exp(-1), abs=1e-12)
    # started adapted, a constant target stays put; monotone approach without overshoot
    assert np.all(adapt_exposure(np.full(10, 1.5), frame_time=0.1) == 1.5)
    ev = adapt_exposure(np.r_[np.zeros(5), np.full(50, 4.0)], frame_time=0.1)
    assert np.all(np.diff(ev) >= 0) and ev.max() < 4.0
    with pytest.raises(ArgumentError):
        adapt_exposure([0.0], frame_time=0)


@settings(deadline=None)  # the first call imports the module and its compiled kernels
@given(st.floats(-1e6, 1e6, allow_nan=False))
def test_srgb_round_trip_property(x):
    assert srgb_decode(srgb_encode(np.float64(x))) == pytest.approx(x, rel=1e-12, abs=1e-15)
    assert np.sign(srgb_encode(np.float64(x))) == np.sign(x)
