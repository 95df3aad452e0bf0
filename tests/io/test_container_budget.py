"""Texture containers (DDS, KTX, KTX2 with Zstandard) and TIFF under the decode budget: the
sizes their headers declare are checked before anything is read, inflated or decoded, and a
Zstandard level never inflates beyond the size its index declares."""

from __future__ import annotations

import json
import struct
import subprocess
import sys
import textwrap
import tracemalloc

import numpy as np
import pytest
import tifffile
import zstandard

from bakeshop.cli.main import main
from bakeshop.errors import FormatError
from bakeshop.io import decode_budget, read_container, read_image, write_image
from bakeshop.io.compress.formats import FORMATS, level_bytes
from bakeshop.io.compress.texture import BlockTexture
from bakeshop.io.dds import write_dds, write_dds_blocks
from bakeshop.io.ktx import write_ktx, write_ktx_blocks
from bakeshop.io.ktx2 import IDENTIFIER, read_ktx2_blocks, write_ktx2
from tests.cli.test_process import one_error_line

BC6H = FORMATS["bc6h"]


def ktx2_blocks(
    width: int, height: int, faces: int, level: bytes, inflated: int, vk: tuple = (BC6H.vk, 1)
) -> bytes:
    """A one-level KTX2 of ``width`` x ``height`` (``faces`` 1 or 6), Zstandard
    supercompressed: ``level`` is the stored frame, ``inflated`` its declared size; ``vk`` the
    VkFormat and typeSize (BC6H by default)."""
    offset = 80 + 24
    header = struct.pack(
        "<12s9I4I2Q", IDENTIFIER, *vk, width, height, 0, 0, faces, 1, 2, 0, 0, 0, 0, 0, 0
    )
    return header + struct.pack("<3Q", offset, len(level), inflated) + level


def zeros_ktx2(side: int, faces: int = 1) -> bytes:
    """A KTX2 whose one level is ``side``^2 BC6H zero blocks, a frame of a few KB at most."""
    size = faces * level_bytes(BC6H, side, side)
    frame = zstandard.ZstdCompressor(level=1).compress(bytes(size))
    return ktx2_blocks(side, side, faces, frame, size)


def peak_of_info(path, *options: str) -> dict:
    """``bakeshop [options] info path`` in a child: its status, stderr and peak memory."""
    code = textwrap.dedent(
        f"""
        import contextlib, io, json, resource, sys
        from bakeshop.cli.main import main
        err = io.StringIO()
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            status = main([*{list(options)!r}, "info", {str(path)!r}])
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
        print(json.dumps({{"status": status, "err": err.getvalue(), "peak": peak}}))
        """
    )
    run = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=False
    )
    assert run.returncode == 0, run.stderr[-2000:]
    return json.loads(run.stdout.strip().splitlines()[-1])


def test_a_declared_16k_cube_is_refused_before_inflating(tmp_path):
    # 6 x 16384^2 BC6H is 1.5 GiB of blocks and 18 GiB of float32: the header alone refuses it,
    # whatever the (here junk) payload
    path = tmp_path / "bomb.ktx2"
    path.write_bytes(ktx2_blocks(16384, 16384, 6, b"\x28\xb5\x2f\xfd" + bytes(60), 6 << 28))
    for read in (read_container, lambda p: read_ktx2_blocks(p)):
        with pytest.raises(FormatError, match="decompression bomb"):
            read(path)


def test_a_small_budget_refuses_what_a_zstd_level_would_inflate_to(tmp_path, capfd):
    path = tmp_path / "bomb.ktx2"
    path.write_bytes(zeros_ktx2(1024))  # 1 MiB of blocks, 12 MiB decoded, from ~100 bytes
    assert path.stat().st_size < 1024
    assert main(["-q", "--max-decoded", "16M", "info", str(path)]) == 0
    capfd.readouterr()
    assert main(["-q", "--max-decoded", "4M", "info", str(path)]) == 2
    line = one_error_line(capfd)
    assert line.startswith(f"bakeshop: error: {path}: ") and "decompression bomb" in line
    with decode_budget(1000 << 10), pytest.raises(FormatError, match="budget set for this run"):
        read_ktx2_blocks(path)  # the blocks alone (1 MiB) are over a smaller budget


def test_the_default_budget_refuses_a_2gib_level(tmp_path):
    # 16384 x 8192 RGBA float32 (VK_FORMAT_R32G32B32A32_SFLOAT): a 2 GiB level declared, above
    # 1 GiB and 256 x the file
    path = tmp_path / "bomb.ktx2"
    path.write_bytes(ktx2_blocks(16384, 8192, 1, bytes(64), 2 << 30, vk=(109, 4)))
    with pytest.raises(FormatError, match=r"decompression bomb.*max\(1 GiB, 256 x"):
        read_ktx2_blocks(path)


@pytest.mark.slow
def test_a_zstd_bomb_is_refused_in_little_memory(tmp_path):
    # 64 MiB of blocks (768 MiB decoded) from a few KB: refused with the memory of a tiny file
    bomb, warm = tmp_path / "bomb.ktx2", tmp_path / "warm.ktx2"
    bomb.write_bytes(zeros_ktx2(8192))
    warm.write_bytes(zeros_ktx2(64))
    assert bomb.stat().st_size < 8 << 10
    small = peak_of_info(warm)
    refused = peak_of_info(bomb, "--max-decoded", "1M")
    assert small["status"] == 0 and refused["status"] == 2
    assert "decompression bomb" in refused["err"] and refused["err"].count("\n") == 1
    assert refused["peak"] < small["peak"] + (16 << 20), (small, refused)


@pytest.mark.parametrize("content_size", [True, False])
def test_a_level_inflating_beyond_its_declared_size_is_refused(tmp_path, content_size):
    # 64 bytes declared by the index; the frame holds 64 MiB (and may say so in its header,
    # which zstandard would trust over any cap: it is refused before inflating)
    frame = zstandard.ZstdCompressor(level=1, write_content_size=content_size).compress(
        bytes(64 << 20)
    )
    path = tmp_path / "liar.ktx2"
    path.write_bytes(ktx2_blocks(8, 8, 1, frame, level_bytes(BC6H, 8, 8)))
    reason = (
        "its Zstandard frame declares 67108864 bytes" if content_size else "corrupt Zstandard data"
    )
    tracemalloc.start()
    try:
        with pytest.raises(FormatError, match=f"level 0: {reason}"):
            read_ktx2_blocks(path)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 4 << 20, peak


def test_float_ktx2_ktx_and_dds_apply_the_budget(tmp_path):
    level = np.ones((64, 64, 4), np.float32)
    write_ktx2(tmp_path / "a.ktx2", [level], dtype="float32")
    write_ktx(tmp_path / "a.ktx", [level], dtype="float32")
    write_dds(tmp_path / "a.dds", [level], dtype="float32")
    for name in ("a.ktx2", "a.ktx", "a.dds"):
        assert read_container(tmp_path / name)[0][0].shape == (64, 64, 4)
        with decode_budget(64 << 10), pytest.raises(FormatError, match="decompression bomb"):
            read_container(tmp_path / name)


def test_block_ktx_and_dds_apply_the_budget(tmp_path):
    texture = BlockTexture(BC6H, 256, 256, False, (bytes(level_bytes(BC6H, 256, 256)),))
    write_ktx_blocks(tmp_path / "b.ktx", texture)
    write_dds_blocks(tmp_path / "b.dds", texture)
    for name in ("b.ktx", "b.dds"):  # 64 KiB of blocks, 768 KiB decoded
        assert read_container(tmp_path / name)[0][0].shape == (256, 256, 3)
        with decode_budget(512 << 10), pytest.raises(FormatError, match="decompression bomb"):
            read_container(tmp_path / name)


def test_tiff_applies_the_budget(tmp_path):
    write_image(tmp_path / "a.tif", np.full((64, 64, 3), 0.5, np.float32))
    assert read_image(tmp_path / "a.tif").shape == (64, 64, 3)
    with pytest.raises(FormatError, match="decompression bomb.*budget of 1000 bytes"):
        read_image(tmp_path / "a.tif", max_decoded=1000)


def test_a_deflate_tiff_bomb_is_refused_from_its_header(tmp_path):
    # 8192^2 uint8 grey deflated to a few hundred KiB: 256 MiB of float32
    path = tmp_path / "bomb.tif"
    tifffile.imwrite(path, np.zeros((8192, 8192), np.uint8), compression="zlib", tile=(1024, 1024))
    assert path.stat().st_size < 1 << 20
    with pytest.raises(FormatError, match="decompression bomb"):
        read_image(path, max_decoded=16 << 20)
