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


# --- geometry per strip: what the integrals of large environments read --------------------------


STRIP_LAYOUTS = ["latlong", "angular", "mirrorball", "cube", "octahedral", "dual-paraboloid",
                 "cross-vertical", "strip-horizontal"]  # fmt: skip


@pytest.mark.parametrize("name", STRIP_LAYOUTS)
def test_strips_and_gathered_texels_are_the_whole_geometry_bit_for_bit(name):
    """texel_strips (strips of whole rows, any size) and texels_at (any texels) give the same
    numbers as the whole layout's texel_geometry, without building it."""
    from bakeshop.sphere import layout, texel_strips, texels_at

    shape = layout(name).shape(20)
    dirs, omega = texel_geometry(name, shape)
    for size in (1, 100, 1 << 20):
        parts = list(texel_strips(name, shape, texels=size))
        assert parts[0][0] == 0 and parts[-1][1] == len(omega)
        assert all(a[1] == b[0] for a, b in zip(parts, parts[1:], strict=False))
        np.testing.assert_array_equal(np.concatenate([p[2] for p in parts]), dirs)
        np.testing.assert_array_equal(np.concatenate([p[3] for p in parts]), omega)
    index = np.random.default_rng(5).integers(0, len(omega), 300)
    got_dirs, got_omega = texels_at(name, shape, index)
    np.testing.assert_array_equal(got_dirs, dirs[index])
    np.testing.assert_array_equal(got_omega, omega[index])


def test_large_cube_faces_compute_their_solid_angles_by_rows_as_the_cached_table_does():
    from bakeshop.sphere import texels_at
    from bakeshop.sphere.layouts.cubemap import _cube_face_solid_angles
    from bakeshop.sphere.texels import cube_face_solid_angles, texel_strips

    s = 1100  # beyond the cached tables
    table = _cube_face_solid_angles(s)
    np.testing.assert_array_equal(cube_face_solid_angles(s), table)
    rows = next(texel_strips("cube", (6, s, s), rows=(s - 300, s + 300), texels=1 << 30))[3]
    np.testing.assert_array_equal(rows, np.concatenate([table[-300:], table[:300]]).reshape(-1))
    index = np.array([0, 7, s * s - 1, 3 * s * s + 5 * s + 9])
    np.testing.assert_array_equal(texels_at("cube", (6, s, s), index)[1],
                                  table.reshape(-1)[index % (s * s)])  # fmt: skip


def test_a_strided_image_is_made_contiguous_once_and_a_contiguous_one_is_never_copied():
    """A PFM's memory map holds its rows bottom-up: the environment is copied once, so that
    no later step copies it again."""
    base = np.ones((8, 16, 3), np.float32)
    flipped = base[::-1]
    env = check_environment(flipped, "latlong")
    assert env.image.flags.c_contiguous and not np.shares_memory(env.image, base)
    np.testing.assert_array_equal(env.image, flipped)
    assert np.shares_memory(check_environment(base, "latlong").image, base)
