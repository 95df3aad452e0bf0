"""EXIF exposure reading: what a camera records comes back, a file without EXIF gives nothing,
and a file that is not an image is refused with its name."""

from __future__ import annotations

import numpy as np
import pytest
import tifffile
from PIL import Image, TiffImagePlugin

from bakeshop.errors import BakeshopError, FormatError
from bakeshop.io import write_image
from bakeshop.io.exif import read_exposure


def test_jpeg_exposure_comes_back(tmp_path):
    exif = Image.Exif()
    exif[0x010F] = "Maker"
    ifd = exif.get_ifd(0x8769)
    ifd[0x829A] = TiffImagePlugin.IFDRational(1, 250)
    ifd[0x829D] = TiffImagePlugin.IFDRational(56, 10)
    ifd[0x8827] = 400
    ifd[0x9204] = TiffImagePlugin.IFDRational(-2, 3)
    Image.fromarray(np.zeros((4, 4, 3), np.uint8)).save(tmp_path / "a.jpg", exif=exif)
    got = read_exposure(tmp_path / "a.jpg")
    assert got.pop("make") == "Maker"
    assert got == pytest.approx(
        {"exposure_time": 0.004, "f_number": 5.6, "iso": 400.0, "exposure_bias": -2 / 3}
    )


def test_tags_in_a_tiffs_first_directory(tmp_path):
    # some writers put the exposure tags in the image's own directory
    tifffile.imwrite(
        tmp_path / "a.tif", np.zeros((4, 4, 3), np.uint16), photometric="rgb",
        extratags=[(33434, 5, 1, (1, 30), True), (33437, 5, 1, (8, 1), True)],
    )  # fmt: skip
    assert read_exposure(tmp_path / "a.tif") == {"exposure_time": 1 / 30, "f_number": 8.0}


def test_no_exif_and_not_an_image(tmp_path):
    write_image(tmp_path / "plain.png", np.zeros((3, 3, 3), np.uint8))
    assert read_exposure(tmp_path / "plain.png") == {}
    (tmp_path / "text.jpg").write_text("hello")
    with pytest.raises(FormatError) as info:
        read_exposure(tmp_path / "text.jpg")
    assert info.value.path == str(tmp_path / "text.jpg")
    with pytest.raises(BakeshopError):
        read_exposure(tmp_path / "missing.jpg")
