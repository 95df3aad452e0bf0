"""Texture arrays and 8-bit unorm samples in KTX2 and DDS (what water flipbooks and two-channel
normal maps are shipped in): header bytes against the Khronos and Microsoft specifications, an
independent KTX2 parser (pyktx2), a real OpenGL driver sampling the layers, round trips and the
refusals that remain."""

import struct

import moderngl
import numpy as np
import pyktx2.parser
import pytest
from pyktx2.parser import VkFormat, parse_bytes

from bakeshop.errors import ArgumentError, UnsupportedError
from bakeshop.io.dds import read_dds, write_dds
from bakeshop.io.ktx2 import read_ktx2, write_ktx2


def u32(data, offset):
    return struct.unpack_from("<I", data, offset)[0]


def u64(data, offset):
    return struct.unpack_from("<Q", data, offset)[0]


def layered_chain(layers, size, channels, levels, seed=0, dtype=np.float32):
    rng = np.random.default_rng(seed)
    out = []
    for m in range(levels):
        s = max(1, size >> m)
        a = rng.random((layers, s, s, channels))
        out.append((a * 255).astype(np.uint8) if dtype == np.uint8 else a.astype(dtype))
    return out


def test_ktx2_array_header_and_level_layout(tmp_path):
    mips = layered_chain(5, 16, 2, 5, dtype=np.uint8)
    path = tmp_path / "a.ktx2"
    write_ktx2(path, mips, dtype="unorm8", array=True)
    data = path.read_bytes()
    assert u32(data, 12) == 16 and u32(data, 16) == 1  # VK_FORMAT_R8G8_UNORM, typeSize 1
    assert (u32(data, 20), u32(data, 24), u32(data, 28)) == (16, 16, 0)  # width, height, depth
    assert (u32(data, 32), u32(data, 36), u32(data, 40)) == (5, 1, 5)  # layers, faces, levels
    for m in range(5):
        s = max(1, 16 >> m)
        offset, length = u64(data, 80 + 24 * m), u64(data, 88 + 24 * m)
        assert length == 5 * s * s * 2 and offset % 4 == 0
        # within a level: layer after layer, rows top to bottom, RG interleaved
        layer3 = np.frombuffer(data, np.uint8, s * s * 2, offset + 3 * s * s * 2)
        np.testing.assert_array_equal(layer3.reshape(s, s, 2), mips[m][3])
    # the format descriptor says unsigned normalised 8-bit samples, 0..255
    dfd_offset = u32(data, 48)
    for c in range(2):
        word = u32(data, dfd_offset + 4 + 24 + 16 * c)
        assert word >> 24 == c  # channel R then G, no signed / float qualifiers
        assert (word >> 16) & 0xFF == 7  # bitLength - 1
        lower, upper = (
            u32(data, dfd_offset + 4 + 24 + 16 * c + 8),
            u32(data, dfd_offset + 40 + 16 * c),
        )
        assert (lower, upper) == (0, 255)


def test_pyktx2_reads_the_array(tmp_path, monkeypatch):
    monkeypatch.setattr(pyktx2.parser, "ColorModel", int)  # see test_ktx2.py
    # pyktx2 0.3 cuts images of RGBA16F files only
    mips = layered_chain(3, 8, 4, 4)
    path = tmp_path / "a.ktx2"
    write_ktx2(path, mips, dtype="float16", array=True)
    ktx = parse_bytes(path.read_bytes())
    assert ktx.vkFormat == VkFormat.VK_FORMAT_R16G16B16A16_SFLOAT
    assert (ktx.pixelWidth, ktx.layerCount, ktx.faceCount, ktx.levelCount) == (8, 3, 1, 4)
    images = iter(ktx.levelImages)
    for level in mips:  # images in level order, layers in order within a level
        for layer in level:
            image = next(images)
            got = np.frombuffer(image.data, "<f2").reshape(image.height, image.width, 4)
            np.testing.assert_array_equal(got, layer.astype(np.float16))


@pytest.mark.parametrize("dtype", ["float16", "float32", "unorm8"])
@pytest.mark.parametrize("channels", [1, 2, 3, 4])
def test_ktx2_array_round_trip(tmp_path, dtype, channels):
    mips = layered_chain(4, 8, channels, 4)
    write_ktx2(tmp_path / "a.ktx2", mips, dtype=dtype, array=True)
    got, meta = read_ktx2(tmp_path / "a.ktx2")
    assert meta["layers"] == 4 and meta["stored"] == dtype and not meta["cube"]
    for a, b in zip(got, mips, strict=True):
        if dtype == "unorm8":
            np.testing.assert_array_equal(a, np.rint(b * 255).astype(np.float32) / 255)
        else:
            np.testing.assert_array_equal(a, b.astype(dtype).astype(np.float32))


def test_ktx2_single_texture_still_reads_without_layers(tmp_path):
    write_ktx2(tmp_path / "t.ktx2", [np.zeros((4, 4, 2), np.float32)])
    got, meta = read_ktx2(tmp_path / "t.ktx2")
    assert got[0].shape == (4, 4, 2) and meta["layers"] == 0


def test_dds_array_header_and_layout(tmp_path):
    mips = layered_chain(3, 8, 2, 4, dtype=np.uint8)
    path = tmp_path / "a.dds"
    write_dds(path, mips, dtype="unorm8", array=True)
    data = path.read_bytes()
    assert data[84:88] == b"DX10"
    assert u32(data, 128) == 49  # DXGI_FORMAT_R8G8_UNORM
    assert (u32(data, 132), u32(data, 136), u32(data, 140)) == (3, 0, 3)  # 2-D, not cube, 3
    assert u32(data, 20) == 8 * 2  # pitch of level 0: bytes per row
    # layer-major, then mips: layer 1 starts after all of layer 0's mips
    per_layer = sum(max(1, 8 >> m) ** 2 * 2 for m in range(4))
    start = 148 + per_layer
    np.testing.assert_array_equal(
        np.frombuffer(data, np.uint8, 8 * 8 * 2, start).reshape(8, 8, 2), mips[0][1]
    )
    assert len(data) == 148 + 3 * per_layer


@pytest.mark.parametrize("dtype", ["float16", "float32", "unorm8"])
@pytest.mark.parametrize("channels", [1, 2, 4])
def test_dds_array_round_trip(tmp_path, dtype, channels):
    mips = layered_chain(3, 8, channels, 4)
    write_dds(tmp_path / "a.dds", mips, dtype=dtype, array=True)
    got, meta = read_dds(tmp_path / "a.dds")
    assert meta["layers"] == 3 and meta["stored"] == dtype
    for a, b in zip(got, mips, strict=True):
        expected = np.rint(b * 255) / 255 if dtype == "unorm8" else b.astype(dtype)
        np.testing.assert_array_equal(a, expected.astype(np.float32))


def test_dds_unorm8_rgb_is_padded_with_opaque_alpha(tmp_path):
    write_dds(tmp_path / "t.dds", [np.full((4, 4, 3), 0.5, np.float32)], dtype="unorm8")
    got, meta = read_dds(tmp_path / "t.dds")
    assert meta["dxgi_format"] == 28
    np.testing.assert_array_equal(got[0][..., :3], np.float32(128) / np.float32(255))
    np.testing.assert_array_equal(got[0][..., 3], 1.0)


def test_array_levels_must_agree(tmp_path):
    with pytest.raises(ArgumentError):
        write_ktx2(
            tmp_path / "a.ktx2", [np.zeros((3, 4, 4, 2)), np.zeros((2, 2, 2, 2))], array=True
        )
    with pytest.raises(ArgumentError):
        write_dds(tmp_path / "a.dds", [np.zeros((4, 4))], array=True)  # no layer axis
    assert not list(tmp_path.iterdir())


def test_cube_arrays_are_refused(tmp_path):
    from tests.io.test_dds import chain

    write_ktx2(tmp_path / "c.ktx2", chain(4, 4, 1))
    data = bytearray((tmp_path / "c.ktx2").read_bytes())
    data[32:36] = struct.pack("<I", 2)
    (tmp_path / "c.ktx2").write_bytes(bytes(data))
    with pytest.raises(UnsupportedError):
        read_ktx2(tmp_path / "c.ktx2")


def test_opengl_samples_each_layer_as_written(tmp_path):
    """The bytes of each layer, cut from the file by the KTX2 level index, uploaded to a
    GL_TEXTURE_2D_ARRAY and fetched by a shader with texelFetch, are the layers we wrote."""
    layers, size = 4, 8
    mips = layered_chain(layers, size, 2, 1, dtype=np.uint8)
    path = tmp_path / "a.ktx2"
    write_ktx2(path, mips, dtype="unorm8", array=True)
    data = path.read_bytes()
    offset, length = u64(data, 80), u64(data, 88)
    ctx = moderngl.create_context(standalone=True, backend="egl")
    ctx.simple_framebuffer((1, 1)).use()  # a standalone context has no default framebuffer
    try:
        tex = ctx.texture_array((size, size, layers), 2, data[offset : offset + length])
        tex.filter = (moderngl.NEAREST, moderngl.NEAREST)
        tex.use(0)
        prog = ctx.program(
            vertex_shader="""
            #version 330
            uniform sampler2DArray tex;
            in ivec3 where;
            out vec2 value;
            void main() { value = texelFetch(tex, where, 0).rg; }
            """,
            varyings=["value"],
        )
        axes = np.meshgrid(np.arange(size), np.arange(size), np.arange(layers), indexing="ij")
        where = np.stack(axes, -1).reshape(-1, 3).astype(np.int32)
        vbo = ctx.buffer(where.tobytes())
        out = ctx.buffer(reserve=len(where) * 8)
        ctx.vertex_array(prog, [(vbo, "3i", "where")]).transform(out, moderngl.POINTS)
        got = np.frombuffer(out.read(), np.float32).reshape(-1, 2)
        expected = mips[0][where[:, 2], where[:, 1], where[:, 0]] / 255.0
        np.testing.assert_allclose(got, expected, atol=1e-6)
    finally:
        ctx.release()
