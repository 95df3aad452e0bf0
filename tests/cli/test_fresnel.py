"""The fresnel and tonemap commands, end to end through bakeshop.cli.main.main."""

import cv2
import numpy as np
import pytest
from PIL import Image

from bakeshop import sphere
from bakeshop.cli.main import main
from bakeshop.image import (
    adapt_exposure,
    auto_exposure,
    exposure,
    srgb_encode,
    to_srgb8,
    tonemap,
)
from bakeshop.io import read_image, write_image
from bakeshop.light.fresnel import bake_fresnel, ldr_exposure
from tests.tolerances import HALF_FLOAT_RTOL


@pytest.fixture
def sky(tmp_path):
    rng = np.random.default_rng(5)
    image = rng.lognormal(0.0, 1.0, (32, 64, 3)).astype(np.float32)
    image[5, 30] = 5000.0  # a sun
    path = tmp_path / "sky.exr"
    write_image(path, image, pixel_type="float")
    return path, image


def test_help_teaches_with_examples(capsys):
    for command in ("fresnel", "tonemap"):
        assert main([command, "--help"]) == 0
        out = capsys.readouterr().out
        assert "Example:" in out and "sRGB" in out


def test_fresnel_float_bake(sky, tmp_path):
    path, image = sky
    out = tmp_path / "water.exr"
    assert main(["fresnel", str(path), str(out), "--ior", "1.5", "--below", "mirror"]) == 0
    np.testing.assert_allclose(
        read_image(out),
        bake_fresnel(image, "latlong", ior=1.5, below="mirror"),
        rtol=HALF_FLOAT_RTOL,  # the EXR writer's default pixel type is half
    )


def test_fresnel_ldr_png_read_back_with_opencv(sky, tmp_path, capsys):
    path, image = sky
    out = tmp_path / "water.png"
    assert main(["fresnel", str(path), str(out), "--ldr"]) == 0
    baked = bake_fresnel(image, "latlong")
    ev = ldr_exposure(baked, "latlong")
    assert f"exposure {ev:+.2f} EV" in capsys.readouterr().out
    expect = np.clip(np.rint(255 * srgb_encode(np.clip(baked * 2**ev, 0, 1))), 0, 255)
    got = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)[..., ::-1]
    assert got.dtype == np.uint8
    np.testing.assert_array_equal(got, expect.astype(np.uint8))
    # a fixed exposure and dither, TGA
    tga = tmp_path / "water.tga"
    assert main(["fresnel", str(path), str(tga), "--ldr", "--exposure", "-1", "--dither"]) == 0
    dithered = np.asarray(Image.open(tga)).astype(int)  # Pillow as the independent TGA reader
    plain = to_srgb8(exposure(baked, -1)).astype(int)
    assert np.abs(dithered - plain).max() <= 1 and (dithered != plain).any()


@pytest.mark.slow
def test_fresnel_cube_faces_and_report(sky, tmp_path, capsys):
    path, _ = sky
    out = tmp_path / "water_{face}.png"
    args = ["fresnel", str(path), str(out), "--layout", "cube", "--size", "16", "--ldr"]
    assert main([*args, "--report"]) == 0
    text = capsys.readouterr().out
    for name in ("posx", "negx", "posy", "negy", "posz", "negz"):
        face = read_image(tmp_path / f"water_{name}.png")
        assert face.shape == (16, 16, 3)
    assert np.all(read_image(tmp_path / "water_negy.png") == 0)  # below the plane
    assert "flat water" in text and "RMS slope" in text and "0.30" in text and "Schlick" in text


def test_fresnel_cube_containers(sky, tmp_path):
    from bakeshop.io.dds import read_dds
    from bakeshop.io.ktx import read_ktx
    from bakeshop.io.ktx2 import read_ktx2

    path, image = sky
    cube = sphere.remap(image, "latlong", "cube", 8, filter="area")  # what the command does
    expect = bake_fresnel(cube, "cube")
    for ext, reader in ((".dds", read_dds), (".ktx", read_ktx), (".ktx2", read_ktx2)):
        out = tmp_path / f"water{ext}"
        assert main(["fresnel", str(path), str(out), "--layout", "cube", "--size", "8"]) == 0
        mips, meta = reader(out)
        assert len(mips) == 1 and meta["cube"] and meta["stored"] == "float16"
        np.testing.assert_allclose(mips[0][..., :3], expect, rtol=HALF_FLOAT_RTOL, atol=1e-7)
    for bad in (["--layout", "cube", "--ldr"], []):
        assert main(["fresnel", str(path), str(tmp_path / "x.dds"), *bad]) == 2


def test_fresnel_bad_arguments(sky, tmp_path, capsys):
    path, _ = sky
    cases = [
        [str(tmp_path / "a.png")],  # 8-bit output without --ldr
        [str(tmp_path / "a.exr"), "--ldr"],
        [str(tmp_path / "a.exr"), "--up", "sideways"],
        [str(tmp_path / "a.exr"), "--exposure", "bright"],
        [str(tmp_path / "a.png"), "--layout", "cube", "--ldr"],  # no {face}
        [str(path)],  # would overwrite the input
    ]
    for extra in cases:
        assert main(["fresnel", str(path), *extra]) == 2
        err = capsys.readouterr().err
        assert err.startswith("bakeshop: error: ") and err.count("\n") == 1
    # an 8-bit picture where radiance is expected: one warning line, or --srgb-decode
    picture = tmp_path / "picture.png"
    write_image(picture, np.full((8, 16, 3), 0.5, np.float32))
    for command, out in (("fresnel", "c.exr"), ("tonemap", "c.png")):
        assert main([command, str(picture), str(tmp_path / out)]) == 0
        err = capsys.readouterr().err
        lines = [line for line in err.splitlines() if line.strip()]
        assert len(lines) == 1 and "display-encoded" in err and "--srgb-decode" in err
        assert main([command, str(picture), str(tmp_path / out), "--srgb-decode"]) == 0
        assert capsys.readouterr().err.strip() == ""  # no warning
    assert main(["fresnel", str(path), str(tmp_path / "d.exr"), "--srgb-decode"]) == 2
    assert "8/16-bit inputs only" in capsys.readouterr().err
    square = tmp_path / "square.exr"
    write_image(square, np.ones((8, 8, 3), np.float32))
    assert main(["fresnel", str(square), str(tmp_path / "b.exr")]) == 2
    assert "--from" in capsys.readouterr().err
    assert main(["fresnel", str(square), str(tmp_path / "b.exr"), "--from", "angular"]) == 0


def test_tonemap_single_frame(sky, tmp_path):
    path, image = sky
    out = tmp_path / "preview.png"
    assert (
        main(
            [
                "tonemap",
                str(path),
                str(out),
                "--operator",
                "reinhard",
                "--white",
                "4",
                "--exposure",
                "-1",
            ]
        )
        == 0
    )
    expect = to_srgb8(tonemap(image, ev=-1, operator="reinhard", white=4))
    np.testing.assert_array_equal(cv2.imread(str(out))[..., ::-1], expect)


def test_tonemap_sequence_adapts(tmp_path, capsys):
    # three dark frames, then three bright ones: auto exposure adapts with tau_brighter
    frames = []
    for i, level in enumerate([0.05] * 3 + [5.0] * 3):
        p = tmp_path / f"in_{i}.exr"
        write_image(p, np.full((8, 16, 3), level, np.float32), pixel_type="float")
        frames.append(p)
    out = tmp_path / "out_{frame:03d}.png"
    args = ["tonemap", str(tmp_path / "in_*.exr"), str(out), "--operator", "none"]
    assert main([*args, "--fps", "10", "--tau-brighter", "0.1", "--center-weight", "0"]) == 0
    targets = [
        auto_exposure(np.full((8, 16, 3), v, np.float32), center_weight=0)
        for v in [0.05] * 3 + [5.0] * 3
    ]
    evs = adapt_exposure(targets, frame_time=0.1, tau_brighter=0.1, tau_darker=2.0)
    for i, ev in enumerate(evs):
        got = cv2.imread(str(tmp_path / f"out_{i:03d}.png"))[..., ::-1]
        np.testing.assert_array_equal(got, to_srgb8(tonemap(read_image(frames[i]), ev=ev)))
    assert "6 frames" in capsys.readouterr().out
    # the step: after one time constant (one frame here) 63% of the way
    assert (evs[3] - evs[2]) / (targets[3] - targets[2]) == pytest.approx(1 - np.exp(-1))


def test_tonemap_bad_arguments(sky, tmp_path, capsys):
    path, _ = sky
    for extra in (
        [str(tmp_path / "x.exr")],
        [str(tmp_path / "x.png"), "--center-weight", "2"],
        [str(tmp_path / "x_{other}.png")],
    ):
        assert main(["tonemap", str(path), *extra]) == 2
        assert capsys.readouterr().err.startswith("bakeshop: error: ")
    assert main(["tonemap", str(path), str(path), str(tmp_path / "x.png")]) == 2
    assert "{frame}" in capsys.readouterr().err
    assert main(["tonemap", str(tmp_path / "none_*.hdr"), str(tmp_path / "x.png")]) == 2


def test_sequence_inputs_in_numeric_order(tmp_path):
    from bakeshop.cli.tonemap import expand_inputs

    for i in (10, 2, 1):
        (tmp_path / f"f_{i}.exr").touch()
    names = [p.name for p in expand_inputs([str(tmp_path / "f_*.exr")])]
    assert names == ["f_1.exr", "f_2.exr", "f_10.exr"]


def test_fresnel_of_a_ktx2_cube_probe(sky, tmp_path):
    # a cube SOURCE is read with the faces of --convention, baked in its own layout
    path, image = sky
    cube = sphere.remap(image, "latlong", "cube", 8, filter="area")
    src = tmp_path / "sky.ktx2"
    argv = ["-q", "remap", str(path), str(src), "--to", "cube", "--size", "8"]
    assert main([*argv, "--convention", "directx"]) == 0
    out = tmp_path / "water_{face}.exr"
    assert main(["fresnel", str(src), str(out), "--convention", "directx"]) == 0
    faces = np.stack([read_image(tmp_path / f"water_{n}.exr") for n in sphere.FACE_NAMES])
    expect = sphere.cube_to_faces(bake_fresnel(cube, "cube"), convention="directx")
    np.testing.assert_allclose(faces, expect, rtol=HALF_FLOAT_RTOL, atol=1e-6)


def test_fresnel_default_size_is_the_remap_default(tmp_path):
    # about as many texels as SOURCE holds directions: an angular probe's disk, not its square
    image = np.ones((32, 32, 3), np.float32)
    src = tmp_path / "probe.exr"
    write_image(src, image, pixel_type="float")
    out = tmp_path / "water.exr"
    assert (
        main(["-q", "fresnel", str(src), str(out), "--from", "angular", "--layout", "latlong"]) == 0
    )
    assert read_image(out).shape == sphere.remap(image, "angular", "latlong").shape
