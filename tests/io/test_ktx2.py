"""KTX2 cube maps and 2-D textures: header and level index against the Khronos specification,
an independent parser (pyktx2), a real OpenGL driver, round trips and broken files."""

import struct

import numpy as np
import pyktx2.parser
import pytest
from hypothesis import given
from hypothesis import strategies as st
from pyktx2.parser import TransferFunction, VkFormat, parse_bytes

from bakeshop.errors import ArgumentError, FormatError, UnsupportedError
from bakeshop.io.ktx2 import IDENTIFIER, read_ktx2, write_ktx2
from tests.io import fuzzing
from tests.io.test_dds import chain, mip_seeds
from tests.io.test_ktx import direction_chain, opengl_lookup


def u32(data, offset):
    return struct.unpack_from("<I", data, offset)[0]


def u64(data, offset):
    return struct.unpack_from("<Q", data, offset)[0]


def test_cube_header_matches_the_specification(tmp_path):
    mips = chain(16, 4, 5)
    path = tmp_path / "env.ktx2"
    write_ktx2(path, mips, dtype="float16")
    data = path.read_bytes()
    assert data[:12] == bytes(
        [0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A]
    )
    assert u32(data, 12) == 97 and u32(data, 16) == 2  # VK_FORMAT_R16G16B16A16_SFLOAT, typeSize
    assert (u32(data, 20), u32(data, 24), u32(data, 28), u32(data, 32)) == (16, 16, 0, 0)
    assert (u32(data, 36), u32(data, 40), u32(data, 44)) == (6, 5, 0)  # faces, levels, no scheme
    assert u32(data, 48) == 80 + 5 * 24  # the format descriptor follows the level index
    assert u32(data, 52) == 4 + 24 + 4 * 16 == u32(data, 80 + 5 * 24)  # dfdTotalSize
    assert u64(data, 64) == 0 and u64(data, 72) == 0  # no supercompression global data
    previous_end = None
    for m in reversed(range(5)):  # smallest level first, each 8-byte aligned (RGBA16F)
        offset, length, raw = (u64(data, 80 + 24 * m + 8 * k) for k in range(3))
        s = max(1, 16 >> m)
        assert length == raw == 6 * s * s * 8 and offset % 8 == 0
        assert previous_end is None or 0 <= offset - previous_end < 8
        previous_end = offset + length
        face1 = np.frombuffer(data, "<f2", s * s * 4, offset + s * s * 8).reshape(s, s, 4)
        np.testing.assert_array_equal(face1, mips[m][1].astype(np.float16))
    assert previous_end == len(data)


def test_independent_parser_reads_it(tmp_path, monkeypatch):
    # pyktx2 0.3's ColorModel enum lists only the Basis Universal models (ETC1S, UASTC), not
    # RGBSDA (1) of uncompressed formats: let it pass the number through.
    monkeypatch.setattr(pyktx2.parser, "ColorModel", int)
    mips = chain(8, 4, 4)
    path = tmp_path / "env.ktx2"
    write_ktx2(path, mips, dtype="float16")
    ktx = parse_bytes(path.read_bytes())
    assert ktx.vkFormat == VkFormat.VK_FORMAT_R16G16B16A16_SFLOAT
    assert (ktx.pixelWidth, ktx.faceCount, ktx.levelCount) == (8, 6, 4)
    dfd, samples = ktx.dfd
    assert dfd.colorModel == 1 and dfd.transferFunction == TransferFunction(1)  # RGBSDA, linear
    assert dfd.colorPrimaries.value == 1 and dfd.bytesPlane0 == 8  # BT.709, 8-byte texels
    # one 16-bit signed float sample per channel: R, G, B and alpha (15), -1.0f..1.0f
    for c, (sample, channel) in enumerate(zip(samples, (0, 1, 2, 15), strict=True)):
        offset, length, kind, _, lower, upper = struct.unpack("<HBBIII", sample)
        assert (offset, length, kind) == (16 * c, 15, channel | 0x40 | 0x80)
        assert (lower, upper) == (0xBF800000, 0x3F800000)
    assert ktx.kv["KTXorientation"] == b"rd\x00"
    # images in level order, faces in order within a level
    images = iter(ktx.levelImages)
    for level in mips:
        for face in level:
            image = next(images)
            got = np.frombuffer(image.data, "<f2").reshape(image.height, image.width, 4)
            np.testing.assert_array_equal(got, face.astype(np.float16))


def test_opengl_finds_every_texel_where_its_direction_points(tmp_path):
    # Bytes cut by the level index (the specification's layout, not read_ktx2) go to OpenGL.
    size, levels = 8, 4
    path = tmp_path / "env.ktx2"
    write_ktx2(path, direction_chain(size, levels), dtype="float32")
    data = path.read_bytes()
    face_bytes = []
    for m in range(levels):
        offset, length = u64(data, 80 + 24 * m), u64(data, 88 + 24 * m)
        n = length // 6
        face_bytes.append([data[offset + f * n : offset + (f + 1) * n] for f in range(6)])
    for m, got in enumerate(opengl_lookup(face_bytes, size, "f4")):
        np.testing.assert_array_equal(got, direction_chain(size, levels)[m])


@pytest.mark.parametrize("dtype", ["float16", "float32"])
@pytest.mark.parametrize("channels", [1, 2, 3, 4])
@pytest.mark.parametrize("cube", [True, False])
def test_round_trip(tmp_path, dtype, channels, cube):
    mips = chain(8, channels, 4, cube=cube)
    write_ktx2(tmp_path / "t.ktx2", mips, dtype=dtype)
    got, meta = read_ktx2(tmp_path / "t.ktx2")
    assert meta["cube"] is cube and meta["stored"] == dtype
    assert u32(meta["dfd"], 0) == len(meta["dfd"]) == 4 + 24 + 16 * channels
    for a, b in zip(got, mips, strict=True):
        np.testing.assert_array_equal(a, b.astype(dtype).astype(np.float32))


def test_bad_chain_is_refused(tmp_path):
    with pytest.raises(ArgumentError):
        write_ktx2(tmp_path / "t.ktx2", [np.zeros((6, 4, 4, 4)), np.zeros((6, 1, 1, 4))])
    assert not list(tmp_path.iterdir())


def test_broken_files(tmp_path):
    write_ktx2(tmp_path / "t.ktx2", chain(8, 4, 4))
    data = (tmp_path / "t.ktx2").read_bytes()
    cases = {
        "short.ktx2": (data[:40], FormatError),
        "truncated.ktx2": (data[:-2], FormatError),
        "magic.ktx2": (b"\x00" + data[1:], FormatError),
        "huge.ktx2": (data[:20] + struct.pack("<2I", 1 << 20, 1 << 20) + data[28:], FormatError),
        "srgb8.ktx2": (data[:12] + struct.pack("<I", 43) + data[16:], UnsupportedError),
        "basislz.ktx2": (data[:44] + struct.pack("<I", 1) + data[48:], UnsupportedError),
        "faces.ktx2": (data[:36] + struct.pack("<I", 5) + data[40:], FormatError),
        "index.ktx2": (data[:80] + struct.pack("<Q", 1 << 40) + data[88:], FormatError),
    }
    for name, (content, error) in cases.items():
        (tmp_path / name).write_bytes(content)
        with pytest.raises(error):
            read_ktx2(tmp_path / name)


# --- fuzzing: only BakeshopError may escape ------------------------------------------------------


def levels(path):
    return read_ktx2(path)[0]


@pytest.fixture(scope="module")
def seed_files(tmp_path_factory):
    return mip_seeds(write_ktx2, tmp_path_factory.mktemp("ktx2_seeds") / "s.ktx2")


scratch = fuzzing.scratch_file("f.ktx2")


@pytest.mark.slow
def test_truncation_at_every_offset_is_refused(scratch, seed_files):
    for data in seed_files:
        fuzzing.assert_truncations_refused(scratch, data, read=levels)
    fuzzing.assert_refused(scratch, seed_files[0][:40], "KTX2", read=levels)


@fuzzing.FUZZ
@given(st.binary(max_size=300))
def test_random_bytes(scratch, data):
    fuzzing.decode(scratch, data, levels)
    fuzzing.decode(scratch, IDENTIFIER + data, levels)


@fuzzing.FUZZ
@given(st.integers(0, 1), fuzzing.edits(300), st.integers(1, 1500))
def test_mutations_of_valid_files(scratch, seed_files, which, changes, end):
    fuzzing.decode(scratch, fuzzing.mutate(seed_files[which], changes, end), levels)


@pytest.mark.parametrize("container", ["ktx", "ktx2"])
def test_a_chain_over_the_budget_is_refused_from_its_header_unread(
    tmp_path, monkeypatch, container
):
    import io
    import os

    from bakeshop.io import ktx, ktx2
    from bakeshop.io.budget import decode_budget

    module = {"ktx": ktx, "ktx2": ktx2}[container]
    path = tmp_path / f"big.{container}"
    getattr(module, f"write_{container}")(path, [np.ones((6, 64, 64, 4), np.float32)])
    read = []

    class Counted(io.BufferedReader):
        def read(self, size: int | None = -1, /) -> bytes:
            data = super().read(size)
            read.append(len(data))
            return data

    monkeypatch.setattr(module, "open_input", lambda p: Counted(io.FileIO(os.fspath(p))))
    with decode_budget(64 << 10), pytest.raises(FormatError, match="decompression bomb"):
        getattr(module, f"read_{container}")(path)
    assert sum(read) < 4096 < path.stat().st_size  # the header and level index only
