"""The environment contract (bakeshop.sphere.check_environment): the same four inputs get the
same answer from every spherical function: a 2-D grey image, an RGBA image, a NaN, and a wrong
layout name."""

import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.light import bake_fresnel, bake_probe, find_sun, irradiance, prefilter_ggx
from bakeshop.sphere import check_environment, remap, texel_cosines, texel_geometry, texels


def probe(channels: int | None = 3) -> np.ndarray:
    """A 32x64 latlong: a smooth sky and a one-texel sun (grey when ``channels`` is None)."""
    from bakeshop.sphere import layout

    dirs, _ = layout("latlong").directions((32, 64))
    sky = (1.2 + dirs[..., 1]).astype(np.float32)
    sky[8, 20] = 5000.0
    if channels is None:
        return sky
    out = np.repeat(sky[..., None], channels, axis=-1)
    if channels == 4:
        out[..., 3] = 1.0
    return out


#: every spherical function, as (name, call(image, layout) -> image-like results)
FUNCTIONS = {
    "remap": lambda img, lay: [remap(img, lay, "latlong", (32, 16))],
    "irradiance": lambda img, lay: [irradiance(img, lay, size=(32, 16))],
    "sun": lambda img, lay: [find_sun(img, lay)],
    "prefilter": lambda img, lay: prefilter_ggx(img, lay, size=8, mips=2, samples=16),
    "bake_fresnel": lambda img, lay: [bake_fresnel(img, lay)],
    "bake_probe": lambda img, lay: (
        lambda b: [b.cube, b.sun_dim, b.shadow_dim, b.shadow_probe, *b.specular]
    )(bake_probe(img, lay, cube_size=8, dim_size=(16, 8), specular_size=8, mips=2, dfg_size=8)),
}


@pytest.mark.parametrize("name", FUNCTIONS)
def test_a_grey_2d_image_gives_2d_results(name):
    grey, rgb = FUNCTIONS[name](probe(None), "latlong"), FUNCTIONS[name](probe(3), "latlong")
    for g, c in zip(grey, rgb, strict=True):
        if isinstance(g, np.ndarray):
            # one channel, no channel axis; the values of each channel of the grey RGB probe
            assert g.shape == c.shape[:-1]
            np.testing.assert_allclose(g, c[..., 0], rtol=1e-5, atol=1e-6)
        else:  # the sun is found in grey as in colour
            np.testing.assert_allclose(g.direction, c.direction, atol=1e-9)


@pytest.mark.parametrize("name", FUNCTIONS)
def test_alpha_is_carried_through_every_function(name):
    rgb, rgba = FUNCTIONS[name](probe(3), "latlong"), FUNCTIONS[name](probe(4), "latlong")
    for a, b in zip(rgb, rgba, strict=True):
        if isinstance(a, np.ndarray):
            assert b.shape == a.shape[:-1] + (4,)
            np.testing.assert_allclose(b[..., :3], a, rtol=1e-5, atol=1e-6)
        else:
            np.testing.assert_allclose(b.direction, a.direction, atol=1e-9)


@pytest.mark.parametrize("name", FUNCTIONS)
@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_a_non_finite_value_is_refused_with_its_count_and_place(name, bad):
    img = probe(3)
    img[5, 7, 1] = bad
    img[6, 7, 0] = bad
    kind = "NaN" if np.isnan(bad) else "infinite"
    where = r"\(the first at row 5, column 7\)"
    with pytest.raises(ArgumentError, match=rf"2 {kind} value\(s\) {where}"):
        FUNCTIONS[name](img, "latlong")


@pytest.mark.parametrize("name", FUNCTIONS)
def test_a_wrong_layout_name_is_refused_naming_the_valid_ones(name):
    with pytest.raises(ArgumentError, match="'lat-long'.*latlong"):
        FUNCTIONS[name](probe(3), "lat-long")


@pytest.mark.parametrize(
    ("image", "layout", "match"),
    [
        (np.zeros((8, 16, 5), np.float32), "latlong", "1 to 4 channels"),
        (np.zeros((8, 16, 3, 1), np.float32), "latlong", r"\(H, W\) or \(H, W, C\)"),
        (np.zeros((8, 9, 3), np.float32), "angular", "square"),
        (np.zeros((8, 16), dtype="U1"), "latlong", "numbers"),
    ],
)
def test_bad_shapes_and_types(image, layout, match):
    with pytest.raises(ArgumentError, match=match):
        check_environment(image, layout)


def test_types_are_kept_or_made_float32():
    assert check_environment(np.zeros((4, 8), np.float64), "latlong").image.dtype == np.float64
    assert check_environment(np.zeros((4, 8), np.uint8), "latlong").image.dtype == np.float32
    env = check_environment(np.zeros((4, 8, 3), np.float32), "latlong")
    assert env.image.dtype == np.float32 and not env.squeezed


def test_texels_integrate_radiance_times_solid_angle():
    """Reference: a uniform sky of radiance L integrates to 4 pi L over any layout."""
    for name, shape in [("latlong", (16, 32)), ("mirrorball", (24, 24)), ("cube", (6, 8, 8))]:
        t = texels(np.full(shape + (3,), 2.0, np.float32), name)
        np.testing.assert_allclose((t.values * t.omega[:, None]).sum(0), 8 * np.pi, rtol=1e-12)
        dirs, omega = texel_geometry(name, shape)
        assert dirs is t.dirs and omega is t.omega  # cached


def test_texel_cosines_are_the_dot_product_of_directions_and_axis():
    from bakeshop.sphere import layout

    for name, shape in [("latlong", (8, 16)), ("angular", (10, 10)), ("cross-vertical", (16, 12))]:
        lay = layout(name)
        dirs, valid = lay.directions(shape)
        axis = np.array([0.3, 0.8, -0.2])
        cos = texel_cosines(name, shape, axis)
        expected = dirs @ (axis / np.linalg.norm(axis))
        np.testing.assert_allclose(cos[valid], expected[valid], atol=1e-12)
        assert np.isnan(cos[~valid]).all()
