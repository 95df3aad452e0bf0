"""The whole probe bake (bakeshop.light.bake_probe) against closed forms: a uniform sky, and a
uniform sky with a disk sun of known radiance, whose irradiance is known exactly."""

import math

import numpy as np
import pytest

from bakeshop.light import bake_probe, contact_sheet
from bakeshop.sphere import layout

SMALL = {"cube_size": 16, "dim_size": (32, 16), "specular_size": 16, "mips": 3, "dfg_size": 16}


@pytest.mark.slow
def test_a_uniform_sky_bakes_to_ones():
    """L = 1 everywhere: every radiance output is 1, a DIM of a uniform sky of 1 is 1 (E/pi),
    the SH's constant term is the integral of Y00 = 1/(2 sqrt(pi)): 4 pi / (2 sqrt(pi)), and
    there is no sun."""
    sky = np.ones((32, 64, 3), np.float32)
    bake = bake_probe(sky, "latlong", **SMALL)
    assert bake.sun is None
    for image in (bake.cube, *bake.specular):
        np.testing.assert_allclose(image, 1.0, rtol=2e-5)
    # the DIM is a quadrature of the cosine over 2048 texels of ~0.1 rad: error ~ h^2 / 12
    for dim in (bake.sun_dim, bake.shadow_dim):
        np.testing.assert_allclose(dim, 1.0, rtol=1e-3)
    np.testing.assert_array_equal(bake.shadow_probe, sky)
    np.testing.assert_allclose(bake.sh[0], 2 * math.sqrt(math.pi), rtol=1e-9)
    # the projection samples Y_lm at texel centres: the higher bands vanish to ~h^2
    np.testing.assert_allclose(bake.sh[1:], 0.0, atol=1e-2)
    assert bake.cube.shape == (6, 16, 16, 3)
    assert [level.shape[1] for level in bake.specular] == [16, 8, 4]
    # scale + bias is the directional albedo of the GGX lobe: at most 1 (energy is lost)
    assert bake.dfg.shape == (16, 16, 2) and bake.dfg.min() >= 0
    assert bake.dfg.sum(axis=-1).max() <= 1 + 1e-4  # a 4096-sample estimate of 1 at smooth


@pytest.mark.slow
def test_a_disk_sun_is_found_and_split_exactly():
    """A disk of radius 3 deg and radiance Ls at direction s on a sky of 1: the sun found at s,
    and sun DIM - shadow DIM at the normal s is the disk's irradiance over pi,
    Ls * pi sin(r)^2 / pi (the exact cosine-weighted integral over a disk around the normal)."""
    h = 256
    lay = layout("latlong")
    dirs, _ = lay.directions((h, 2 * h))
    s = np.array([0.5, 0.6, -0.4])
    s /= np.linalg.norm(s)
    r = math.radians(3.0)
    radiance = 400.0
    sky = np.ones((h, 2 * h, 3), np.float32)
    sky[dirs @ s > math.cos(r)] += radiance
    bake = bake_probe(sky, "latlong", **{**SMALL, "dim_size": (64, 32)})
    assert bake.sun is not None
    assert math.degrees(math.acos(np.clip(bake.sun.direction @ s, -1, 1))) < 0.3
    # the disk as the latlong's texels hold it (its solid angle, to the texel), cosine-weighted
    omega = lay.solid_angles((h, 2 * h))
    inside = dirs @ s > math.cos(r)
    exact = radiance * np.sum(omega[inside] * (dirs[inside] @ s)) / math.pi
    assert exact == pytest.approx(radiance * math.sin(r) ** 2, rel=0.05)  # the continuous disk
    dim_dirs, _ = lay.directions(lay.shape((64, 32)))
    k = np.unravel_index(np.argmax(dim_dirs @ s), dim_dirs.shape[:2])
    cos = dim_dirs[k] @ s
    split = (bake.sun_dim - bake.shadow_dim)[k]
    np.testing.assert_allclose(split, exact * cos, rtol=0.02)  # normal a texel off s
    np.testing.assert_allclose(bake.shadow_dim, 1.0, rtol=0.01)  # the sky alone, filled in


@pytest.mark.slow
def test_default_cube_size_is_the_power_of_two_nearest_the_probes_texels():
    bake = bake_probe(np.ones((64, 128, 3), np.float32), "latlong", **{**SMALL, "cube_size": None})
    # 8192 texels / 6 = 1365 = 37^2: 32 is the power of two nearest 37
    assert bake.cube.shape[1] == 32


@pytest.mark.slow
def test_the_contact_sheet_is_a_picture():
    sky = np.ones((32, 64, 3), np.float32)
    sheet = contact_sheet(bake_probe(sky, "latlong", **SMALL), sky, thumb_height=32)
    assert sheet.dtype == np.uint8 and sheet.ndim == 3 and sheet.shape[2] == 3
    assert sheet.shape[0] > 100 and sheet.shape[1] > 100 and sheet.std() > 0
