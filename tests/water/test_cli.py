"""`bakeshop water ocean|ripples|murk` end to end through bakeshop.cli.main.main, the files
read back with independent readers (OpenCV, OpenImageIO) where there are any."""

import json

import cv2
import numpy as np
import OpenImageIO as oiio
import pytest

from bakeshop.cli.main import main
from bakeshop.io.ktx2 import read_ktx2
from bakeshop.water.ocean import ocean, ocean_fields
from bakeshop.water.spectra import Spectrum
from bakeshop.water.textures import pack_normals


def test_help_teaches_with_examples(capsys):
    for args in (["water"], ["water", "ocean"], ["water", "ripples"], ["water", "murk"]):
        assert main([*args, "--help"]) == 0
        out = capsys.readouterr().out
        assert "Example:" in out
    assert main(["--help"]) == 0 and "water" in capsys.readouterr().out


OCEAN = ["--wind", "7", "--fetch", "30000", "--size", "32", "--resolution", "32", "--period",
         "5", "--seed", "4"]  # fmt: skip


@pytest.mark.slow
def test_ocean_frames_match_the_library_and_the_sidecar_says_what_they_are(tmp_path, capsys):
    out = tmp_path / "sea"
    assert main(["-q", "water", "ocean", str(out), *OCEAN, "--choppiness", "0.5",
                 "--outputs", "normal,height,foam"]) == 0  # fmt: skip
    doc = json.loads((out / "ocean.json").read_text())
    frames = doc["frames"]
    o = ocean(Spectrum("jonswap", wind_speed=7.0, fetch=30000.0), size=32.0, resolution=32,
              seed=4, loop_period=5.0)  # fmt: skip
    assert frames % 8 == 0 and frames >= o.minimum_frames() > frames - 8
    assert doc["tile_size_m"] == 32 and doc["loop_period_s"] == 5
    assert doc["frame_rate_hz"] == pytest.approx(frames / 5)
    assert doc["parameters"]["spectrum"]["wind_speed"] == 7
    assert doc["report"]["frozen_modes"] == 0
    normals = ocean_fields(o, frames=frames, fields=("normal",), choppiness=0.5)["normal"]
    for f in (0, frames - 1):
        png = cv2.imread(str(out / f"ocean_normal_{f:04d}.png"), cv2.IMREAD_UNCHANGED)[..., ::-1]
        assert png.dtype == np.uint16
        expected = np.rint(pack_normals(normals[f]) * 65535)
        assert np.abs(png - expected).max() <= 1
    height = oiio.ImageBuf(str(out / "ocean_height_0000.exr")).get_pixels(oiio.FLOAT)
    assert height.shape[:2] == (32, 32) and np.isfinite(height).all()
    assert (out / "ocean_foam_0000.png").exists()
    assert (out / "ocean_preview_frames.png").exists() and (
        out / "ocean_preview_tiled.png"
    ).exists()
    assert "frames per 5 s loop" in capsys.readouterr().out


def test_ocean_atlas_and_bc5_ready_array(tmp_path):
    out = tmp_path / "sheet"
    assert main(["-q", "water", "ocean", str(out), *OCEAN, "--layout", "atlas", "--gutter",
                 "2", "--columns", "8", "--no-preview"]) == 0  # fmt: skip
    doc = json.loads((out / "ocean.json").read_text())
    atlas = doc["files"][0]["atlas"]
    assert atlas["columns"] == 8 and atlas["cell"] == 36
    image = cv2.imread(str(out / "ocean_normal_atlas.png"), cv2.IMREAD_UNCHANGED)
    assert image.shape[:2] == (atlas["rows"] * 36, 8 * 36)
    arrays = tmp_path / "arrays"
    assert main(["-q", "water", "ocean", str(arrays), *OCEAN, "--layout", "array",
                 "--normal-format", "xy8", "--no-preview"]) == 0  # fmt: skip
    mips, meta = read_ktx2(arrays / "ocean_normal.ktx2")
    frames = json.loads((arrays / "ocean.json").read_text())["frames"]
    assert meta["layers"] == frames and meta["stored"] == "unorm8"
    assert mips[0].shape == (frames, 32, 32, 2) and len(mips) == 6  # 32 .. 1


def test_too_few_frames_are_refused_in_one_line(tmp_path, capsys):
    code = main(["water", "ocean", str(tmp_path / "x"), *OCEAN, "--frames", "4"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and err.count("\n") == 0
    assert err.startswith("bakeshop: error:") and "at least" in err
    assert main(["-q", "water", "ocean", str(tmp_path / "y"), *OCEAN, "--frames", "4",
                 "--alias", "drop", "--no-preview"]) == 0  # fmt: skip
    report = json.loads((tmp_path / "y" / "ocean.json").read_text())["report"]
    assert report["aliased_modes"] > 0


@pytest.mark.parametrize(
    "args",
    [
        ["ocean", "--wind", "nan"],
        ["ocean", "--wind", "-3"],
        ["ocean", "--wind", "0.1", "--size", "64"],  # no wave fits the tile
        ["ocean", "--period", "inf"],
        ["ocean", "--outputs", "normal,colour"],
        ["ocean", "--outputs", "foam"],  # foam needs choppiness
        ["ripples", "--courant", "0.9"],
        ["ripples", "--drop-diameter", "1"],
        ["murk", "--visibility", "500"],
        ["murk", "--water-type", "IV"],
    ],
)
def test_bad_arguments_give_one_line(tmp_path, capsys, args):
    code = main(["water", args[0], str(tmp_path / "out"), *args[1:]])
    err = capsys.readouterr().err.strip()
    assert code == 2 and err.startswith("bakeshop: error:") and err.count("\n") == 0
    assert not (tmp_path / "out").exists()  # refused before anything is made


def test_ripples_analytic_and_wave(tmp_path):
    out = tmp_path / "drop"
    assert main(["-q", "water", "ripples", str(out), "--resolution", "64", "--frames", "4",
                 "--duration", "0.4"]) == 0  # fmt: skip
    doc = json.loads((out / "ripples.json").read_text())
    assert doc["parameters"]["crater"]["front_speed_m_s"] > 0.15
    assert (out / "ripples_ring_texture.png").exists()
    lut = oiio.ImageBuf(str(out / "ripples_ring_lut.exr")).get_pixels(oiio.FLOAT)
    assert lut.shape == (64, 64, 3)
    rain = cv2.imread(str(out / "ripples_rain_atlas.png"), cv2.IMREAD_UNCHANGED)
    assert rain.shape == (64, 64, 4) and rain.dtype == np.uint16
    wave = tmp_path / "puddle"
    assert main(["-q", "water", "ripples", str(wave), "--model", "wave", "--size", "0.5",
                 "--resolution", "64", "--frames", "3", "--duration", "0.3", "--rain", "3",
                 "--impact", "0.25,0.25,0"]) == 0  # fmt: skip
    doc = json.loads((wave / "ripples.json").read_text())
    assert doc["parameters"]["wave"]["courant"] <= 0.866
    assert len(list(wave.glob("ripples_normal_*.png"))) == 3


def test_murk_constants_and_luts(tmp_path, capsys):
    out = tmp_path / "murk"
    assert main(["water", "murk", str(out), "--water-type", "II", "--lut-size", "16x8"]) == 0
    assert "visibility" in capsys.readouterr().out
    doc = json.loads((out / "murk.json").read_text())
    assert len(doc["beam_attenuation_per_m"]) == 3
    ue = doc["engines"]["unreal_single_layer_water"]
    assert len(ue["absorption_coefficients_per_cm"]) == 3 and 0 < ue["phase_g"] < 1
    t = oiio.ImageBuf(str(out / "murk_transmittance.exr")).get_pixels(oiio.FLOAT)
    s = oiio.ImageBuf(str(out / "murk_inscatter.exr")).get_pixels(oiio.FLOAT)
    assert t.shape == (1, 16, 3) and s.shape == (8, 16, 3)
    assert np.allclose(t[0, 0], 1, atol=1e-6) and (np.diff(t[0, :, 1]) < 0).all()
    assert "vec3 waterTransmittance(float d)" in (out / "murk.glsl").read_text()
    lake = tmp_path / "lake"
    assert main(["-q", "water", "murk", str(lake), "--water-type", "3C", "--visibility", "4"]) == 0
    assert json.loads((lake / "murk.json").read_text())["visibility_m"] == pytest.approx(4.0)


def test_a_refused_ripples_flipbook_creates_no_output_folder(tmp_path, capfd, monkeypatch):
    from bakeshop import resources
    from tests.cli.test_process import one_error_line

    monkeypatch.setattr(resources, "memory_limits", lambda: {"memory available": 16 << 20})
    folder = tmp_path / "new" / "drop"
    args = ["-q", "water", "ripples", str(folder), "--resolution", "512", "--frames", "64"]
    assert main(args) == 2
    assert "a flipbook of 64 frames" in one_error_line(capfd)
    assert not (tmp_path / "new").exists()
