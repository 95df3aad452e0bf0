"""TIFF: exact round trips at 8, 16 and 32 bits, OpenCV (libtiff) reading what bakeshop writes
and bakeshop reading what OpenCV writes, planar and grey + alpha files, compressions that need
imagecodecs, bad files, and fuzzing."""

from __future__ import annotations

import io

import cv2
import numpy as np
import pytest
import tifffile
from hypothesis import given
from hypothesis import strategies as st

from bakeshop.errors import ArgumentError, FormatError, UnsupportedError
from bakeshop.io import read_image, write_image
from tests.io import fuzzing


def ramp(h, w, c, dtype):
    top = np.iinfo(dtype).max
    v = (np.arange(h * w * c, dtype=np.int64) * 7919) % (top + 1)
    return v.reshape(h, w, c).astype(dtype)


@pytest.mark.parametrize("dtype,bits", [(np.uint8, 8), (np.uint16, 16)])
@pytest.mark.parametrize("channels", [1, 3, 4])
def test_integer_round_trip_is_exact(tmp_path, dtype, bits, channels):
    values = ramp(5, 7, channels, dtype)
    path = tmp_path / "a.tif"
    write_image(path, values)
    image, meta = read_image(path, with_metadata=True)
    assert image.dtype == np.float32 and image.shape == (5, 7, channels)
    np.testing.assert_array_equal(np.rint(image * ((1 << bits) - 1)), values)
    assert meta["stored"] == np.dtype(dtype).name and meta["bits"] == bits


def test_float_round_trip_is_bit_exact(tmp_path):
    rng = np.random.default_rng(1)
    image = (rng.lognormal(0, 4, (6, 9, 3))).astype(np.float32)
    path = tmp_path / "hdr.tiff"
    write_image(path, image, compression="none")
    np.testing.assert_array_equal(read_image(path), image)


@pytest.mark.parametrize("dtype", [np.uint8, np.uint16])
def test_opencv_reads_ours_and_we_read_opencvs(tmp_path, dtype):
    values = ramp(8, 11, 3, dtype)
    ours = tmp_path / "ours.tif"
    write_image(ours, values)
    np.testing.assert_array_equal(cv2.imread(str(ours), cv2.IMREAD_UNCHANGED)[..., ::-1], values)
    theirs = tmp_path / "theirs.tif"
    cv2.imwrite(str(theirs), values[..., ::-1].copy())  # libtiff, LZW by default
    try:
        got = read_image(theirs)
    except UnsupportedError as e:  # LZW without imagecodecs: the hint names the extra
        assert "bakeshop[tiff]" in str(e)
        return
    np.testing.assert_array_equal(np.rint(got * np.iinfo(dtype).max), values)


def test_planar_and_grey_alpha_become_interleaved(tmp_path):
    values = ramp(4, 6, 3, np.uint16)
    path = tmp_path / "planar.tif"
    tifffile.imwrite(path, np.moveaxis(values, -1, 0), photometric="rgb", planarconfig="separate")
    image, meta = read_image(path, with_metadata=True)
    assert meta["planar"]
    np.testing.assert_array_equal(np.rint(image * 65535), values)
    grey_alpha = ramp(4, 6, 2, np.uint8)
    path = tmp_path / "ga.tif"
    tifffile.imwrite(path, grey_alpha, photometric="minisblack", extrasamples=["unassalpha"])
    np.testing.assert_array_equal(np.rint(read_image(path) * 255), grey_alpha[..., [0, 0, 0, 1]])


def test_bad_options_are_refused(tmp_path):
    with pytest.raises(ArgumentError, match="bits"):
        write_image(tmp_path / "a.tif", np.zeros((2, 2, 3), np.float32), bits=12)
    with pytest.raises(ArgumentError, match="compression"):
        write_image(tmp_path / "a.tif", np.zeros((2, 2, 3), np.float32), compression="jpeg")
    with pytest.raises(ArgumentError, match="floats"):
        write_image(tmp_path / "a.tif", np.zeros((2, 2, 3), np.uint8), bits=32)


def test_lying_size_and_wrong_format_are_refused(tmp_path):
    path = tmp_path / "huge.tif"
    write_image(path, np.zeros((4, 4, 3), np.uint8))
    with pytest.raises(FormatError, match="exceeds"):
        read_image(path, max_pixels=8)
    png = tmp_path / "png.tif"
    write_image(tmp_path / "a.png", np.zeros((2, 2, 3), np.uint8))
    png.write_bytes((tmp_path / "a.png").read_bytes())
    fuzzing.assert_refused(png, png.read_bytes(), "PNG/JPEG, not TIFF")


def small_tiff(values, **options) -> bytes:
    buffer = io.BytesIO()
    tifffile.imwrite(buffer, values, **options)
    return buffer.getvalue()


SEEDS = [
    small_tiff(ramp(3, 4, 3, np.uint8), photometric="rgb"),
    small_tiff(ramp(2, 3, 1, np.uint16)[..., 0], compression="zlib"),
]
scratch = fuzzing.scratch_file("f.tif", seeds=SEEDS)


@fuzzing.FUZZ
@given(st.sampled_from(SEEDS), fuzzing.edits(300), st.integers(1, 400))
def test_mutations_of_a_valid_file(scratch, data, changes, end):
    fuzzing.decode(scratch, fuzzing.mutate(data, changes, end))


@fuzzing.FUZZ
@given(st.binary(max_size=200))
def test_random_bytes(scratch, data):
    fuzzing.decode(scratch, b"II*\x00" + data)


@pytest.mark.parametrize("data", SEEDS)
def test_truncation_at_every_offset_is_refused(scratch, data):
    fuzzing.assert_truncations_refused(scratch, data)
