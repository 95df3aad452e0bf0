"""Cube maps against a real OpenGL driver (moderngl over EGL; Mesa's llvmpipe without a GPU).

bakeshop's cube faces are uploaded in order to GL_TEXTURE_CUBE_MAP_POSITIVE_X + i and sampled
in a shader at thousands of random directions (transform feedback); the driver's values must be
bakeshop's own lookups. This test must run in CI: `make sysdeps` installs libEGL and Mesa.
"""

import moderngl
import numpy as np
import pytest

from bakeshop.sphere import cube_to_faces, layout, remap, sample
from tests.tolerances import SPHERE_GL_LINEAR_ATOL, SPHERE_GL_PANORAMA_ATOL

SEAMLESS = 0x884F  # GL_TEXTURE_CUBE_MAP_SEAMLESS

SHADER = """
#version 330
uniform samplerCube tex;
uniform vec3 flip;
in vec3 dir;
out vec4 value;
void main() { value = textureLod(tex, dir * flip, 0.0); }
"""


@pytest.fixture(scope="module")
def gl():
    ctx = moderngl.create_context(standalone=True, backend="egl")
    # a standalone context has no default framebuffer: bind one for the draw call
    fbo = ctx.simple_framebuffer((1, 1))
    fbo.use()
    prog = ctx.program(vertex_shader=SHADER, varyings=["value"])
    yield ctx, prog
    ctx.release()


def gl_sample(gl, faces, dirs, *, linear=False, flip=(1.0, 1.0, 1.0)):
    """Sample a (6, S, S, C) cube uploaded face by face, rows in order, at directions."""
    ctx, prog = gl
    s, c = faces.shape[1], faces.shape[3]
    rgba = np.zeros((6, s, s, 4), np.float32)
    rgba[..., :c] = faces
    tex = ctx.texture_cube((s, s), 4, rgba.tobytes(), dtype="f4")
    f = moderngl.LINEAR if linear else moderngl.NEAREST
    tex.filter = (f, f)
    tex.use(0)
    if "tex" in prog:
        prog["tex"].value = 0
    prog["flip"].value = flip
    if linear:
        ctx.enable_direct(SEAMLESS)
    vbo = ctx.buffer(np.ascontiguousarray(dirs, np.float32).tobytes())
    out = ctx.buffer(reserve=len(dirs) * 16)
    vao = ctx.vertex_array(prog, [(vbo, "3f", "dir")])
    vao.transform(out, moderngl.POINTS, vertices=len(dirs))
    result = np.frombuffer(out.read(), np.float32).reshape(-1, 4)[:, :c].copy()
    for obj in (vao, out, vbo, tex):
        obj.release()
    if linear:
        ctx.disable_direct(SEAMLESS)
    return result


def random_directions(n, seed=0):
    d = np.random.default_rng(seed).normal(size=(n, 3))
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def unambiguous(d, s, margin=1e-3):
    """Directions not within ``margin`` texel of a texel edge or a face edge (where float32 in
    the driver may pick the neighbour)."""
    c = layout("cube").coordinates(d.astype(np.float32).astype(np.float64), (6, s, s))
    frac = c[:, 1:] % 1
    ad = np.sort(np.abs(d), axis=1)
    return (np.abs(frac - 0.5) < 0.5 - margin).all(axis=1) & (ad[:, 2] - ad[:, 1] > 1e-5)


def smooth(d):
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    return np.stack([1 + 0.5 * x + 0.3 * y - 0.2 * z + 0.4 * x * y, np.exp(z), 1 + y * y], -1)


@pytest.mark.parametrize("convention", ["opengl", "vulkan"])
def test_driver_finds_each_texel_where_bakeshop_put_it(gl, convention):
    """Random texel values: NEAREST lookups in the driver are bakeshop's texels, exactly."""
    s = 16
    cube = np.random.default_rng(1).random((6, s, s, 3)).astype(np.float32)
    faces = cube_to_faces(cube, convention=convention)
    d = random_directions(20000)
    ok = unambiguous(d, s)
    assert ok.sum() > 19000
    driver = gl_sample(gl, faces, d)
    ours = sample(cube, "cube", d, filter="nearest")
    np.testing.assert_array_equal(driver[ok], ours[ok])


@pytest.mark.parametrize("convention", ["opengl", "vulkan"])
def test_driver_sees_the_source_panorama(gl, convention):
    """A latlong converted to a cube and sampled by the driver shows the latlong's world: the
    driver's value at d is bakeshop's lookup of the source panorama at d, to the nearest
    filter's half-texel bound."""
    src_dirs, _ = layout("latlong").directions((256, 512))
    pano = smooth(src_dirs).astype(np.float32)
    cube = remap(pano, "latlong", "cube", 128)
    d = random_directions(20000, seed=2)
    driver = gl_sample(gl, cube_to_faces(cube, convention=convention), d)
    ours = sample(pano, "latlong", d)
    assert np.abs(driver - ours).max() < SPHERE_GL_PANORAMA_ATOL
    # a mirrored or rotated face would be off by the function's range (about 2), not 0.03


def test_seamless_linear_filtering_matches_the_driver(gl):
    """With GL_TEXTURE_CUBE_MAP_SEAMLESS, the driver's LINEAR filter blends across face edges
    and corners as bakeshop's bilinear does (the texel across the edge at the same place along
    it; at a corner the mean of three)."""
    s = 8
    cube = np.random.default_rng(3).random((6, s, s, 3)).astype(np.float32)
    d = random_directions(20000, seed=4)
    driver = gl_sample(gl, cube, d, linear=True)
    ours = sample(cube, "cube", d, filter="bilinear")
    assert np.abs(driver - ours).max() < SPHERE_GL_LINEAR_ATOL


def test_directx_faces_are_the_gl_cube_of_the_mirrored_world(gl):
    """The directx face set is the GL cube of the z-mirrored world: equal to remapping with the
    mirror diag(1, 1, -1), and a driver sampling it with left-handed vectors (x, y, -z), as
    Direct3D does, sees our world."""
    src_dirs, _ = layout("latlong").directions((128, 256))
    rng = np.random.default_rng(5)
    pano = (smooth(src_dirs) + 0 * rng.random((128, 256, 1))).astype(np.float32)
    cube = remap(pano, "latlong", "cube", 32)
    dx = cube_to_faces(cube, convention="directx")
    mirrored = remap(pano, "latlong", "cube", 32, rotation=np.diag([1.0, 1.0, -1.0]))
    np.testing.assert_allclose(dx, mirrored, atol=1e-5)
    d = random_directions(20000, seed=6)
    ok = unambiguous(d * [1, 1, -1], 32)
    driver = gl_sample(gl, dx, d, flip=(1.0, 1.0, -1.0))
    np.testing.assert_array_equal(driver[ok], sample(cube, "cube", d, filter="nearest")[ok])
