"""Compressed DDS, KTX2 and KTX 1 files, field by field against the specifications (Microsoft's
DDS_HEADER / DDS_HEADER_DXT10, Khronos KTX 2.0 and 1.1, the Khronos Data Format spec's example
descriptors), an independent KTX2 parser (pyktx2), round trips and broken files."""

import struct

import numpy as np
import pyktx2.parser
import pytest
import zstandard

from bakeshop.errors import FormatError
from bakeshop.io.compress.formats import FORMATS
from bakeshop.io.compress.texture import BlockTexture, encode_texture
from bakeshop.io.dds import read_dds, read_dds_blocks, write_dds_blocks
from bakeshop.io.ktx import read_ktx, write_ktx_blocks
from bakeshop.io.ktx2 import read_ktx2, read_ktx2_blocks, write_ktx2_blocks
from tests.io.compress.conftest import hdr_chain, ldr_chain


def u32(data, offset):
    return struct.unpack_from("<I", data, offset)[0]


def u64(data, offset):
    return struct.unpack_from("<Q", data, offset)[0]


@pytest.fixture(scope="module")
def bc6h_cube():
    return encode_texture(hdr_chain(7, 16), "bc6h")  # 16, 8, 4, 2, 1: five levels


def blocks_of(size: int, fmt) -> int:
    blocks = (size + 3) // 4
    return blocks * blocks * fmt.block_bytes


def test_dds_header_and_layout_match_the_specification(tmp_path, bc6h_cube):
    path = tmp_path / "env.dds"
    write_dds_blocks(path, bc6h_cube)
    data = path.read_bytes()
    assert data[:4] == b"DDS " and u32(data, 4) == 124  # magic, dwSize
    # CAPS | HEIGHT | WIDTH | PIXELFORMAT | MIPMAPCOUNT | LINEARSIZE
    assert u32(data, 8) == 0x1 | 0x2 | 0x4 | 0x1000 | 0x20000 | 0x80000
    assert (u32(data, 12), u32(data, 16)) == (16, 16)  # height, width
    assert u32(data, 20) == 4 * 4 * 16  # linear size: the blocks of one face of level 0
    assert (u32(data, 24), u32(data, 28)) == (0, 5)  # depth, mip count
    assert u32(data, 76) == 32 and u32(data, 80) == 0x4 and data[84:88] == b"DX10"
    assert u32(data, 108) == 0x1000 | 0x8 | 0x400000  # TEXTURE | COMPLEX | MIPMAP
    assert u32(data, 112) == 0x200 | 0xFC00  # CUBEMAP | all six faces
    # DDS_HEADER_DXT10: DXGI_FORMAT_BC6H_UF16, TEXTURE2D, TEXTURECUBE, array size 1, misc2 0
    assert [u32(data, 128 + 4 * i) for i in range(5)] == [95, 3, 0x4, 1, 0]
    # payload: each face's whole chain, then the next face
    sizes = [blocks_of(16 >> m, bc6h_cube.format) for m in range(5)]
    assert len(data) == 148 + 6 * sum(sizes)
    offset = 148
    for face in range(6):
        for m in range(5):
            assert data[offset : offset + sizes[m]] == bc6h_cube.face(m, face)
            offset += sizes[m]


@pytest.mark.parametrize("name", list(FORMATS))
def test_dds_dxgi_format_of_every_block_format(tmp_path, name):
    fmt = FORMATS[name]
    level0 = hdr_chain(1, 8, cube=False)[0] if fmt.hdr else ldr_chain(1, 8, cube=False)[0]
    texture = encode_texture([level0], name)
    write_dds_blocks(tmp_path / "t.dds", texture)
    data = (tmp_path / "t.dds").read_bytes()
    assert u32(data, 128) == fmt.dxgi and u32(data, 8) & 0x20000 == 0  # one level: no MIPMAPCOUNT
    assert u32(data, 112) == 0 and u32(data, 136) == 0  # not a cube
    got, meta = read_dds_blocks(tmp_path / "t.dds")
    assert got.format is fmt and got.levels == texture.levels and meta["stored"] == name


def test_ktx2_header_index_and_descriptor_match_the_specification(tmp_path, bc6h_cube):
    path = tmp_path / "env.ktx2"
    write_ktx2_blocks(path, bc6h_cube)
    data = path.read_bytes()
    assert data[:12] == b"\xabKTX 20\xbb\r\n\x1a\n"
    assert u32(data, 12) == 143 and u32(data, 16) == 1  # VK_FORMAT_BC6H_UFLOAT_BLOCK, typeSize 1
    assert [u32(data, 20 + 4 * i) for i in range(7)] == [16, 16, 0, 0, 6, 5, 0]
    dfd_offset, dfd_length = u32(data, 48), u32(data, 52)
    assert dfd_offset == 80 + 5 * 24 and dfd_length == 44 == u32(data, dfd_offset)
    words = struct.unpack_from("<10I", data, dfd_offset + 4)
    assert words[0] == 0 and words[1] == 2 | 40 << 16  # Khronos basic block, version 2, size 40
    assert words[2] == 133 | 1 << 8 | 1 << 16  # KHR_DF_MODEL_BC6H, BT.709, linear, straight alpha
    assert words[3] == 3 | 3 << 8  # texel block 4x4x1x1
    assert words[4] == 16 and words[5] == 0  # bytesPlane0
    # one sample: bits 0..127, channel COLOR with the FLOAT qualifier, 0.0f .. 1.0f
    assert words[6] == 0 | 127 << 16 | 0x80 << 24 and words[7] == 0
    assert (words[8], words[9]) == (0, 0x3F800000)
    # levels: smallest first, each aligned to lcm(16, 4) = 16, sizes of six faces
    offsets = [u64(data, 80 + 24 * m) for m in range(5)]
    for m in range(5):
        size = 6 * blocks_of(16 >> m, bc6h_cube.format)
        assert u64(data, 88 + 24 * m) == u64(data, 96 + 24 * m) == size
        assert offsets[m] % 16 == 0
        assert data[offsets[m] : offsets[m] + len(bc6h_cube.levels[m])] == bc6h_cube.levels[m]
    assert offsets == sorted(offsets, reverse=True)
    assert offsets[0] + len(bc6h_cube.levels[0]) == len(data)


def test_ktx2_descriptors_of_signed_and_srgb_formats():
    from bakeshop.io.ktx2 import block_format_descriptor

    signed = struct.unpack("<11I", block_format_descriptor(FORMATS["bc6h-signed"]))
    assert signed[7] >> 24 == 0x80 | 0x40 and (signed[9], signed[10]) == (0xBF800000, 0x3F800000)
    srgb = struct.unpack("<11I", block_format_descriptor(FORMATS["bc7-srgb"]))
    assert srgb[3] == 134 | 1 << 8 | 2 << 16  # BC7, BT.709, sRGB transfer
    assert (srgb[9], srgb[10]) == (0, 0xFFFFFFFF)
    bc5 = struct.unpack("<15I", block_format_descriptor(FORMATS["bc5"]))
    assert bc5[0] == 60 and bc5[5] == 16  # two samples; 16 bytes per block
    assert bc5[7] == 0 | 63 << 16 and bc5[11] == 64 | 63 << 16 | 1 << 24  # red, then green
    bc1 = struct.unpack("<11I", block_format_descriptor(FORMATS["bc1"]))
    assert bc1[3] == 128 | 1 << 8 | 1 << 16 and bc1[5] == 8  # BC1A, 8 bytes per block
    assert bc1[7] == 0 | 63 << 16 | 1 << 24  # channel 1: BC1A_ALPHAPRESENT (VK ..._RGBA_...)
    bc3 = struct.unpack("<15I", block_format_descriptor(FORMATS["bc3"]))
    assert bc3[7] == 63 << 16 | 15 << 24 and bc3[11] == 64 | 63 << 16  # alpha, then colour


def test_ktx2_zstandard_levels_inflate_to_the_blocks(tmp_path, bc6h_cube):
    path = tmp_path / "z.ktx2"
    write_ktx2_blocks(path, bc6h_cube, supercompression="zstd", zstd_level=3)
    data = path.read_bytes()
    assert u32(data, 44) == 2  # KTX_SS_ZSTD
    inflate = zstandard.ZstdDecompressor()
    for m in range(5):
        offset, length, full = (u64(data, 80 + 24 * m + 8 * i) for i in range(3))
        assert full == len(bc6h_cube.levels[m])
        raw = inflate.decompress(data[offset : offset + length], max_output_size=full)
        assert raw == bc6h_cube.levels[m]
    dfd = struct.unpack_from("<10I", data, u32(data, 48) + 4)
    assert dfd[4] == 16  # bytesPlane0 kept (KTX 2.0, "DFD for Supercompressed Data")
    got, meta = read_ktx2_blocks(path)
    assert got.levels == bc6h_cube.levels and meta["supercompression"] == "zstd"
    assert meta["key_values"]["KTXwriterScParams"] == b"--zcmp 3\x00"


def test_pyktx2_reads_the_descriptor(tmp_path, bc6h_cube, monkeypatch):
    """pyktx2 0.3 cuts images of uncompressed formats only, but its descriptor parser reads
    bakeshop's block descriptors (its ColorModel enum lacks the BC models: pass numbers)."""
    monkeypatch.setattr(pyktx2.parser, "ColorModel", int)
    path = tmp_path / "env.ktx2"
    write_ktx2_blocks(path, bc6h_cube)
    data = path.read_bytes()
    dfd, samples = pyktx2.parser.parse_dfd(data[u32(data, 48) : u32(data, 48) + u32(data, 52)])
    assert dfd.colorModel == 133 and dfd.colorPrimaries.value == 1
    assert dfd.transferFunction.value == 1 and dfd.bytesPlane0 == 16 and len(samples) == 1
    offset, length, kind, position, lower, upper = struct.unpack("<HBBIII", samples[0])
    assert (offset, length, kind, position, lower, upper) == (0, 127, 0x80, 0, 0, 0x3F800000)
    kv = read_ktx2_blocks(path)[1]["key_values"]
    assert list(kv) == sorted(kv) == ["KTXorientation", "KTXwriter"]  # keys in byte order


def test_ktx1_header_matches_the_specification(tmp_path, bc6h_cube):
    path = tmp_path / "env.ktx"
    write_ktx_blocks(path, bc6h_cube)
    data = path.read_bytes()
    assert data[:12] == b"\xabKTX 11\xbb\r\n\x1a\n" and u32(data, 12) == 0x04030201
    # glType 0, glTypeSize 1, glFormat 0 (compressed), RGB_BPTC_UNSIGNED_FLOAT, base GL_RGB
    assert [u32(data, 16 + 4 * i) for i in range(5)] == [0, 1, 0, 0x8E8F, 0x1907]
    assert [u32(data, 36 + 4 * i) for i in range(5)] == [16, 16, 0, 0, 6]
    assert u32(data, 56) == 5
    offset = 64 + u32(data, 60)
    for m in range(5):
        size = blocks_of(16 >> m, bc6h_cube.format)
        assert u32(data, offset) == size  # imageSize: one face of a cube map
        offset += 4
        for face in range(6):
            assert data[offset : offset + size] == bc6h_cube.face(m, face)
            offset += size
    assert offset == len(data)


@pytest.mark.parametrize("suffix", ["dds", "ktx2", "ktx"])
@pytest.mark.parametrize("name", ["bc6h", "bc7-srgb", "bc5"])
def test_readers_return_decoded_float_mips(tmp_path, suffix, name):
    writers = {"dds": write_dds_blocks, "ktx2": write_ktx2_blocks, "ktx": write_ktx_blocks}
    readers = {"dds": read_dds, "ktx2": read_ktx2, "ktx": read_ktx}
    chain = hdr_chain(9, 8) if name == "bc6h" else ldr_chain(9, 8)
    texture = encode_texture(chain, name)
    writers[suffix](tmp_path / f"t.{suffix}", texture)
    mips, meta = readers[suffix](tmp_path / f"t.{suffix}")
    assert meta["cube"] and meta["stored"] == name and len(mips) == 4
    for got, want in zip(mips, texture.decode(), strict=True):
        assert got.dtype == np.float32 and got.shape[0] == 6
        np.testing.assert_array_equal(got, want)


def test_read_environment_of_a_bc6h_cube(tmp_path, bc6h_cube):
    from bakeshop.io import read_environment

    for suffix, write in (("ktx2", write_ktx2_blocks), ("dds", write_dds_blocks)):
        write(tmp_path / f"env.{suffix}", bc6h_cube)
        cube, layout, _ = read_environment(tmp_path / f"env.{suffix}", None)
        assert layout == "cube" and cube.shape == (6, 16, 16, 3) and cube.dtype == np.float32
        np.testing.assert_array_equal(cube, bc6h_cube.decode()[0])


def test_broken_compressed_files_are_refused(tmp_path, bc6h_cube):
    write_dds_blocks(tmp_path / "t.dds", bc6h_cube)
    write_ktx2_blocks(tmp_path / "t.ktx2", bc6h_cube, supercompression="zstd")
    write_ktx_blocks(tmp_path / "t.ktx", bc6h_cube)
    dds = (tmp_path / "t.dds").read_bytes()
    ktx2 = (tmp_path / "t.ktx2").read_bytes()
    ktx = (tmp_path / "t.ktx").read_bytes()
    level0 = u64(ktx2, 80)
    cases = {
        "short.dds": (dds[:-1], read_dds),
        "short.ktx2": (ktx2[:-3], read_ktx2),
        "zstd.ktx2": (ktx2[:level0] + bytes(8) + ktx2[level0 + 8 :], read_ktx2),
        "short.ktx": (ktx[:-1], read_ktx),
        "size.ktx": (
            ktx[: 64 + u32(ktx, 60)] + struct.pack("<I", 7) + ktx[68 + u32(ktx, 60) :],
            read_ktx,
        ),  # fmt: skip
    }
    for name, (content, read) in cases.items():
        (tmp_path / name).write_bytes(content)
        with pytest.raises(FormatError):
            read(tmp_path / name)


def test_block_texture_refuses_wrong_level_sizes():
    with pytest.raises(FormatError):
        BlockTexture(FORMATS["bc7"], 8, 8, False, (bytes(63),))
