"""``bakeshop compress``, ``bake-probe --compress/--engine`` and ``normals combine --compress``,
end to end through bakeshop.cli.main.main."""

import json

import numpy as np
import pytest

from bakeshop.cli.main import main
from bakeshop.io import write_image
from bakeshop.io.compress.decode import decode_image
from bakeshop.io.dds import read_dds, read_dds_blocks
from bakeshop.io.ktx import read_ktx
from bakeshop.io.ktx2 import read_ktx2_blocks
from bakeshop.sphere import layout
from tests.io.compress.conftest import NORMALS


def _sky(height=32, sun=3e3):
    d, _ = layout("latlong").directions((height, 2 * height))
    s = np.array([0.5, 0.6, -0.62]) / np.linalg.norm([0.5, 0.6, -0.62])
    img = 0.3 + np.array([0.5, 0.7, 1.0]) * np.clip(d[..., 1:2], 0, None)
    img = img + sun * (d @ s > np.cos(np.radians(6)))[..., None]
    return img.astype(np.float32)


@pytest.fixture
def probe(tmp_path):
    path = tmp_path / "probe.pfm"
    write_image(path, _sky())
    return path


def run(capsys, *args):
    status = main([str(a) for a in args])
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def test_help_teaches_with_an_example(capsys):
    status, out, _ = run(capsys, "compress", "--help")
    assert status == 0 and "Example:" in out


def test_environment_to_bc6h_cube_with_sidecar(capsys, probe, tmp_path):
    out = tmp_path / "env.dds"
    status, text, err = run(capsys, "compress", probe, out, "--cube", "--size", "16")
    assert status == 0, err
    assert "multi-exposure PSNR" in text and "sidecar" in text
    mips, meta = read_dds(out)
    assert meta["stored"] == "bc6h" and meta["cube"]
    assert [m.shape[1] for m in mips] == [16, 8, 4, 2, 1]
    report = json.loads((tmp_path / "env.dds.json").read_text())
    assert report["format"] == "bc6h" and report["dxgi_format"] == 95 and report["levels"] == 5
    assert report["quality"]["kind"] == "hdr" and len(report["quality"]["levels"]) == 5
    assert report["quality"]["mpsnr_db"] > 40 and report["overflow"]["clamped_values"] == 0
    assert report["faces"] == "OpenGL order and orientation"


def test_overflow_is_refused_then_clamped_and_recorded(capsys, tmp_path):
    src = tmp_path / "sun.pfm"
    write_image(src, _sky(sun=2e5))
    out = tmp_path / "sun.ktx2"
    status, _, err = run(capsys, "compress", src, out, "--cube", "--size", "16")
    assert status == 2 and err.startswith("bakeshop: error: ") and err.count("\n") == 1
    assert "65504" in err and "--overflow clamp" in err and not out.exists()
    status, text, err = run(capsys, "compress", src, out, "--cube", "--size", "16",
                            "--overflow", "clamp", "--zstd")  # fmt: skip
    assert status == 0, err
    assert "clamped" in text
    report = json.loads((tmp_path / "sun.ktx2.json").read_text())
    assert report["overflow"]["overflow"] == "clamp" and report["overflow"]["clamped_values"] > 0
    assert report["supercompression"] == "zstd"
    texture, _ = read_ktx2_blocks(out)
    assert all(np.isfinite(level).all() for level in texture.decode())


def test_min_psnr_fails_without_writing(capsys, probe, tmp_path):
    out = tmp_path / "env.dds"
    status, _, err = run(capsys, "compress", probe, out, "--cube", "--size", "16",
                         "--min-psnr", "150")  # fmt: skip
    assert status == 2 and "below --min-psnr" in err
    assert not out.exists() and not (tmp_path / "env.dds.json").exists()


def test_normal_map_to_bc5_for_unreal(capsys, tmp_path):
    out = tmp_path / "n.dds"
    status, text, err = run(capsys, "compress", NORMALS, out, "--normal", "--engine", "unreal")
    assert status == 0, err
    assert "deg mean" in text
    texture, meta = read_dds_blocks(out)
    assert meta["stored"] == "bc5" and len(texture.levels) == 9
    report = json.loads((tmp_path / "n.dds.json").read_text())
    assert report["normal_convention"] == "dx" and report["quality"]["angle_mean_deg"] < 1
    # Unreal's green channel points down: the stored y is the negated OpenGL y
    from bakeshop.normals.encoding import read_normal_map

    gl = read_normal_map(NORMALS)
    stored = decode_image(texture.face(0, 0), "bc5", 256, 256) * 2 - 1
    assert np.mean(np.abs(stored[..., 1] + gl[..., 1])) < 0.02


def test_rgbd_png_faces_and_levels(capsys, probe, tmp_path):
    pattern = tmp_path / "env_{mip}_{face}.png"
    status, text, err = run(capsys, "compress", probe, pattern, "--cube", "--size", "8",
                            "--format", "rgbd", "--mips", "2")  # fmt: skip
    assert status == 0, err
    assert "decode: value = RGB ^ 2.2 / A" in text
    assert len(list(tmp_path.glob("env_*_*.png"))) == 12
    report = json.loads((tmp_path / "env.png.json").read_text())
    assert report["packing"]["name"] == "rgbd" and "RGB ^ 2.2 / A" in report["packing"]["decode"]
    status, _, err = run(capsys, "compress", probe, tmp_path / "env.png", "--cube", "--size", "8",
                         "--format", "rgbd")  # fmt: skip
    assert status == 2 and "{face}" in err


def test_godot_gets_its_panorama(capsys, probe, tmp_path):
    out = tmp_path / "sky.dds"
    status, _, err = run(capsys, "compress", probe, out, "--from", "latlong", "--engine", "godot")
    assert status == 0, err
    mips, meta = read_dds(out)
    assert not meta["cube"] and mips[0].shape == (32, 64, 3)
    rolled = np.roll(mips[0], 32, axis=1)  # back to bakeshop's latlong: the sun where it was
    src = _sky()
    assert np.unravel_index(np.argmax(rolled[..., 0]), (32, 64)) == np.unravel_index(
        np.argmax(src[..., 0]), (32, 64)
    )


def test_bad_arguments_give_one_line(capsys, probe, tmp_path):
    for args in (
        ["compress", probe, tmp_path / "a.dds", "--format", "bc9"],
        ["compress", probe, tmp_path / "a.png", "--cube", "--size", "8"],
        ["compress", probe, tmp_path / "a.dds", "--cube", "--zstd"],
        ["compress", tmp_path / "missing.hdr", tmp_path / "a.dds"],
        ["compress", probe, probe],
        ["compress", probe, tmp_path / "a.dds", "--cube", "--min-psnr", "nan"],
    ):
        status, _, err = run(capsys, *args)
        assert status == 2 and err.startswith("bakeshop: error: ") and err.count("\n") == 1, args


def test_normals_combine_compress(capsys, tmp_path):
    out = tmp_path / "combined.ktx"
    status, text, err = run(capsys, "normals", "combine", NORMALS, NORMALS, out, "--tile", "2",
                            "--compress")  # fmt: skip
    assert status == 0, err
    assert "bc5" in text and "deg mean" in text
    mips, meta = read_ktx(out)
    assert meta["stored"] == "bc5" and mips[0].shape == (256, 256, 2) and len(mips) == 9


@pytest.mark.slow
def test_bake_probe_for_unity(capsys, probe, tmp_path):
    out = tmp_path / "baked"
    sizes = ["--specular-size", "16", "--cube-size", "16", "--mips", "5"]
    status, text, err = run(capsys, "bake-probe", probe, "-o", out, "--engine", "unity", *sizes)
    assert status == 0, err
    assert "compressed for Unity" in text
    env, meta = read_dds(out / "unity" / "environment.dds")
    assert meta["stored"] == "bc6h" and meta["cube"]
    spec, _ = read_dds(out / "unity" / "specular.dds")
    assert len(spec) == 5  # Unity's 6 LOD steps need 7 levels; a 16 face has 5
    report = json.loads((out / "unity" / "specular.dds.json").read_text())
    assert report["engine"] == "unity" and len(report["roughness_per_level"]) == 5
    sh_unity = json.loads((out / "unity" / "sh_unity.json").read_text())
    assert len(sh_unity["flat"]) == 27
