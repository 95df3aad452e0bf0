"""``bakeshop remap`` end to end through bakeshop.cli.main.main."""

import numpy as np
import pytest

from bakeshop.cli.main import main
from bakeshop.io import read_image, write_image
from bakeshop.sphere import cube_to_faces, layout, remap
from tests.tolerances import HALF_FLOAT_RTOL


def smooth(d):
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    return np.stack([1 + 0.5 * x + 0.3 * y - 0.2 * z, np.exp(z), 1 + y * y], -1).astype(np.float32)


@pytest.fixture
def latlong(tmp_path):
    dirs, _ = layout("latlong").directions((64, 128))
    image = smooth(dirs)
    path = tmp_path / "sky.exr"
    write_image(path, image, pixel_type="float")
    return path, image


def test_help_teaches_with_examples(capsys):
    assert main(["remap", "--help"]) == 0
    out = capsys.readouterr().out
    assert "Example:" in out and "cross-vertical" in out


def test_latlong_to_cross_guesses_and_says_so(latlong, tmp_path, capsys):
    path, image = latlong
    out = tmp_path / "cross.pfm"
    assert main(["-q", "remap", str(path), str(out), "--to", "cross-vertical", "--size", "16"]) == 0
    said = capsys.readouterr().out
    assert "guessed" in said and "latlong" in said
    got = read_image(out)
    np.testing.assert_allclose(got, remap(image, "latlong", "cross-vertical", 16, filter="area"))


def test_faces_round_trip_in_every_convention(latlong, tmp_path):
    path, image = latlong
    cube = remap(image, "latlong", "cube", 16)
    for convention in ("opengl", "vulkan", "directx"):
        pattern = tmp_path / f"{convention}_{{face}}.pfm"
        argv = ["-q", "remap", str(path), str(pattern), "--to", "faces", "--size", "16",
                "--filter", "bilinear", "--convention", convention]  # fmt: skip
        assert main(argv) == 0
        faces = np.stack([read_image(tmp_path / f"{convention}_{n}.pfm") for n in
                          ("posx", "negx", "posy", "negy", "posz", "negz")])  # fmt: skip
        np.testing.assert_array_equal(faces, cube_to_faces(cube, convention=convention))
        back = tmp_path / f"{convention}.exr"
        argv = ["-q", "remap", str(pattern), str(back), "--from", "faces", "--to", "latlong",
                "--size", "128x64", "--convention", convention]  # fmt: skip
        assert main(argv) == 0
        np.testing.assert_allclose(read_image(back), image, atol=0.02)


@pytest.mark.parametrize("ext", [".dds", ".ktx", ".ktx2"])
def test_cube_containers_hold_the_same_faces_as_face_files(latlong, tmp_path, ext):
    from bakeshop.io.dds import read_dds
    from bakeshop.io.ktx import read_ktx
    from bakeshop.io.ktx2 import read_ktx2

    path, image = latlong
    common = ["--to", "faces", "--size", "16", "--convention", "directx"]
    assert main(["-q", "remap", str(path), str(tmp_path / "f_{face}.pfm"), *common]) == 0
    faces = np.stack([read_image(tmp_path / f"f_{n}.pfm") for n in
                      ("posx", "negx", "posy", "negy", "posz", "negz")])  # fmt: skip
    container = tmp_path / f"sky{ext}"
    assert main(["-q", "remap", str(path), str(container), *common]) == 0
    reader = {".dds": read_dds, ".ktx": read_ktx, ".ktx2": read_ktx2}[ext]
    mips, meta = reader(container)
    assert len(mips) == 1 and meta["cube"] and meta["stored"] == "float16"
    np.testing.assert_allclose(mips[0][..., :3], faces, rtol=HALF_FLOAT_RTOL)
    # and read back as an input, in the same convention
    back = tmp_path / "back.exr"
    argv = ["-q", "remap", str(container), str(back), "--to", "latlong", "--size", "128x64",
            "--convention", "directx"]  # fmt: skip
    assert main(argv) == 0
    np.testing.assert_allclose(read_image(back), image, atol=0.02)


def test_short_face_names_and_rotation(latlong, tmp_path):
    path, image = latlong
    pattern = tmp_path / "s_{face}.hdr"
    argv = ["-q", "remap", str(path), str(pattern), "--to", "faces", "--size", "8",
            "--short-face-names", "--rotate", "90,0,0"]  # fmt: skip
    assert main(argv) == 0
    assert sorted(p.name for p in tmp_path.glob("s_*.hdr")) == sorted(
        f"s_{n}.hdr" for n in ("px", "nx", "py", "ny", "pz", "nz")
    )


def test_ambiguous_square_is_refused_with_choices(tmp_path, capsys):
    path = tmp_path / "ball.exr"
    write_image(path, np.ones((32, 32, 3), np.float32))
    assert main(["remap", str(path), str(tmp_path / "o.exr"), "--to", "latlong"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "angular, mirrorball, octahedral" in err and "--from" in err
    argv = ["-q", "remap", str(path), str(tmp_path / "o.exr"), "--from", "mirrorball", "--to",
            "latlong", "--size", "32"]  # fmt: skip
    assert main(argv) == 0
    assert read_image(tmp_path / "o.exr").shape == (32, 64, 3)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--to", "faces"], "{face}"),
        (["--to", "latlong", "--rotate", "90,0"], "YAW,PITCH,ROLL"),
        (["--to", "octahedral", "--size", "15"], "even"),
        (["--to", "latlong", "--size", "0x3"], "size"),
    ],
)
def test_bad_arguments_are_one_line(latlong, tmp_path, capsys, args, message):
    path, _ = latlong
    assert main(["remap", str(path), str(tmp_path / "out.exr"), *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("bakeshop: error: ") and err.count("\n") == 1 and message in err


def test_refuses_to_overwrite_its_input(latlong, capsys):
    path, _ = latlong
    assert main(["remap", str(path), str(path), "--to", "latlong"]) == 2
    assert "input" in capsys.readouterr().err


def test_missing_face_file(tmp_path, capsys):
    argv = ["remap", str(tmp_path / "x_{face}.exr"), str(tmp_path / "o.exr"), "--to", "latlong"]
    assert main(argv) == 2
    assert "x_posx.exr" in capsys.readouterr().err


def test_openexr_cube_is_read_by_its_attribute_and_written_with_it(tmp_path, capsys):
    """An .exr with envmap = cube converts as OpenEXR's cube (not as a strip), and an output in
    OpenEXR's layouts carries the attribute; a format that cannot say so is refused before any
    work, in one line."""
    dirs, _ = layout("openexr-cube").directions((96, 16))
    source = tmp_path / "env.exr"
    write_image(source, smooth(dirs), pixel_type="float", envmap="cube")
    out = tmp_path / "ll.exr"
    argv = ["-q", "remap", str(source), str(out), "--to", "latlong", "--size", "16", "--filter",
            "bilinear"]  # fmt: skip
    assert main(argv) == 0
    assert "envmap attribute is cube" in capsys.readouterr().out
    want = smooth(layout("latlong").directions((16, 32))[0])
    np.testing.assert_allclose(read_image(out), want, atol=0.05)
    env = tmp_path / "back.exr"
    argv = ["-q", "remap", str(out), str(env), "--to", "openexr-latlong", "--size", "16"]
    assert main(argv) == 0
    assert read_image(env, with_metadata=True)[1]["envmap"] == "latlong"
    capsys.readouterr()
    bad = tmp_path / "back.hdr"
    assert main(["remap", str(out), str(bad), "--to", "openexr-latlong"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "back.hdr" in err and ".exr" in err and not bad.exists()


def test_physical_probe_layouts_on_the_command_line(tmp_path, capsys):
    dirs, _ = layout("mirrorball-physical").directions((64, 64))
    ball = tmp_path / "ball.exr"
    write_image(ball, smooth(dirs), pixel_type="float")
    out = tmp_path / "sky.exr"
    argv = ["-q", "remap", str(ball), str(out), "--from", "mirrorball-physical", "--to",
            "latlong", "--size", "16"]  # fmt: skip
    assert main(argv) == 0
    sky = read_image(out)
    d = layout("latlong").directions((16, 32))[0]
    front = d[..., 2] > -0.7  # away from the ball's rim (ahead of the camera)
    assert np.abs(sky - smooth(d))[front].max() < 0.05
