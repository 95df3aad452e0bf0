"""No command writes over its own input: not by the same name, a symbolic link either way, a
link through a directory, a hard link, nor through a pattern ({face}, {mip}, {frame}, a glob of
input frames). The refusal is one line naming the output, before any work: the input is intact
and nothing else was written.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from bakeshop.cli.main import main
from bakeshop.io import write_image
from bakeshop.sphere import FACE_NAMES, FACE_NAMES_SHORT
from tests.cli.test_process import one_error_line

REFUSED = "refusing to write over the command's own input"


def probe(path: Path, shape=(16, 32, 3), seed=0) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    write_image(path, np.random.default_rng(seed).lognormal(0, 1, shape).astype(np.float32))
    return path


def snapshot(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` (links followed) and its bytes."""
    return {
        str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()
    }


def refused(capfd, folder: Path, args: list[str], named: Path, *words: str) -> None:
    """Run ``args``: one error line naming ``named``, saying ``words``; nothing changed."""
    before = snapshot(folder)
    assert main(["-q", *map(str, args)]) == 2
    line = one_error_line(capfd)
    assert line.startswith(f"bakeshop: error: {named}: {REFUSED}"), line
    for word in words:
        assert word in line, line
    assert snapshot(folder) == before


def test_the_same_name(tmp_path, capfd):
    source = probe(tmp_path / "a.hdr")
    refused(capfd, tmp_path, ["convert", source, source], source)
    refused(capfd, tmp_path, ["resize", source, source, "--size", "8"], source)


def test_six_faces_in_and_one_of_them_out(tmp_path, capfd):
    # issue 12: remap "f_{face}.hdr" f_posx.hdr wrote over its own +X face
    for i, face in enumerate(FACE_NAMES):
        probe(tmp_path / f"f_{face}.hdr", (8, 8, 3), seed=i)
    pattern = str(tmp_path / "f_{face}.hdr")
    target = tmp_path / "f_posx.hdr"
    args = ["remap", pattern, target, "--from", "faces", "--to", "cross-vertical"]
    refused(capfd, tmp_path, args, target, f"the input {pattern} includes it")


def test_one_file_in_and_six_faces_out(tmp_path, capfd):
    # issue 12: bake-probe out/env_posx.hdr -o out wrote over its input
    source = probe(tmp_path / "out" / "env_posx.hdr", (16, 32, 3))
    args = ["bake-probe", source, "-o", tmp_path / "out", "--cube-size", "8"]
    refused(capfd, tmp_path, args, source, "env_{face}.hdr includes it")
    args = ["remap", source, tmp_path / "out" / "env_{face}.hdr", "--to", "faces"]
    refused(capfd, tmp_path, args, source, "env_{face}.hdr includes it")


def test_short_face_names(tmp_path, capfd):
    source = probe(tmp_path / "sky_nz.hdr")
    args = ["remap", source, tmp_path / "sky_{face}.hdr", "--to", "faces", "--short-face-names"]
    refused(capfd, tmp_path, args, source)
    # the long names as well: a pattern is refused for any face name it may stand for
    args = ["remap", source, tmp_path / "sky_{face}.hdr", "--to", "faces"]
    refused(capfd, tmp_path, args, source)


def test_a_mip_chain_over_its_source(tmp_path, capfd):
    source = probe(tmp_path / "spec_1_negy.hdr")
    args = ["prefilter", source, tmp_path / "spec_{mip}_{face}.hdr", "--size", "8", "--mips", "2"]
    refused(capfd, tmp_path, args, source, "spec_{mip}_{face}.hdr includes it")
    cross = probe(tmp_path / "c_3.hdr", (16, 12, 3))
    args = ["prefilter", cross, tmp_path / "c_{mip}.hdr", "--from", "cross-vertical"]
    refused(capfd, tmp_path, args, cross)


def test_frames_over_their_own_frames(tmp_path, capfd):
    for i in range(3):
        probe(tmp_path / f"shot_{i:04d}.hdr", seed=i)
    pattern = str(tmp_path / "shot_*.hdr")
    target = tmp_path / "shot_{frame:04d}.hdr"
    refused(capfd, tmp_path, ["tonemap", pattern, target], tmp_path / "shot_0000.hdr")
    refused(
        capfd,
        tmp_path,
        ["tonemap", tmp_path / "shot_0002.hdr", tmp_path / "shot_{frame}.hdr"],
        tmp_path / "shot_0002.hdr",
    )


def test_symbolic_links_either_way(tmp_path, capfd):
    real = probe(tmp_path / "real.hdr")
    link = tmp_path / "link.hdr"
    link.symlink_to(real.name)
    # reading through the link, writing the file it points to
    refused(capfd, tmp_path, ["convert", link, real], real, "a symbolic link makes it the input")
    # reading the file, writing through a link to it
    refused(capfd, tmp_path, ["convert", real, link], link, "a symbolic link makes it the input")


def test_a_directory_link(tmp_path, capfd):
    source = probe(tmp_path / "data" / "p.hdr")
    (tmp_path / "alias").symlink_to("data")
    target = tmp_path / "alias" / "p.hdr"
    refused(capfd, tmp_path, ["convert", source, target], target, "a symbolic link")
    target = tmp_path / "alias" / "p_{face}.hdr"
    other = probe(tmp_path / "data" / "p_posz.hdr")
    refused(
        capfd,
        tmp_path,
        ["remap", other, target, "--to", "faces", "--from", "latlong"],
        tmp_path / "alias" / "p_posz.hdr",
        "a symbolic link",
    )


def test_a_hard_link(tmp_path, capfd):
    source = probe(tmp_path / "p.hdr")
    twin = tmp_path / "twin.hdr"
    os.link(source, twin)
    refused(capfd, tmp_path, ["convert", source, twin], twin, "a hard link to the input")
    refused(capfd, tmp_path, ["fresnel", source, twin], twin, "a hard link")


def test_every_output_of_a_command(tmp_path, capfd):
    source = probe(tmp_path / "p.hdr")
    # a second output of the command (irradiance --sh-json), a folder's file (dims)
    args = ["irradiance", source, tmp_path / "dim.hdr", "--sh-json", source]
    refused(capfd, tmp_path, args, source)
    folder = tmp_path / "dims"
    inside = probe(folder / "sun_dim.hdr")
    refused(capfd, tmp_path, ["dims", inside, "-o", folder, "--size", "8x4"], inside)
    # an engine's file in bake-probe's DIR/ENGINE/ (here a hard link to the probe)
    engine_file = tmp_path / "baked" / "unity" / "environment.dds"
    engine_file.parent.mkdir(parents=True)
    os.link(source, engine_file)
    args = ["bake-probe", source, "-o", tmp_path / "baked", "--engine", "unity"]
    refused(capfd, tmp_path, args, engine_file, "a hard link")
    # an input given inside a --layer specification (normals combine)
    n = tmp_path / "n.png"
    flat = np.zeros((8, 8, 3), np.float32)
    flat[..., 2] = 1
    write_image(n, (flat + 1) / 2)
    layer = tmp_path / "layer.png"
    write_image(layer, (flat + 1) / 2)
    refused(capfd, tmp_path, ["normals", "combine", n, n, layer, "--layer", layer], layer)


def test_the_commands_main_gained(tmp_path, capfd):
    # compress writes a chain of {mip} and {face} pictures: one of them is its input
    source = tmp_path / "env_0_posy.png"
    write_image(source, np.full((16, 32, 3), 90, np.uint8))
    args = ["compress", source, tmp_path / "env_{mip}_{face}.png", "--cube", "--format", "rgbd"]
    refused(capfd, tmp_path, args, source, "env_{mip}_{face}.png includes it")
    # merge's confidence map and saved response, unwrap's probe through a link
    frames = []
    for k in range(2):
        frames.append(tmp_path / f"bracket_{k}.png")
        write_image(frames[-1], np.full((8, 16, 3), 60 * (k + 1), np.uint8))
    merge = ["merge", *frames, "-o", tmp_path / "m.exr", "--times", "1/100,1/25"]
    refused(capfd, tmp_path, [*merge, "--confidence", frames[1]], frames[1])
    refused(capfd, tmp_path, [*merge, "--save-response", frames[0]], frames[0])
    ball = probe(tmp_path / "ball.exr", (16, 16, 3))
    (tmp_path / "probe.exr").symlink_to(ball.name)
    args = ["unwrap", ball, "-o", tmp_path / "probe.exr"]
    refused(capfd, tmp_path, args, tmp_path / "probe.exr", "a symbolic link")


def test_what_is_not_an_input_is_written(tmp_path, capfd):
    # the pattern's other files, names its glob matches but its fields cannot make, and a copy
    source = probe(tmp_path / "f_posx.hdr")
    probe(tmp_path / "f_other.hdr")
    (tmp_path / "f_posx.hdr.bak").write_bytes(source.read_bytes())
    args = ["remap", tmp_path / "f_other.hdr", tmp_path / "f_{face}.hdr", "--to", "faces"]
    assert main(["-q", *map(str, args)]) == 0
    capfd.readouterr()
    names = {p.name for p in tmp_path.iterdir()}
    assert {f"f_{face}.hdr" for face in FACE_NAMES} <= names
    copy = tmp_path / "copy.hdr"
    copy.write_bytes(source.read_bytes())
    assert main(["-q", "convert", str(source), str(copy)]) == 0


@pytest.mark.parametrize("names", [FACE_NAMES, FACE_NAMES_SHORT])
def test_the_check_itself_on_face_sets(tmp_path, names):
    from bakeshop.cli._paths import refuse_overwriting_inputs
    from bakeshop.errors import ArgumentError

    for name in names:
        probe(tmp_path / f"in_{name}.hdr", (4, 4, 3))
    pattern = str(tmp_path / "in_{face}.hdr")
    for name in names:
        with pytest.raises(ArgumentError, match="own input"):
            refuse_overwriting_inputs(tmp_path / f"in_{name}.hdr", pattern)
    refuse_overwriting_inputs(tmp_path / "other_{face}.hdr", pattern)
