"""The prefilter, dfg and bake-probe commands, end to end through bakeshop.cli.main.main."""

import json

import numpy as np
import pytest

from bakeshop.cli.main import main
from bakeshop.io import read_image, write_image
from bakeshop.io.dds import read_dds
from bakeshop.io.ktx import read_ktx
from bakeshop.light.dfg import dfg_table
from bakeshop.light.specular import prefilter_ggx
from bakeshop.sphere import FACE_NAMES, cube_to_faces, layout
from tests.cli.test_process import one_error_line
from tests.tolerances import EXACT


def _sky(height=32, sun=(0.5, 0.6, -0.62)):
    d, _ = layout("latlong").directions((height, 2 * height))
    s = np.asarray(sun) / np.linalg.norm(sun)
    img = 0.3 + np.array([0.5, 0.7, 1.0]) * np.clip(d[..., 1:2], 0, None)
    img = img + 3e3 * (d @ s > np.cos(np.radians(4)))[..., None]
    return img.astype(np.float32)


@pytest.fixture
def probe(tmp_path):
    path = tmp_path / "probe.pfm"
    write_image(path, _sky())
    return path


def test_help_teaches_with_examples(capsys):
    for command in ("prefilter", "dfg", "bake-probe"):
        assert main([command, "--help"]) == 0
        assert "Example:" in capsys.readouterr().out


@pytest.mark.parametrize("convention", ["opengl", "directx"])
def test_prefilter_writes_the_chain_in_one_dds(probe, tmp_path, convention):
    out = tmp_path / "spec.dds"
    args = ["prefilter", str(probe), str(out), "--size", "16", "--mips", "4"]
    assert main([*args, "--convention", convention, "--float32"]) == 0
    mips, meta = read_dds(out)
    assert meta["cube"] and meta["stored"] == "float32"
    want = prefilter_ggx(read_image(probe), layout="latlong", size=16, mips=4)
    assert [m.shape for m in mips] == [(6, s, s, 4) for s in (16, 8, 4, 2)]
    for got, level in zip(mips, want, strict=True):
        faces = cube_to_faces(level, convention=convention)
        assert np.abs(got[..., :3] - faces).max() == EXACT


def test_prefilter_ktx2(probe, tmp_path):
    from bakeshop.io.ktx2 import read_ktx2

    out = tmp_path / "spec.ktx2"
    assert main(["prefilter", str(probe), str(out), "--size", "8", "--mips", "4"]) == 0
    mips, meta = read_ktx2(out)
    assert meta["cube"] and [m.shape for m in mips] == [(6, s, s, 3) for s in (8, 4, 2, 1)]
    assert main(["dfg", str(tmp_path / "dfg.ktx2"), "--size", "8", "--samples", "64"]) == 0
    assert read_ktx2(tmp_path / "dfg.ktx2")[0][0].shape == (8, 8, 2)


def test_prefilter_half_floats_unless_they_overflow(probe, tmp_path):
    out = tmp_path / "spec.ktx"
    assert main(["prefilter", str(probe), str(out), "--size", "8", "--mips", "2"]) == 0
    assert read_ktx(out)[1]["stored"] == "float16"
    bright = tmp_path / "bright.pfm"
    write_image(bright, _sky() * 100)
    assert main(["prefilter", str(bright), str(out), "--size", "8", "--mips", "2"]) == 0
    assert read_ktx(out)[1]["stored"] == "float32"


def test_prefilter_separate_files(probe, tmp_path):
    pattern = tmp_path / "spec_{mip}_{face}.pfm"
    assert main(["prefilter", str(probe), str(pattern), "--size", "8", "--mips", "3"]) == 0
    for m, s in enumerate((8, 4, 2)):
        for face in FACE_NAMES:
            assert read_image(tmp_path / f"spec_{m}_{face}.pfm").shape == (s, s, 3)
    crosses = tmp_path / "cross_{mip}.pfm"
    assert main(["prefilter", str(probe), str(crosses), "--size", "8", "--mips", "2"]) == 0
    assert read_image(tmp_path / "cross_1.pfm").shape == (16, 12, 3)


def test_prefilter_phong_single_lobe(probe, tmp_path, capsys):
    out = tmp_path / "glossy.dds"
    args = ["prefilter", str(probe), str(out), "--brdf", "phong", "--exponent", "20", "--size", "8"]
    assert main(args) == 0
    mips, _ = read_dds(out)
    assert len(mips) == 1 and "Phong exponent 20" in capsys.readouterr().out


@pytest.mark.parametrize(
    "extra, message",
    [
        (["--exponent", "20"], "--brdf phong"),
        (["--brdf", "phong", "--exponent", "20", "--mips", "3"], "one level"),
        (["--mips", "9", "--size", "16"], "mip levels"),
    ],
)
def test_prefilter_bad_arguments(probe, tmp_path, capsys, extra, message):
    assert main(["prefilter", str(probe), str(tmp_path / "o.dds"), *extra]) == 2
    assert message in capsys.readouterr().err


@pytest.mark.parametrize("command", ["bake-probe", "prefilter"])
def test_more_levels_than_the_cube_has_are_refused_before_the_probe_is_read(
    tmp_path, capfd, command
):
    junk = tmp_path / "probe.hdr"
    junk.write_bytes(b"not a probe")
    if command == "bake-probe":
        out, size = tmp_path / "out", "--specular-size"
        args = [command, str(junk), "-o", str(out)]
    else:
        out, size = tmp_path / "spec.dds", "--size"
        args = [command, str(junk), str(out)]
    assert main([*args, size, "8", "--mips", "9"]) == 2
    assert one_error_line(capfd) == (
        f"bakeshop: error: {out}: --mips 9: an 8-texel cube has 1..4 mip levels; "
        f"lower --mips or raise {size}"
    )
    assert not out.exists()


@pytest.mark.parametrize(
    ("extra", "reason"),
    [(["--zstd"], "--zstd is an option of the compressed files: add --compress or --engine"),
     (["--min-psnr", "40"], "--min-psnr is an option of the compressed files"),
     (["--quality", "fast"], "--quality is an option of the compressed files"),
     (["--engine", "unity", "--zstd"], "--zstd supercompresses KTX2 files only; this engine "
      "loads .dds")],
)  # fmt: skip
def test_bake_probe_refuses_an_encoder_option_that_would_do_nothing(tmp_path, capfd, extra, reason):
    junk = tmp_path / "probe.hdr"
    junk.write_bytes(b"not a probe")
    out = tmp_path / "out"
    assert main(["bake-probe", str(junk), "-o", str(out), *extra]) == 2
    assert one_error_line(capfd).startswith(f"bakeshop: error: {out}: {reason}")
    assert not out.exists()


@pytest.mark.slow
def test_bake_probe_default_levels_fit_the_specular_size(probe, tmp_path):
    out = tmp_path / "baked"
    assert main(["bake-probe", str(probe), "-o", str(out), "--specular-size", "4"]) == 0
    chain, _ = read_dds(out / "specular.dds")
    assert [level.shape[1] for level in chain] == [4, 2, 1]


def test_prefilter_refuses_a_single_image_output(probe, tmp_path, capsys):
    assert main(["prefilter", str(probe), str(tmp_path / "spec.exr")]) == 2
    assert "{mip}" in capsys.readouterr().err


def test_dfg_container_and_image(tmp_path):
    assert main(["dfg", str(tmp_path / "dfg.dds"), "--size", "16", "--samples", "256"]) == 0
    mips, meta = read_dds(tmp_path / "dfg.dds")
    assert not meta["cube"] and meta["dxgi_format"] == 34  # R16G16_FLOAT
    want = dfg_table(16, samples=256)
    np.testing.assert_array_equal(mips[0], want.astype(np.float16).astype(np.float32))
    assert main(["dfg", str(tmp_path / "dfg.pfm"), "--size", "16", "--samples", "256"]) == 0
    rgb = read_image(tmp_path / "dfg.pfm")
    np.testing.assert_array_equal(rgb[..., :2], want)
    assert np.abs(rgb[..., 2]).max() == EXACT


@pytest.mark.slow
def test_bake_probe_writes_everything(probe, tmp_path, capsys):
    out = tmp_path / "baked"
    args = ["bake-probe", str(probe), "-o", str(out), "--specular-size", "16", "--mips", "5"]
    assert main([*args, "--format", "pfm"]) == 0
    for face in FACE_NAMES:
        assert read_image(out / f"env_{face}.pfm").shape[2] == 3
    assert read_image(out / "sun_dim.pfm").shape == (180, 360, 3)
    assert read_image(out / "shadow_probe.pfm").shape == (32, 64, 3)
    sun = json.loads((out / "sun.json").read_text())["direction"]
    np.testing.assert_allclose(
        sun, np.array([0.5, 0.6, -0.62]) / np.linalg.norm([0.5, 0.6, -0.62]), atol=0.02
    )
    assert len(json.loads((out / "sh.json").read_text())["coefficients"]) == 9
    assert len(read_dds(out / "specular.dds")[0]) == 5
    assert read_dds(out / "dfg.dds")[0][0].shape == (128, 128, 2)
    sheet = read_image(out / "contact_sheet.png")
    assert sheet.ndim == 3 and sheet.shape[1] > 800
    text = capsys.readouterr().out
    assert "specular.dds" in text and "sun: direction" in text


@pytest.mark.slow
def test_bake_probe_default_probe(tmp_path, capsys):
    # make demo runs this (at full size): the embedded probe when IN is left out
    args = ["bake-probe", "-o", str(tmp_path), "--specular-size", "8", "--mips", "2"]
    assert main([*args, "--cube-size", "16", "--container", "ktx"]) == 0
    assert "default_probe.hdr" in capsys.readouterr().out
    assert (tmp_path / "specular.ktx").is_file() and (tmp_path / "contact_sheet.png").is_file()


@pytest.mark.slow
@pytest.mark.parametrize("channels", [1, 4])
def test_bake_probe_rgba_and_grey_probes_give_rgb_files(tmp_path, channels):
    sky = _sky()
    image = np.concatenate([sky, np.ones_like(sky[..., :1])], -1) if channels == 4 else sky[..., :1]
    src = tmp_path / "probe.exr"
    write_image(src, image, pixel_type="float")
    out = tmp_path / "baked"
    args = ["bake-probe", str(src), "-o", str(out), "--specular-size", "8", "--mips", "2"]
    assert main([*args, "--cube-size", "8"]) == 0
    for name in ("env_posx.hdr", "sun_dim.hdr", "shadow_probe.hdr"):
        assert read_image(out / name).shape[-1] == 3


@pytest.mark.slow
def test_bake_probe_from_a_ktx2_cube(probe, tmp_path, capsys):
    # a cube probe: its shadow probe is a cube too, written as one vertical cross picture
    cube = tmp_path / "probe.ktx2"
    assert main(["-q", "remap", str(probe), str(cube), "--to", "cube", "--size", "16"]) == 0
    out = tmp_path / "baked"
    args = ["bake-probe", str(cube), "-o", str(out), "--specular-size", "8", "--mips", "2"]
    assert main([*args, "--cube-size", "16", "--container", "ktx2"]) == 0
    assert read_image(out / "shadow_probe.hdr").shape == (64, 48, 3)
    assert read_image(out / "env_posx.hdr").shape == (16, 16, 3)
    assert (out / "specular.ktx2").is_file() and (out / "dfg.ktx2").is_file()
    assert "vertical cross" in capsys.readouterr().out


def test_bake_probe_paints_its_own_copy_and_never_its_input(probe, tmp_path):
    """The shadow probe is painted into a copy, never into the probe the engine chains are
    made from nor into its file: a PFM input is left as it was, and the shadow probe is the
    library's."""
    from bakeshop.light import bake_probe

    before = probe.read_bytes()
    out = tmp_path / "baked"
    args = ["bake-probe", str(probe), "-o", str(out), "--specular-size", "8", "--mips", "2"]
    assert main([*args, "--cube-size", "16", "--format", "pfm"]) == 0
    assert probe.read_bytes() == before
    sky = read_image(probe)
    baked = bake_probe(sky, "latlong", cube_size=16, specular_size=8, mips=2)
    np.testing.assert_array_equal(read_image(out / "shadow_probe.pfm"), baked.shadow_probe)
    assert not np.array_equal(baked.shadow_probe, sky)
