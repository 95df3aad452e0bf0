"""The one display rule (bakeshop.image.to_picture): exposure, metering over valid texels only,
tone curve, clamp, sRGB from its definition, 8 and 16 bits, and what a picture records."""

import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.image import (
    auto_exposure,
    check_ev,
    choose_exposure,
    encode_picture,
    fit_exposure,
    to_picture,
)
from bakeshop.sphere import layout


def _srgb(x):
    """IEC 61966-2-1 written from its definition, float64."""
    x = np.clip(x, 0, 1)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)


def test_fixed_exposure_clamp_and_srgb_at_8_and_16_bits():
    rng = np.random.default_rng(0)
    image = rng.uniform(0, 3, (6, 9, 3)).astype(np.float32)
    for bits, top, dtype in ((8, 255, np.uint8), (16, 65535, np.uint16)):
        p = to_picture(image, ev=-1.0, bits=bits)
        want = np.rint(_srgb(image.astype(np.float64) * 0.5) * top)
        assert p.pixels.dtype == dtype
        assert np.abs(p.pixels.astype(np.int64) - want).max() <= 1  # float32 vs float64 ties
        clipped = (image * 0.5 >= 1).any(axis=-1).mean()
        assert p.clipped == pytest.approx(clipped)
        assert (
            p.describe().startswith("exposure -1.00 EV, clamped") and f"{bits}-bit" in p.describe()
        )
    linear = to_picture(image, encoding="linear", bits=16)
    np.testing.assert_array_equal(linear.pixels, np.rint(np.clip(image, 0, 1) * 65535))
    assert "linear" in linear.describe()
    # alpha is clamped, never encoded
    rgba = np.concatenate([image, np.full((6, 9, 1), 0.5, np.float32)], axis=-1)
    assert (to_picture(rgba).pixels[..., 3] == 128).all()


def test_auto_exposure_meters_only_valid_texels_of_a_cross():
    # a vertical cross of a grey sky: half its cells are empty (black). Metering every texel
    # puts the log of delta into half the average and brightens the picture by many stops;
    # the rule meters the cross's valid texels (solid angles, 0 in the empty cells)
    lay = layout("cross-vertical")
    shape = lay.shape(16)
    valid = lay.solid_angles(shape) > 0
    image = np.where(valid[..., None], 0.5, 0.0).astype(np.float32) * np.ones(3, np.float32)
    whole = auto_exposure(image, center_weight=0)
    p = to_picture(image, ev="auto", weights=lay.solid_angles(shape))
    assert p.ev == pytest.approx(np.log2(0.18 / (0.5 + 1e-4)), abs=1e-6)
    assert whole - p.ev > 5  # what metering every texel did: many stops brighter
    assert p.metered == pytest.approx(valid.mean())
    assert "auto over 50.0% of texels" in p.describe()
    # without a layout, exact black is left out of the frame's metering as well
    assert to_picture(image, ev="auto", center_weight=0).ev == pytest.approx(p.ev, abs=1e-6)


def test_auto_exposure_of_a_fresnel_bake_meters_above_the_horizon():
    from bakeshop.cli._common import environment_weights
    from bakeshop.light import bake_fresnel

    lay = layout("latlong")
    shape = lay.shape(32)
    dirs, _ = lay.directions(shape)
    sky = (0.2 + dirs[..., 1:2].clip(0) * np.array([1.0, 1.0, 2.0])).astype(np.float32)
    baked = bake_fresnel(sky, "latlong")  # the lower half is 0
    weights = environment_weights("latlong", shape, up=(0, 1, 0))
    got = choose_exposure(baked, "auto", weights=weights).ev
    # by hand: the solid-angle weighted log-average luminance of the upper half only
    upper = weights > 0
    lum = baked[..., :3] @ np.array([0.2126, 0.7152, 0.0722])
    w = lay.solid_angles(shape)[upper]
    log_avg = np.exp(np.sum(w * np.log(1e-4 + lum[upper])) / w.sum())
    assert got == pytest.approx(np.log2(0.18 / log_avg), abs=1e-6)  # float32 luminance
    assert (baked[~upper] == 0).all()


def test_fit_exposure_clips_the_chosen_fraction():
    values = np.linspace(0.01, 10, 1000, dtype=np.float32).reshape(10, 100)
    ev = fit_exposure(values, clip_fraction=0.05)
    assert (values * 2**ev > 1 + 1e-6).mean() == pytest.approx(0.05, abs=2e-3)
    with pytest.raises(ArgumentError):
        fit_exposure(np.zeros((4, 4)))


def test_exposure_range_and_modes_are_checked():
    for bad in (float("nan"), float("inf"), 1e308, 65, -65, "bright"):
        with pytest.raises(ArgumentError):
            check_ev(bad)
    assert check_ev("-64") == -64
    with pytest.raises(ArgumentError):
        to_picture(np.ones((2, 2, 3)), ev="median")
    with pytest.raises(ArgumentError):
        encode_picture(np.ones((2, 2, 3)), bits=12)


def test_picture_metadata_round_trips_through_a_png(tmp_path):
    from PIL import Image  # an independent reader of the PNG text chunk

    from bakeshop.io import read_image, write_image

    image = np.random.default_rng(1).uniform(0, 4, (8, 16, 3)).astype(np.float32)
    p = to_picture(image, ev="auto", operator="aces")
    path = tmp_path / "p.png"
    write_image(path, p.pixels, description=p.metadata())
    text = Image.open(path).info["Description"]
    assert f"exposure {p.ev:+.4f} EV" in text and "ACES" in text
    assert read_image(path, with_metadata=True)[1]["description"] == text
