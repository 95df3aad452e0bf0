"""Reading brackets: exposures from EXIF (JPEG, PNG) or given (16-bit TIFF, PNG), stored codes
exactly, and the stacks that cannot be merged refused with the reason."""

from __future__ import annotations

import numpy as np
import pytest
import tifffile
from PIL import Image, TiffImagePlugin

from bakeshop.errors import ArgumentError, UnsupportedError
from bakeshop.io import write_image
from bakeshop.io.exif import read_exposure
from bakeshop.photo import read_stack


def save_with_exif(path, codes, time, f_number=8.0, iso=100):
    exif = Image.Exif()
    ifd = exif.get_ifd(0x8769)
    ifd[0x829A] = TiffImagePlugin.IFDRational(*(time.as_integer_ratio()))
    ifd[0x829D] = TiffImagePlugin.IFDRational(*(f_number.as_integer_ratio()))
    ifd[0x8827] = iso
    exif[0x0110] = "Test camera"
    options = {"quality": 100, "subsampling": 0} if path.suffix == ".jpg" else {}
    Image.fromarray(codes).save(path, exif=exif, **options)


def test_exif_exposures_of_jpeg_and_png(tmp_path):
    rng = np.random.default_rng(0)
    codes = rng.integers(0, 256, (8, 10, 3), dtype=np.uint8)
    paths = []
    for k, t in enumerate((1 / 256, 1 / 64, 1 / 16)):
        path = tmp_path / f"f{k}.{'png' if k == 1 else 'jpg'}"
        save_with_exif(path, codes, t, iso=200)
        paths.append(path)
    assert read_exposure(paths[1]) == {
        "exposure_time": 1 / 64, "f_number": 8.0, "iso": 200.0, "model": "Test camera"
    }  # fmt: skip
    stack = read_stack(paths[::-1])  # any order: sorted darkest first
    np.testing.assert_allclose(stack.exposures, np.array([1 / 256, 1 / 64, 1 / 16]) * 2 / 64)
    assert stack.absolute and stack.span_stops == pytest.approx(4.0)
    np.testing.assert_array_equal(stack.codes[1], codes)  # PNG codes exactly


def test_sixteen_bit_tiff_with_given_times(tmp_path):
    rng = np.random.default_rng(1)
    frames = [rng.integers(0, 65536, (6, 7, 3), dtype=np.uint16) for _ in range(3)]
    paths = []
    for k, f in enumerate(frames):
        paths.append(tmp_path / f"b{k}.tif")
        tifffile.imwrite(paths[-1], f, photometric="rgb")
    stack = read_stack(paths, exposure_times=[0.5, 0.125, 2.0])
    assert stack.codes.dtype == np.uint16 and stack.bits == 16 and not stack.absolute
    np.testing.assert_array_equal(stack.codes, np.stack([frames[1], frames[0], frames[2]]))
    assert [s["source"] for s in stack.settings] == ["given"] * 3


@pytest.mark.slow
def test_stacks_that_cannot_be_merged_are_refused(tmp_path):
    codes = np.zeros((4, 4, 3), np.uint8)
    write_image(tmp_path / "a.png", codes)
    write_image(tmp_path / "b.png", codes)
    with pytest.raises(ArgumentError, match="no exposure time") as info:
        read_stack([tmp_path / "a.png", tmp_path / "b.png"])
    assert info.value.path == str(tmp_path / "a.png")
    with pytest.raises(ArgumentError, match="same exposure"):
        read_stack([tmp_path / "a.png", tmp_path / "b.png"], exposure_times=[0.1, 0.1])
    write_image(tmp_path / "c.png", np.zeros((5, 4, 3), np.uint8))
    with pytest.raises(ArgumentError, match="one size"):
        read_stack([tmp_path / "a.png", tmp_path / "c.png"], exposure_times=[0.1, 0.2])
    write_image(tmp_path / "d.exr", np.zeros((4, 4, 3), np.float32))
    with pytest.raises(UnsupportedError, match="8- or 16-bit"):
        read_stack([tmp_path / "a.png", tmp_path / "d.exr"], exposure_times=[0.1, 0.2])
    with pytest.raises(ArgumentError, match="need 2 values"):
        read_stack([tmp_path / "a.png", tmp_path / "b.png"], exposure_times=[0.1])
