"""DDS cube maps and 2-D textures: header bytes against Microsoft's documented values, round
trips, the data layout (face-major, then mips), and broken files."""

import struct

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bakeshop.errors import ArgumentError, FormatError, UnsupportedError
from bakeshop.io import write_container
from bakeshop.io.dds import read_dds, write_dds
from tests.io import fuzzing
from tests.tolerances import EXACT


def chain(size, channels, levels, cube=True, seed=0):
    rng = np.random.default_rng(seed)
    lead = (6,) if cube else ()
    return [
        (rng.random(lead + (max(1, size >> m),) * 2 + (channels,)) * 100).astype(np.float32)
        for m in range(levels)
    ]


def u32(data, offset):
    return struct.unpack_from("<I", data, offset)[0]


def test_cube_header_matches_the_specification(tmp_path):
    mips = chain(16, 4, 5)
    path = tmp_path / "env.dds"
    write_dds(path, mips, dtype="float16")
    data = path.read_bytes()
    # Offsets and values from Microsoft's DDS_HEADER / DDS_PIXELFORMAT / DDS_HEADER_DXT10 pages.
    assert data[:4] == b"DDS "
    assert u32(data, 4) == 124  # dwSize
    assert u32(data, 8) == 0x1 | 0x2 | 0x4 | 0x8 | 0x1000 | 0x20000  # CAPS..MIPMAPCOUNT, PITCH
    assert (u32(data, 12), u32(data, 16)) == (16, 16)  # height, width
    assert u32(data, 20) == 16 * 4 * 2  # pitch: bytes per row of level 0
    assert u32(data, 28) == 5  # dwMipMapCount
    assert u32(data, 76) == 32 and u32(data, 80) == 0x4 and data[84:88] == b"DX10"
    assert u32(data, 108) == 0x1000 | 0x8 | 0x400000  # TEXTURE | COMPLEX | MIPMAP
    assert u32(data, 112) == 0x200 | 0xFC00  # CUBEMAP and all six faces
    assert u32(data, 128) == 10  # DXGI_FORMAT_R16G16B16A16_FLOAT
    assert u32(data, 132) == 3  # D3D10_RESOURCE_DIMENSION_TEXTURE2D
    assert u32(data, 136) == 0x4  # DDS_RESOURCE_MISC_TEXTURECUBE
    assert u32(data, 140) == 1  # arraySize: one cube
    levels = sum(6 * max(1, 16 >> m) ** 2 for m in range(5))
    assert len(data) == 148 + levels * 4 * 2
    # Face-major layout: face 1's level 0 follows face 0's whole chain.
    face_bytes = sum(max(1, 16 >> m) ** 2 for m in range(5)) * 8
    got = np.frombuffer(data, "<f2", 16 * 16 * 4, 148 + face_bytes).reshape(16, 16, 4)
    np.testing.assert_array_equal(got, mips[0][1].astype(np.float16))
    last = np.frombuffer(data, "<f2", 4, len(data) - 8)
    np.testing.assert_array_equal(last, mips[4][5, 0, 0].astype(np.float16))


@pytest.mark.parametrize("dtype, fmt", [("float32", 2), ("float16", 10)])
@pytest.mark.parametrize("cube", [True, False])
def test_round_trip(tmp_path, dtype, fmt, cube):
    mips = chain(8, 4, 4, cube=cube)
    write_dds(tmp_path / "t.dds", mips, dtype=dtype)
    got, meta = read_dds(tmp_path / "t.dds")
    assert meta["cube"] is cube and meta["dxgi_format"] == fmt and meta["stored"] == dtype
    for a, b in zip(got, mips, strict=True):
        assert a.dtype == np.float32 and a.shape == b.shape
        np.testing.assert_array_equal(a, b.astype(dtype).astype(np.float32))
    if dtype == "float32":
        assert max(np.abs(a - b).max() for a, b in zip(got, mips, strict=True)) == EXACT


@pytest.mark.parametrize("channels, fmt, stored", [(1, 41, 1), (2, 16, 2), (3, 2, 4)])
def test_channels(tmp_path, channels, fmt, stored):
    mips = chain(4, channels, 3, cube=False)
    write_dds(tmp_path / "t.dds", mips, dtype="float32")
    got, meta = read_dds(tmp_path / "t.dds")
    assert meta["dxgi_format"] == fmt and got[0].shape[-1] == stored
    np.testing.assert_array_equal(got[0][..., :channels], mips[0])
    if channels == 3:  # padded to RGBA with an opaque alpha
        np.testing.assert_array_equal(got[1][..., 3], 1.0)


def test_half_refuses_a_bright_sun_that_float32_keeps(tmp_path):
    mips = [np.full((6, 2, 2, 4), 1e5, np.float32), np.full((6, 1, 1, 4), -1e6, np.float32)]
    with pytest.raises(ArgumentError, match='reach 1e\\+05, beyond the 65504 .*dtype="float32"'):
        write_dds(tmp_path / "t.dds", mips)
    assert not (tmp_path / "t.dds").exists()
    write_container(tmp_path / "t.dds", mips)  # the containers' writer widens it
    got, meta = read_dds(tmp_path / "t.dds")
    assert meta["stored"] == "float32" and got[1].min() == -1e6


def test_legacy_fourcc_float_files_are_read(tmp_path):
    # An A32B32G32R32F file as older tools write it: FourCC 116, no DX10 header.
    mips = chain(4, 4, 1)
    write_dds(tmp_path / "t.dds", mips, dtype="float32")
    data = bytearray((tmp_path / "t.dds").read_bytes())
    data[84:88] = struct.pack("<I", 116)
    (tmp_path / "legacy.dds").write_bytes(bytes(data[:128] + data[148:]))
    got, meta = read_dds(tmp_path / "legacy.dds")
    assert meta["header"] == "legacy" and meta["cube"]
    np.testing.assert_array_equal(got[0], mips[0])


@pytest.mark.parametrize(
    "mips",
    [
        [],
        [np.zeros((6, 4, 4, 4)), np.zeros((6, 3, 3, 4))],  # wrong halving
        [np.zeros((6, 4, 4, 4)), np.zeros((6, 2, 2, 3))],  # channels change
        [np.zeros((4, 4, 5))],  # five channels
        [np.zeros((6, 4, 2, 4))],  # non-square faces
        [np.full((2, 2, 4), np.nan)],
        [np.zeros((2, 2, 4), bool)],
        [np.zeros((1, 1, 4)), np.zeros((1, 1, 4))],  # more levels than the size has
    ],
)
def test_bad_chains_are_refused(tmp_path, mips):
    with pytest.raises(ArgumentError):
        write_dds(tmp_path / "t.dds", mips)
    assert not list(tmp_path.iterdir())


def test_broken_files(tmp_path):
    write_dds(tmp_path / "t.dds", chain(8, 4, 4))
    data = (tmp_path / "t.dds").read_bytes()
    cases = {
        "short.dds": (data[:100], FormatError),
        "truncated.dds": (data[:-1], FormatError),
        "magic.dds": (b"XXXX" + data[4:], FormatError),
        "huge.dds": (data[:12] + struct.pack("<2I", 1 << 20, 1 << 20) + data[20:], FormatError),
        "levels.dds": (data[:28] + struct.pack("<I", 40) + data[32:], FormatError),
        "bgra8.dds": (data[:128] + struct.pack("<I", 87) + data[132:], UnsupportedError),
        "array.dds": (data[:140] + struct.pack("<I", 2) + data[144:], UnsupportedError),
    }
    for name, (content, error) in cases.items():
        (tmp_path / name).write_bytes(content)
        with pytest.raises(error):
            read_dds(tmp_path / name)


# --- fuzzing: only BakeshopError may escape -------------------------------------------------------


def mip_seeds(write, path):
    """Fuzz seeds made with ``write`` (write_dds or write_ktx) at ``path``: a half-float RGB cube
    map and a float 2-D texture, three mips each."""
    seeds = []
    for cube, dtype in ((True, "float16"), (False, "float32")):
        write(path, chain(4, 3, 3, cube=cube), dtype=dtype)
        seeds.append(path.read_bytes())
    return seeds


def levels(path):
    return read_dds(path)[0]


@pytest.fixture(scope="module")
def seed_files(tmp_path_factory):
    return mip_seeds(write_dds, tmp_path_factory.mktemp("dds_seeds") / "s.dds")


scratch = fuzzing.scratch_file("f.dds")


@pytest.mark.slow
def test_truncation_at_every_offset_is_refused(scratch, seed_files):
    for data in seed_files:
        fuzzing.assert_truncations_refused(scratch, data, read=levels)
    fuzzing.assert_refused(scratch, seed_files[0][:40], "DDS", read=levels)


@fuzzing.FUZZ
@given(st.binary(max_size=300))
def test_random_bytes(scratch, data):
    fuzzing.decode(scratch, data, levels)
    fuzzing.decode(scratch, b"DDS " + data, levels)


@fuzzing.FUZZ
@given(st.integers(0, 1), fuzzing.edits(160), st.integers(1, 1200))
def test_mutations_of_valid_files(scratch, seed_files, which, changes, end):
    fuzzing.decode(scratch, fuzzing.mutate(seed_files[which], changes, end), levels)


def test_opengl_finds_every_texel_where_its_direction_points(tmp_path):
    # The DDS bytes cut by Microsoft's layout (face-major: each face's whole chain), uploaded to
    # OpenGL as RGBA16F: the driver's cube lookup of each texel's direction returns that texel.
    from tests.io.test_ktx import direction_chain, opengl_lookup

    size, levels = 8, 4
    chain = direction_chain(size, levels)
    path = tmp_path / "env.dds"
    write_dds(path, chain, dtype="float16")
    data = path.read_bytes()
    level_bytes = [max(1, size >> m) ** 2 * 4 * 2 for m in range(levels)]
    face_bytes = [[None] * 6 for _ in range(levels)]
    offset = 148
    for f in range(6):
        for m in range(levels):
            face_bytes[m][f] = data[offset : offset + level_bytes[m]]
            offset += level_bytes[m]
    for m, got in enumerate(opengl_lookup(face_bytes, size, "f2")):
        np.testing.assert_array_equal(got, chain[m].astype(np.float16).astype(np.float32))
