"""Command-line contracts that hold across commands: messages that read as English, one parser
per kind of value (the memory bound, codec options), and outputs that never name one file."""

from __future__ import annotations

import numpy as np
import pytest

from bakeshop.cli.main import main
from bakeshop.errors import ArgumentError
from bakeshop.huge.memory import parse_memory, resolve_memory
from bakeshop.io import read_image, write_image
from tests.cli.test_process import one_error_line


@pytest.fixture
def probe(tmp_path):
    """A small latlong probe (.hdr)."""
    path = tmp_path / "probe.hdr"
    write_image(path, np.full((8, 16, 3), 0.5, np.float32))
    return path


# -- a or an -------------------------------------------------------------------------------------


def test_an_angular_image_and_an_openexr_file(tmp_path, probe, capfd):
    out = tmp_path / "out.hdr"
    assert main(["-q", "remap", str(probe), str(out), "--from", "angular", "--to", "latlong"]) == 2
    assert "an angular image must be square" in one_error_line(capfd)
    fake = tmp_path / "fake.exr"
    fake.write_bytes(b"not an image at all" * 4)
    assert main(["-q", "info", str(fake)]) == 2
    assert "not an OpenEXR file" in one_error_line(capfd)


# -- codec options: typed by the codec's signature -----------------------------------------------


@pytest.mark.parametrize("value", ["maybe", "2", "truthy", ""])
def test_a_boolean_codec_option_takes_only_boolean_words(tmp_path, probe, capfd, value):
    out = tmp_path / "out.hdr"
    assert main(["-q", "convert", str(probe), str(out), "-O", f"rle={value}"]) == 2
    line = one_error_line(capfd)
    assert "option rle takes true or false" in line and repr(value) in line
    assert not out.exists()


@pytest.mark.parametrize("value", ["true", "YES", "1", "false", "no", "0"])
def test_a_boolean_codec_option_reads_its_words(tmp_path, probe, capfd, value):
    out = tmp_path / "out.tga"
    assert main(["-q", "convert", str(probe), str(out), "-O", f"rle={value}"]) == 0
    rle = value.lower() in ("true", "yes", "1")
    assert (out.read_bytes()[2] == 10) is rle  # TGA image type 10: run-length encoded RGB


def test_numeric_codec_options_are_checked(tmp_path, probe, capfd):
    out = tmp_path / "out.pfm"
    assert main(["-q", "convert", str(probe), str(out), "-O", "scale=big"]) == 2
    assert "option scale takes a number, not 'big'" in one_error_line(capfd)
    assert main(["-q", "convert", str(probe), str(out), "-O", "scale=2"]) == 0
    np.testing.assert_array_equal(read_image(out), read_image(probe))


# -- the memory bound: one parser for --memory and BAKESHOP_MEMORY --------------------------------


@pytest.mark.parametrize("text", ["1PB", "1 PB", "1pb", "0.5 PiB", "2 GB", "1.5GiB"])
def test_memory_sizes_the_help_names_are_accepted(text):
    assert 4 << 20 <= parse_memory(text) <= 10**15 + 2**50


@pytest.mark.parametrize("text", ["1e30", "2PB", "1 EB", "1", "nan", "lots"])
def test_the_variable_and_the_option_refuse_alike(tmp_path, probe, capfd, monkeypatch, text):
    out = tmp_path / "out.hdr"
    args = ["-q", "resize", str(probe), str(out), "--size", "8x4"]
    assert main([*args, "--memory", text]) == 2
    assert "--memory" in one_error_line(capfd)
    monkeypatch.setenv("BAKESHOP_MEMORY", text)
    with pytest.raises(ArgumentError, match="BAKESHOP_MEMORY"):
        resolve_memory(None)
    assert main(args) == 2
    assert "BAKESHOP_MEMORY" in one_error_line(capfd)
    assert not out.exists()


# -- two outputs of one command ------------------------------------------------------------------


def test_two_outputs_naming_one_file_are_refused(tmp_path, probe, capfd):
    dim = tmp_path / "dim.hdr"
    for other in (dim, tmp_path / "sub" / ".." / "dim.hdr"):
        args = ["-q", "irradiance", str(probe), str(dim), "--sh-json", str(other)]
        assert main(args) == 2
        assert "two outputs name this file" in one_error_line(capfd)
        assert not dim.exists()


def test_a_pattern_output_including_another_output_is_refused(tmp_path, probe, capfd):
    faces = tmp_path / "cube_{face}.hdr"
    args = ["-q", "remap", str(probe), str(faces), "--to", "cube"]
    assert main([*args]) == 0
    capfd.readouterr()
    from bakeshop.cli._paths import refuse_shared_outputs

    with pytest.raises(ArgumentError, match="two outputs name this file"):
        refuse_shared_outputs([str(faces), str(tmp_path / "cube_posx.hdr")])
    refuse_shared_outputs([str(faces), str(tmp_path / "cube_posx.json")])


# -- alpha into formats that store RGB only ------------------------------------------------------


def _rgba(tmp_path, alpha):
    """A latlong RGBA .exr of colour 0.5 and the given alpha."""
    image = np.full((8, 16, 4), 0.5, np.float32)
    image[..., 3] = alpha
    path = tmp_path / "rgba.exr"
    write_image(path, image, pixel_type="float")
    return path


#: commands that may write .hdr/.pfm/.jpg from an RGBA input: (arguments after IN, output)
RGB_ONLY_WRITERS = [
    (["convert"], ["{out}.hdr"]),
    (["convert"], ["{out}.jpg"]),
    (["resize"], ["{out}.pfm", "--size", "8x4"]),
    (["remap"], ["{out}.hdr", "--to", "mirrorball", "--size", "8"]),
    (["irradiance"], ["{out}.hdr", "--size", "8x4", "--method", "exact"]),
    (["fresnel"], ["{out}.hdr"]),
    (["prefilter"], ["{out}_{{mip}}_{{face}}.pfm", "--size", "4", "--mips", "1"]),
    (["tonemap"], ["{out}.jpg"]),
    (["dims"], ["-o", "{out}", "--method", "exact", "--size", "8x4"]),
]


@pytest.mark.parametrize(
    "words, rest", RGB_ONLY_WRITERS, ids=[" ".join(w) for w, _ in RGB_ONLY_WRITERS]
)
def test_an_alpha_of_one_is_dropped_with_a_note_any_other_needs_the_option(
    tmp_path, capfd, words, rest
):
    out = str(tmp_path / "out")
    args = [a.format(out=out) for a in rest]
    opaque = _rgba(tmp_path, 1.0)
    assert main(["-q", *words, str(opaque), *args]) == 0, capfd.readouterr().err
    captured = capfd.readouterr()
    assert "alpha (1 everywhere) dropped" in captured.out and captured.err == ""
    for made in tmp_path.glob("out*"):
        made.unlink() if made.is_file() else None

    ramp = _rgba(tmp_path, np.linspace(0, 1, 16, dtype=np.float32))
    assert main(["-q", *words, str(ramp), *args]) == 2
    assert "--alpha drop or --alpha premultiply" in one_error_line(capfd)
    assert main(["-q", *words, str(ramp), *args, "--alpha", "premultiply"]) == 0


#: the same commands on the out-of-core path (a --memory bound), reading the input by windows
CHUNKED_RGB_ONLY_WRITERS = [
    (["resize"], ["{out}.pfm", "--size", "8x4"]),
    (["remap"], ["{out}.hdr", "--to", "mirrorball", "--size", "8"]),
    (["dims"], ["-o", "{out}", "--method", "exact", "--size", "8x4"]),
]


@pytest.mark.parametrize(
    "words, rest", CHUNKED_RGB_ONLY_WRITERS, ids=[" ".join(w) for w, _ in CHUNKED_RGB_ONLY_WRITERS]
)
def test_out_of_core_paths_follow_the_same_alpha_rule(tmp_path, capfd, words, rest):
    out = str(tmp_path / "out")
    args = [*(a.format(out=out) for a in rest), "--memory", "8MB"]
    assert main(["-q", *words, str(_rgba(tmp_path, 1.0)), *args]) == 0, capfd.readouterr().err
    captured = capfd.readouterr()
    assert "alpha dropped as it is read" in captured.out and captured.err == ""

    ramp = _rgba(tmp_path, np.linspace(0, 1, 16, dtype=np.float32))
    assert main(["-q", *words, str(ramp), *args]) == 2
    assert "--alpha drop or --alpha premultiply" in one_error_line(capfd)
    assert main(["-q", *words, str(ramp), *args, "--alpha", "premultiply"]) == 0


def test_out_of_core_premultiply_multiplies_the_colour_by_alpha(tmp_path, capfd):
    ramp = np.linspace(0, 1, 16, dtype=np.float32)
    out = tmp_path / "out.pfm"
    args = ["--size", "16x8", "--memory", "8MB", "--alpha", "premultiply"]
    assert main(["-q", "resize", str(_rgba(tmp_path, ramp)), str(out), *args]) == 0
    np.testing.assert_allclose(
        read_image(out), np.broadcast_to(0.5 * ramp[None, :, None], (8, 16, 3))
    )


def test_premultiply_multiplies_the_colour_by_alpha(tmp_path, capfd):
    ramp = np.linspace(0, 1, 16, dtype=np.float32)
    source = _rgba(tmp_path, ramp)
    out = tmp_path / "out.pfm"
    assert main(["-q", "convert", str(source), str(out), "--alpha", "premultiply"]) == 0
    np.testing.assert_allclose(
        read_image(out), np.broadcast_to(0.5 * ramp[None, :, None], (8, 16, 3))
    )


# -- a refused command creates nothing -----------------------------------------------------------


def test_a_refused_dims_creates_no_output_folder(tmp_path, probe, capfd):
    folder = tmp_path / "new" / "dims"
    args = ["-q", "dims", str(probe), "-o", str(folder), "--method", "exact"]
    assert main([*args, "--size", "8192x4096"]) == 2  # refused by the DIM's texel bound
    assert "360x180 is plenty" in one_error_line(capfd)
    ramp = _rgba(tmp_path, np.linspace(0, 1, 16, dtype=np.float32))
    args[2] = str(ramp)
    assert main([*args, "--size", "8x4", "--memory", "8MB"]) == 2  # refused while read by windows
    assert "--alpha drop" in one_error_line(capfd)
    assert not (tmp_path / "new").exists()
