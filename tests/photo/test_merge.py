"""Merging: within 1 % of the truth wherever a frame saw it, ahead of OpenCV's calibrate and
merge on the same stack (multi-exposure PSNR and log2 error, measured in the same run),
clipping judged per pixel across channels with weights exactly zero at the clipped ends, the
confidence map, ghost suppression and the absolute scale of EXIF exposures."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.photo import (
    CLIPPED,
    DARK,
    MEASURED,
    confidence_image,
    known_response,
    log2_rmse,
    make_stack,
    merge_stack,
    multi_exposure_psnr,
    recover_response,
    relative_scale,
)
from bakeshop.photo.merge import _tables, clip_codes
from bakeshop.photo.stack import LUMINANCE_PER_UNIT
from tests.photo import synthetic
from tests.photo.tolerances import MERGE_RMS, MPSNR_GAIN_DB

#: 11 frames a stop apart; the brightest shows the probe's darkest 0.1 % at a quarter of white.
TIMES = 2.0 ** np.arange(-8, 3)
GAIN = 8.0


@pytest.fixture(scope="module")
def scene():
    truth = synthetic.default_probe()
    stack = make_stack(synthetic.shoot(truth, TIMES, gain=GAIN), TIMES)
    response = recover_response(stack.codes, stack.exposures)
    return truth, stack, merge_stack(stack, response)


def relative_rms(result, truth, mask, scale_mask=None):
    k = relative_scale(result, truth, scale_mask if scale_mask is not None else mask)
    rel = result[mask] / k / truth[mask] - 1
    return float(np.sqrt(np.mean(rel * rel)))


@pytest.mark.slow
def test_merge_within_one_percent_where_some_frame_saw_it(scene):
    truth, stack, merged = scene
    seen = merged.votes > 0
    assert seen.mean() > 0.999
    assert relative_rms(merged.radiance, truth, seen) < MERGE_RMS


@pytest.mark.slow
def test_ahead_of_opencv_on_the_same_stack(scene):
    truth, stack, merged = scene
    images = [np.ascontiguousarray(f[..., ::-1]) for f in stack.codes]
    times = stack.exposures.astype(np.float32)
    curve = cv2.createCalibrateDebevec().process(images, times)
    theirs = cv2.createMergeDebevec().process(images, times, curve)[..., ::-1]
    ours = merged.radiance / relative_scale(merged.radiance, truth)
    theirs = theirs / relative_scale(theirs, truth)
    ours_db, theirs_db = multi_exposure_psnr(ours, truth), multi_exposure_psnr(theirs, truth)
    print(f"mPSNR bakeshop {ours_db:.2f} dB, OpenCV {theirs_db:.2f} dB")
    assert ours_db >= theirs_db + MPSNR_GAIN_DB
    assert log2_rmse(ours, truth) < log2_rmse(theirs, truth)


def test_a_pixel_clipped_in_one_channel_does_not_vote_in_that_frame():
    # two frames of a saturated red: in the long one only red clips, in the short one nothing
    dark = np.array([[[120, 40, 30]]], np.uint8)
    bright = np.array([[[255, 80, 60]]], np.uint8)
    stack = make_stack([dark, bright], [1.0, 2.0])
    response = known_response("linear")
    merged = merge_stack(stack, response)
    np.testing.assert_allclose(merged.radiance[0, 0], dark[0, 0] / 255, rtol=1e-6)
    assert merged.votes[0, 0] == 1 and merged.status[0, 0] == MEASURED
    assert merged.clipped_high.tolist() == [0.0, 1.0]


def test_weights_are_exactly_zero_at_the_clipped_ends():
    for bits in (8, 16):
        low, high = clip_codes(bits, None, None)
        _, weight, _ = _tables(known_response("srgb"), bits, 3, low, high)
        assert np.all(weight[: low + 1] == 0) and np.all(weight[high:] == 0)
        assert np.all(weight[low + 1 : high] > 0)


@pytest.mark.slow
def test_confidence_says_clipped_and_dark(scene):
    truth, stack, merged = scene
    sun = np.unravel_index(np.argmax(truth.mean(-1)), truth.shape[:2])
    assert merged.status[sun] == CLIPPED and merged.votes[sun] == 0
    conf = confidence_image(merged)
    assert conf.shape == truth.shape and conf.dtype == np.float32
    np.testing.assert_array_equal(conf[..., 0], merged.votes)
    np.testing.assert_array_equal(conf[..., 2], merged.status)
    # a stack too bright for a black pixel: dark in every frame, an upper bound
    frames = [np.array([[[0, 0, 0], [128, 128, 128]]], np.uint8)] * 2
    m = merge_stack(make_stack(frames, [1.0, 2.0]), known_response("srgb"))
    assert m.status[0, 0] == DARK and m.status[0, 1] == MEASURED and m.votes[0, 1] == 2


def test_ghost_suppression_keeps_the_walker_out():
    truth = synthetic.default_probe()[150:406, 300:812].copy()
    times = 2.0 ** np.arange(-4, 3)
    frames = synthetic.shoot(truth, times, gain=GAIN / 4)
    walker = np.zeros(truth.shape[:2], bool)
    walker[100:180, 200:240] = True
    moved = truth.copy()
    moved[walker] = truth[walker].mean((0,)) * 6  # someone bright in one frame only
    frames[2] = synthetic.shoot(moved, times[2:3], gain=GAIN / 4, seed=9)[0]
    stack = make_stack(frames, times)
    response = synthetic.true_response()
    plain = merge_stack(stack, response)
    clean = merge_stack(stack, response, ghost=0.25)
    everywhere = np.ones(walker.shape, bool)
    err_plain = relative_rms(plain.radiance, truth, walker, everywhere)
    err_clean = relative_rms(clean.radiance, truth, walker, everywhere)
    assert err_plain > 0.2 and err_clean < 0.03, (err_plain, err_clean)
    assert clean.ghost_rejected[2] > 0.5 * walker.mean()
    assert clean.ghost_rejected.sum() < 2 * walker.mean()  # the rest of the scene passes


def test_exif_exposures_give_luminance_in_candela():
    # sRGB code 118 at 1/100 s, f/4, ISO 100 is mid-grey of L = 10 N^2 / (0.65 t S) (ISO 12232)
    frames = [np.full((2, 2, 3), 118, np.uint8), np.full((2, 2, 3), 255, np.uint8)]
    stack = make_stack(frames, [0.01 * 1 / 16, 0.04 * 1 / 16], absolute=True)
    merged = merge_stack(stack, known_response("srgb"))
    expected = 10 * 16 / (0.65 * 0.01 * 100) * (((118 / 255 + 0.055) / 1.055) ** 2.4 / 0.18)
    assert LUMINANCE_PER_UNIT == pytest.approx(10 / (0.65 * 0.18 * 100))
    np.testing.assert_allclose(merged.radiance[0, 0, 0], expected, rtol=1e-5)


@pytest.mark.slow
def test_bad_arguments_are_refused(scene):
    _, stack, _ = scene
    response = known_response("srgb")
    with pytest.raises(ArgumentError, match="ghost"):
        merge_stack(stack, response, ghost=float("inf"))
    with pytest.raises(ArgumentError, match="shifts"):
        merge_stack(stack, response, shifts=np.zeros((2, 2)))
    with pytest.raises(ArgumentError, match="clip levels"):
        merge_stack(stack, response, clip_low=0.6, clip_high=0.7)
    with pytest.raises(ArgumentError, match="same exposure"):
        make_stack(stack.codes[:3], [0.5, 0.5, 0.5])


@pytest.mark.slow
def test_sixteen_bit_frames():
    truth = synthetic.default_probe()[::2, ::2]
    times = 2.0 ** np.arange(-8, 3, 2)
    frames = synthetic.shoot(truth, times, gain=GAIN, bits=16, noise=0.1)
    stack = make_stack(frames, times)
    assert stack.bits == 16
    merged = merge_stack(stack, recover_response(stack.codes, stack.exposures))
    seen = merged.votes > 0
    assert relative_rms(merged.radiance, truth, seen) < MERGE_RMS
