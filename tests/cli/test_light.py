"""The irradiance, sun and dims commands, end to end through bakeshop.cli.main.main."""

import json

import numpy as np
import pytest

import bakeshop.light as ir
from bakeshop.cli.main import main
from bakeshop.io import read_image, write_image
from bakeshop.light import sh
from bakeshop.sphere import layout, remap
from tests.tolerances import HALF_FLOAT_RTOL


def _sky_with_sun(height=128, sun=(0.5, 0.6, -0.62), radiance=5e4):
    lay = layout("latlong")
    d, _ = lay.directions((height, 2 * height))
    s = np.asarray(sun) / np.linalg.norm(sun)
    img = 0.3 + np.array([0.5, 0.7, 1.0]) * np.clip(d[..., 1:2], 0, None)
    img = img + radiance * (d @ s > np.cos(np.radians(1.5)))[..., None]
    return img.astype(np.float32), s


@pytest.fixture
def probe(tmp_path):
    img, s = _sky_with_sun()
    path = tmp_path / "probe.hdr"
    write_image(path, img)
    return path, read_image(path), s


def test_help_teaches_with_examples(capsys):
    for command in ("irradiance", "sun", "dims"):
        assert main([command, "--help"]) == 0
        assert "Example:" in capsys.readouterr().out


def test_irradiance_writes_the_dim(probe, tmp_path, capsys):
    path, img, _ = probe
    out = tmp_path / "dim.pfm"
    assert main(["-q", "irradiance", str(path), str(out), "--size", "64x32"]) == 0
    assert "method auto" in capsys.readouterr().out
    dim = read_image(out)
    np.testing.assert_allclose(dim, ir.irradiance(img, "latlong", size=(64, 32)), rtol=1e-6)


def test_irradiance_sh_json_and_shader(probe, tmp_path):
    path, img, _ = probe
    out, js, glsl = tmp_path / "dim.pfm", tmp_path / "sh.json", tmp_path / "irr.hlsl"
    args = ["-q", "irradiance", str(path), str(out), "--method", "sh", "--order", "3"]
    assert (
        main(
            args
            + ["--to", "cross-vertical", "--size", "8", "--sh-json", str(js), "--shader", str(glsl)]
        )
        == 0
    )
    assert read_image(out).shape == (32, 24, 3)
    coeffs = sh.from_document(json.loads(js.read_text()))
    assert coeffs.shape == (16, 3)
    np.testing.assert_allclose(coeffs, ir.sh_coefficients(img, "latlong", order=3), rtol=1e-12)
    assert "float4x4" in glsl.read_text()


def test_irradiance_errors(probe, tmp_path, capsys):
    path, _, _ = probe
    assert main(["-q", "irradiance", str(path), str(path)]) == 2
    assert "refusing to write over" in capsys.readouterr().err
    assert main(["-q", "irradiance", str(path), str(tmp_path / "d.hdr"), "--size", "0x3"]) == 2
    assert "0 is not in the range 1<=x<=8192" in capsys.readouterr().err
    assert (
        main(
            [
                "-q",
                "irradiance",
                str(path),
                str(tmp_path / "d.hdr"),
                "--shader",
                str(tmp_path / "x.txt"),
            ]
        )
        == 2
    )
    square = tmp_path / "square.hdr"
    write_image(square, np.ones((16, 16, 3), np.float32))
    assert main(["-q", "irradiance", str(square), str(tmp_path / "d.hdr")]) == 2
    assert "--from" in capsys.readouterr().err
    assert (
        main(
            [
                "-q",
                "irradiance",
                str(square),
                str(tmp_path / "d.hdr"),
                "--from",
                "angular",
                "--size",
                "16x8",
            ]
        )
        == 0
    )


def test_sun_reports_the_sun(probe, capsys):
    path, _, s = probe
    assert main(["-q", "sun", str(path), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert np.degrees(np.arccos(np.dot(doc["direction"], s))) < 0.5
    assert main(["-q", "sun", str(path)]) == 0
    assert "angular radius" in capsys.readouterr().out


def test_sun_says_when_there_is_none(tmp_path, capsys):
    path = tmp_path / "overcast.hdr"
    write_image(path, np.ones((32, 64, 3), np.float32))
    assert main(["-q", "sun", str(path)]) == 0
    assert "no sun" in capsys.readouterr().out
    assert main(["-q", "sun", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == {"sun": None}


def test_dims_writes_the_pair(probe, tmp_path, capsys):
    path, img, s = probe
    out = tmp_path / "dims"
    assert (
        main(["-q", "dims", str(path), "--out-dir", str(out), "--size", "64x32", "--format", "exr"])
        == 0
    )
    names = sorted(p.name for p in out.iterdir())
    assert names == ["shadow_dim.exr", "shadow_probe.exr", "sun.json", "sun_dim.exr"]
    doc = json.loads((out / "sun.json").read_text())
    assert np.degrees(np.arccos(np.dot(doc["direction"], s))) < 0.5
    lit, shade = read_image(out / "sun_dim.exr"), read_image(out / "shadow_dim.exr")
    assert lit.shape == shade.shape == (32, 64, 3)
    normals, _ = layout("latlong").directions((32, 64))
    law = np.clip(normals @ doc["direction"], 0, None)[..., None] * doc["irradiance"] / np.pi
    assert np.abs(lit - shade - law).max() < 0.02 * law.max()
    probe_out = read_image(out / "shadow_probe.exr")
    assert probe_out.shape == img.shape and probe_out.max() < 10


@pytest.mark.parametrize("method", ["exact", "auto"])
def test_dims_of_a_panorama_larger_than_memory_equal_the_in_memory_ones(tmp_path, capsys, method):
    """``--memory`` takes the chunked path (two passes of strips, the sun's search piece by
    piece, the shadow probe written by strips): the same sun and shadow probe, and the DIMs
    within the rounding of their partial sums, as the command in memory."""
    img, _ = _sky_with_sun(height=256)
    path = tmp_path / "pano.pfm"
    write_image(path, img)
    common = ["--size", "64x32", "--format", "pfm", "--method", method]
    assert main(["-q", "dims", str(path), "-o", str(tmp_path / "mem"), *common]) == 0
    assert main(["dims", str(path), "-o", str(tmp_path / "big"), *common, "--memory", "5MB"]) == 0
    assert "chunked" in capsys.readouterr().out
    want, got = (json.loads((tmp_path / d / "sun.json").read_text()) for d in ("mem", "big"))
    assert got == want
    same = read_image(tmp_path / "big" / "shadow_probe.pfm")
    assert np.array_equal(same, read_image(tmp_path / "mem" / "shadow_probe.pfm"))
    tolerance = 1e-6 if method == "exact" else 2e-3  # auto: its bins are made strip by strip
    for name in ("sun_dim.pfm", "shadow_dim.pfm"):
        a, b = (read_image(tmp_path / d / name) for d in ("mem", "big"))
        assert np.abs(a - b).max() <= tolerance * np.abs(a).max()


def test_dims_of_a_panorama_refuses_a_bound_its_suns_search_cannot_fit(tmp_path, capsys):
    # 8192 x 4096 (a sparse file): its strips fit 5 MB, a light's cap at a pole (185 rows) not
    path = tmp_path / "wide.pfm"
    header = b"PF\n8192 4096\n-1.0\n"
    with open(path, "wb") as f:
        f.write(header)
        f.truncate(len(header) + 8192 * 4096 * 12)
    out = tmp_path / "d"
    status = main(["-q", "dims", str(path), "-o", str(out), "--size", "64x32", "--memory", "5MB"])
    err = capsys.readouterr().err
    assert status == 2 and err.count("\n") == 1
    assert "the sun's search needs at least" in err and "raise it with --memory" in err
    assert not out.exists() or not any(out.iterdir())


def test_cube_probes_from_ktx2_and_face_files(probe, tmp_path, capsys):
    # a cube file gives the DIM of that cube (stored as half floats), close to the latlong's
    # (the area remap into 48-texel faces keeps all but ~0.8% of the tiny sun's energy), and
    # the same sun; a cube shadow probe is written as a vertical cross
    path, img, s = probe
    cube = tmp_path / "probe.ktx2"
    assert main(["-q", "remap", str(path), str(cube), "--to", "cube", "--size", "48"]) == 0
    faces = tmp_path / "probe_{face}.exr"
    assert main(["-q", "remap", str(path), str(faces), "--to", "faces", "--size", "48"]) == 0
    latlong = ir.irradiance(img, "latlong", size=(64, 32))
    cube_map = remap(img, "latlong", "cube", 48, filter="area")  # what remap --size 48 does
    expect = ir.irradiance(cube_map, "cube", size=(64, 32))
    for source in (cube, faces):
        out = tmp_path / "dim.pfm"
        assert main(["-q", "irradiance", str(source), str(out), "--size", "64x32"]) == 0
        assert "cube (6 faces of 48x48)" in capsys.readouterr().out
        got = read_image(out)
        assert np.abs(got - expect).max() < HALF_FLOAT_RTOL * expect.max()
        assert np.abs(got - latlong).max() < 0.015 * latlong.max()
    dims = tmp_path / "dims"
    assert main(["-q", "dims", str(cube), "-o", str(dims), "--size", "64x32"]) == 0
    assert read_image(dims / "shadow_probe.hdr").shape == (192, 144, 3)
    sun = json.loads((dims / "sun.json").read_text())["direction"]
    assert np.degrees(np.arccos(np.dot(sun, s))) < 1.0
