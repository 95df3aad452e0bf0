"""Sun detection, measurement and removal: synthetic skies with known suns, real probes."""

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bakeshop.io import read_image, write_json
from bakeshop.light import sun as sunlib
from bakeshop.sphere import layout
from tests.files import probe_path
from tests.tolerances import SUN_DIRECTION_DEG, SUN_SOLID_ANGLE

SUPERSAMPLE = 4


def _unit(v):
    v = np.asarray(v, np.float64)
    return v / np.linalg.norm(v)


def _sky(d):
    up = np.clip(d[..., 1], 0, None)[..., None]
    return 0.3 + np.array([0.6, 0.8, 1.4]) * up + 0.2 * np.clip(d[..., :1], 0, None)


def _render(name, size, sun_dir, radius_deg, radiance):
    """A smooth sky with a sun disk; texels near the disk's edge hold their covered fraction of
    the disk's radiance (SUPERSAMPLE^2 sub-texel samples)."""
    lay = layout(name)
    shape = lay.shape(size)
    dirs, valid = lay.directions(shape)
    sky = np.where(valid[..., None], _sky(dirs), 0)
    cos_r = math.cos(math.radians(radius_deg))
    pitch = math.sqrt(4 * math.pi / valid.sum()) * 4  # generous texel size (distorted layouts)
    near = np.flatnonzero(
        valid.reshape(-1)
        & (dirs.reshape(-1, 3) @ sun_dir > math.cos(math.radians(radius_deg) + pitch))
    )
    index = np.stack(np.unravel_index(near, shape), -1)  # (n, len(shape)): [face,] row, col
    offsets = (np.arange(SUPERSAMPLE) + 0.5) / SUPERSAMPLE
    ox, oy = np.meshgrid(offsets, offsets)
    coords = np.zeros((len(near), SUPERSAMPLE**2, len(shape)))
    coords[..., -2] = index[:, -1, None] + ox.reshape(-1)  # x: column
    coords[..., -1] = index[:, -2, None] + oy.reshape(-1)  # y: row
    if len(shape) == 3:
        coords[..., 0] = index[:, 0, None]  # cube face
    sub = lay.directions_at(coords, shape)
    cover = (sub @ sun_dir > cos_r).mean(-1)
    img = sky.reshape(-1, 3).copy()
    img[near] += cover[:, None] * np.asarray(radiance, np.float64)
    return img.reshape(sky.shape).astype(np.float32), sky


def _angle_deg(a, b):
    return math.degrees(math.acos(min(1.0, float(np.dot(_unit(a), _unit(b))))))


CASES = [
    # layout, size, direction, radius (deg), radiance
    ("latlong", 1024, [0.5, 0.45, -0.6], 0.8, [4e4, 3.5e4, 3e4]),
    ("latlong", 512, [-0.3, 0.2, 0.9], 2.0, [3e3, 2e3, 1e3]),  # across the latlong seam (+Z)
    ("latlong", 512, [0.05, 0.99, 0.08], 3.0, [500, 500, 450]),  # at the pole
    ("latlong", 512, [0.9, -0.1, 0.3], 1.5, [80.0, 60.0, 40.0]),  # faint, below the horizon
    ("cube", 256, [0.7, 0.69, 0.2], 1.0, [2e4, 2e4, 2e4]),  # near a cube corner
    ("angular", 800, [0.2, 0.4, 0.89], 1.5, [1e4, 9e3, 8e3]),  # near the rim (behind, +Z)
]


@pytest.mark.parametrize("name, size, direction, radius, radiance", CASES)
def test_synthetic_sun_is_found_and_measured(name, size, direction, radius, radiance):
    s = _unit(direction)
    img, _ = _render(name, size, s, radius, radiance)
    sun = sunlib.find_sun(img, name)
    assert sun is not None
    assert _angle_deg(sun.direction, s) < SUN_DIRECTION_DEG
    omega = 2 * math.pi * (1 - math.cos(math.radians(radius)))
    assert sun.solid_angle_sr == pytest.approx(omega, rel=SUN_SOLID_ANGLE)
    assert sun.angular_radius_deg == pytest.approx(radius, rel=SUN_SOLID_ANGLE / 2)
    # colour: the disk's radiance above the sky behind it; irradiance ~ radiance * solid angle
    np.testing.assert_allclose(sun.color, radiance, rtol=SUN_SOLID_ANGLE)
    np.testing.assert_allclose(sun.irradiance, np.asarray(radiance) * omega, rtol=SUN_SOLID_ANGLE)


def test_removal_restores_the_sky_and_leaves_the_rest_alone():
    s = _unit([0.4, 0.5, -0.7])
    img, true_sky = _render("latlong", 512, s, 2.0, [5e3, 4e3, 3e3])
    probe, sun = sunlib.remove_sun(img, "latlong")
    assert sun is not None and probe.dtype == img.dtype and probe.shape == img.shape
    changed = np.any(probe != img, axis=-1)
    dirs, _ = layout("latlong").directions(img.shape[:2])
    angle = np.degrees(np.arccos(np.clip(dirs @ sun.direction, -1, 1)))
    assert angle[changed].max() <= sun.mask_radius_deg + 0.5  # only the sun's region changed
    region = angle < sun.mask_radius_deg
    # the harmonic fill of a smooth sky is the sky, to a few per cent
    np.testing.assert_allclose(probe[region], true_sky[region], rtol=0.03)
    # and nothing of the sun is left: no texel brighter than twice the sky
    assert probe.max() < 2 * true_sky.max()


def test_rgba_keeps_its_alpha():
    img, _ = _render("latlong", 256, _unit([0.3, 0.8, -0.5]), 3.0, [2e3, 2e3, 2e3])
    rgba = np.concatenate([img, np.full(img.shape[:2] + (1,), 0.5, np.float32)], -1)
    probe, sun = sunlib.remove_sun(rgba, "latlong")
    assert sun is not None and probe.shape == rgba.shape
    np.testing.assert_array_equal(probe[..., 3], 0.5)
    rgb, _ = sunlib.remove_sun(img, "latlong")
    np.testing.assert_array_equal(probe[..., :3], rgb)


def test_no_sun_in_a_uniform_or_black_environment():
    assert sunlib.find_sun(np.ones((64, 128, 3), np.float32), "latlong") is None
    assert sunlib.find_sun(np.zeros((64, 128, 3), np.float32), "latlong") is None
    env, _ = _render("latlong", 128, _unit([0, 1, 0]), 1.0, [0, 0, 0])
    assert sunlib.find_sun(env, "latlong") is None
    same, sun = sunlib.remove_sun(env, "latlong")
    assert sun is None
    np.testing.assert_array_equal(same, env)


def test_two_equal_lamps_are_not_a_sun():
    a, sky = _render("latlong", 512, _unit([0.5, 0.5, -0.7]), 1.0, [1e3] * 3)
    b, _ = _render("latlong", 512, _unit([-0.5, 0.5, -0.7]), 1.0, [1e3] * 3)
    assert sunlib.find_sun(a + b - sky.astype(np.float32), "latlong") is None
    assert sunlib.find_sun(a, "latlong") is not None


@pytest.mark.parametrize(
    "name, has_sun",
    [
        ("quarry_01", True),
        ("rooitou_park", True),
        ("venice_sunset", True),
        ("st_fagans_interior", False),
        ("forest_slope", False),
        ("kiara_1_dawn", False),
    ],
)
def test_real_probes(name, has_sun):
    env = read_image(probe_path(name))
    sun = sunlib.find_sun(env, "latlong")
    assert (sun is not None) == has_sun
    if has_sun:
        # the direction is that of the brightest texel, within the disk's size
        lum = env @ np.array([0.2126, 0.7152, 0.0722], np.float32)
        dirs, _ = layout("latlong").directions(env.shape[:2])
        peak = dirs.reshape(-1, 3)[np.argmax(lum)]
        assert _angle_deg(sun.direction, peak) < 0.5
        assert sun.direction[1] > 0  # in the sky
        assert 0.1 < sun.angular_radius_deg < 1.0  # the real sun is 0.27 degrees
        assert np.all(sun.irradiance >= 0) and np.all(sun.color >= 0)


def test_sun_json(tmp_path):
    img, _ = _render("latlong", 256, _unit([0.3, 0.8, -0.5]), 3.0, [2e3, 2e3, 2e3])
    sun = sunlib.find_sun(img, "latlong")
    path = tmp_path / "sun.json"
    write_json(path, sunlib.sun_document(sun))
    doc = json.loads(path.read_text())
    assert set(doc) >= {"direction", "angular_radius_deg", "solid_angle_sr", "color", "irradiance"}
    assert np.linalg.norm(doc["direction"]) == pytest.approx(1)
    write_json(path, sunlib.sun_document(None))
    assert json.loads(path.read_text()) == {"sun": None}


@pytest.mark.slow
@settings(max_examples=12, deadline=None)
@given(
    z=st.floats(-0.99, 0.99),
    azimuth=st.floats(0, 2 * math.pi),
    radius=st.floats(1.0, 4.0),
    radiance=st.floats(100.0, 1e5),
)
def test_random_suns_anywhere(z, azimuth, radius, radiance):
    s = np.array(
        [math.sqrt(1 - z * z) * math.cos(azimuth), z, math.sqrt(1 - z * z) * math.sin(azimuth)]
    )
    img, _ = _render("latlong", 512, s, radius, [radiance] * 3)
    sun = sunlib.find_sun(img, "latlong")
    assert sun is not None
    assert _angle_deg(sun.direction, s) < SUN_DIRECTION_DEG
    omega = 2 * math.pi * (1 - math.cos(math.radians(radius)))
    assert sun.solid_angle_sr == pytest.approx(omega, rel=SUN_SOLID_ANGLE)
