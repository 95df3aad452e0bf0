"""2-D texture containers (.dds, .ktx, .ktx2; float, 8-bit and block-compressed) as the input
of compress and convert, and cube maps refused by convert in one line."""

from __future__ import annotations

import numpy as np
import pytest

from bakeshop.cli.main import main
from bakeshop.io import read_container, read_image
from bakeshop.io.compress.texture import encode_texture
from bakeshop.io.dds import write_dds_blocks
from bakeshop.io.ktx import write_ktx
from bakeshop.io.ktx2 import write_ktx2, write_ktx2_blocks
from tests.cli.test_process import one_error_line


def _texture() -> np.ndarray:
    y, x = np.mgrid[0:16, 0:32] / 32.0
    return np.stack([x, y, 1 - x, np.ones_like(x)], -1).astype(np.float32)


def _write(path, kind: str) -> None:
    image = _texture()
    if kind == "float":
        {".ktx2": write_ktx2, ".ktx": write_ktx}[path.suffix](path, [image], dtype="float32")
    elif kind == "unorm8":
        write_ktx2(path, [image], dtype="unorm8")
    else:
        texture = encode_texture([image], "bc7")
        {".ktx2": write_ktx2_blocks, ".dds": write_dds_blocks}[path.suffix](path, texture)


CASES = [("a.ktx2", "float"), ("b.ktx2", "unorm8"), ("c.ktx2", "bc7"), ("d.dds", "bc7"),
         ("e.ktx", "float")]  # fmt: skip


@pytest.mark.parametrize("name, kind", CASES)
def test_compress_takes_a_2d_container(tmp_path, capfd, name, kind):
    source = tmp_path / name
    _write(source, kind)
    status = main(["-q", "compress", str(source), str(tmp_path / "o.dds"), "--format", "bc7"])
    assert status == 0, capfd.readouterr().err
    mips, meta = read_container(tmp_path / "o.dds")
    assert meta["stored"] == "bc7" and mips[0].shape == (16, 32, 4) and not meta["cube"]
    np.testing.assert_allclose(mips[0], read_container(source)[0][0], atol=0.05)  # BC7, fast


@pytest.mark.parametrize("name, kind", CASES)
def test_convert_takes_a_2d_containers_level_0(tmp_path, capfd, name, kind):
    source = tmp_path / name
    _write(source, kind)
    target = tmp_path / "o.exr"
    assert main(["-q", "convert", str(source), str(target), "-O", "pixel_type=float"]) == 0
    capfd.readouterr()
    np.testing.assert_array_equal(read_image(tmp_path / "o.exr"), read_container(source)[0][0])


def test_convert_refuses_a_cube_map_in_one_line(tmp_path, capfd):
    source = tmp_path / "cube.ktx2"
    write_ktx2(source, [np.ones((6, 8, 8, 3), np.float32)])
    assert main(["-q", "convert", str(source), str(tmp_path / "o.exr")]) == 2
    line = one_error_line(capfd)
    assert line.startswith(f"bakeshop: error: {source}: a cube map is not one picture")
    assert not (tmp_path / "o.exr").exists()
