"""A remap computed part by part from windows of its latlong source (bakeshop.sphere.windows,
what bakeshop.huge runs) is bit-identical to the in-memory remap, sample and texel geometry."""

import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.sphere import layout, remap, sample, texel_geometry
from bakeshop.sphere.windows import (
    gather_taps,
    latlong_window_geometry,
    localise_taps,
    remap_part_taps,
    sample_taps,
    taps_window,
)

SRC_SHAPE = (48, 96)


@pytest.fixture(scope="module")
def source():
    return np.random.default_rng(3).random(SRC_SHAPE + (3,), dtype=np.float32)


def _from_window(image, taps, frac):
    """What a task does: load only the window the taps read, renumber them, blend."""
    rows, ranges = taps_window(taps, image.shape[1])
    window = np.concatenate([image[rows[0] : rows[1], a:b] for a, b in ranges], axis=1)
    local = localise_taps(taps, image.shape[1], rows, ranges)
    return gather_taps(window.reshape(-1, image.shape[2]), local, frac), window.size


@pytest.mark.parametrize("filter", ["nearest", "bilinear"])
def test_cube_parts_from_windows_are_the_whole_remap(source, filter):
    whole = remap(source, "latlong", "cube", 16, filter=filter)
    face_shape = (6, 16, 16)
    for face in range(6):
        for rows, cols in [((0, 8), (0, 16)), ((8, 16), (3, 11))]:
            taps, frac = remap_part_taps("latlong", SRC_SHAPE, "cube", face_shape, face=face,
                                         rows=rows, cols=cols, filter=filter)  # fmt: skip
            got, _ = _from_window(source, taps, frac)
            expected = whole[face, rows[0] : rows[1], cols[0] : cols[1]].reshape(-1, 3)
            np.testing.assert_array_equal(got, expected)


def test_a_part_reads_a_small_window_and_one_across_the_seam_reads_two_ranges(source):
    # the centre of the cube's +Z face looks backwards, where a latlong's longitude wraps
    whole = remap(source, "latlong", "cube", 16)
    taps, frac = remap_part_taps("latlong", SRC_SHAPE, "cube", (6, 16, 16), face=4, rows=(6, 10),
                                 cols=(6, 10))  # fmt: skip
    _, ranges = taps_window(taps, SRC_SHAPE[1])
    assert len(ranges) == 2  # the last columns, then the first (around the seam)
    assert ranges[0][1] == SRC_SHAPE[1] and ranges[1][0] == 0
    got, read = _from_window(source, taps, frac)
    np.testing.assert_array_equal(got, whole[4, 6:10, 6:10].reshape(-1, 3))
    assert read < source.size // 8  # the window, not the image


@pytest.mark.parametrize("filter", ["nearest", "bilinear"])
def test_sample_taps_are_sample(source, filter):
    dirs = np.random.default_rng(4).normal(size=(500, 3))
    taps, frac = sample_taps("latlong", SRC_SHAPE, dirs, filter=filter)
    got, _ = _from_window(source, taps, frac)
    np.testing.assert_array_equal(got, sample(source, "latlong", dirs, filter=filter))


def test_latlong_window_geometry_is_the_layouts_own():
    dirs, omega = texel_geometry("latlong", SRC_SHAPE)
    dirs = dirs.reshape(SRC_SHAPE + (3,))
    omega = omega.reshape(SRC_SHAPE)
    got_dirs, got_omega = latlong_window_geometry(SRC_SHAPE, (5, 20), (30, 70))
    np.testing.assert_array_equal(got_dirs, dirs[5:20, 30:70].reshape(-1, 3))
    np.testing.assert_array_equal(got_omega, omega[5:20, 30:70].reshape(-1))
    whole_rows, _ = latlong_window_geometry(SRC_SHAPE, (0, 2))
    assert whole_rows.shape == (2 * SRC_SHAPE[1], 3)


def test_taps_window_of_no_valid_tap_is_empty():
    assert taps_window(np.full((4, 4), -1, np.int32), 10) == ((0, 0), [])


def test_localise_keeps_missing_taps_missing():
    taps = np.array([[12, -1], [13, 22]], np.int32)
    local = localise_taps(taps, 10, (1, 3), [(2, 4)])
    np.testing.assert_array_equal(local, [[0, -1], [1, 2]])


def test_parts_outside_or_between_pictures_are_refused():
    with pytest.raises(ArgumentError):
        remap_part_taps("latlong", SRC_SHAPE, "cube", (6, 16, 16), face=6, rows=(0, 1),
                        cols=(0, 1))  # fmt: skip
    with pytest.raises(ArgumentError):
        remap_part_taps("latlong", SRC_SHAPE, "cross-vertical", (64, 48), rows=(0, 1),
                        cols=(0, 1))  # fmt: skip
    with pytest.raises(ArgumentError):
        latlong_window_geometry(SRC_SHAPE, (40, 60))
    with pytest.raises(ArgumentError):
        sample_taps(layout("cross-horizontal"), (48, 64), np.zeros((1, 3)))
