"""The transferred map against a real OpenGL driver (moderngl over EGL; llvmpipe without a GPU).

A mesh is drawn in its macro UV space, so each fragment is one texel of the macro map. The
fragment shader reconstructs the world normal twice, as an engine does: from the detail
sampled through the second UV set with that set's tangent frame, and from bakeshop's
transferred map with the macro frame (normalize(m.x T + m.y B + m.z N), B = sign N x T, the
interpolated vectors left unnormalised, as MikkTSpace prescribes). The driver rasterises,
interpolates and filters; the two must agree wherever a triangle covers the texel. This test
must run in CI: `make sysdeps` installs libEGL and Mesa.
"""

import moderngl
import numpy as np
import pytest

from bakeshop.io.mesh import Mesh
from bakeshop.normals.transfer import corner_tangents, transfer_detail
from tests.normals.test_transfer import cylinder, wave_detail
from tests.tolerances import TRANSFER_GL_DEG

VERTEX = """
#version 330
in vec2 in_uv;
in vec3 in_n;
in vec4 in_t;
in vec2 in_uv2;
in vec4 in_t2;
out vec3 n;
out vec4 t;
out vec2 uv2;
out vec4 t2;
void main() {
    gl_Position = vec4(in_uv * 2.0 - 1.0, 0.0, 1.0);
    n = in_n; t = in_t; uv2 = in_uv2; t2 = in_t2;
}
"""

FRAGMENT = """
#version 330
uniform sampler2D detail;
uniform sampler2D baked;
in vec3 n;
in vec4 t;
in vec2 uv2;
in vec4 t2;
layout(location = 0) out vec4 engine;
layout(location = 1) out vec4 ours;
void main() {
    vec3 d = normalize(texture(detail, uv2).xyz);
    vec3 b2 = t2.w * cross(n, t2.xyz);
    engine = vec4(normalize(d.x * t2.xyz + d.y * b2 + d.z * n), 1.0);
    vec3 m = texelFetch(baked, ivec2(gl_FragCoord.xy), 0).xyz;
    vec3 b = t.w * cross(n, t.xyz);
    ours = vec4(normalize(m.x * t.xyz + m.y * b + m.z * n), 1.0);
}
"""


@pytest.fixture(scope="module")
def ctx():
    context = moderngl.create_context(standalone=True, backend="egl")
    yield context
    context.release()


def float_texture(ctx, image):
    """An RGBA32F texture of an (H, W, 3) image whose row 0 is the top (GL's row 0 is the
    bottom, t = 0: the rows are flipped on upload, so t runs up like v)."""
    h, w = image.shape[:2]
    rgba = np.ones((h, w, 4), np.float32)
    rgba[..., :3] = image[::-1]
    return ctx.texture((w, h), 4, rgba.tobytes(), dtype="f4")


def curved_mesh():
    """A cylinder whose second UV set is scaled, rotated by 30 degrees and jittered, so its
    tangent frame differs from the macro one everywhere."""
    c = cylinder(segments=32)
    th = np.radians(30)
    uv2 = c.uv * (3, 2) @ np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
    uv2 += np.random.default_rng(0).normal(scale=0.01, size=uv2.shape)
    return Mesh(c.positions, c.faces, c.normals, c.uv, uv2)


def test_transferred_map_decodes_in_opengl_to_the_detail_through_uv2(ctx):
    size = 256
    mesh = curved_mesh()
    detail = wave_detail(64)  # footprint < 1 detail texel per macro texel: no mip level
    baked, covered = transfer_detail(mesh, detail, (size, size), projection="uv2", padding=0)

    frame = corner_tangents(mesh.positions, mesh.normals, mesh.uv, mesh.faces)
    frame2 = corner_tangents(mesh.positions, mesh.normals, mesh.uv2, mesh.faces)
    corners = mesh.faces.reshape(-1)
    vertices = np.concatenate(
        [
            mesh.uv[corners],
            mesh.normals[corners],
            frame.reshape(-1, 4),
            mesh.uv2[corners],
            frame2.reshape(-1, 4),
        ],
        axis=1,
    ).astype(np.float32)
    prog = ctx.program(vertex_shader=VERTEX, fragment_shader=FRAGMENT)
    vbo = ctx.buffer(vertices.tobytes())
    vao = ctx.vertex_array(
        prog, [(vbo, "2f 3f 4f 2f 4f", "in_uv", "in_n", "in_t", "in_uv2", "in_t2")]
    )
    tex_detail = float_texture(ctx, detail)
    tex_detail.filter = (moderngl.LINEAR, moderngl.LINEAR)
    tex_detail.repeat_x = tex_detail.repeat_y = True
    tex_baked = float_texture(ctx, baked)
    tex_baked.filter = (moderngl.NEAREST, moderngl.NEAREST)
    tex_detail.use(0)
    tex_baked.use(1)
    prog["detail"].value = 0
    prog["baked"].value = 1
    targets = [ctx.texture((size, size), 4, dtype="f4") for _ in range(2)]
    fbo = ctx.framebuffer(color_attachments=targets)
    fbo.use()
    fbo.clear(0.0, 0.0, 0.0, 0.0)
    vao.render(moderngl.TRIANGLES)
    engine, ours = (
        np.frombuffer(fbo.read(components=4, dtype="f4", attachment=k), np.float32).reshape(
            size, size, 4
        )[::-1]
        for k in range(2)
    )
    for obj in (vao, vbo, prog, tex_detail, tex_baked, fbo, *targets):
        obj.release()

    drawn = (engine[..., 3] == 1) & covered
    assert drawn.mean() > 0.95
    cos = np.clip(np.sum(engine[..., :3] * ours[..., :3], axis=-1), -1, 1)
    angle = np.degrees(np.arccos(cos))[drawn]
    # the detail is not flat: the comparison sees the rotation between the two frames
    tilt = np.degrees(np.arccos(np.clip(detail[..., 2], -1, 1)))
    assert tilt.max() > 15
    assert angle.max() < TRANSFER_GL_DEG
