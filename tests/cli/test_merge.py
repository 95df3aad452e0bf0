"""``bakeshop merge`` and ``bakeshop unwrap`` end to end: brackets with EXIF to an HDR probe
with its sun and confidence map, a saved response reused, ball photos to a probe, and bad
input as one line on stderr with exit 2."""

from __future__ import annotations

import json
from fractions import Fraction

import numpy as np
import pytest
from PIL import Image, TiffImagePlugin

from bakeshop.cli.main import main
from bakeshop.io import read_image, write_image
from bakeshop.photo import CLIPPED, MODELLED
from tests.cli.test_process import one_error_line
from tests.photo import synthetic

TIMES = 1 / 4000 * 4.0 ** np.arange(7)


@pytest.fixture(scope="module")
def brackets(tmp_path_factory):
    folder = tmp_path_factory.mktemp("brackets")
    probe, sky, irradiance = synthetic.sunny_probe()
    frames = synthetic.shoot(probe, TIMES, gain=0.18 * 60 / 0.5)
    paths = []
    for k, (t, codes) in enumerate(zip(TIMES, frames, strict=True)):
        exif = Image.Exif()
        ifd = exif.get_ifd(0x8769)
        exposure = Fraction(float(t)).limit_denominator(100000)
        ifd[0x829A] = TiffImagePlugin.IFDRational(exposure.numerator, exposure.denominator)
        ifd[0x829D] = TiffImagePlugin.IFDRational(8, 1)
        ifd[0x8827] = 100
        exif[0x010F] = "Test"  # Pillow drops an EXIF block whose first directory is empty
        path = folder / f"sky_{k}.png"
        Image.fromarray(codes).save(path, exif=exif)
        paths.append(str(path))
    return paths, probe


def test_help_teaches_with_examples(capsys):
    for command in ("merge", "unwrap"):
        assert main([command, "--help"]) == 0
        assert "Example:" in capsys.readouterr().out


def test_brackets_to_a_probe_with_its_sun(brackets, tmp_path, capsys):
    paths, probe = brackets
    out = tmp_path / "probe.exr"
    assert (
        main(["-q", "merge", *paths, "-o", str(out), "--save-response", str(tmp_path / "cam.json")])
        == 0
    )
    said, err = capsys.readouterr()
    assert "frames: 7 of 1024x512, 8-bit, exposures spanning 12.0 stops" in said
    assert "cd/m^2" in said and "1/4000 s f/8 ISO 100" in said
    assert "sun: modelled" in said and "circumsolar ratio" in said
    hdr, meta = read_image(out, with_metadata=True)
    # the modelled sun is brighter than half floats hold: float32, said in one line, not clamped
    assert meta["stored"] == "float" and hdr.max() > 65504
    assert "beyond the 65504 that half floats hold: written as 32-bit floats" in err
    conf = read_image(tmp_path / "probe_confidence.exr")
    assert hdr.shape == probe.shape and conf.shape == probe.shape
    assert (conf[..., 2] == MODELLED).any() and not (conf[..., 2] == CLIPPED).any()
    assert conf[..., 0].max() == 7
    doc = json.loads((tmp_path / "cam.json").read_text())
    assert doc["method"] == "debevec" and len(doc["linear"]) == 256
    # the saved response, reused, gives the same merge
    again = tmp_path / "again.exr"
    assert (
        main(["-q", "merge", *paths, "-o", str(again), "--response", str(tmp_path / "cam.json")])
        == 0
    )
    np.testing.assert_allclose(read_image(again), hdr, rtol=1e-5)


def test_sun_off_keeps_the_lower_bounds(brackets, tmp_path, capsys):
    paths, _ = brackets
    out = tmp_path / "off.hdr"
    assert main(["-q", "merge", *paths, "-o", str(out), "--sun", "off", "--response", "srgb"]) == 0
    assert "sun: not modelled (--sun off)" in capsys.readouterr().out
    conf = read_image(tmp_path / "off_confidence.exr")
    assert (conf[..., 2] == CLIPPED).any()


def test_errors_are_one_line_with_exit_two(brackets, tmp_path, capsys):
    paths, _ = brackets
    cases = [
        (["merge", paths[0], "-o", str(tmp_path / "x.exr"), "--ghost", "nan"], "not a finite"),
        (
            ["merge", *paths[:2], "-o", str(tmp_path / "x.exr"), "--times", "1/100"],
            "need 2 values for --times",
        ),
        (
            ["-q", "merge", *paths[:2], "-o", str(tmp_path / "x.exr"), "-O", "pixel_type=half"],
            "beyond the 65504 that half floats hold; pixel_type=float keeps them",
        ),
        (
            ["merge", *paths[:2], "-o", str(tmp_path / "x.exr"), "--times", "1/100,1/0"],
            "not a number or a fraction like 1/250",
        ),
        (
            ["merge", *paths[:2], "-o", str(tmp_path / "x.exr"), "--response", "cam.txt"],
            "--response takes",
        ),
        (["merge", *paths[:2], "-o", str(tmp_path / "x.jpeg2")], "unknown image extension"),
        (["merge", *paths[:2], "-o", paths[0]], "refusing to write over"),
        (
            ["unwrap", paths[0], paths[1], paths[2], "-o", str(tmp_path / "x.exr")],
            "one or two photos",
        ),
    ]
    for argv, words in cases:
        assert main(argv) == 2, argv
        err = capsys.readouterr().err
        assert err.startswith("bakeshop: error: ") and words in err and err.count("\n") == 1, err
    assert not (tmp_path / "x.exr").exists()
    no_exif = tmp_path / "plain.png"
    write_image(no_exif, np.zeros((4, 4, 3), np.uint8))
    assert main(["merge", str(no_exif), str(no_exif), "-o", str(tmp_path / "x.exr")]) == 2
    assert "no exposure time" in capsys.readouterr().err
    # a writer option the format does not take is refused before the frames are read
    argv = ["merge", str(no_exif), str(no_exif), "-o", str(tmp_path / "x.exr"), "-O", "bits=16"]
    assert main(argv) == 2
    assert "OpenEXR takes no option 'bits'" in capsys.readouterr().err


def test_ball_photos_to_a_probe(tmp_path, capsys):
    circle = (311.37, 248.81, 180.23)
    photo = synthetic.ball_photo(500, 640, *circle)
    write_image(tmp_path / "ball.exr", photo)
    out = tmp_path / "probe.exr"
    argv = ["-q", "unwrap", str(tmp_path / "ball.exr"), "-o", str(out), "--size", "128",
            "--reflectance", "0.5"]  # fmt: skip
    assert main(argv) == 0
    said = capsys.readouterr().out
    assert "ball at (311.3" in said and "radius 180." in said and "reflectance [0.5]" in said
    got = read_image(out)
    assert got.shape == (128, 256, 3)
    dirs = synthetic.latlong_dirs(128, 256)
    expected = synthetic.smooth_probe(dirs * [1, 1, -1]) / 0.5
    front = dirs[..., 2] < 0.5
    assert np.sqrt(np.mean((got[front] / expected[front] - 1) ** 2)) < 0.01
    assert main(["unwrap", str(tmp_path / "ball.exr"), "-o", str(out), "--reflectance", "2"]) == 2
    assert "0.05<=x<=1" in capsys.readouterr().err


def test_codec_options_reach_the_writer(brackets, tmp_path, capsys):
    paths, _ = brackets
    out = tmp_path / "piz.exr"
    argv = ["-q", "merge", *paths[:3], "-o", str(out), "-O", "compression=piz", "--sun", "off",
            "--response", "srgb"]  # fmt: skip
    assert main(argv) == 0
    assert read_image(out, with_metadata=True)[1]["compression"] == "piz"


@pytest.mark.parametrize("code", [0, 255])
def test_black_or_white_brackets_are_one_line_with_robertson(tmp_path, capfd, code):
    paths = []
    for k in range(3):
        paths.append(str(tmp_path / f"f{k}.png"))
        write_image(paths[-1], np.full((32, 64, 3), code, np.uint8))
    argv = ["merge", *paths, "-o", str(tmp_path / "x.exr"), "--times", "1/100,1/50,1/25",
            "--response", "robertson"]  # fmt: skip
    assert main(argv) == 2
    assert "too few samples unclipped in two frames" in one_error_line(capfd)


@pytest.mark.parametrize("text", ['"samples": 1e999', '"samples": ' + "9" * 5000])
def test_a_response_with_huge_numbers_is_one_line(brackets, tmp_path, capfd, text):
    paths, _ = brackets
    doc = json.dumps({"bakeshop_camera_response": 1, "method": "debevec",
                      "linear": [[i + 1.0] for i in range(256)]})  # fmt: skip
    (tmp_path / "cam.json").write_text(doc[:-1] + ", " + text + "}")
    argv = ["merge", *paths[:2], "-o", str(tmp_path / "x.exr"), "--response",
            str(tmp_path / "cam.json")]  # fmt: skip
    assert main(argv) == 2
    assert "cam.json" in one_error_line(capfd)


@pytest.mark.slow
def test_an_implausible_sun_is_left_clipped_and_said(tmp_path, capsys):
    """A sun of the clearest sky leaves no aureole to fit: the fit is refused in one line
    naming --sun-illuminance, and --sun model fails with it."""
    probe, _, _ = synthetic.sunny_probe(2e5, 0.005)
    paths = []
    for k, codes in enumerate(synthetic.shoot(probe, TIMES[:5], gain=0.18 * 60 / 0.5)):
        paths.append(str(tmp_path / f"f{k}.png"))
        write_image(paths[-1], codes)
    times = ",".join(str(t) for t in TIMES[:5])
    argv = ["-q", "merge", *paths, "-o", str(tmp_path / "x.pfm"), "--times", times]
    assert main(argv) == 0
    said = capsys.readouterr().out
    assert "sun: not modelled: the aureole's fit" in said and "--sun-illuminance" in said
    conf = read_image(tmp_path / "x_confidence.exr")
    assert (conf[..., 2] == CLIPPED).any() and not (conf[..., 2] == MODELLED).any()
    assert main([*argv, "--sun", "model"]) == 2
    assert "give the sun's --sun-illuminance" in capsys.readouterr().err
