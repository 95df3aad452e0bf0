"""KTX 1.1 cube maps and 2-D textures: header bytes against the Khronos specification, round
trips, row padding, and broken files."""

import struct

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bakeshop.errors import ArgumentError, FormatError, UnsupportedError
from bakeshop.io.ktx import read_ktx, write_ktx
from tests.io import fuzzing
from tests.io.test_dds import chain, mip_seeds, u32

#: The file identifier, byte for byte from the KTX 1.1 specification (section 3.1).
KTX_MAGIC = bytes([0xAB, 0x4B, 0x54, 0x58, 0x20, 0x31, 0x31, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A])


def test_cube_header_matches_the_specification(tmp_path):
    mips = chain(16, 4, 5)
    path = tmp_path / "env.ktx"
    write_ktx(path, mips, dtype="float16")
    data = path.read_bytes()
    assert data[:12] == KTX_MAGIC
    assert u32(data, 12) == 0x04030201
    assert u32(data, 16) == 0x140B and u32(data, 20) == 2  # GL_HALF_FLOAT, 2 bytes
    assert u32(data, 24) == 0x1908 and u32(data, 28) == 0x881A  # GL_RGBA, GL_RGBA16F
    assert u32(data, 32) == 0x1908
    assert (u32(data, 36), u32(data, 40), u32(data, 44)) == (16, 16, 0)
    assert u32(data, 48) == 0 and u32(data, 52) == 6 and u32(data, 56) == 5
    kv = u32(data, 60)
    assert kv % 4 == 0 and b"KTXorientation\x00S=r,T=d\x00" in data[64 : 64 + kv]
    offset = 64 + kv
    assert u32(data, offset) == 16 * 16 * 8  # imageSize of one face of level 0
    face1 = np.frombuffer(data, "<f2", 16 * 16 * 4, offset + 4 + 16 * 16 * 8)
    np.testing.assert_array_equal(face1.reshape(16, 16, 4), mips[0][1].astype(np.float16))
    total = 64 + kv + sum(4 + 6 * max(1, 16 >> m) ** 2 * 8 for m in range(5))
    assert len(data) == total


def test_rows_are_padded_to_four_bytes(tmp_path):
    # An RGB half texel is 6 bytes: rows of odd width need 2 bytes of padding (GL_UNPACK_ALIGNMENT).
    mips = chain(3, 3, 2, cube=False)
    write_ktx(tmp_path / "t.ktx", mips, dtype="float16")
    data = (tmp_path / "t.ktx").read_bytes()
    offset = 64 + u32(data, 60)
    assert u32(data, offset) == 3 * 20  # rows of 18 bytes padded to 20
    got, meta = read_ktx(tmp_path / "t.ktx")
    assert meta["gl_internal_format"] == 0x881B and not meta["cube"]
    for a, b in zip(got, mips, strict=True):
        np.testing.assert_array_equal(a, b.astype(np.float16).astype(np.float32))


@pytest.mark.parametrize("dtype", ["float16", "float32"])
@pytest.mark.parametrize("channels", [1, 2, 3, 4])
@pytest.mark.parametrize("cube", [True, False])
def test_round_trip(tmp_path, dtype, channels, cube):
    mips = chain(8, channels, 4, cube=cube)
    write_ktx(tmp_path / "t.ktx", mips, dtype=dtype)
    got, meta = read_ktx(tmp_path / "t.ktx")
    assert meta["cube"] is cube and meta["stored"] == dtype
    assert meta["key_values"] == {"KTXorientation": b"S=r,T=d\x00"}
    for a, b in zip(got, mips, strict=True):
        np.testing.assert_array_equal(a, b.astype(dtype).astype(np.float32))


def test_big_endian_files_are_read(tmp_path):
    mips = chain(4, 4, 3)
    write_ktx(tmp_path / "t.ktx", mips, dtype="float32")
    data = (tmp_path / "t.ktx").read_bytes()
    fields = struct.unpack_from("<13I", data, 12)
    kv = fields[-1]
    out = bytearray(data[:12] + struct.pack(">13I", *fields))
    out += struct.pack(">I", u32(data, 64)) + data[68 : 64 + kv]
    offset = 64 + kv
    for _ in range(3):
        size = u32(data, offset)
        out += struct.pack(">I", size)
        out += np.frombuffer(data, "<f4", 6 * size // 4, offset + 4).astype(">f4").tobytes()
        offset += 4 + 6 * size
    (tmp_path / "be.ktx").write_bytes(bytes(out))
    got, _ = read_ktx(tmp_path / "be.ktx")
    for a, b in zip(got, mips, strict=True):
        np.testing.assert_array_equal(a, b)


def test_bad_chain_is_refused(tmp_path):
    with pytest.raises(ArgumentError):
        write_ktx(tmp_path / "t.ktx", [np.zeros((6, 4, 4, 4)), np.zeros((6, 1, 1, 4))])
    with pytest.raises(ArgumentError):
        write_ktx(tmp_path / "t.ktx", [np.zeros((4, 4, 4))], dtype="float64")
    assert not list(tmp_path.iterdir())


def test_broken_files(tmp_path):
    write_ktx(tmp_path / "t.ktx", chain(8, 4, 4))
    data = (tmp_path / "t.ktx").read_bytes()
    cases = {
        "short.ktx": (data[:40], FormatError),
        "truncated.ktx": (data[:-2], FormatError),
        "magic.ktx": (b"\x00" + data[1:], FormatError),
        "endian.ktx": (data[:12] + b"\x00\x00\x00\x00" + data[16:], FormatError),
        "huge.ktx": (data[:36] + struct.pack("<2I", 1 << 20, 1 << 20) + data[44:], FormatError),
        "rgba8.ktx": (data[:28] + struct.pack("<I", 0x8058) + data[32:], UnsupportedError),
        "bc6h.ktx": (data[:28] + struct.pack("<I", 0x8E8F) + data[32:], FormatError),
        "faces.ktx": (data[:52] + struct.pack("<I", 5) + data[56:], FormatError),
        "kv.ktx": (data[:60] + struct.pack("<I", 1 << 30) + data[64:], FormatError),
    }
    for name, (content, error) in cases.items():
        (tmp_path / name).write_bytes(content)
        with pytest.raises(error):
            read_ktx(tmp_path / name)


# --- fuzzing: only BakeshopError may escape -------------------------------------------------------


def levels(path):
    return read_ktx(path)[0]


@pytest.fixture(scope="module")
def seed_files(tmp_path_factory):
    return mip_seeds(write_ktx, tmp_path_factory.mktemp("ktx_seeds") / "s.ktx")


scratch = fuzzing.scratch_file("f.ktx")


@pytest.mark.slow
def test_truncation_at_every_offset_is_refused(scratch, seed_files):
    for data in seed_files:
        fuzzing.assert_truncations_refused(scratch, data, read=levels)
    fuzzing.assert_refused(scratch, seed_files[0][:40], "KTX", read=levels)


@fuzzing.FUZZ
@given(st.binary(max_size=300))
def test_random_bytes(scratch, data):
    fuzzing.decode(scratch, data, levels)
    fuzzing.decode(scratch, KTX_MAGIC + data, levels)


@fuzzing.FUZZ
@given(st.integers(0, 1), fuzzing.edits(100), st.integers(1, 1200))
def test_mutations_of_valid_files(scratch, seed_files, which, changes, end):
    fuzzing.decode(scratch, fuzzing.mutate(seed_files[which], changes, end), levels)


# --- a real OpenGL driver reads what was written -----------------------------------------------

GL_LOOKUP = """
#version 330
uniform samplerCube env;
uniform sampler2D dirs;
out vec4 colour;
void main() {
    vec3 d = texelFetch(dirs, ivec2(gl_FragCoord.xy), 0).xyz;
    colour = texture(env, d);
}
"""
FULL_SCREEN = """
#version 330
in vec2 p;
void main() { gl_Position = vec4(p, 0.0, 1.0); }
"""


def direction_chain(size, levels):
    """Cube levels whose texels hold their own direction (RGB) and level index (A)."""
    from bakeshop.sphere import layout

    chain = []
    for m in range(levels):
        s = max(1, size >> m)
        d, _ = layout("cube").directions((6, s, s))
        chain.append(np.concatenate([d, np.full(d.shape[:-1] + (1,), m)], -1).astype(np.float32))
    return chain


def opengl_lookup(face_bytes, size, dtype):
    """Upload each level's six faces (raw bytes as stored in a file, face +X first) to its own
    GL cube map and look every texel-centre direction up through the driver's cube sampling.

    Returns, per level, the (6, s, s, 4) values OpenGL returns at the texel-centre directions.
    """
    import moderngl

    from bakeshop.sphere import layout

    ctx = moderngl.create_context(standalone=True, backend="egl")
    try:
        prog = ctx.program(vertex_shader=FULL_SCREEN, fragment_shader=GL_LOOKUP)
        quad = ctx.buffer(np.array([-1, -1, 3, -1, -1, 3], np.float32).tobytes())
        vao = ctx.vertex_array(prog, [(quad, "2f", "p")])
        out = []
        for m, faces in enumerate(face_bytes):
            s = max(1, size >> m)
            env = ctx.texture_cube((s, s), 4, dtype=dtype)
            for face, data in enumerate(faces):
                env.write(face, data)
            env.filter = (moderngl.NEAREST, moderngl.NEAREST)
            d, _ = layout("cube").directions((6, s, s))
            rows = d.reshape(6 * s, s, 3).astype(np.float32)
            dirs = ctx.texture((s, 6 * s), 3, rows.tobytes(), dtype="f4")
            dirs.filter = (moderngl.NEAREST, moderngl.NEAREST)
            target = ctx.texture((s, 6 * s), 4, dtype="f4")
            fbo = ctx.framebuffer([target])
            fbo.use()
            env.use(0)
            dirs.use(1)
            prog["env"], prog["dirs"] = 0, 1
            vao.render(moderngl.TRIANGLES, 3)
            got = np.frombuffer(fbo.read(components=4, dtype="f4"), np.float32)
            out.append(got.reshape(6, s, s, 4))
            for obj in (env, dirs, target, fbo):
                obj.release()
        return out
    finally:
        ctx.release()


def test_opengl_finds_every_texel_where_its_direction_points(tmp_path):
    # The file's bytes, cut by the KTX specification's layout (not by read_ktx), are uploaded
    # face by face; OpenGL's own cube lookup of each texel's direction must return that texel.
    size, levels = 8, 4
    path = tmp_path / "env.ktx"
    write_ktx(path, direction_chain(size, levels), dtype="float32")
    data = path.read_bytes()
    offset = 64 + u32(data, 60)
    face_bytes = []
    for _ in range(levels):
        n = u32(data, offset)
        face_bytes.append([data[offset + 4 + f * n : offset + 4 + (f + 1) * n] for f in range(6)])
        offset += 4 + 6 * n
    for m, got in enumerate(opengl_lookup(face_bytes, size, "f4")):
        np.testing.assert_array_equal(got, direction_chain(size, levels)[m])


def big_endian(data: bytes) -> bytes:
    """A little-endian KTX 1 file (one key/value entry, as bakeshop writes it) in big-endian
    order: every field swapped, and every sample per glTypeSize (blocks, size 1, as they are)."""
    fields = struct.unpack_from("<13I", data, 12)
    type_size, faces, levels, kv = fields[2], fields[10], fields[11], fields[12]
    out = bytearray(data[:12] + struct.pack(">13I", *fields))
    out += struct.pack(">I", u32(data, 64)) + data[68 : 64 + kv]
    offset = 64 + kv
    sample = {1: "u1", 2: "u2", 4: "u4"}[type_size]
    for _ in range(max(levels, 1)):
        size = u32(data, offset)
        out += struct.pack(">I", size)
        values = np.frombuffer(data, "<" + sample, faces * size // type_size, offset + 4)
        out += values.astype(">" + sample).tobytes()
        offset += 4 + faces * size
    return bytes(out)


def test_big_endian_half_and_block_files_read_as_the_little_endian_ones(tmp_path):
    from bakeshop.io.compress.texture import encode_texture
    from bakeshop.io.ktx import write_ktx_blocks

    write_ktx(tmp_path / "h.ktx", chain(8, 3, 4), dtype="float16")
    write_ktx_blocks(tmp_path / "b.ktx", encode_texture(chain(8, 3, 4), "bc6h"))
    for name in ("h.ktx", "b.ktx"):
        (tmp_path / f"be_{name}").write_bytes(big_endian((tmp_path / name).read_bytes()))
        little, _ = read_ktx(tmp_path / name)
        big, _ = read_ktx(tmp_path / f"be_{name}")
        for a, b in zip(big, little, strict=True):
            np.testing.assert_array_equal(a, b)


def test_a_compressed_file_with_another_type_size_is_refused(tmp_path):
    from bakeshop.io.compress.texture import encode_texture
    from bakeshop.io.ktx import write_ktx_blocks

    write_ktx_blocks(tmp_path / "b.ktx", encode_texture(chain(8, 3, 1), "bc6h"))
    data = bytearray((tmp_path / "b.ktx").read_bytes())
    struct.pack_into("<I", data, 20, 2)  # glTypeSize 2: swapping 2-byte units would be wrong
    (tmp_path / "b.ktx").write_bytes(bytes(data))
    with pytest.raises(FormatError, match="glTypeSize 1"):
        read_ktx(tmp_path / "b.ktx")
