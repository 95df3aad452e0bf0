"""Compressed cube maps sampled by a real OpenGL driver (moderngl over EGL, Mesa's llvmpipe).

The blocks are cut out of bakeshop's KTX2 and DDS files by the specifications' layouts (level
index, face-major DDS payload), uploaded face by face and level by level with
glCompressedTexImage2D (moderngl has no compressed upload, so the GL entry points are called
through ctypes on moderngl's context), and sampled at the centre of every texel of the six
faces of every level with textureLod; the driver's values must be bakeshop's decoder's.
llvmpipe decodes BPTC (BC6H, BC7), RGTC (BC4, BC5) and S3TC (BC1, BC3).
"""

import ctypes
import struct

import moderngl
import numpy as np
import pytest

from bakeshop.io.compress.formats import FORMATS
from bakeshop.io.compress.texture import encode_texture
from bakeshop.io.dds import write_dds_blocks
from bakeshop.io.ktx2 import write_ktx2_blocks
from bakeshop.sphere import layout
from tests.io.compress.conftest import hdr_chain, ldr_chain
from tests.io.compress.tolerances import BPTC_EXACT, LLVMPIPE_S3TC, SRGB_TABLE, UNORM8_FLOAT

GL_TEXTURE_CUBE_MAP, GL_TEXTURE_CUBE_MAP_POSITIVE_X, GL_TEXTURE0 = 0x8513, 0x8515, 0x84C0
GL_TEXTURE_MIN_FILTER, GL_TEXTURE_MAG_FILTER, GL_TEXTURE_MAX_LEVEL = 0x2801, 0x2800, 0x813D
GL_NEAREST_MIPMAP_NEAREST, GL_NEAREST = 0x2700, 0x2600

SHADER = """
#version 330
uniform samplerCube tex;
in vec4 dirlod;
out vec4 value;
void main() { value = textureLod(tex, dirlod.xyz, dirlod.w); }
"""


class GL:
    """The few GL 1.x-4.x entry points moderngl does not expose, looked up through EGL."""

    def __init__(self):
        egl = ctypes.CDLL("libEGL.so.1")
        egl.eglGetProcAddress.restype = ctypes.c_void_p
        egl.eglGetProcAddress.argtypes = [ctypes.c_char_p]
        u, i = ctypes.c_uint, ctypes.c_int

        def fn(name, restype, *args):
            return ctypes.CFUNCTYPE(restype, *args)(egl.eglGetProcAddress(name.encode()))

        self.gen = fn("glGenTextures", None, i, ctypes.POINTER(u))
        self.delete = fn("glDeleteTextures", None, i, ctypes.POINTER(u))
        self.bind = fn("glBindTexture", None, u, u)
        self.active = fn("glActiveTexture", None, u)
        self.image = fn("glCompressedTexImage2D", None, u, i, u, i, i, i, i, ctypes.c_void_p)
        self.parameter = fn("glTexParameteri", None, u, u, i)
        self.error = fn("glGetError", u)


@pytest.fixture(scope="module")
def gl():
    ctx = moderngl.create_context(standalone=True, backend="egl")
    fbo = ctx.simple_framebuffer((1, 1))
    fbo.use()
    prog = ctx.program(vertex_shader=SHADER, varyings=["value"])
    yield ctx, prog, GL()
    ctx.release()


def sample_cube(gl, internal_format, face_blocks, size):
    """Upload ``face_blocks[level][face]`` (bytes) as a compressed cube map and return the
    driver's texel values, ``(6, S_m, S_m, 4)`` per level, at every texel centre."""
    ctx, prog, api = gl
    name = ctypes.c_uint()
    api.gen(1, ctypes.byref(name))
    api.active(GL_TEXTURE0)
    api.bind(GL_TEXTURE_CUBE_MAP, name.value)
    keep = []
    for m, faces in enumerate(face_blocks):
        s = max(1, size >> m)
        for f, data in enumerate(faces):
            buf = ctypes.create_string_buffer(data, len(data))
            keep.append(buf)
            api.image(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f, m, internal_format, s, s, 0, len(data),
                      ctypes.cast(buf, ctypes.c_void_p))  # fmt: skip
    api.parameter(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST)
    api.parameter(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_NEAREST)
    api.parameter(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAX_LEVEL, len(face_blocks) - 1)
    assert api.error() == 0
    if "tex" in prog:
        prog["tex"].value = 0
    out = []
    for m in range(len(face_blocks)):
        s = max(1, size >> m)
        d, _ = layout("cube").directions((6, s, s))
        dirlod = np.concatenate([d.reshape(-1, 3), np.full((6 * s * s, 1), m)], 1)
        vbo = ctx.buffer(dirlod.astype(np.float32).tobytes())
        res = ctx.buffer(reserve=6 * s * s * 16)
        vao = ctx.vertex_array(prog, [(vbo, "4f", "dirlod")])
        api.active(GL_TEXTURE0)
        api.bind(GL_TEXTURE_CUBE_MAP, name.value)
        vao.transform(res, moderngl.POINTS, vertices=6 * s * s)
        out.append(np.frombuffer(res.read(), np.float32).reshape(6, s, s, 4).copy())
        for obj in (vao, res, vbo):
            obj.release()
    api.delete(1, ctypes.byref(name))
    return out


def ktx2_faces(path):
    """``[level][face]`` block bytes cut out of a KTX2 file by its level index."""
    data = path.read_bytes()
    levels = struct.unpack_from("<I", data, 40)[0]
    out = []
    for m in range(levels):
        offset, length = struct.unpack_from("<2Q", data, 80 + 24 * m)
        n = length // 6
        out.append([data[offset + f * n : offset + (f + 1) * n] for f in range(6)])
    return out


def dds_faces(path, fmt, size, levels):
    """``[level][face]`` block bytes of a DDS cube map: each face's chain, then the next."""
    data = path.read_bytes()
    sizes = [((max(1, size >> m) + 3) // 4) ** 2 * fmt.block_bytes for m in range(levels)]
    out = [[None] * 6 for _ in range(levels)]
    offset = 148
    for f in range(6):
        for m in range(levels):
            out[m][f] = data[offset : offset + sizes[m]]
            offset += sizes[m]
    assert offset == len(data)
    return out


CASES = [
    ("bc6h", BPTC_EXACT),
    ("bc6h-signed", BPTC_EXACT),
    ("bc7", UNORM8_FLOAT),
    ("bc7-srgb", SRGB_TABLE),
    ("bc5", LLVMPIPE_S3TC),
    ("bc4", LLVMPIPE_S3TC),
    ("bc3", LLVMPIPE_S3TC),
    ("bc1", LLVMPIPE_S3TC),
]


@pytest.mark.parametrize("name,tolerance", CASES)
@pytest.mark.parametrize("container", ["ktx2", "dds"])
def test_driver_samples_the_decoded_texels(gl, tmp_path, name, tolerance, container):
    fmt = FORMATS[name]
    size = 16  # levels 16, 8, 4, 2, 1: the last two are padded blocks
    chain = hdr_chain(11, size) if fmt.hdr else ldr_chain(12, size)
    if name == "bc6h-signed":
        chain = [level * np.where(np.arange(level.shape[2]) % 3, 1, -1)[:, None] for level in chain]
    texture = encode_texture(chain, name)
    path = tmp_path / f"env.{container}"
    if container == "ktx2":
        write_ktx2_blocks(path, texture)
        blocks = ktx2_faces(path)
    else:
        write_dds_blocks(path, texture)
        blocks = dds_faces(path, fmt, size, len(chain))
    got = sample_cube(gl, fmt.gl, blocks, size)
    want = texture.decode()
    assert len(got) == len(want) == 5
    for m, (g, w) in enumerate(zip(got, want, strict=True)):
        assert g.shape[:3] == w.shape[:3] == (6, size >> m, size >> m)
        c = w.shape[-1]
        np.testing.assert_allclose(g[..., :c], w, rtol=0, atol=tolerance, err_msg=f"level {m}")
