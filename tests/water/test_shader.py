"""The reference water shader in a real OpenGL driver (moderngl over EGL, Mesa's llvmpipe),
driven by the files bakeshop writes: the normals it decodes from a BC5-ready KTX2 texture
array are the ocean's own (brute-force sums at the same world points and times), the loop and
the tiling close, its refracted underwater path obeys Fermat's principle, and its ripples are
the analytic ring."""

import math
import struct

import numpy as np
import pytest

from bakeshop.io.ktx2 import write_ktx2
from bakeshop.water import murk
from bakeshop.water.ocean import evaluate, ocean, ocean_fields
from bakeshop.water.ripples import drop_crater, rain_atlas, ring, ring_lut
from bakeshop.water.shader import WaterScene, look_at, orthographic_down, render_water
from bakeshop.water.spectra import Spectrum
from bakeshop.water.textures import angle_between, pack_normals
from tests.water.tolerances import (
    SHADER_NORMAL_DEG,
    SHADER_PATH_RTOL,
    SHADER_RIPPLE_RTOL,
)


@pytest.fixture(scope="module")
def sea(tmp_path_factory):
    """A looping ocean written as a BC5-ready (two-channel unorm8) KTX2 array, and the layers
    cut from the file by its level index (the specification's layout, not read_ktx2)."""
    o = ocean(Spectrum("jonswap", wind_speed=7.0, fetch=30e3, wind_direction=35.0),
              size=40.0, resolution=64, seed=9, loop_period=6.0)  # fmt: skip
    frames = o.minimum_frames()
    normals = ocean_fields(o, frames=frames, fields=("normal",), choppiness=0.4)["normal"]
    path = tmp_path_factory.mktemp("sea") / "ocean_normal.ktx2"
    write_ktx2(path, [pack_normals(normals, channels="xy")], dtype="unorm8", array=True)
    data = path.read_bytes()
    offset, length = struct.unpack_from("<2Q", data, 80)
    layers = np.frombuffer(data, np.uint8, length, offset).reshape(frames, 64, 64, 2)
    return o, frames, layers.astype(np.float32) / 255


def _texel_view(o, shift=(0.0, 0.0)):
    n = o.resolution
    return orthographic_down(shift[0], shift[1], o.size, o.size), n


def _world_normals(o, t, choppiness):
    """Brute-force normals at the texel centres, turned into the world frame."""
    c = (np.arange(o.resolution) + 0.5) * o.texel
    x, z = np.meshgrid(c, c)  # image row j at z = (j + 1/2) dx
    tangent = evaluate(o, x, -z, t, choppiness=choppiness)["normal"]
    return np.stack([tangent[..., 0], tangent[..., 2], -tangent[..., 1]], -1)


def test_shader_normals_are_the_oceans_at_every_world_point(sea):
    o, frames, layers = sea
    scene = WaterScene(normals=layers, frame_rate=frames / o.loop_period, tile_size=o.size)
    view, n = _texel_view(o)
    for k in (0, 5):
        t = k * o.loop_period / frames
        got = render_water(scene, width=n, height=n, inv_view_proj=view, time=t, mode="normal")
        expected = _world_normals(o, t, 0.4)
        err = np.degrees(angle_between(got[..., :3], expected))
        assert err.max() < SHADER_NORMAL_DEG, k


def test_shader_loops_and_tiles(sea):
    o, frames, layers = sea
    scene = WaterScene(normals=layers, frame_rate=frames / o.loop_period, tile_size=o.size)
    view, n = _texel_view(o)
    start = render_water(scene, width=n, height=n, inv_view_proj=view, time=0.0, mode="normal")
    looped = render_water(scene, width=n, height=n, inv_view_proj=view, time=o.loop_period,
                          mode="normal")  # fmt: skip
    assert np.degrees(angle_between(start[..., :3], looped[..., :3])).max() < 0.05
    shifted_view, _ = _texel_view(o, shift=(o.size, -3 * o.size))
    shifted = render_water(scene, width=n, height=n, inv_view_proj=shifted_view, mode="normal")
    assert np.degrees(angle_between(start[..., :3], shifted[..., :3])).max() < 0.05


def test_shader_underwater_path_obeys_fermat():
    w = murk.water("II")
    depth, eye = 3.0, np.array([0.0, 2.5, 0.0])
    scene = WaterScene(bottom_depth=depth, water=_uniforms(w))
    view = look_at(eye, [6.0, 0.0, -8.0], fov=50.0)
    got = render_water(scene, width=48, height=48, inv_view_proj=view, mode="path")
    path, hx, hz = got[..., 0], got[..., 1], got[..., 2]
    checked = 0
    for j in range(0, 48, 5):
        for i in range(0, 48, 5):
            if path[j, i] <= 0:
                continue  # the ray misses the water (sky)
            horizontal = math.hypot(hx[j, i] - eye[0], hz[j, i] - eye[2])
            expected = murk.underwater_path(eye[1], depth, horizontal, refraction=True)
            assert path[j, i] == pytest.approx(expected, rel=SHADER_PATH_RTOL)
            checked += 1
    assert checked > 40


def _uniforms(w):
    from bakeshop.water.shader import scene_water

    return scene_water(w)


def test_shader_ripples_are_the_analytic_ring():
    crater = drop_crater(drop_diameter=0.003, drop_speed=6.0, viscosity=1e-6)
    cells, res, tile = 4, 128, 1.0
    cell = tile / cells
    atlas = rain_atlas(resolution=res, cells=cells, seed=5, margin=0.35)
    radius, duration = 0.35 * cell, 0.6
    lut = ring_lut(crater, radius=radius, duration=duration, radii=512, steps=512)
    scene = WaterScene(rain=atlas, ring=lut, rain_cell=cell, rain_tile=tile, ring_radius=radius,
                       ring_duration=duration)  # fmt: skip
    view = orthographic_down(0.0, 0.0, tile, tile)
    time = 0.37
    got = render_water(scene, width=res, height=res, inv_view_proj=view, time=time,
                       mode="ripple")  # fmt: skip
    d = atlas[..., :2].astype(np.float64) * 2 - 1
    r = np.hypot(d[..., 0], d[..., 1]) * cell
    tau = np.mod(time / duration + atlas[..., 2], 1.0) * duration
    inside = atlas[..., 3] > 0
    expected = np.zeros((res, res))
    for value in np.unique(tau[inside]):
        sel = inside & (tau == value)
        expected[sel] = ring(crater, r[sel], [value])[1][0]
    scale = np.abs(expected).max()
    assert scale > 0
    assert np.abs(got[..., 0] - expected).max() < SHADER_RIPPLE_RTOL * scale
    np.testing.assert_array_equal(got[..., 1] > 0.5, inside)


def test_shaded_colour_is_physical():
    w = murk.water("IB")
    dark = np.zeros((16, 32, 3), np.float32)  # no reflection: only what comes from below
    view = look_at([0.0, 3.0, 0.0], [0.0, 0.0, -4.0], fov=40.0)
    colours = []
    for depth in (1.0, 4.0, 12.0):
        scene = WaterScene(environment=dark, bottom_depth=depth, water=_uniforms(w))
        image = render_water(scene, width=32, height=32, inv_view_proj=view)
        assert np.isfinite(image).all() and (image[..., :3] >= 0).all()
        colours.append(image[20:, :, :3].mean((0, 1)))
    assert (colours[0] > colours[1]).all() and (colours[1] > colours[2]).all()
    # red fades fastest with depth in ocean water
    assert colours[2][0] / colours[0][0] < colours[2][2] / colours[0][2]
