"""``bakeshop preview`` as a user runs it: bake-probe's folder in, PNGs out, one error line for
bad input."""

import re
import shutil
import socket

import numpy as np
import pytest

from bakeshop.cli.main import main
from bakeshop.io import read_image, write_image
from bakeshop.preview import Renderer, View, read_bake
from bakeshop.sphere import layout
from tests.preview.bakes import sky


@pytest.fixture(scope="module")
def bake_dir(tmp_path_factory):
    """A small bake written by `bakeshop bake-probe` from a synthetic sky with a sun."""
    folder = tmp_path_factory.mktemp("preview")
    d, _ = layout("latlong").directions((64, 128))
    sun = np.array([0.5, 0.5, -0.7071])
    probe = sky(d) + 5000.0 * ((d @ sun) > np.cos(np.radians(2)))[..., None]
    write_image(folder / "sky.hdr", probe.astype(np.float32))
    args = ["-q", "bake-probe", str(folder / "sky.hdr"), "-o", str(folder / "bake")]
    assert main(args + ["--cube-size", "32", "--specular-size", "16", "--mips", "5"]) == 0
    return folder / "bake"


@pytest.mark.slow
def test_preview_writes_each_scene_as_the_library_renders_it(bake_dir, tmp_path):
    out = tmp_path / "p_{scene}.png"
    args = ["-q", "preview", str(bake_dir), "-o", str(out), "--scene", "all", "--size", "96x64"]
    assert main(args + ["--exposure", "0", "--no-water"]) == 0
    from bakeshop.image import to_picture

    bake = read_bake(bake_dir)
    with Renderer(bake) as r:
        for scene in ("sky", "balls", "golf"):
            picture = read_image(tmp_path / f"p_{scene}.png")
            assert picture.shape == (64, 96, 3)
            linear = r.render(View(scene, 96, 64, water=False))[..., :3]
            expected = to_picture(linear, ev=0.0, operator="aces").pixels
            np.testing.assert_array_equal(np.rint(picture * 255), expected)


@pytest.mark.slow
@pytest.mark.parametrize(
    "extra, reason",
    [
        (["--size", "0x5"], "1<=x<=8192"),
        (["--size", "9000x10"], "1<=x<=8192"),
        (["--camera", "10,90,5"], "-90<x<90"),
        (["--camera", "10,nan,5"], "not a finite number"),
        (["--exposure", "inf"], "not a finite number"),
        (["--scene", "all", "-o", "one.png"], "{scene}"),
        (["-o", "x.jpg"], "name the output .png"),
        (["-o", "x_{view}.png"], "{view} is not a pattern this command writes"),
        (["--scene", "all", "-o", "x_{scene!r}.png"], "is not a pattern"),
    ],
)
def test_bad_arguments_give_one_line(bake_dir, capsys, extra, reason):
    assert main(["-q", "preview", str(bake_dir), *extra]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("bakeshop: error: ") and reason in err


def test_a_folder_that_is_not_a_bake_is_named(tmp_path, capsys):
    assert main(["-q", "preview", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and str(tmp_path) in err and "env_posx" in err


def test_help_teaches_with_examples(capsys):
    for command in ("preview", "view"):
        assert main([command, "--help"]) == 0
        assert "Example:" in capsys.readouterr().out


def test_view_of_a_folder_that_is_not_a_bake_is_one_line(tmp_path, capsys):
    assert main(["-q", "view", str(tmp_path), "--no-browser"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "env_posx" in err


@pytest.fixture
def no_serving(monkeypatch):
    """A view that starts serving stops at once (Ctrl-C) instead of serving until killed."""

    def interrupt(seconds):
        raise KeyboardInterrupt

    monkeypatch.setattr("bakeshop.cli.view.time.sleep", interrupt)


def test_view_of_a_file_names_it(tmp_path, capsys):
    (tmp_path / "a.hdr").write_bytes(b"")
    assert main(["-q", "view", str(tmp_path / "a.hdr"), "--no-browser"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"bakeshop: error: {tmp_path / 'a.hdr'}: not a folder ")
    assert err.count("\n") == 1


def test_view_on_a_port_in_use_names_it(bake_dir, capsys, no_serving):
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        assert main(["-q", "view", str(bake_dir), "--port", str(port), "--no-browser"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"bakeshop: error: 127.0.0.1:{port}: cannot serve on it: ")
    assert err.count("\n") == 1


@pytest.mark.parametrize("name", ["sun.json", "sh.json"])
@pytest.mark.parametrize("number", ["1" + "0" * 400, "1" + "0" * 5000, "1e999"])
def test_view_of_a_sidecar_with_a_huge_number_is_one_line(
    bake_dir, tmp_path, capsys, no_serving, name, number
):
    folder = tmp_path / "bake"
    shutil.copytree(bake_dir, folder)
    text = (folder / name).read_text()
    (folder / name).write_text(re.sub(r"-?\d+\.\d+", number, text, count=1))
    assert main(["-q", "view", str(folder), "--no-browser"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"bakeshop: error: {folder / name}: ") and err.count("\n") == 1
    assert "not a finite float64" in err
