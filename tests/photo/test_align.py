"""Alignment: a stack shifted by known sub-pixel offsets (applied to the radiance by cubic
splines before the camera) is re-aligned within 0.1 pixel; large shifts are found by the
pyramid; aligned merging beats unaligned."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.ndimage import shift as spline_shift

from bakeshop.errors import ArgumentError
from bakeshop.photo import align_stack, make_stack, merge_stack
from tests.photo import synthetic
from tests.photo.tolerances import ALIGN_PX

TIMES = 2.0 ** np.arange(-6, 3, 2)
GAIN = 0.5


def shifted_stack(offsets, seed=0):
    """Frame j shows the scene moved by offsets[j] = (dy, dx): frame_j(p) = scene(p - d_j), so
    frame j read at p + d_j is the scene at p."""
    truth = synthetic.default_probe()
    frames = []
    for j, (t, d) in enumerate(zip(TIMES, offsets, strict=True)):
        moved = np.stack(
            [spline_shift(truth[..., c], d, order=3, mode="nearest") for c in range(3)], -1
        )
        frames += synthetic.shoot(np.maximum(moved, 0), [t], gain=GAIN, seed=seed + j)
    return np.stack(frames)


@pytest.mark.slow
def test_sub_pixel_offsets_are_recovered_within_a_tenth_of_a_pixel():
    rng = np.random.default_rng(5)
    offsets = rng.uniform(-6, 6, (len(TIMES), 2))
    offsets[len(TIMES) // 2] = 0
    found = align_stack(shifted_stack(offsets))
    assert np.abs(found - offsets).max() < ALIGN_PX, found - offsets


def test_large_shifts_are_found_by_the_pyramid():
    offsets = np.array([[23.4, -17.7], [-1.3, 2.2], [0.0, 0.0], [-9.2, 30.6], [5.1, -3.8]])
    found = align_stack(shifted_stack(offsets, seed=7), max_shift=64)
    assert np.abs(found - offsets).max() < ALIGN_PX, found - offsets


@pytest.mark.slow
def test_aligned_merge_is_sharper_than_unaligned():
    offsets = np.array([[2.5, -1.25], [0.5, 3.0], [0.0, 0.0], [-2.0, 1.5], [1.0, -2.5]])
    codes = shifted_stack(offsets, seed=3)
    stack = make_stack(list(codes), TIMES)
    response = synthetic.true_response()
    truth = synthetic.default_probe() * GAIN
    inner = (slice(16, -16), slice(16, -16))

    def error(m):
        seen = m.votes[inner] > 0
        rel = m.radiance[inner][seen] / truth[inner][seen] - 1
        return float(np.sqrt(np.mean(rel * rel)))

    plain = merge_stack(stack, response)
    aligned = merge_stack(stack, response, shifts=align_stack(stack.codes))
    assert error(aligned) < 0.5 * error(plain), (error(aligned), error(plain))


def test_bad_arguments():
    codes = np.zeros((3, 32, 32, 3), np.uint8)
    with pytest.raises(ArgumentError, match="reference"):
        align_stack(codes, reference=5)
    with pytest.raises(ArgumentError, match="max_shift"):
        align_stack(codes, max_shift=0)
    with pytest.raises(ArgumentError, match="uint8 or uint16"):
        align_stack(codes.astype(np.float32))


@pytest.mark.slow
def test_a_still_wide_bracket_stays_put():
    # 12 stops in 7 frames: the darkest shows the sky at a few codes; a count of differing bits
    # (not a rate) and a threshold in its noise once moved it by 30 pixels
    probe, _, _ = synthetic.sunny_probe()
    times = 1 / 4000 * 4.0 ** np.arange(7)
    codes = np.stack(synthetic.shoot(probe, times, gain=0.18 * 60 / 0.5))
    assert np.abs(align_stack(codes)).max() < ALIGN_PX
