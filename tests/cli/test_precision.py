"""No silent loss: bit depth follows the inputs in every command, one display rule for pictures
of HDR data, a warning for display-encoded inputs, and SH irradiance windowed as exported."""

import json

import cv2
import numpy as np
import pytest
from PIL import Image

from bakeshop.cli.main import main
from bakeshop.io import read_image, write_image
from bakeshop.sphere import layout


def _png16(path, values):
    """A 16-bit PNG written by OpenCV (an independent writer), values in [0, 1]."""
    codes = np.rint(np.clip(values, 0, 1) * 65535).astype(np.uint16)
    cv2.imwrite(str(path), codes[..., ::-1] if codes.shape[-1] == 3 else codes)
    return codes


def _lines(text):
    return [line for line in text.splitlines() if line.strip()]


def _tilted_normals(h, w):
    y, x = np.mgrid[0:h, 0:w] / max(h, w)
    n = np.stack([0.4 * np.sin(6 * x), 0.3 * np.cos(5 * y), np.ones_like(x)], axis=-1)
    return n / np.linalg.norm(n, axis=-1, keepdims=True)


@pytest.mark.slow
def test_a_flat_detail_on_a_16_bit_macro_map_stays_16_bit(tmp_path, capsys):
    macro = tmp_path / "macro.png"
    codes = _png16(macro, (_tilted_normals(64, 64) + 1) / 2)
    flat = tmp_path / "flat.exr"  # exactly flat (an 8-bit 128 is tilted by 0.32 degrees)
    write_image(flat, np.full((8, 8, 3), [0.5, 0.5, 1.0], np.float32))
    out = tmp_path / "out.png"
    assert main(["normals", "combine", str(macro), str(flat), str(out)]) == 0
    assert "16-bit" in capsys.readouterr().out
    got = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)[..., ::-1]
    assert got.dtype == np.uint16
    # the 8-bit copy had 0.35 degree errors; 16 bits keep the macro map within a code value
    assert np.abs(got.astype(int) - codes.astype(int)).max() <= 1
    # with an 8-bit detail the result is 16-bit as well
    detail8 = tmp_path / "detail8.png"
    write_image(detail8, ((_tilted_normals(8, 8) + 1) / 2).astype(np.float32))
    assert main(["normals", "combine", str(macro), str(detail8), str(out)]) == 0
    assert cv2.imread(str(out), cv2.IMREAD_UNCHANGED).dtype == np.uint16
    # TGA stores 8 bits: said in one warning line
    tga = tmp_path / "out.tga"
    assert main(["normals", "combine", str(macro), str(flat), str(tga)]) == 0
    err = _lines(capsys.readouterr().err)
    assert len(err) == 1 and "8 bits" in err[0] and "16-bit" in err[0] and str(tga) in err[0]
    # asked for explicitly: 8 bits, said too
    assert main(["normals", "combine", str(macro), str(flat), str(out), "-O", "bits=8"]) == 0
    assert "as asked" in capsys.readouterr().err
    assert read_image(out, with_metadata=True)[1]["stored"] == "uint8"


def test_normals_from_16_bit_height_and_float_maps_write_16_bit_png(tmp_path):
    height = tmp_path / "h.png"
    _png16(height, np.random.default_rng(0).uniform(0, 1, (32, 32)))
    out = tmp_path / "n.png"
    assert main(["normals", "from-height", str(height), str(out)]) == 0
    assert read_image(out, with_metadata=True)[1]["stored"] == "uint16"
    exr = tmp_path / "n.exr"
    write_image(exr, ((_tilted_normals(16, 16) + 1) / 2).astype(np.float32))
    conv = tmp_path / "n_dx.png"
    assert main(["normals", "convert", str(exr), str(conv), "--from", "gl", "--to", "dx"]) == 0
    assert cv2.imread(str(conv), cv2.IMREAD_UNCHANGED).dtype == np.uint16


def test_convert_and_resize_keep_16_bits(tmp_path, capsys):
    src = tmp_path / "a.png"
    codes = _png16(src, np.random.default_rng(2).uniform(0, 1, (16, 16, 3)))
    out = tmp_path / "b.png"
    assert main(["convert", str(src), str(out)]) == 0
    np.testing.assert_array_equal(cv2.imread(str(out), cv2.IMREAD_UNCHANGED)[..., ::-1], codes)
    small = tmp_path / "c.png"
    assert main(["resize", str(src), str(small), "--size", "8"]) == 0
    assert cv2.imread(str(small), cv2.IMREAD_UNCHANGED).dtype == np.uint16
    jpg = tmp_path / "d.jpg"
    capsys.readouterr()
    assert main(["convert", str(src), str(jpg)]) == 0
    err = _lines(capsys.readouterr().err)
    assert len(err) == 1 and "8 bits" in err[0]
    # display-encoded values get no exposure: refused with the way out
    assert main(["convert", str(src), str(out), "--exposure", "1"]) == 2
    assert "--srgb-decode" in capsys.readouterr().err


def test_remap_to_a_picture_follows_the_display_rule_and_records_it(tmp_path, capsys):
    lay = layout("latlong")
    shape = lay.shape(32)
    dirs, _ = lay.directions(shape)
    hdr = (0.05 + 4 * np.clip(dirs[..., 1:2], 0, 1) * np.array([1.0, 0.8, 0.6])).astype(np.float32)
    src = tmp_path / "sky.exr"
    write_image(src, hdr, pixel_type="float")
    # plain: exposure 0, clamp, sRGB (before: clamped linear values)
    out = tmp_path / "sky.png"
    assert main(["remap", str(src), str(out), "--to", "latlong", "--size", "32"]) == 0
    said = capsys.readouterr().out
    assert "exposure +0.00 EV, clamped" in said and "sRGB, 8-bit" in said
    x = np.clip(hdr.astype(np.float64), 0, 1)
    srgb = np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)
    got = cv2.imread(str(out))[..., ::-1].astype(np.float64) / 255
    assert np.abs(got - srgb).max() <= 0.5 / 255 + 1e-6
    # a cross, auto exposure: metered over the valid cells only, recorded in the file
    cross = tmp_path / "cross.png"
    args = ["remap", str(src), str(cross), "--to", "cross-vertical", "--size", "16"]
    assert main([*args, "--exposure", "auto", "--tonemap", "aces"]) == 0
    text = Image.open(cross).info["Description"]
    ev = float(text.split("exposure ")[1].split(" EV")[0])
    floats = tmp_path / "cross.exr"
    assert main(["remap", str(src), str(floats), "--to", "cross-vertical", "--size", "16"]) == 0
    image = read_image(floats)
    omega = layout("cross-vertical").solid_angles(image.shape[:2])
    lum = image @ np.array([0.2126, 0.7152, 0.0722], np.float32)
    valid = omega > 0
    log_avg = np.exp(np.sum(omega[valid] * np.log(1e-4 + lum[valid])) / omega[valid].sum())
    assert ev == pytest.approx(np.log2(0.18 / log_avg), abs=1e-3)
    everything = np.exp(np.mean(np.log(1e-4 + lum)))  # what metering every texel gives
    assert np.log2(0.18 / everything) - ev > 3


def test_prefilter_mip_pictures_share_one_exposure(tmp_path, capsys):
    src = tmp_path / "sky.exr"
    write_image(src, np.full((16, 32, 3), 0.3, np.float32))
    out = tmp_path / "spec_{mip}.png"
    assert main(["prefilter", str(src), str(out), "--size", "8", "--mips", "3",
                 "--exposure", "auto"]) == 0  # fmt: skip
    texts = {Image.open(tmp_path / f"spec_{m}.png").info["Description"] for m in range(3)}
    assert len(texts) == 1 and "exposure" in texts.pop()
    assert "pictures: exposure" in capsys.readouterr().out


def test_an_8_bit_probe_into_irradiance_warns_or_is_linearised(tmp_path, capsys):
    lay = layout("latlong")
    dirs, _ = lay.directions(lay.shape(16))
    linear = (0.2 + 0.6 * np.clip(dirs[..., 1:2], 0, 1) * np.ones(3)).astype(np.float32)
    x = linear.astype(np.float64)
    encoded = np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)
    png = tmp_path / "sky.png"
    cv2.imwrite(str(png), np.rint(encoded * 255).astype(np.uint8)[..., ::-1])
    assert main(["irradiance", str(png), str(tmp_path / "a.exr"), "--size", "16"]) == 0
    err = _lines(capsys.readouterr().err)
    assert len(err) == 1 and "display-encoded" in err[0] and "--srgb-decode" in err[0]
    args = ["irradiance", str(png), str(tmp_path / "b.exr"), "--size", "16", "--srgb-decode"]
    assert main(args) == 0 and capsys.readouterr().err.strip() == ""  # no warning
    decoded = read_image(tmp_path / "b.exr")
    as_stored = read_image(tmp_path / "a.exr")
    # the decoded DIM is the linear sky's (within 8-bit quantisation), the other is not
    ref = tmp_path / "ref.exr"
    write_image(ref, linear, pixel_type="float")
    assert main(["irradiance", str(ref), str(tmp_path / "c.exr"), "--size", "16"]) == 0
    exact = read_image(tmp_path / "c.exr")
    assert np.abs(decoded - exact).max() < 5e-3 < np.abs(as_stored - exact).max()


@pytest.mark.slow
def test_irradiance_sh_is_windowed_and_reports_the_negative_fraction(tmp_path, capsys):
    lay = layout("latlong")
    shape = lay.shape(64)
    dirs, _ = lay.directions(shape)
    sun = np.array([0.5, 0.5, -0.7071])
    sky = 0.1 + 3000 * np.exp(400 * (dirs @ sun - 1))[..., None] * np.ones(3)
    src = tmp_path / "sunny.exr"
    write_image(src, sky.astype(np.float32), pixel_type="float")
    doc_path = tmp_path / "sh.json"
    args = ["irradiance", str(src), str(tmp_path / "dim.exr"), "--method", "sh"]
    assert main([*args, "--sh-json", str(doc_path)]) == 0
    said = capsys.readouterr().out
    assert "negative over 0.00% of the sphere" in said and "minimal window" in said
    assert read_image(tmp_path / "dim.exr").min() >= 0
    doc = json.loads(doc_path.read_text())
    assert doc["irradiance"]["negative_fraction"] == 0
    assert doc["irradiance"]["negative_fraction_unwindowed"] > 0.05
    assert main([*args, "--window", "none"]) == 0
    assert read_image(tmp_path / "dim.exr").min() < 0  # the raw ring, kept available


def test_tonemap_meters_a_cross_as_an_environment(tmp_path, capsys):
    lay = layout("cross-vertical")
    shape = lay.shape(8)
    omega = lay.solid_angles(shape)
    rng = np.random.default_rng(5)
    image = np.where((omega > 0)[..., None], rng.uniform(0.1, 2, shape + (3,)), 0)
    src = tmp_path / "cross.exr"
    write_image(src, image.astype(np.float32), pixel_type="float")
    out = tmp_path / "cross.png"
    assert main(["tonemap", str(src), str(out), "--from", "cross-vertical"]) == 0
    ev = float(Image.open(out).info["Description"].split("exposure ")[1].split(" EV")[0])
    lum = image @ np.array([0.2126, 0.7152, 0.0722])
    valid = omega > 0
    log_avg = np.exp(np.sum(omega[valid] * np.log(1e-4 + lum[valid])) / omega[valid].sum())
    assert ev == pytest.approx(np.log2(0.18 / log_avg), abs=1e-4)
    assert "auto exposure" in capsys.readouterr().out
