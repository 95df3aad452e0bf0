"""The info, convert and resize commands, end to end through bakeshop.cli.main.main."""

import json

import numpy as np
import OpenImageIO as oiio
import pytest

from bakeshop.cli.main import main
from bakeshop.io import read_image, write_image


@pytest.fixture
def hdr_image(tmp_path):
    rng = np.random.default_rng(7)
    image = rng.lognormal(0.0, 2.0, (32, 64, 3)).astype(np.float32)
    path = tmp_path / "probe.exr"
    write_image(path, image, pixel_type="float")
    return path, image


def test_version(capsys):
    assert main(["--version"]) == 0
    assert "bakeshop" in capsys.readouterr().out


def test_help_teaches_with_examples(capsys):
    for command in ("info", "convert", "resize"):
        assert main([command, "--help"]) == 0
        assert "Example:" in capsys.readouterr().out


def test_unknown_command_is_one_line(capsys):
    assert main(["frobnicate"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("bakeshop: error: ") and err.count("\n") == 1


def test_info_json_reports_statistics(hdr_image, capsys):
    path, image = hdr_image
    assert main(["info", "--json", str(path)]) == 0
    report = json.loads(capsys.readouterr().out)
    assert (report["width"], report["height"], report["channels"]) == (64, 32, 3)
    assert report["channel_stats"][1]["max"] == pytest.approx(float(image[..., 1].max()))
    lum = image @ np.array([0.2126, 0.7152, 0.0722], np.float32)
    assert report["dynamic_range_stops"] == pytest.approx(np.log2(lum.max() / lum.min()), rel=1e-5)
    assert report["layout_guess"] == ["latlong"]


def test_info_counts_nan_and_inf(tmp_path, capsys):
    image = np.ones((4, 8, 3), np.float32)
    image[0, 0, 0], image[1, 1, 1], image[2, 2, 2] = np.nan, np.inf, -np.inf
    path = tmp_path / "bad.exr"
    write_image(path, image, pixel_type="float")
    assert main(["info", "--json", str(path)]) == 0
    report = json.loads(capsys.readouterr().out)
    assert (report["nan"], report["inf"]) == (1, 2)


def test_info_default_probe(capsys):
    assert main(["info"]) == 0
    out = capsys.readouterr().out
    assert "1024x512" in out and "latlong" in out


def test_convert_hdr_to_png_applies_exposure_and_srgb(hdr_image, tmp_path, capsys):
    path, image = hdr_image
    out = tmp_path / "preview.png"
    assert main(["convert", str(path), str(out), "--exposure", "-2"]) == 0
    said = capsys.readouterr().out
    assert "exposure -2.00 EV, clamped" in said and "sRGB, 8-bit" in said
    # independent check: OpenImageIO reads the PNG; the sRGB curve written from its definition
    buf = oiio.ImageBuf(str(out))
    stored = buf.get_pixels(oiio.UINT8).astype(np.float64) / 255
    x = np.clip(image.astype(np.float64) * 0.25, 0, 1)
    srgb = np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)
    assert np.abs(stored - srgb).max() <= 0.5 / 255 + 1e-6


def test_convert_float_round_trip_is_exact(hdr_image, tmp_path):
    path, image = hdr_image
    out = tmp_path / "copy.pfm"
    assert main(["convert", str(path), str(out)]) == 0
    np.testing.assert_array_equal(read_image(out), image)


def test_convert_passes_writer_options(hdr_image, tmp_path):
    path, image = hdr_image
    out = tmp_path / "half.exr"
    assert (
        main(["convert", str(path), str(out), "-O", "pixel_type=half", "-O", "compression=piz"])
        == 0
    )
    spec = oiio.ImageInput.open(str(out)).spec()
    assert spec.format == oiio.HALF and spec.get_string_attribute("compression") == "piz"


def test_convert_refuses_an_unknown_option(hdr_image, tmp_path, capsys):
    path, _ = hdr_image
    assert main(["convert", str(path), str(tmp_path / "x.exr"), "-O", "colour=blue"]) == 2
    assert "colour" in capsys.readouterr().err
    assert not (tmp_path / "x.exr").exists()


def test_convert_refuses_to_overwrite_its_input(hdr_image, capsys):
    path, image = hdr_image
    assert main(["convert", str(path), str(path)]) == 2
    assert "own input" in capsys.readouterr().err
    np.testing.assert_array_equal(read_image(path), image)


def test_convert_truncated_input_is_one_line_and_writes_nothing(hdr_image, tmp_path, capsys):
    path, _ = hdr_image
    broken = tmp_path / "broken.exr"
    broken.write_bytes(path.read_bytes()[:300])
    out = tmp_path / "out.hdr"
    assert main(["convert", str(broken), str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"bakeshop: error: {broken}") and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == [path, broken] or not out.exists()


def test_convert_unknown_extension(hdr_image, tmp_path, capsys):
    path, _ = hdr_image
    assert main(["convert", str(path), str(tmp_path / "x.webp")]) == 2
    assert "unknown image extension '.webp'" in capsys.readouterr().err


def test_resize_preserves_the_mean(hdr_image, tmp_path):
    path, image = hdr_image
    out = tmp_path / "small.exr"
    assert main(["-q", "resize", str(path), str(out), "--size", "20x10"]) == 0
    small = read_image(out)
    assert small.shape == (10, 20, 3)
    assert small.mean(dtype=np.float64) == pytest.approx(image.mean(dtype=np.float64), rel=1e-3)


def test_resize_single_width_keeps_aspect(hdr_image, tmp_path):
    path, _ = hdr_image
    out = tmp_path / "small.pfm"
    assert main(["resize", str(path), str(out), "--size", "16"]) == 0
    assert read_image(out).shape == (8, 16, 3)


def test_resize_bad_size(hdr_image, tmp_path, capsys):
    path, _ = hdr_image
    assert main(["resize", str(path), str(tmp_path / "o.exr"), "--size", "0x5"]) == 2
    assert "0 is not in the range 1<=x<=65536" in capsys.readouterr().err


def test_convert_drops_alpha_where_the_target_stores_none(tmp_path, capfd):
    rgba = np.random.default_rng(3).random((8, 16, 4), dtype=np.float32)
    src = tmp_path / "rgba.exr"
    write_image(src, rgba, pixel_type="float")
    assert main(["convert", str(src), str(tmp_path / "rgb.pfm")]) == 2
    assert "--alpha drop or --alpha premultiply" in capfd.readouterr().err
    assert main(["convert", str(src), str(tmp_path / "rgb.pfm"), "--alpha", "drop"]) == 0
    assert "alpha: drop" in capfd.readouterr().out
    np.testing.assert_array_equal(read_image(tmp_path / "rgb.pfm"), rgba[:, :, :3])
    assert main(["convert", str(src), str(tmp_path / "rgba.tga")]) == 0
    assert read_image(tmp_path / "rgba.tga").shape == (8, 16, 4)
